"""The workshop's typed data: its options (the design's ``[fabrication]`` section), the parts
(plate parts and splice plates) and the plan (:func:`compas_ccu.fabrication.workshop.plan_workshop`
makes it; ``fabrication.json`` ``workshop`` and ``sheets.json`` are its summaries).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from compas_ccu.design.schema import STOCK_SHEET

__all__ = [
    "WorkshopOptions",
    "Part",
    "WorkshopPlan",
    "RollNesting",
    "NestingSearch",
    "NESTING_SEARCH_KEYS",
    "SpliceCutBending",
    "SpliceBending",
    "outline_ring",
]


@dataclass(frozen=True)
class WorkshopOptions:
    """The ``[fabrication]`` section in metres (see docs/design-files.md).

    >>> WorkshopOptions().spacing
    0.016
    """

    sheets: tuple = (STOCK_SHEET,)
    kerf: float | None = None
    tool_diameter: float = 0.006
    bridge: float = 0.01
    margin: float = 0.01
    grain: str = "along"
    splice_width: float = 0.15
    splice_thickness: float | None = None
    fasteners_per_splice: int = 8
    roll_width: float = 1.4
    score_rulings: bool = False
    nesting: str = "auto"
    nesting_time: float = 600.0
    nesting_seed: int = 0
    nesting_steps: int = 500
    nesting_generations: int = 3
    currency: str = "EUR"
    sheet_price: float = 60.0
    textile_price: float = 12.0
    glue_price: float = 0.3
    fastener_price: float = 0.05

    @classmethod
    def from_section(cls, section, **overrides) -> WorkshopOptions:
        """From a design's ``[fabrication]`` section (``design.fabrication``) and overrides."""
        values = {k: v for k, v in section.to_dict().items() if v is not None}
        values.update({k: v for k, v in overrides.items() if v is not None})
        values["sheets"] = tuple(tuple(float(x) for x in s) for s in values["sheets"])
        return cls(**values)

    @property
    def cut(self) -> float:
        """The kerf, m (the tool diameter unless set)."""
        return self.tool_diameter if self.kerf is None else float(self.kerf)

    @property
    def spacing(self) -> float:
        """Least distance between two parts' true outlines: kerf + bridge, m."""
        return round(self.cut + self.bridge, 12)

    @property
    def inset(self) -> float:
        """Least distance from a sheet edge to a part's true outline: margin + kerf, m."""
        return self.margin + self.cut

    def usable(self, s: int) -> tuple:
        """(length, width) of sheet size ``s`` the parts' true outlines may occupy, m."""
        length, width = self.sheets[s]
        return length - 2.0 * self.inset, width - 2.0 * self.inset


@dataclass
class Part:
    """One piece cut from a sheet.

    Attributes
    ----------
    name : str
        Label: ``P3`` (a whole plate), ``P3.1`` (part 1 of a split plate), ``S3.1U`` /
        ``S3.1D`` (the splice plates of plate 3's cut 1, upper and lower face).
    kind : str
        ``"plate"`` or ``"splice"``.
    plate : int
        The plate id it belongs to.
    outline : (m, 2) float
        True outline, m, in the plate's cut-pattern frame.
    grain : float
        Face-grain direction in that frame, degrees.
    score : list of (2, 2) float
        Interior rulings (score lines), m, same frame.
    marks : list of (k, 2) float
        Where the splice plates go (engraved outlines), m, same frame.
    label : list of str
        Lines of the engraved label.
    creases : list of dict
        The crease edges on the part: ``crease`` (id), ``kind`` (as the crease records) and
        ``points`` (k, 2) m, same frame (empty for a splice plate).
    sheet : int
        Index of its sheet in :attr:`WorkshopPlan.sheets` (-1 before nesting).
    rotation : float
        Rotation about the frame's origin, degrees, then ``translation`` (m): its place on the
        sheet.
    thickness : float
        m: the sheets it is nested on have this thickness.
    """

    name: str
    kind: str
    plate: int
    outline: np.ndarray
    grain: float
    score: list = field(default_factory=list)
    marks: list = field(default_factory=list)
    label: list = field(default_factory=list)
    creases: list = field(default_factory=list)
    sheet: int = -1
    rotation: float = 0.0
    translation: tuple = (0.0, 0.0)
    thickness: float = 0.0

    @property
    def area(self) -> float:
        """Area of the true outline, m²."""
        x, y = self.outline[:, 0], self.outline[:, 1]
        return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))

    def placed(self, points) -> np.ndarray:
        """``points`` (k, 2) of the part's frame moved to the sheet, m."""
        a = math.radians(self.rotation)
        r = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        return np.asarray(points, dtype=float) @ r.T + np.asarray(self.translation)


