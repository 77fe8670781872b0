"""Design files: read, validate and hold a design (the input of the deployable model)."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

from compas.data import Data

from compas_ccu.design.curve_files import read_curve_files
from compas_ccu.design.schema import SCHEMA, validate
from compas_ccu.design.sections import DesignSections
from compas_ccu.design.units import convert_document, plausibility_warnings
from compas_ccu.errors import DesignError, UnitsWarning
from compas_ccu.materials import DesignFactors, Material, MaterialError, design_factors
from compas_ccu.materials import material as library_material

__all__ = ["Design", "load_design", "read_toml", "parse_toml"]


def parse_toml(text: str) -> dict:
    """Parse TOML text (``tomllib`` on Python >= 3.11, ``tomli`` before)."""
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.9 / 3.10 (Rhino 8)
        import tomli as tomllib
    return tomllib.loads(text)


class Design(Data):
    """A validated design: the contents of a design TOML file, typed by section.

    Parameters
    ----------
    document : dict
        Parsed TOML, validated on construction (:func:`compas_ccu.design.schema.validate`).
    name : str, optional
        Fallback name when the document has no ``design.name``.
    base : str or Path, optional
        Folder that relative curve-file paths (``crease.points = "crease.dxf"``) are read from;
        default: the current folder (:func:`load_design` gives the design file's).

    Attributes
    ----------
    document : dict
        The document as given, in its ``[design] units`` (written back as it is).
    values : dict
        ``{section: {key: value}}`` with defaults filled in, lengths in metres.
    units : str
        The file's length units (``[design] units``, default ``"m"``); everything the design
        gives (``values``, ``sections``) is metres.
    sections : DesignSections
        The same, typed: ``design.sections.crease.span``; the sections are also attributes
        (``design.crease``, ``design.layout``, ...).

    Examples
    --------
    >>> d = Design({"crease": {"profile": "arc", "span": 2.0, "rise": 0.5},
    ...             "rulings": {"type": "orthogonal"}, "deployment": {"alpha": 30.0},
    ...             "layout": {"width": 0.3}})
    >>> d.crease.span, d.alpha, d.name
    (2.0, 30.0, 'design')

    A design in millimetres is metres inside:

    >>> d = Design({"design": {"units": "mm"},
    ...             "crease": {"profile": "arc", "span": 2000, "rise": 500},
    ...             "rulings": {"type": "orthogonal"}, "deployment": {"alpha": 30.0},
    ...             "layout": {"width": 300}})
    >>> d.units, d.crease.span, d.layout.width, d.metric_document()["layout"]
    ('mm', 2.0, 0.3, {'width': 0.3})

    Warns
    -----
    UnitsWarning
        A length is implausible for the file's units (a 2500 m span: "did you mean
        units = "mm"?"); the message names the key and the value.
    """

    def __init__(self, document: dict, *, name: str | None = None, base=None):
        values = read_curve_files(validate(document), base, plane_given="plane" in document)
        super().__init__(name=values["design"]["name"] or name or "design")
        self.document = document
        self.base = None if base is None else str(Path(base).resolve())
        self.values = values
        self.sections = DesignSections.from_values(values)
        for message in plausibility_warnings(values, self.units):
            warnings.warn(message, UnitsWarning, stacklevel=2)

    @classmethod
    def from_metric(
        cls, document: dict, *, units: str = "m", name: str | None = None, base=None
    ) -> Design:
        """A design from a document in metres, kept in ``units`` (its lengths converted and
        ``[design] units`` set): a design derived from another one in the other's units
        (``base``: the folder its curve files are read from).

        Examples
        --------
        >>> d = Design.from_metric({"crease": {"profile": "arc", "span": 2.0, "rise": 0.5},
        ...     "rulings": {"type": "orthogonal"}, "deployment": {"alpha": 30.0},
        ...     "layout": {"width": 0.3}}, units="cm")
        >>> d.document["crease"]["span"], d.document["design"], d.crease.span
        (200.0, {'units': 'cm'}, 2.0)
        """
        return cls(convert_document(document, SCHEMA, to=units, source="m"), name=name, base=base)

    @property
    def units(self) -> str:
        """The file's length units (``[design] units``): ``"m"``, ``"mm"``, ``"cm"``,
        ``"ft"`` or ``"in"``. The design's values are metres whatever the units."""
        return self.values["design"]["units"]

    def metric_document(self) -> dict:
        """The document with every length in metres and no ``[design] units``: the form to
        edit with values in metres (derived designs, scale studies)."""
        return convert_document(self.document, SCHEMA, to="m")

    def document_in(self, units: str) -> dict:
        """The document with its lengths in ``units`` (``[design] units`` set accordingly).

        Raises
        ------
        DesignError
            ``units`` is not an allowed length unit.
        """
        return convert_document(self.document, SCHEMA, to=units)

    @property
    def __data__(self) -> dict:
        return {"document": self.document, "name": self.name, "base": self.base}

    @classmethod
    def __from_data__(cls, data: dict) -> Design:
        return cls(data["document"], name=data.get("name"), base=data.get("base"))

    # the sections, typed
    @property
    def crease(self):
        return self.sections.crease

    @property
    def rulings(self):
        return self.sections.rulings

    @property
    def deployment(self):
        return self.sections.deployment

    @property
    def layout(self):
        return self.sections.layout

    @property
    def target(self):
        return self.sections.target

    @property
    def plates(self):
        return self.sections.plates

    @property
    def plane(self):
        return self.sections.plane

    @property
    def design_code(self):
        return self.sections.design_code

    @property
    def loads(self):
        """The ``[loads]`` section: the load cases of the structural checks."""
        return self.sections.loads

    @property
    def supports(self):
        """The ``[supports]`` section: how the feet are held under the load cases."""
        return self.sections.supports

    @property
    def hinges(self):
        """The ``[hinges]`` section: rigid or spring hinges in the FE model."""
        return self.sections.hinges

    @property
    def fabrication(self):
        """The ``[fabrication]`` section: sheets, cutter, nesting and unit prices."""
        return self.sections.fabrication

    @property
    def materials(self):
        """The file's ``[materials.NAME]`` tables: name -> Material."""
        return self.sections.materials

    @property
    def material(self) -> Material:
        """The plate material (``[plates] material``), resolved: the file's or the library's."""
        return self.resolve_material(None)

    def resolve_material(self, spec=None) -> Material:
        """A material by name (the file's ``[materials.NAME]`` first, then the library), a
        dict of values, a Material, or None for ``[plates] material``.

        Raises
        ------
        compas_ccu.materials.MaterialError
            An unknown name (the message lists the file's and the library's).
        """
        if spec is None:
            spec = self.plates.material
        if isinstance(spec, str) and spec in self.materials:
            return self.materials[spec]
        if isinstance(spec, str):
            try:
                return library_material(spec)
            except MaterialError as exc:
                if self.materials:
                    raise MaterialError(
                        f"{exc}; the design file defines {sorted(self.materials)}"
                    ) from None
                raise
        return library_material(spec)

    def design_factors(self, material=None, **overrides) -> DesignFactors:
        """The design factors of the bending check: the ``[design_code]`` section (with
        ``overrides``) for ``material`` (default: the plate material).

        Raises
        ------
        compas_ccu.materials.MaterialError
            A material without default factors (gfrp, other) and no k_mod / gamma_M given.
        """
        values = {**self.design_code.to_dict(), **overrides}
        return design_factors(self.resolve_material(material), **values)

    @property
    def alpha(self) -> float:
        """Design reflection angle at the reference vertex, degrees."""
        return self.sections.deployment.alpha

    def __repr__(self) -> str:
        return (
            f"Design({self.name!r}, profile={self.crease.profile!r}, layout={self.layout.type!r})"
        )


def read_toml(path, *, error=DesignError, what: str = "design") -> dict:
    """Parse a TOML file; a missing file or bad TOML becomes ``error`` naming the path."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise error(f"cannot read {what} file {str(path)!r}: {exc.strerror}") from exc
    except UnicodeDecodeError as exc:
        bom = {b"\xff\xfe": "UTF-16", b"\xfe\xff": "UTF-16"}.get(path.read_bytes()[:2])
        saved = f" (it looks saved as {bom})" if bom else ""
        raise error(
            f"{what} file {str(path)!r} is not UTF-8 text{saved}: TOML files are UTF-8; "
            f"save it as UTF-8 (byte {exc.start} is {exc.object[exc.start : exc.start + 1]!r})"
        ) from exc
    try:
        return parse_toml(text)
    except Exception as exc:  # tomllib.TOMLDecodeError
        raise error(f"{path}: not valid TOML: {exc}") from exc


def load_design(path) -> Design:
    """Load and validate a design TOML file.

    Raises
    ------
    DesignError
        The file is missing, not TOML, or not a valid design (the message names the key).
    """
    path = Path(path)
    document = read_toml(path)
    try:
        return Design(document, name=path.stem, base=path.parent)
    except DesignError as exc:
        error = DesignError(f"{path}: {exc}")
        error.key = exc.key  # the message names the key already; keep it for callers
        raise error from exc
