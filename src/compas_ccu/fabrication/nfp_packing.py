"""Deterministic true-shape packing onto sheets with compas_nest: the same shapes, seed and
generations give the same placements, whatever the machine and its load.

:func:`sheet_pack` places true-shape parts on rectangular sheets (as many as needed) with
compas_nest's ``opennest`` engine (OpenNest's no-fit polygons and genetic algorithm, C++,
MIT), the nester that has wheels for Python 3.9 (Rhino 8) as well as for 3.10 - 3.13. Its
search is bounded by a count, never by seconds: ``generations`` of the genetic algorithm, each
of :data:`POPULATION` part orders placed, one after the other on one thread (the engine's
``mode`` 0, no parallel evaluation) from the engine's own random generator seeded by ``seed``.
The engine releases the GIL while it searches (measured: a Python thread beside a 20 s search
ran with at most 20 ms between its turns), so it runs in this process, on a thread; the clock
only guards: a search that has not ended within ``time_limit`` seconds is cancelled and
refused (a :class:`~compas_ccu.errors.LimitError`), never returned.

The engine keeps no distance between the parts of its own (its collision engine ignores the
requested spacing): every outline is grown by half the gap (mitred corners, which contain the
round offset) before it is packed, and the sheet by the same on every side, so that the true
outlines lie a gap apart and within the sheet. Identical outlines are packed as copies of one
part (the engine computes the no-fit polygons once per part): the vault's ten plates are two
outlines, each five times. The rotations are those the grain allows: every outline is first
turned by its first allowed rotation, and the engine then tries the turns of 360 / n degrees
(n = 2: 0 and 180 degrees). Every layout is checked independently before it is returned:
each true outline within its sheet and at least the gap from every other one (shapely).

Measured (compas_nest 0.1.0, 3 generations, seed 0; docs/fabrication.md): the vault's 10
plates on 5 sheets, the cone's 8 parts on 2, the dome preset's 48 on 10 and the 22-plate dome's
88 on 16, in 3.2, 0.3, 1.1 and 1.6 s with the hinge roll (spyrrow: 5, 2, 9 and 19 sheets in 57,
10, 33 and 95 s). The engine adds an offset of its own, about 8 x its curve tolerance on every
side (measured: 2.45 mm at 0.3 mm), so the parts end up a little further apart than the gap.
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import GeometryError, LimitError, require
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "SheetPacking",
    "sheet_pack",
    "nester_version",
    "NESTER",
    "POPULATION",
    "PART_TOLERANCE",
    "ROLL_TOLERANCE",
    "FREE_ROTATIONS",
]

#: The nester's package.
NESTER = "compas_nest"
#: Part orders the genetic algorithm places per generation (compas_nest's default).
POPULATION = 10
#: The engine's curve tolerance for the parts, mm (its default): it simplifies every outline
#: within this and grows it to contain the original. Looser is faster and wastes area: at 1 mm
#: the vault's pairs of plates no longer fit on one sheet (10 sheets instead of 5).
PART_TOLERANCE = 0.3
#: The engine's curve tolerance for the hinge strips on the textile roll, mm: the vault's nine
#: long curved strips take 2.1 s of CPU and 6.26 m of roll at 1 mm, 6.9 s and 6.25 m at 0.3 mm.
ROLL_TOLERANCE = 1.0
#: Rotations tried (every 360 / n degrees) when the grain leaves the parts free to turn.
FREE_ROTATIONS = 8
#: Growth added to half the gap, mm: a margin over the engine's rounding (it places the grown
#: outlines touching).
EPSILON = 0.05

# the engine keeps its progress and cancel flag in globals: one search at a time per process
_LOCK = threading.Lock()


@dataclass(frozen=True)
class SheetPacking:
    """One packing onto sheets.

    Attributes
    ----------
    sheets : list of dict
        Per sheet used, in order: part name -> ``(rotation, (tx, ty))``, degrees about the
        shape's origin, then mm in the sheet's frame (its corner at the origin).
    unplaced : tuple of str
        The parts the engine placed on no sheet (sorted).
    generations : int
        Generations of the genetic search.
    layouts : int
        Part orders placed: ``generations`` x :data:`POPULATION`.
    seed : int
        The engine's seed.
    solver, version : str
        The nester's package and its version.
    """

    sheets: list
    unplaced: tuple
    generations: int
    layouts: int
    seed: int
    solver: str = NESTER
    version: str = ""


def nester_version() -> str:
    """The version of compas_nest (the nester the results depend on).

    Raises
    ------
    MissingExtraError
        compas_nest is not installed.
    """
    require(
        "compas_nest",
        "fab",
        what="nesting the parts onto sheets with compas_nest",
        note=" (or [fabrication] nesting = 'shelf', bounding boxes in rows)",
    )
    import compas_nest

    return str(getattr(compas_nest, "__version__", "unknown"))


def _turn(pts: np.ndarray, degrees: float) -> np.ndarray:
    a = math.radians(degrees)
    r = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    return pts @ r.T


def _rotations(orientations: dict) -> tuple:
    """The engine's rotation count and each part's first allowed rotation (deg): the allowed
    rotations of every part must be its first one plus the turns of 360 / n degrees, the same
    n for every part (None: free, :data:`FREE_ROTATIONS`)."""
    counts, base = set(), {}
    for name, allowed in orientations.items():
        if allowed is None:
            counts.add(FREE_ROTATIONS)
            base[name] = 0.0
            continue
        angles = [float(a) % 360.0 for a in allowed]
        n = len(angles)
        expected = [(angles[0] + k * 360.0 / n) % 360.0 for k in range(n)]
        if n < 1 or not np.allclose(sorted(angles), sorted(expected), atol=EXACT_RELATIVE):
            raise ValueError(
                f"part {name}: compas_nest turns a part by equal steps from its first "
                f"rotation; {list(allowed)} deg are not such turns"
            )
        counts.add(n)
        base[name] = angles[0]
    if len(counts) > 1:
        raise ValueError(f"compas_nest turns every part alike; the parts allow {sorted(counts)}")
    return (counts.pop() if counts else 1), base


def _grown_ring(pts: np.ndarray, grow: float) -> list:
    """The outline grown by ``grow`` (mitred corners: they contain the round offset), as the
    engine's closed polyline (x, y, 0)."""
    from shapely import Polygon

    poly = Polygon(pts)
    if not poly.is_valid:
        poly = poly.buffer(0.0)
    grown = poly.buffer(grow, join_style="mitre", mitre_limit=2.0)
    if grown.geom_type != "Polygon":  # pragma: no cover - a valid polygon grows into one
        grown = max(grown.geoms, key=lambda g: g.area)
    ring = np.asarray(grown.exterior.coords, dtype=float)
    return [[float(x), float(y), 0.0] for x, y in ring]


