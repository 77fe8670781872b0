"""The workshop: plates split to fit the sheets, parts nested onto sheets, the bill of materials
and the assembly sequence.

:func:`plan_workshop` turns a :class:`~compas_ccu.fabrication.data.FabricationData` and the
design's ``[fabrication]`` section (:class:`WorkshopOptions`) into a :class:`WorkshopPlan`:

1. every plate is checked against the sheets in stock in the orientations the grain allows; a
   plate that fits no sheet is split along rulings (straight lines on the plate, so the joint
   does not fight the bending), as few parts as the sheets allow, the cuts staggered between
   plates so that the splice plates do not pile up in the stack
   (:mod:`compas_ccu.fabrication.splices`), and every cut gets two splice plates (one on each
   face) with their fasteners;
2. every part (plate parts and splice plates) is nested onto sheets with spyrrow (the Python
   bindings of sparrow, a true-shape strip-packing solver): per sheet, the remaining parts are
   strip-packed into the sheet's usable width, the parts that lie wholly within its usable
   length stay on it, and smaller parts are tried in the space left; the hinge strips are
   strip-packed onto the textile roll the same way (the roll's used length);
3. the bill of materials (areas, masses, sheets, textile, glue line, fasteners, cost) and the
   assembly steps in stack order (:mod:`compas_ccu.fabrication.assembly`).

:func:`write_sheet_dxf` writes one sheet's DXF with kerf-compensated toolpaths. Units: metres
and degrees here, millimetres in the DXF files.
"""

from __future__ import annotations

import importlib.util
import math
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from compas_ccu.design.schema import STOCK_SHEET
from compas_ccu.errors import CCUWarning, GeometryError
from compas_ccu.fabrication.assembly import assembly_steps
from compas_ccu.fabrication.dxf import APPID, MM, label_frame, new_document, save_document, xy_list
from compas_ccu.fabrication.packing import PATIENCE, SOLVER, solver_version, strip_pack
from compas_ccu.fabrication.splices import (
    fitting_size,
    part_orientations,
    splice_records,
    splice_rectangle,
    split_plate,
    stagger_cuts,
    sub_outline,
)

__all__ = [
    "WorkshopOptions",
    "Part",
    "WorkshopPlan",
    "plan_workshop",
    "split_plate",
    "splice_bending",
    "write_sheet_dxf",
    "write_bom_csv",
    "SHEET_LAYERS",
]