@dataclass(frozen=True)
class RollNesting:
    """The hinge strips on the textile roll (:func:`~compas_ccu.fabrication.nesting.nest_roll`).

    Attributes
    ----------
    width : float
        The roll's width, m.
    length : float
        The length of roll used, margins included, m (0 without strips).
    strips : dict
        Per hinge strip (``"C<crease id>"``): the length of its centre line, m.
    """

    width: float
    length: float
    strips: dict

    def to_dict(self) -> dict:
        """Plain data (``fabrication.json`` ``workshop.roll``): ``width``, ``length``,
        ``strips``."""
        return {"width": self.width, "length": self.length, "strips": self.strips}


#: The keys of :meth:`NestingSearch.to_dict` per solver (any other: the strip packing's).
NESTING_SEARCH_KEYS = {
    "compas_nest": (
        "solver", "version", "seed", "generations", "population", "part_tolerance",
        "roll_tolerance", "time_limit", "packings", "layouts_searched",
    ),
    "shelf": (
        "solver", "version", "seed", "steps", "roll_improvements", "time_limit", "packings",
        "steps_searched",
    ),
    None: (
        "solver", "version", "seed", "steps", "roll_improvements", "patience", "merge_patience",
        "time_limit", "packings", "steps_searched",
    ),
}  # fmt: skip


@dataclass(frozen=True)
class NestingSearch:
    """What the nesting searched (:func:`~compas_ccu.fabrication.nesting.nesting_search`;
    ``fabrication.json`` ``workshop.nesting_search``). A field the solver does not have is None
    (and :meth:`to_dict` leaves it out).

    Attributes
    ----------
    solver : str
        ``"compas_nest"``, ``"shelf"`` or the strip packer's name (spyrrow).
    version : str or None
        The solver's version (None: the shelves).
    seed : int or None
        The nesting seed (None: the shelves).
    time_limit : float or None
        The time limit of a packing (a safety limit only), s.
    packings : int
        The packings searched (sheets and roll).
    steps, roll_improvements, patience, merge_patience : int or None
        The strip packer's steps per packing, improving reports of the roll, infeasible steps
        and merge attempts it stops at.
    steps_searched : int or None
        The strip packer's steps over every packing.
    generations, population : int or None
        compas_nest's generations and population.
    part_tolerance, roll_tolerance : float or None
        compas_nest's curve tolerances of the parts and of the hinge strips, mm.
    layouts_searched : int or None
        The part orders compas_nest placed over every packing.
    """

    solver: str
    version: str | None = None
    seed: int | None = None
    time_limit: float | None = None
    packings: int = 0
    steps: int | None = None
    roll_improvements: int | None = None
    patience: int | None = None
    merge_patience: int | None = None
    steps_searched: int | None = None
    generations: int | None = None
    population: int | None = None
    part_tolerance: float | None = None
    roll_tolerance: float | None = None
    layouts_searched: int | None = None

    def to_dict(self) -> dict:
        """Plain data: the solver's keys (:data:`NESTING_SEARCH_KEYS`) in its order."""
        keys = NESTING_SEARCH_KEYS.get(self.solver, NESTING_SEARCH_KEYS[None])
        return {k: getattr(self, k) for k in keys}


@dataclass(frozen=True)
class SpliceCutBending:
    """The bending check of one cut under its splice plates (:class:`SpliceBending`).

    Attributes
    ----------
    plate : int
        The plate's id.
    ruling : int
        The ruling the cut follows.
    plate_utilisation : float
        The plate's largest bending utilisation within ``splice_width / 2`` of the cut.
    utilisation : float
        The same times :attr:`SpliceBending.factor`: the outer fibres of the splice plates.
    utilisation_characteristic : float
        The same against characteristic strengths.
    """

    plate: int
    ruling: int
    plate_utilisation: float
    utilisation: float
    utilisation_characteristic: float