def sheet_pack(
    shapes: dict,
    orientations: dict,
    *,
    length: float,
    width: float,
    gap: float,
    seed: int = 0,
    generations: int = 3,
    time_limit: float = 600.0,
    sheets: int | None = None,
    tolerance: float = PART_TOLERANCE,
) -> SheetPacking:
    """Pack ``shapes`` onto sheets ``length`` x ``width``, as few as the search finds.

    Parameters
    ----------
    shapes : dict
        Part name -> (m, 2) outline, mm (centred: the rotations are about its origin).
    orientations : dict
        Part name -> the allowed rotations (degrees), or None for any: the first one plus the
        turns of 360 / n degrees (0 and 180 for a grain).
    length, width : float
        The area of a sheet the true outlines may occupy, mm.
    gap : float
        Least distance between two parts, mm (not kept from the sheet's edges).
    seed : int
        The engine's random seed (taken modulo 2**31).
    generations : int
        Generations of the genetic search: the result of one never depends on time.
    time_limit : float
        Seconds the search may take before it is refused: a safety limit, not a budget.
    sheets : int, optional
        Sheets available (default: one per part).
    tolerance : float
        The engine's curve tolerance, mm (:data:`PART_TOLERANCE`).

    Returns
    -------
    SheetPacking

    Raises
    ------
    GeometryError
        The engine returned a layout with a part off its sheet or closer than ``gap`` to
        another (named; never returned).
    LimitError
        The search did not end within ``time_limit``.
    MissingExtraError
        compas_nest is not installed.
    """
    generations, seed = int(generations), int(seed)
    if generations < 1:
        raise ValueError(f"generations must be >= 1, got {generations}")
    if not (math.isfinite(time_limit) and time_limit > 0):
        raise ValueError(f"time_limit must be > 0 s, got {time_limit!r}")
    version = nester_version()
    names = sorted(shapes)
    if not names:
        return SheetPacking([], (), generations, 0, seed, NESTER, version)
    count, base = _rotations({m: orientations[m] for m in names})
    from compas.geometry import Polyline
    from compas_nest import nest_geo, nest_sheets, opennest

    turned = {m: _turn(np.asarray(shapes[m], dtype=float), base[m]) for m in names}
    members: dict = {}  # identical turned outlines: one part of the engine, with copies
    for m in names:
        members.setdefault(np.round(turned[m], 6).tobytes(), []).append(m)
    geo, copies = nest_geo(), []
    grow = 0.5 * float(gap) + EPSILON
    for group in members.values():
        geo.add_part(Polyline(_grown_ring(turned[group[0]], grow)), copies=len(group))
        copies.append(group)
    size = (float(length) + float(gap), float(width) + float(gap))
    board = nest_sheets()
    outline = [[0.0, 0.0, 0.0], [size[0], 0.0, 0.0], [size[0], size[1], 0.0], [0.0, size[1], 0.0]]
    for _ in range(len(names) if sheets is None else int(sheets)):
        board.add_sheet(Polyline([*outline, outline[0]]))
    engine = opennest(
        generations=generations,
        rotations=count,
        seed=seed % 2**31,
        mode=0,  # one thread, candidates in order: the layout depends on the seed only
        use_parallel=False,
        population_size=POPULATION,
        curve_tolerance=float(tolerance),
        verbose=False,
    )
    result = _solve(engine, geo, board, time_limit, len(names))
    queues = [list(group) for group in copies]
    placed: dict = {}
    for p in result.placements:  # instance order: part 0 x its copies, part 1 ...
        name = queues[p["part_index"]].pop(0)
        if p["sheet_id"] >= 0:
            rotation = _allowed(base[name] + math.degrees(p["angle"]), orientations[name], name)
            shift = (p["tx"] - 0.5 * gap, p["ty"] - 0.5 * gap)
            placed[name] = (int(p["sheet_id"]), rotation, shift)
    used = sorted({v[0] for v in placed.values()})
    out = [{m: v[1:] for m, v in sorted(placed.items()) if v[0] == s} for s in used]
    for sheet in out:
        check_layout({m: shapes[m] for m in sheet}, sheet, length, width, gap)
    unplaced = tuple(m for m in names if m not in placed)
    return SheetPacking(out, unplaced, generations, generations * POPULATION, seed, NESTER,
                        version)  # fmt: skip