#: Sheet file layers and their ACI colours: the toolpaths (cutter centre lines), the score
#: lines, the engraved labels, and for reference only the parts' true outlines and the sheet.
SHEET_LAYERS = {
    "OUTER_CUT": 1,
    "INNER_CUT": 6,
    "SCORE": 3,
    "LABEL": 7,
    "PART_OUTLINE": 8,
    "SHEET": 9,
}


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
    nesting: str = "spyrrow"
    nesting_time: float = 600.0
    nesting_seed: int = 0
    nesting_steps: int = 500
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
    roll : dict
        The hinge strips on the textile roll: ``width``, ``length`` (m used), ``strips``.
    bom : dict
        The bill of materials (:meth:`bom_rows` for its table).
    assembly : list of dict
        The assembly steps in order.
    splice_bending : dict or None
        The bending check of the spliced cuts (:func:`splice_bending`); None without the
        plates' bending utilisation.
    design : str or None
        The design's name (:meth:`layout` records it).
    model_plate_ids : list of int or None
        The model's plate id of every workshop plate id (``fabrication.json`` ``model_ids``).
    nesting_search : dict or None
        What the nesting searched (:func:`nesting_search`): solver, version, seed, steps.
    splices : list of compas_ccu.thickness.splices.Splice
        The splice plates (:func:`~compas_ccu.fabrication.splices.splice_records`).
    """

    options: WorkshopOptions
    parts: list
    sheets: list
    splits: dict
    roll: dict
    bom: dict = field(default_factory=dict)
    assembly: list = field(default_factory=list)
    splice_bending: dict | None = None
    design: str | None = None
    model_plate_ids: list | None = None
    nesting_search: dict | None = None
    splices: list = field(default_factory=list)

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
            "nesting_search": self.nesting_search,
            "sheet_count": len(self.sheets),
            "utilisation": self.utilisation,
            "sheets": self.sheets,
            "splits": {str(k): v for k, v in self.splits.items()},
            "roll": self.roll,
            "splice_thickness": self.parts_thickness("splice"),
            "splice_bending": self.splice_bending,
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
                    marks.append(xy(_ring(mark)))
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


# --------------------------------------------------------------------------- fitting, splitting


def _rulings_between(flat, n: int, j0: int, j1: int) -> list:
    return [np.array([flat[j], flat[n + 1 + j]]) for j in range(j0 + 1, j1)]


def _part_creases(flat, n: int, j0: int, j1: int, on_plate, kinds: dict) -> list:
    """The crease edges of a plate that lie on its part between rulings ``j0`` and ``j1``."""
    out = []
    for cid, _, verts in on_plate:
        verts = [int(v) for v in verts]
        base = 0 if max(verts) <= n else n + 1  # the near or the far row
        inside = [v for v in verts if j0 <= v - base <= j1]
        if len(inside) >= 2:
            out.append({"crease": int(cid), "kind": kinds[int(cid)], "points": flat[inside]})
    return out


def make_parts(data, options: WorkshopOptions, splits: dict | None = None) -> tuple:
    """The plate parts and splice plates of every plate: ``(parts, splits)``; the cuts
    ``splits`` (plate id -> rulings), default
    :func:`~compas_ccu.fabrication.splices.stagger_cuts`."""
    splits = stagger_cuts(data, options) if splits is None else splits
    n = data.segments
    grain = float(data.metadata.get("grain", 0.0) or 0.0)
    t = float(data.thickness)
    t_splice = t if options.splice_thickness is None else float(options.splice_thickness)
    parts = []
    for i, pid in enumerate(data.plate_ids):
        flat = np.asarray(data.flat[i], dtype=float)
        cuts = list(splits.get(int(pid), []))
        bounds = [0, *cuts, n]
        k = len(bounds) - 1
        stack = int(data.stack_position[i])
        on_plate = data.plate_creases(i)
        creases = [f"C{cid}-P{other}" for cid, other, _ in on_plate]
        kinds = {int(c["id"]): str(c.get("kind", "")) for c in data.creases}
        splice_rects = [splice_rectangle(flat, n, j, options, data.hinge_width) for j in cuts]
        for q, (a, b) in enumerate(zip(bounds, bounds[1:])):
            name = f"P{pid}" if k == 1 else f"P{pid}.{q + 1}"
            label = [name + ("" if k == 1 else f" of {k}"), f"stack {stack + 1}", *creases, "UP"]
            marks = [r for j, r in zip(cuts, splice_rects) if j in (a, b)]
            parts.append(
                Part(
                    name=name,
                    kind="plate",
                    plate=int(pid),
                    outline=sub_outline(flat, n, a, b),
                    grain=grain,
                    score=_rulings_between(flat, n, a, b),
                    marks=marks,
                    label=label,
                    thickness=t,
                    creases=_part_creases(flat, n, a, b, on_plate, kinds),
                )
            )
        for q, rect in enumerate(splice_rects):
            for face in ("U", "D"):
                name = f"S{pid}.{q + 1}{face}"
                side = "upper" if face == "U" else "lower"
                parts.append(
                    Part(
                        name=name,
                        kind="splice",
                        plate=int(pid),
                        outline=rect,
                        grain=grain,
                        label=[name, f"P{pid}.{q + 1}/{q + 2} {side}"],
                        thickness=t_splice,
                    )
                )
    return parts, splits


def splice_bending(
    data, splits: dict, utilisation, options: WorkshopOptions, *, strength_factor: float = 1.0
) -> dict:
    """The bending check of the plates where the splice plates are glued across a cut.

    A splice plate glued to both faces bends with the plate: the three layers take the
    plate's curvature κ together and their outer fibres lie ``(t + 2 t_s) / 2`` from the
    middle, so the bending stress there is ``E κ (t + 2 t_s) / 2``, the plate's times
    ``(t + 2 t_s) / t`` (same material; the layers do not slide on each other). The plate's
    utilisation is taken at every vertex within ``splice_width / 2`` of the cut's ruling.

    Parameters
    ----------
    data : FabricationData
    splits : dict
        Plate id -> the rulings its cuts follow (:func:`make_parts`).
    utilisation : (p, 2n + 2) float
        The plates' bending utilisation at every vertex (the largest along the deployment
        path, design strengths), plates in ``data`` order.
    options : WorkshopOptions
    strength_factor : float
        Design over characteristic strength (k_mod / γ_M; 1 for characteristic strengths):
        the characteristic utilisation is ``utilisation · strength_factor``.

    Returns
    -------
    dict
        ``factor`` (t + 2 t_s) / t, ``thickness`` and ``splice_thickness`` (m), ``cuts`` (per
        cut: ``plate``, ``ruling``, ``plate_utilisation``, ``utilisation``,
        ``utilisation_characteristic``), ``max_utilisation`` and
        ``max_utilisation_characteristic`` (0 without cuts) and ``exceeded``.

    Examples
    --------
    A plate at utilisation 0.5 spliced with plates of its own thickness: 0.5 · 3 = 1.5.

    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> flat = np.array([[0.0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]])
    >>> data = SimpleNamespace(thickness=0.008, segments=2, plate_ids=[0], flat=[flat])
    >>> check = splice_bending(data, {0: [1]}, np.full((1, 6), 0.5), WorkshopOptions())
    >>> check["factor"], check["max_utilisation"], check["exceeded"]
    (3.0, 1.5, True)
    """
    t = float(data.thickness)
    ts = t if options.splice_thickness is None else float(options.splice_thickness)
    factor = (t + 2.0 * ts) / t
    u = np.asarray(utilisation, dtype=float)
    n = data.segments
    cuts = []
    for i, pid in enumerate(data.plate_ids):
        flat = np.asarray(data.flat[i], dtype=float)[:, :2]
        for j in splits.get(int(pid), []):
            a, b = flat[j], flat[n + 1 + j]
            d = (b - a) / np.linalg.norm(b - a)
            off = np.abs((flat - a) @ np.array([-d[1], d[0]]))
            band = off <= 0.5 * options.splice_width + 1e-12
            plate_u = float(u[i, band].max())
            cuts.append(
                {
                    "plate": int(pid),
                    "ruling": int(j),
                    "plate_utilisation": plate_u,
                    "utilisation": plate_u * factor,
                    "utilisation_characteristic": plate_u * factor * strength_factor,
                }
            )
    worst = max((c["utilisation"] for c in cuts), default=0.0)
    return {
        "factor": factor,
        "thickness": t,
        "splice_thickness": ts,
        "cuts": cuts,
        "max_utilisation": worst,
        "max_utilisation_characteristic": worst * strength_factor,
        "exceeded": bool(worst > 1.0),
    }


# --------------------------------------------------------------------------------- nesting


#: Failed packing steps that end a merge attempt (the question "do these parts fit on one
#: sheet?"): the first failure answers no.
MERGE_PATIENCE = 1

#: Improving reports that end the hinge strips' packing on the textile roll. Long curved strips
#: interlock: once the strip is tight, sparrow works through many improving layouts per step
#: and one step costs seconds to a minute (the vault with a 0.9 m rise: 40 improvements by step
#: 340 in 5 s, then steps 400-437 in 180 s), while the roll is the cheapest line of the bill.
#: The vault's own roll needs 18 in its 500 steps.
ROLL_IMPROVEMENTS = 40


def _strip_pack(shapes: dict, orientations: dict, height: float, gap: float, options, log,
                *, fit=None, patience=PATIENCE, improvements=None):  # fmt: skip
    """:func:`~compas_ccu.fabrication.packing.strip_pack` of ``shapes`` (name -> (m, 2) mm,
    centred) in a strip ``height`` high with the options' seed, steps and time limit: name ->
    (rotation deg, (tx, ty) mm), and the strip length used (mm). ``log`` collects every
    :class:`~compas_ccu.fabrication.packing.Packing`."""
    packing = strip_pack(
        shapes,
        orientations,
        height=height,
        gap=gap,
        seed=options.nesting_seed,
        steps=options.nesting_steps,
        time_limit=options.nesting_time,
        fit=fit,
        patience=patience,
        improvements=improvements,
    )
    if log is not None:
        log.append(packing)
    return packing.placements, packing.width


def _moved(pts: np.ndarray, rotation: float, translation) -> np.ndarray:
    a = math.radians(rotation)
    r = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    return pts @ r.T + np.asarray(translation)


def _window_sheets(shapes, orientations, length, width, options, log) -> list:
    """Every part strip-packed once into the sheets' usable width, then the strip cut into
    sheets: a sheet starts at the leftmost part not yet placed and takes every part lying wholly
    within its usable length. Returns one ``name -> (rotation, translation, points)`` per sheet
    (mm, the sheet's origin at its usable area's corner).

    One packing of ``nesting_steps`` steps, instead of one to three packings per sheet as the
    sheets were filled before.
    """
    place, _ = _strip_pack(shapes, orientations, width, options.spacing * MM, options, log)
    pts = {m: _moved(shapes[m], *place[m]) for m in place}
    left, out = set(pts), []
    while left:
        x0 = min(pts[m][:, 0].min() for m in left)
        on = sorted(m for m in left if pts[m][:, 0].max() <= x0 + length + 1e-6)
        y0 = min(0.0, min(pts[m][:, 1].min() for m in on))
        out.append(
            {
                m: (place[m][0], (place[m][1][0] - x0, place[m][1][1] - y0), pts[m] - [x0, y0])
                for m in on
            }
        )
        left -= set(on)
    return out


def _area(pts: np.ndarray) -> float:
    x, y = pts[:, 0], pts[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def _shelf_sheet(shapes, orientations, length, width, gap):
    """Shelf packing by bounding boxes (the fallback without spyrrow): the parts of ``shapes``
    (mm) that go on one sheet, name -> (rotation, translation, placed points)."""
    boxes = {}
    for name, pts in shapes.items():
        angles = orientations[name]
        angles = np.arange(0.0, 180.0, 1.0) if angles is None else np.asarray(angles[:1])
        best = None
        for a in angles:
            q = _moved(pts, float(a), (0.0, 0.0))
            lo, hi = q.min(axis=0), q.max(axis=0)
            size = hi - lo
            if size[0] <= length and size[1] <= width and (best is None or size[1] < best[2][1]):
                best = (float(a), lo, size)
        boxes[name] = best
    order = sorted(shapes, key=lambda k: -boxes[k][2][1])
    on, x, y, shelf = {}, 0.0, 0.0, 0.0
    for name in order:
        a, lo, size = boxes[name]
        if x + size[0] > length:  # next shelf
            x, y, shelf = 0.0, y + shelf + gap, 0.0
        if y + size[1] > width:
            continue
        t = (x - lo[0], y - lo[1])
        on[name] = (a, t, _moved(shapes[name], a, t))
        x += size[0] + gap
        shelf = max(shelf, size[1])
    return on


def nest_parts(parts: list, options: WorkshopOptions, *, log=None) -> list:
    """Nest ``parts`` onto sheets (sets their ``sheet``, ``rotation``, ``translation``).

    Parts of different thickness go on different sheets (the plates and thinner splice plates).
    ``log`` (a list) collects every :class:`~compas_ccu.fabrication.packing.Packing` searched.

    Returns
    -------
    list of dict
        Per sheet: ``size`` [length, width] m, ``thickness`` m, ``parts`` (names),
        ``utilisation``.
    """
    groups: dict = {}
    for p in parts:
        k = fitting_size(p.outline, options, p.grain)
        if k is None:
            raise GeometryError(
                f"part {p.name} ({np.ptp(p.outline, axis=0).round(3).tolist()} m) fits no sheet "
                f"in stock {[list(s) for s in options.sheets]} m"
            )
        groups.setdefault((-round(p.thickness, 9), k), []).append(p)
    sheets, centres = [], {}
    for group in sorted(groups):
        thickness, k = -group[0], group[1]
        length, width = (v * MM for v in options.usable(k))
        left = {p.name: p for p in groups[group]}
        centres.update({p.name: p.outline.mean(axis=0) for p in groups[group]})
        shapes = {m: (p.outline - centres[m]) * MM for m, p in left.items()}
        orient = {m: part_orientations(options, p.grain) for m, p in left.items()}
        if options.nesting != "shelf":  # one strip of every part, cut into sheet lengths
            windows = _window_sheets(shapes, orient, length, width, options, log)
        while left:
            if options.nesting == "shelf":
                rest = {m: shapes[m] for m in left}
                on = _shelf_sheet(rest, orient, length, width, options.spacing * MM)
            else:  # spyrrow places every part of the strip: the windows hold them all
                on = windows.pop(0) if windows else {}
            if not on:  # pragma: no cover - every part fits a sheet alone (fitting_size)
                raise GeometryError(f"no part of {sorted(left)} could be placed on a sheet")
            index = len(sheets)
            names = []
            for m, (rot, t, _) in sorted(on.items()):
                p = left.pop(m)
                a = math.radians(rot)
                r = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
                # sheet (m) = R (x - c) + t / 1000 + inset  =  R x + (t / 1000 + inset - R c)
                shift = np.asarray(t) / MM + options.inset - r @ centres[m]
                p.sheet, p.rotation, p.translation = index, float(rot), tuple(shift.tolist())
                names.append(m)
            sheets.append({"size": list(options.sheets[k]), "thickness": thickness, "parts": names})
        if options.nesting != "shelf":
            _merge_sheets(sheets, parts, centres, options, k, thickness, length, width, log)
    for index, sheet in enumerate(sheets):
        for p in parts:
            if p.name in sheet["parts"]:
                p.sheet = index
        size = sheet["size"]
        area = sum(p.area for p in parts if p.sheet == index)
        sheet["utilisation"] = area / (size[0] * size[1])
    return sheets


#: Packings :func:`nest_parts` spends at most on emptying sheets (merging pairs of sheets,
#: moving the emptiest sheet's parts onto the others).
MERGE_ATTEMPTS = 8


def _merge_sheets(sheets, parts, centres, options, k, thickness, length, width, log) -> None:
    """Empty the emptiest sheets of size ``k`` and ``thickness``: merge pairs of sheets whose
    parts fit on one, then move the parts of the emptiest sheet onto the others, where they
    fit."""
    by_name = {p.name: p for p in parts}
    capacity = length * width / MM**2
    budget = [MERGE_ATTEMPTS]

    def area(names):
        return sum(by_name[m].area for m in names)

    def repack(names) -> bool:
        """Place ``names`` on one sheet if they fit (one packing of the budget)."""
        if budget[0] <= 0 or area(names) > 0.9 * capacity:
            return False
        budget[0] -= 1
        shapes = {m: (by_name[m].outline - centres[m]) * MM for m in names}
        orient = {m: part_orientations(options, by_name[m].grain) for m in names}
        place, used = _strip_pack(
            shapes, orient, width, options.spacing * MM, options, log, fit=length,
            patience=MERGE_PATIENCE,
        )  # fmt: skip
        if used > length + 1e-6 or len(place) != len(names):
            return False
        x0 = min(_moved(shapes[m], *place[m])[:, 0].min() for m in names)
        for m in names:
            rot, t = place[m]
            a = math.radians(rot)
            r = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
            shift = (np.asarray(t) - [x0, 0.0]) / MM + options.inset - r @ centres[m]
            by_name[m].rotation, by_name[m].translation = float(rot), tuple(shift.tolist())
        return True

    def mine():
        out = [
            s
            for s in sheets
            if s["size"] == list(options.sheets[k]) and s["thickness"] == thickness
        ]
        return sorted(out, key=lambda s: area(s["parts"]))

    merged = True
    while merged and budget[0] > 0:  # pairs of sheets onto one
        merged = False
        ours = mine()
        for a in range(len(ours)):
            for b in range(a + 1, len(ours)):
                names = ours[a]["parts"] + ours[b]["parts"]
                if area(names) <= 0.85 * capacity and repack(names):
                    ours[a]["parts"] = sorted(names)
                    sheets.remove(ours[b])
                    merged = True
                    break
            if merged or budget[0] <= 0:
                break
    ours = mine()
    if len(ours) > 1:  # the emptiest sheet's parts onto the others, the freest first
        last = ours[0]
        for m in sorted(last["parts"], key=lambda n: -by_name[n].area):
            for target in sorted(ours[1:], key=lambda s: area(s["parts"]))[:2]:
                names = target["parts"] + [m]
                if repack(names):
                    target["parts"] = sorted(names)
                    last["parts"].remove(m)
                    break
        if not last["parts"]:
            sheets.remove(last)


def nest_roll(strips, options: WorkshopOptions, *, log=None) -> dict:
    """The hinge strips strip-packed on the textile roll, each along the roll (0 or 180 deg
    after turning its chord along it): ``width``, ``length`` (m used), ``strips`` (per crease:
    length of its centre line, m). ``log`` (a list) collects the packing."""
    if not strips:
        return {"width": options.roll_width, "length": 0.0, "strips": {}}
    shapes, orient, lengths = {}, {}, {}
    for s in strips:
        c = np.asarray(s.centre, dtype=float)
        d = c[-1] - c[0]
        a = -math.atan2(d[1], d[0])
        r = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        pts = (np.asarray(s.outline, dtype=float) - c.mean(axis=0)) @ r.T
        name = f"C{s.crease_id}"
        if np.ptp(pts[:, 1]) > options.roll_width - 2.0 * options.margin:
            raise GeometryError(
                f"hinge strip {name} is {np.ptp(pts[:, 1]):.3f} m wide across the roll, wider "
                f"than the roll ({options.roll_width:g} m less margins)"
            )
        shapes[name] = pts * MM
        orient[name] = [0.0, 180.0]
        lengths[name] = float(np.linalg.norm(np.diff(c, axis=0), axis=1).sum())
    height = (options.roll_width - 2.0 * options.margin) * MM
    if options.nesting == "shelf":
        on = _shelf_sheet(shapes, orient, 1e12, height, options.spacing * MM)
        used = max(float(v[2][:, 0].max()) for v in on.values())
        return {
            "width": options.roll_width,
            "length": used / MM + 2.0 * options.margin,
            "strips": lengths,
        }
    _, used = _strip_pack(shapes, orient, height, options.spacing * MM, options, log,
                          improvements=ROLL_IMPROVEMENTS)  # fmt: skip
    return {
        "width": options.roll_width,
        "length": used / MM + 2.0 * options.margin,
        "strips": lengths,
    }


# ----------------------------------------------------------------------------- BOM, assembly


def bill_of_materials(data, parts, sheets, roll, options: WorkshopOptions, density: float) -> dict:
    """Rows and totals of the bill of materials (strict-JSON values)."""
    rows = []
    for p in parts:
        rows.append(
            {
                "item": p.name,
                "kind": p.kind,
                "plate": p.plate,
                "sheet": p.sheet + 1,
                "area_m2": p.area,
                "thickness_m": p.thickness,
                "mass_kg": p.area * p.thickness * density,
                "quantity": 1,
            }
        )
    hinge_lengths = roll["strips"]
    glue_hinges = 2.0 * sum(hinge_lengths.values())  # each strip glued to both plates
    splices = [p for p in parts if p.kind == "splice"]
    glue_splices = sum(
        float(np.linalg.norm(np.diff(np.r_[p.outline, p.outline[:1]], axis=0), axis=1).sum())
        for p in splices
    )
    fasteners = len(splices) * options.fasteners_per_splice
    mass = sum(r["mass_kg"] for r in rows)
    textile = float(roll["length"])
    glue = glue_hinges + glue_splices
    costs = {
        "sheets": len(sheets) * options.sheet_price,
        "textile": textile * options.textile_price,
        "glue": glue * options.glue_price,
        "fasteners": fasteners * options.fastener_price,
    }
    for c, length in sorted(hinge_lengths.items(), key=lambda kv: int(kv[0][1:])):
        rows.append(
            {
                "item": f"hinge {c}",
                "kind": "hinge",
                "plate": None,
                "sheet": None,
                "area_m2": length * data.hinge_width,
                "thickness_m": None,
                "mass_kg": None,
                "quantity": 1,
            }
        )
    return {
        "rows": rows,
        "plates": sum(1 for p in parts if p.kind == "plate"),
        "splices": len(splices),
        "sheets": len(sheets),
        "sheet_area_m2": sum(s["size"][0] * s["size"][1] for s in sheets),
        "parts_area_m2": sum(p.area for p in parts),
        "mass_kg": mass,
        "density_kg_m3": density,
        "textile_roll_width_m": float(roll["width"]),
        "textile_length_m": textile,
        "hinge_length_m": sum(hinge_lengths.values()),
        "glue_line_m": glue,
        "glue_line_hinges_m": glue_hinges,
        "glue_line_splices_m": glue_splices,
        "fasteners": fasteners,
        "currency": options.currency,
        "cost": costs,
        "cost_total": sum(costs.values()),
        "anchors": anchors(data),
    }


def anchors(data) -> list:
    """Per plate: the feet (mid-points of the end rulings) where the actuators or the tie of the
    deployment are fixed, in the cut pattern (m) and in the world at the design state (m), and
    the tie length between them at the design state (m)."""
    n = data.segments
    out = []
    for i, pid in enumerate(data.plate_ids):
        flat = np.asarray(data.flat[i], dtype=float)
        xyz = np.asarray(data.deployed_mid[i], dtype=float)
        ends = [(0, n + 1), (n, 2 * n + 1)]
        f = [0.5 * (flat[a] + flat[b]) for a, b in ends]
        w = [0.5 * (xyz[a] + xyz[b]) for a, b in ends]
        out.append(
            {
                "plate": int(pid),
                "flat": [v.tolist() for v in f],
                "world": [v.tolist() for v in w],
                "tie_length": float(np.linalg.norm(w[1] - w[0])),
            }
        )
    return out


def plan_workshop(
    data,
    strips,
    options: WorkshopOptions,
    *,
    density: float,
    pairing=None,
    utilisation=None,
    strength_factor: float = 1.0,
):
    """Split, nest, count and order: the :class:`WorkshopPlan` of a design.

    Parameters
    ----------
    data : FabricationData
    strips : list of compas_ccu.fabrication.hinges.HingeStrip
    options : WorkshopOptions
    density : float
        Plate material density, kg/m³ (masses).
    pairing : list of str, optional
        Per crease id: the faces its hinge joins (``ThickModel.pairing``).
    utilisation : (p, 2n + 2) float, optional
        The plates' bending utilisation per vertex (:func:`splice_bending`); without it the
        splices are not checked.
    strength_factor : float
        Design over characteristic strength of ``utilisation`` (:func:`splice_bending`).

    Returns
    -------
    WorkshopPlan

    Raises
    ------
    GeometryError
        A part fits no sheet (e.g. a plate wider than every sheet), or a hinge strip is wider
        than the roll.
    """
    if options.nesting == "spyrrow" and importlib.util.find_spec("spyrrow") is None:
        warnings.warn(
            "spyrrow is not installed (pip install 'compas_ccu[fab]'; it has no wheel for "
            "Python 3.9): the parts are nested by shelves of bounding boxes, which wastes sheets",
            CCUWarning,
            stacklevel=2,
        )
        options = replace(options, nesting="shelf")
    parts, splits = make_parts(data, options)
    log: list = []
    sheets = nest_parts(parts, options, log=log)
    roll = nest_roll(strips, options, log=log)
    plan = WorkshopPlan(
        options=options,
        parts=parts,
        sheets=sheets,
        splits=splits,
        roll=roll,
        design=data.name,
        model_plate_ids=data.metadata.get("model_plate_ids"),
        nesting_search=nesting_search(options, log),
        splices=splice_records(data, splits, options),
    )
    plan.bom = bill_of_materials(data, parts, sheets, roll, options, density)
    plan.assembly = assembly_steps(data, splits, pairing)
    if utilisation is not None:
        plan.splice_bending = splice_bending(
            data, splits, utilisation, options, strength_factor=strength_factor
        )
    return plan


def nesting_search(options: WorkshopOptions, packings: list) -> dict:
    """What the nesting searched (``fabrication.json`` ``workshop.nesting_search``): the solver
    and its version, the seed, the steps per packing, the time limit (a safety limit only), the
    packings and the steps they searched. The shelf packing searches nothing (only ``solver``
    is set)."""
    if options.nesting == "shelf":
        return {"solver": "shelf", "version": None, "seed": None, "steps": None,
                "roll_improvements": None, "time_limit": None, "packings": 0,
                "steps_searched": 0}  # fmt: skip
    return {
        "solver": SOLVER,
        "version": solver_version(),
        "seed": int(options.nesting_seed),
        "steps": int(options.nesting_steps),
        "roll_improvements": ROLL_IMPROVEMENTS,
        "patience": PATIENCE,
        "merge_patience": MERGE_PATIENCE,
        "time_limit": float(options.nesting_time),
        "packings": len(packings),
        "steps_searched": int(sum(p.steps for p in packings)),
    }


# --------------------------------------------------------------------------------- writers


def _ring(poly) -> np.ndarray:
    return np.asarray(poly.exterior.coords, dtype=float)[:-1]


def write_sheet_dxf(plan: WorkshopPlan, s: int, path, *, name: str = "design") -> Path:
    """Write sheet ``s`` of ``plan`` in millimetres.

    Layers: ``OUTER_CUT`` (every part's toolpath: its outline offset by kerf / 2 outwards,
    round corners), ``INNER_CUT`` (holes; none yet), ``SCORE`` (interior rulings when
    ``score_rulings``), ``LABEL`` (engraved part names and splice positions), and for
    reference ``PART_OUTLINE`` (true outlines) and ``SHEET`` (the sheet's edge). Every toolpath
    carries XDATA ``COMPAS_CCU``: "part", its name, rotation (deg) and translation (mm).
    """
    from ezdxf.enums import TextEntityAlignment
    from shapely import Polygon

    o = plan.options
    sheet = plan.sheets[s]
    doc = new_document(SHEET_LAYERS)
    doc.header["$PROJECTNAME"] = str(name)
    msp = doc.modelspace()
    length, width = (v * MM for v in sheet["size"])
    msp.add_lwpolyline(
        [(0.0, 0.0), (length, 0.0), (length, width), (0.0, width)],
        format="xy",
        close=True,
        dxfattribs={"layer": "SHEET"},
    )
    for p in plan.parts:
        if p.sheet != s:
            continue
        outline = p.placed(p.outline) * MM
        poly = Polygon(outline)
        path_poly = poly.buffer(0.5 * o.cut * MM, join_style="round", quad_segs=8)
        e = msp.add_lwpolyline(
            xy_list(_ring(path_poly)), format="xy", close=True, dxfattribs={"layer": "OUTER_CUT"}
        )
        e.set_xdata(
            APPID,
            [
                (1000, "part"),
                (1000, p.name),
                (1040, p.rotation),
                (1040, p.translation[0] * MM),
                (1040, p.translation[1] * MM),
            ],
        )
        msp.add_lwpolyline(
            xy_list(outline), format="xy", close=True, dxfattribs={"layer": "PART_OUTLINE"}
        )
        if o.score_rulings:
            for line in p.score:
                a, b = p.placed(line) * MM
                msp.add_line(tuple(a), tuple(b), dxfattribs={"layer": "SCORE"})
        for rect in p.marks:  # the splice plate's place, clipped to the part
            mark = Polygon(p.placed(rect) * MM).intersection(poly)
            if mark.geom_type == "Polygon" and not mark.is_empty:
                msp.add_lwpolyline(
                    xy_list(_ring(mark)), format="xy", close=True, dxfattribs={"layer": "LABEL"}
                )
        anchor, u, h = label_frame(
            outline, lines=len(p.label) + 1, chars=max(len(t) for t in p.label)
        )
        v = np.array([-u[1], u[0]])
        rotation = math.degrees(math.atan2(u[1], u[0]))
        top = 0.5 * 1.6 * h * (len(p.label) - 1)
        for k, text in enumerate(p.label):
            t = msp.add_text(
                text,
                height=h * (1.4 if k == 0 else 1.0),
                rotation=rotation,
                dxfattribs={"layer": "LABEL"},
            )
            t.set_placement(
                tuple(anchor + (top - 1.6 * h * k) * v), align=TextEntityAlignment.MIDDLE_CENTER
            )
    title = msp.add_text(
        f"{name}: sheet {s + 1} of {len(plan.sheets)}, {length:g} x {width:g} x "
        f"{sheet.get('thickness', 0.0) * MM:g} mm, kerf "
        f"{o.cut * MM:g} mm, utilisation {100 * sheet['utilisation']:.1f} %",
        height=0.012 * width,
        dxfattribs={"layer": "LABEL"},
    )
    title.set_placement((0.0, width + 0.01 * width), align=TextEntityAlignment.BOTTOM_LEFT)
    save_document(doc, Path(path))
    return Path(path)


BOM_COLUMNS = ("item", "kind", "plate", "sheet", "area_m2", "thickness_m", "mass_kg", "quantity")


def write_bom_csv(plan: WorkshopPlan, path) -> Path:
    """The bill of materials as CSV: one row per part and hinge strip, then the totals."""
    import csv

    b = plan.bom
    path = Path(path)
    with path.open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(BOM_COLUMNS)
        for r in b["rows"]:
            w.writerow(
                [
                    "" if r[c] is None else (f"{r[c]:.6g}" if isinstance(r[c], float) else r[c])
                    for c in BOM_COLUMNS
                ]
            )
        cur = b["currency"]
        totals = [
            ("sheets", b["sheets"], "", b["cost"]["sheets"]),
            ("parts area", f"{b['parts_area_m2']:.4f}", "m2", ""),
            ("mass", f"{b['mass_kg']:.2f}", "kg", ""),
            (
                f"textile (roll {b['textile_roll_width_m']:g} m)",
                f"{b['textile_length_m']:.3f}",
                "m",
                b["cost"]["textile"],
            ),
            ("glue line", f"{b['glue_line_m']:.3f}", "m", b["cost"]["glue"]),
            ("fasteners", b["fasteners"], "", b["cost"]["fasteners"]),
            ("total", "", "", b["cost_total"]),
        ]
        w.writerow([])
        w.writerow(["total", "quantity", "unit", f"cost {cur}"])
        for label, q, unit, cost in totals:
            w.writerow([label, q, unit, "" if cost == "" else f"{cost:.2f}"])
    return path