@dataclass(frozen=True)
class SpliceBending:
    """The bending check of the plates where the splice plates are glued across a cut
    (:func:`~compas_ccu.fabrication.parts.splice_bending`; ``fabrication.json``
    ``workshop.splice_bending``).

    Attributes
    ----------
    factor : float
        ``(t + 2 t_s) / t``: the outer fibres' stress over the plate's.
    thickness, splice_thickness : float
        ``t`` and ``t_s``, m.
    cuts : tuple of SpliceCutBending
        Per cut, plates in ``data`` order.
    max_utilisation, max_utilisation_characteristic : float
        The largest over the cuts (0 without cuts).
    exceeded : bool
        :attr:`max_utilisation` above 1.
    """

    factor: float
    thickness: float
    splice_thickness: float
    cuts: tuple
    max_utilisation: float
    max_utilisation_characteristic: float
    exceeded: bool

    def to_dict(self) -> dict:
        """Plain data (strict JSON), the fields in order (``cuts`` a list of dicts)."""
        return {**asdict(self), "cuts": [asdict(c) for c in self.cuts]}


@dataclass
class WorkshopPlan:
    """The parts, the sheets they are nested on, the hinge roll, the BOM and the assembly.

    Attributes
    ----------
    options : WorkshopOptions
    parts : list of Part
    sheets : list of dict
        Per sheet: ``size`` [length, width] m, ``parts`` (names), ``utilisation`` (parts'
        area / sheet area).
    splits : dict
        Plate id -> the rulings its cuts follow (empty if it fits whole).
    roll : RollNesting
        The hinge strips on the textile roll: ``width``, ``length`` (m used), ``strips``.
    bom : dict
        The bill of materials (:meth:`bom_rows` for its table).
    assembly : list of dict
        The assembly steps in order.
    splice_bending : SpliceBending or None
        The bending check of the spliced cuts
        (:func:`~compas_ccu.fabrication.parts.splice_bending`); None without the plates'
        bending utilisation.
    design : str or None
        The design's name (:meth:`layout` records it).
    model_plate_ids : list of int or None
        The model's plate id of every workshop plate id (``fabrication.json`` ``model_ids``).
    nesting_search : NestingSearch or None
        What the nesting searched (:func:`~compas_ccu.fabrication.nesting.nesting_search`):
        solver, version, seed, steps.
    splices : list of compas_ccu.thickness.splices.Splice
        The splice plates (:func:`~compas_ccu.fabrication.splices.splice_records`).
    warnings : list of str
        What the user must know about the plan: the nester asked for is not installed and
        another one, or the shelves, nested the parts
        (:func:`~compas_ccu.fabrication.nesting.nesting_choice`).
    """

    options: WorkshopOptions
    parts: list
    sheets: list
    splits: dict
    roll: RollNesting
    bom: dict = field(default_factory=dict)
    assembly: list = field(default_factory=list)
    splice_bending: SpliceBending | None = None
    design: str | None = None
    model_plate_ids: list | None = None
    nesting_search: NestingSearch | None = None
    splices: list = field(default_factory=list)
    warnings: list = field(default_factory=list)

    @property
    def utilisation(self) -> float:
        """Area of every part over the area of every sheet used."""
        used = sum(s["size"][0] * s["size"][1] for s in self.sheets)
        return sum(p.area for p in self.parts) / used if used else 0.0

    def summary(self) -> dict:
        """Strict-JSON summary for ``fabrication.json`` (key ``workshop``)."""
        o = self.options
        return {
            "sheets_in_stock": [list(s) for s in o.sheets],
            "kerf": o.cut,
            "tool_diameter": o.tool_diameter,
            "bridge": o.bridge,
            "margin": o.margin,
            "grain": o.grain,
            "score_rulings": o.score_rulings,
            "nesting": o.nesting,
            "nesting_search": (
                None if self.nesting_search is None else self.nesting_search.to_dict()
            ),
            "warnings": list(self.warnings),
            "sheet_count": len(self.sheets),
            "utilisation": self.utilisation,
            "sheets": self.sheets,
            "splits": {str(k): v for k, v in self.splits.items()},
            "roll": self.roll.to_dict(),
            "splice_thickness": self.parts_thickness("splice"),
            "splice_bending": (
                None if self.splice_bending is None else self.splice_bending.to_dict()
            ),
            "bom": self.bom,
            "assembly": self.assembly,
        }

    def parts_thickness(self, kind: str):
        """The thickness of the parts of ``kind`` (m), None if there are none."""
        values = {p.thickness for p in self.parts if p.kind == kind}
        return max(values) if values else None

    def layout(self) -> dict:
        """Strict-JSON nesting of the parts on the sheets, already placed (``sheets.json``).

        Every coordinate is in its sheet's frame (m, the sheet's corner at the origin, its
        length along x), exactly :meth:`Part.placed` of the part's frame: the placement the
        sheet DXFs use. The viewer (:func:`compas_ccu.viz.viewer.viewer_figure` ``sheets=``)
        draws it.

        Returns
        -------
        dict
            ``format`` ``"ccu.sheets"``, ``version`` 1, ``design``, ``units`` ``"m"``,
            ``model_plate_ids`` (model plate id of every workshop plate id, or None),
            ``score_rulings``, ``sheets`` (per sheet: ``size`` [length, width], ``utilisation``,
            ``parts`` names) and ``parts`` (per part: ``name``, ``kind``, ``plate`` (workshop
            id), ``sheet`` (index), ``rotation`` (deg), ``translation`` [x, y] (m),
            ``outline`` (its near row, then its far row back: a strip of quads between
            rulings), ``creases`` (``crease``, ``kind``, ``points``), ``score`` (the score
            lines as the sheet DXF cuts them: empty unless ``score_rulings``), ``marks``
            (where the splice plates go, clipped to the part) and ``label`` (the engraved
            lines)).

        Examples
        --------
        >>> from compas_ccu.model import load_model
        >>> from compas_ccu.fabrication import fabrication_data
        >>> from compas_ccu.fabrication.hinges import hinge_strips
        >>> from compas_ccu.fabrication.workshop import plan_workshop
        >>> data = fabrication_data(load_model("examples/vault.toml"))
        >>> plan = plan_workshop(data, hinge_strips(data), WorkshopOptions(nesting="shelf"),
        ...                      density=500.0)
        >>> doc = plan.layout()
        >>> len(doc["sheets"]), len(doc["parts"]), doc["parts"][0]["name"]
        (15, 40, 'P0.1')
        """
        from shapely import Polygon

        def xy(points) -> list:
            return np.asarray(points, dtype=float).tolist()

        parts = []
        for p in self.parts:
            outline = p.placed(p.outline)
            poly = Polygon(outline)
            marks = []
            for rect in p.marks:  # the splice plate's place, clipped to the part (as the DXF)
                mark = Polygon(p.placed(rect)).intersection(poly)
                if mark.geom_type == "Polygon" and not mark.is_empty:
                    marks.append(xy(outline_ring(mark)))
            parts.append(
                {
                    "name": p.name,
                    "kind": p.kind,
                    "plate": int(p.plate),
                    "sheet": int(p.sheet),
                    "rotation": float(p.rotation),
                    "translation": [float(v) for v in p.translation],
                    "outline": xy(outline),
                    "creases": [
                        {
                            "crease": int(c["crease"]),
                            "kind": str(c["kind"]),
                            "points": xy(p.placed(c["points"])),
                        }
                        for c in p.creases
                    ],
                    "score": [xy(p.placed(line)) for line in p.score]
                    if self.options.score_rulings
                    else [],
                    "marks": marks,
                    "label": list(p.label),
                }
            )
        return {
            "format": "ccu.sheets",
            "version": 1,
            "design": self.design,
            "units": "m",
            "model_plate_ids": None
            if self.model_plate_ids is None
            else [int(v) for v in self.model_plate_ids],
            "score_rulings": bool(self.options.score_rulings),
            "sheets": [
                {
                    "size": [float(v) for v in s["size"]],
                    "thickness": float(s.get("thickness", 0.0)),
                    "utilisation": float(s["utilisation"]),
                    "parts": list(s["parts"]),
                }
                for s in self.sheets
            ],
            "parts": parts,
        }


def outline_ring(poly) -> np.ndarray:
    return np.asarray(poly.exterior.coords, dtype=float)[:-1]