def _solve(engine, geo, board, time_limit: float, parts: int):
    """The engine's result, searched on a thread of this process (it releases the GIL);
    cancelled and refused after ``time_limit`` seconds."""
    with _LOCK:
        handle = engine.start(geo, board)
        deadline = time.monotonic() + time_limit  # the safety limit: never decides a result
        while handle.is_running():
            if time.monotonic() > deadline:
                handle.cancel()
                handle.wait()
                raise LimitError(
                    f"the nesting of {parts} part{'s' if parts != 1 else ''} (compas_nest) "
                    f"did not end in the time limit of {time_limit:g} s; raise [fabrication] "
                    "nesting_time or lower nesting_generations"
                )
            time.sleep(0.005)
        return handle.wait()


def _allowed(rotation: float, allowed, name: str) -> float:
    """``rotation`` (deg) as the allowed rotation it is (the engine's turns are exact to
    float precision), in [0, 360)."""
    rotation %= 360.0
    if allowed is None:
        return rotation
    for a in allowed:
        d = (rotation - float(a) + 180.0) % 360.0 - 180.0
        if abs(d) < 1e-6:
            return float(a) % 360.0
    raise GeometryError(  # pragma: no cover - the engine turns by the steps it was given
        f"compas_nest turned part {name} by {rotation:.6g} deg, not one of {list(allowed)}"
    )


def check_layout(shapes: dict, placements: dict, length: float, width: float, gap: float):
    """Refuse a layout of one sheet unless every true outline lies within ``[0, length] x
    [0, width]`` and at least ``gap`` from every other one (mm, to 1e-6).

    Parameters
    ----------
    shapes : dict
        Part name -> (m, 2) outline, mm.
    placements : dict
        Part name -> ``(rotation, (tx, ty))``.

    Raises
    ------
    GeometryError
        Naming the part off the sheet, or the two parts too close and their distance.
    """
    from shapely import Polygon, STRtree, box

    polys, names = [], sorted(placements)
    for m in names:
        rotation, shift = placements[m]
        poly = Polygon(_turn(np.asarray(shapes[m], dtype=float), rotation) + np.asarray(shift))
        x0, y0, x1, y1 = poly.bounds
        if min(x0, y0) < -1e-6 or x1 > length + 1e-6 or y1 > width + 1e-6:
            raise GeometryError(
                f"the nesting placed part {m} off its sheet ({x0:.3f}, {y0:.3f}) - "
                f"({x1:.3f}, {y1:.3f}) mm, the sheet {length:.3f} x {width:.3f} mm"
            )
        polys.append(poly)
    tree, limit = STRtree(polys), float(gap) - 1e-6
    for i, poly in enumerate(polys):
        x0, y0, x1, y1 = poly.bounds
        near = tree.query(box(x0 - gap, y0 - gap, x1 + gap, y1 + gap))
        for j in (int(k) for k in near if k > i):
            d = poly.distance(polys[j])
            if d < limit or (d == 0.0 and poly.intersection(polys[j]).area > 1e-6):
                raise GeometryError(
                    f"the nesting placed parts {names[i]} and {names[j]} {d:.4f} mm apart, "
                    f"less than the {gap:g} mm they need"
                )
