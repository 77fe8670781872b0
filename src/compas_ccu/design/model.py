"""Design files: load, validate and turn into a deployable model."""

from __future__ import annotations

import sys
from pathlib import Path

from compas_ccu.design.schema import validate
from compas_ccu.errors import DesignError

__all__ = ["Design", "load_design", "read_toml"]


def _toml_loads(text: str) -> dict:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.9 / 3.10 (Rhino 8)
        import tomli as tomllib
    return tomllib.loads(text)


class Design:
    """A validated design (the contents of a design TOML file).

    Parameters
    ----------
    document : dict
        Parsed TOML, validated on construction.
    name : str, optional
        Fallback name when the file has no ``design.name``.

    Examples
    --------
    >>> d = Design({"crease": {"profile": "arc", "span": 2.0, "rise": 0.5},
    ...             "rulings": {"type": "orthogonal"}, "deployment": {"alpha": 30.0},
    ...             "layout": {"width": 0.3}})
    >>> model = d.build()
    >>> round(model.deploy(30.0).alpha, 12)
    30.0
    """

    def __init__(self, document: dict, *, name: str | None = None):
        self.document = document
        self.values = validate(document)
        self.name = self.values["design"]["name"] or name or "design"

    @classmethod
    def from_toml(cls, text: str, *, name: str | None = None) -> Design:
        """Parse TOML text; a syntax error becomes a :class:`DesignError`."""
        try:
            document = _toml_loads(text)
        except Exception as exc:  # tomllib.TOMLDecodeError
            raise DesignError(f"not valid TOML: {exc}") from exc
        return cls(document, name=name)

    @property
    def alpha(self) -> float:
        """Design reflection angle at the reference vertex, degrees."""
        return self.values["deployment"]["alpha"]

    def build(self):
        """Build the deployable model (:class:`compas_ccu.model.CCUModel`)."""
        from compas_ccu.model import CCUModel

        return CCUModel(self)


def read_toml(path, *, error=DesignError, what: str = "design") -> dict:
    """Parse a TOML file; a missing file or bad TOML becomes ``error`` naming the path."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise error(f"cannot read {what} file {str(path)!r}: {exc.strerror}") from exc
    try:
        return _toml_loads(text)
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
        return Design(document, name=path.stem)
    except DesignError as exc:
        raise DesignError(f"{path}: {exc}") from exc
