"""Where the plates are cut to fit the sheets, and the splice plates that join them again.

A plate that fits no sheet in stock is cut along rulings (:func:`split_plate`: as few parts as
a greedy cover needs, evened out towards equal arc lengths), and every cut gets two splice
plates, one on each face (:func:`splice_rectangle`). Cut at the same ruling, the splice plates
of all the plates lie over each other in the flat-folded stack: the vault's ten plates, cut at
their middle ruling, pile 20 splice plates of 8 mm at the crown. :func:`stagger_cuts` chooses
the cuts plate by plate from the bottom of the stack: among the admissible cut sets (the
evened-out cuts shifted by the same number of rulings, every part still fitting a sheet) the
one that keeps the highest pile of splice plates over the stack lowest
(:class:`compas_ccu.thickness.splices.PileMap`), the smallest shift on a tie (then the shift
towards ruling 0). The choice is deterministic: the same design, the same cuts.
:func:`splice_records` gives the splice plates as
:class:`~compas_ccu.thickness.splices.Splice` records for the thick model (stack height with
splices, their mass and their collisions along the path).

Options are a :class:`compas_ccu.fabrication.workshop.WorkshopOptions` (``sheets``, ``grain``,
``splice_width``, ``splice_thickness``). Units: metres, degrees.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from compas_ccu.errors import GeometryError
from compas_ccu.thickness.splices import PileMap, Splice, max_pile
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = [
    "part_orientations",
    "fitting_size",
    "sub_outline",
    "split_plate",
    "splice_rectangle",
    "shifted_cuts",
    "stagger_cuts",
    "splice_records",
    "splice_pile",
    "splice_summary",
]


# --------------------------------------------------------------------------- fitting, splitting


def part_orientations(options, grain: float):
    """Rotations (degrees) a part of face grain ``grain`` may take on a sheet; None: any."""
    if options.grain == "free":
        return None
    base = -grain if options.grain == "along" else 90.0 - grain
    return [base % 360.0, (base + 180.0) % 360.0]


def _fit_angles(options, grain: float) -> np.ndarray:
    angles = part_orientations(options, grain)
    return np.arange(0.0, 180.0, 1.0) if angles is None else np.asarray(angles[:1])


def fitting_size(points, options, grain: float):
    """Index of the first sheet size ``points`` (a part outline, m) fits on, or None.

    The part fits if, turned by an angle the grain allows, its bounding box lies within the
    sheet's usable area (:meth:`WorkshopOptions.usable`).
    """
    pts = np.asarray(points, dtype=float)
    a = np.radians(_fit_angles(options, grain))
    c, s = np.cos(a)[:, None], np.sin(a)[:, None]
    x = c * pts[:, 0] - s * pts[:, 1]
    y = s * pts[:, 0] + c * pts[:, 1]
    dx, dy = np.ptp(x, axis=1), np.ptp(y, axis=1)
    for k in range(len(options.sheets)):
        length, width = options.usable(k)
        # the nesting keeps parts a spacing apart from each other, and its own margin
        length, width = length - options.spacing, width - options.spacing
        if np.any((dx <= length) & (dy <= width)):
            return k
    return None


def sub_outline(flat: np.ndarray, n: int, j0: int, j1: int) -> np.ndarray:
    """The outline of the quads ``j0 .. j1 - 1`` of a plate (near row, far row back)."""
    near = flat[j0 : j1 + 1]
    far = flat[n + 1 + j0 : n + 2 + j1][::-1]
    return np.concatenate([near, far])


def split_plate(flat, options, grain: float, *, name: str = "plate") -> list:
    """The rulings a plate is cut along so that every part fits a sheet.

    Parameters
    ----------
    flat : (2n + 2, 2) float
        The plate's cut pattern, m (near row ``0 .. n``, far row ``n + 1 .. 2n + 1``; ruling
        ``j`` joins ``j`` and ``n + 1 + j``).
    options : WorkshopOptions
    grain : float
        Face-grain direction in the cut pattern, degrees.
    name : str
        Plate name for the error message.

    Returns
    -------
    list of int
        Interior rulings to cut along, in order (empty if the plate fits whole). As few parts
        as a greedy cover needs, then the cuts moved towards equal arc lengths where the parts
        still fit.

    Raises
    ------
    GeometryError
        A single quad (between two neighbouring rulings) fits no sheet, e.g. a plate wider
        than every sheet.

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [2, 0], [3, 0], [0, 1], [1, 1], [2, 1], [3, 1]])
    >>> from compas_ccu.fabrication.workshop import WorkshopOptions
    >>> split_plate(square * 1.0, WorkshopOptions(), 0.0)  # 3 m long: two parts, 1 + 2 m
    [1]
    """
    flat = np.asarray(flat, dtype=float)
    n = flat.shape[0] // 2 - 1

    def fits(a, b):
        return fitting_size(sub_outline(flat, n, a, b), options, grain) is not None

    if fits(0, n):
        return []
    cuts, start = [], 0
    while start < n:
        end = start + 1
        if not fits(start, end):
            sizes = ", ".join(f"{a * 1000:g} x {b * 1000:g} mm" for a, b in options.sheets)
            raise GeometryError(
                f"{name}: the quad between rulings {start} and {start + 1} fits no sheet in stock "
                f"({sizes}, less margin and kerf, grain {options.grain!r}); a part must lie "
                "between two rulings, so the plate cannot be split to fit"
            )
        while end < n and fits(start, end + 1):
            end += 1
        if end < n:
            cuts.append(end)
        start = end
    # even out: cuts at equal arc length along the crease, where every part still fits
    arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(flat[: n + 1], axis=0), axis=1))]
    k = len(cuts) + 1
    even = [int(np.argmin(np.abs(arc - arc[-1] * q / k))) for q in range(1, k)]
    bounds = [0, *even, n]
    if len(set(bounds)) == len(bounds) and all(fits(a, b) for a, b in zip(bounds, bounds[1:])):
        return even
    return cuts


def splice_rectangle(flat, n: int, j: int, options, hinge_width: float) -> np.ndarray:
    """The splice plate rectangle across the cut along ruling ``j``: (4, 2) m.

    ``splice_width`` wide, centred on the ruling, ending ``hinge_width`` (at most a quarter
    of the ruling) short of the plate's boundaries: clear of the hinge strips.
    """
    a, b = flat[j], flat[n + 1 + j]
    length = float(np.linalg.norm(b - a))
    u = (b - a) / length
    v = np.array([-u[1], u[0]])
    inset = min(hinge_width, 0.25 * length)  # clear of the hinge strips along the creases
    p, q = a + inset * u, b - inset * u
    h = 0.5 * options.splice_width
    return np.array([p - h * v, q - h * v, q + h * v, p + h * v])


# ----------------------------------------------------------------------------------- staggering


def _splice_thickness(data, options) -> float:
    t = float(data.thickness)
    return t if options.splice_thickness is None else float(options.splice_thickness)


def shifted_cuts(flat, options, grain: float, cuts: list) -> list:
    """The admissible cut sets of a plate: ``cuts`` shifted by ``δ`` rulings, every part still
    fitting a sheet, in the order of preference (``|δ|``, then ``δ``; ``cuts`` itself first).

    Parameters
    ----------
    flat : (2n + 2, 2) float
        The plate's cut pattern, m.
    options : WorkshopOptions
    grain : float
        Face-grain direction in the cut pattern, degrees.
    cuts : list of int
        The cuts of :func:`split_plate` (empty: the plate fits whole, ``[[]]`` is returned).

    Returns
    -------
    list of list of int

    Examples
    --------
    >>> from compas_ccu.fabrication.workshop import WorkshopOptions
    >>> x = np.linspace(0.0, 3.0, 7)  # a 3 m x 1 m strip of six 0.5 m quads
    >>> flat = np.r_[np.c_[x, 0 * x], np.c_[x, 0 * x + 1]]
    >>> shifted_cuts(flat, WorkshopOptions(), 0.0, [3])  # 2.44 m sheets: parts <= 2 m
    [[3], [2], [4]]
    """
    if not cuts:
        return [[]]
    flat = np.asarray(flat, dtype=float)
    n = flat.shape[0] // 2 - 1
    out = []
    for delta in sorted(range(-n, n + 1), key=lambda d: (abs(d), d)):
        shifted = [c + delta for c in cuts]
        if shifted[0] < 1 or shifted[-1] > n - 1:
            continue
        bounds = [0, *shifted, n]
        if all(
            fitting_size(sub_outline(flat, n, a, b), options, grain) is not None
            for a, b in zip(bounds, bounds[1:])
        ):
            out.append(shifted)
    return out


def stagger_cuts(data, options, *, stagger: bool = True) -> dict[int, list[int]]:
    """The cuts of every plate, staggered so that the splice plates do not pile up.

    Parameters
    ----------
    data : FabricationData
    options : WorkshopOptions
    stagger : bool
        False: the cuts of :func:`split_plate` (the same ruling on every like plate).

    Returns
    -------
    dict of int to list of int
        Plate id -> the rulings its cuts follow, in order (empty if it fits whole).

    Raises
    ------
    GeometryError
        A quad of a plate fits no sheet (:func:`split_plate`).
    """
    n = data.segments
    grain = float(data.metadata.get("grain", 0.0) or 0.0)
    thick = 2.0 * _splice_thickness(data, options)  # the upper and the lower splice plate
    order = sorted(range(len(data.plate_ids)), key=lambda i: int(data.stack_position[i]))
    piles = PileMap()
    splits = {}
    for i in order:
        pid = int(data.plate_ids[i])
        flat = np.asarray(data.flat[i], dtype=float)
        cuts = split_plate(flat, options, grain, name=f"plate {pid}")
        if cuts and stagger:
            best = None
            for option in shifted_cuts(flat, options, grain, cuts):
                rects = [splice_rectangle(flat, n, j, options, data.hinge_width) for j in option]
                pile = piles.trial(np.array(rects), thick)
                if best is None or pile < best[0] - ZERO_LENGTH:
                    best = (pile, option, rects)
                if pile <= piles.max + ZERO_LENGTH:  # no higher than the stack already is
                    break
            _, cuts, rects = best
            piles.add(np.array(rects), thick)
        splits[pid] = [int(j) for j in cuts]
    return splits


def splice_records(data, splits: dict, options) -> list:
    """The splice plates of the cuts ``splits`` (plate id -> rulings) as
    :class:`~compas_ccu.thickness.splices.Splice` records, plates in stack order, per cut the
    lower then the upper one: ``S<plate>.<cut>D`` / ``U``; plate ids as in ``data``."""
    n = data.segments
    ts = _splice_thickness(data, options)
    order = sorted(range(len(data.plate_ids)), key=lambda i: int(data.stack_position[i]))
    out = []
    for i in order:
        pid = int(data.plate_ids[i])
        flat = np.asarray(data.flat[i], dtype=float)
        for q, j in enumerate(splits.get(pid, [])):
            rect = splice_rectangle(flat, n, j, options, data.hinge_width)
            for face, side in (("D", "lower"), ("U", "upper")):
                out.append(Splice(f"S{pid}.{q + 1}{face}", pid, int(j), side, rect, ts))
    return out


def splice_pile(records) -> float:
    """The highest pile of splice plates over one point of the plan, m."""
    quads = np.array([r.footprint for r in records], dtype=float).reshape(-1, 4, 2)
    return max_pile(quads, [r.thickness for r in records])[0]


def splice_summary(thick, data, records, splits: dict, options) -> dict:
    """``fabrication.json``'s ``splices``: the records, the stack with them, their collisions.

    Parameters
    ----------
    thick : compas_ccu.thickness.ThickModel
    data : FabricationData
        Of ``thick``; its ``metadata["model_plate_ids"]`` maps the workshop ids to the model's.
    records : list of Splice
        Workshop plate ids (:func:`splice_records`).
    splits : dict
        The cuts (plate id -> rulings).
    options : WorkshopOptions

    Returns
    -------
    dict
        ``records`` (:meth:`Splice.to_dict`), ``cuts`` (plate id -> rulings), the
        :meth:`~compas_ccu.thickness.ThickModel.splice_stack` values (``stack_height`` with
        the splices, ``stack_height_plates``, ``max_pile``, ``pile_point``, ``count``, ``area``,
        ``mass``), ``max_pile_unstaggered`` (every plate cut where :func:`split_plate` cuts
        it) and ``collisions`` (:meth:`~compas_ccu.thickness.ThickModel.splice_collisions`,
        neighbours in workshop ids). Strict JSON.
    """
    model_ids = list(data.metadata["model_plate_ids"])
    workshop = {int(m): k for k, m in enumerate(model_ids)}
    in_model = [replace(r, plate=int(model_ids[r.plate])) for r in records]
    out = {"records": [r.to_dict() for r in records]}
    out["cuts"] = {str(k): [int(j) for j in v] for k, v in splits.items()}
    out.update(thick.splice_stack(in_model).to_dict())
    plain = splice_records(data, stagger_cuts(data, options, stagger=False), options)
    out["max_pile_unstaggered"] = splice_pile(plain)
    collisions = thick.splice_collisions(in_model)
    per = [
        sp if sp.neighbour is None else replace(sp, neighbour=workshop[int(sp.neighbour)])
        for sp in collisions.splices
    ]
    out["collisions"] = replace(collisions, splices=tuple(per)).to_dict()
    return out
