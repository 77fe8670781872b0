"""Nesting the parts onto the sheets and the hinge strips onto the textile roll, by the nester
the options name and is installed (:func:`nesting_choice`): compas_nest packs onto the sheets
directly (:mod:`compas_ccu.fabrication.nfp_packing`, bounded by generations); spyrrow strip-packs
(:mod:`compas_ccu.fabrication.packing`, bounded by steps), the strip cut into sheets and sheets
merged where their parts fit fewer; shelves of bounding boxes are the last fallback. No search
is bounded by seconds.
"""

from __future__ import annotations

import importlib.util
import math
import warnings
from dataclasses import replace

import numpy as np

from compas_ccu.errors import CCUWarning, GeometryError
from compas_ccu.fabrication.dxf_document import MM
from compas_ccu.fabrication.nfp_packing import PART_TOLERANCE as NFP_PART_TOLERANCE
from compas_ccu.fabrication.nfp_packing import (
    POPULATION,
    ROLL_TOLERANCE,
    SheetPacking,
    nester_version,
    sheet_pack,
)
from compas_ccu.fabrication.packing import PATIENCE, SOLVER, solver_version, strip_pack
from compas_ccu.fabrication.plan import NestingSearch, RollNesting, WorkshopOptions
from compas_ccu.fabrication.splices import (
    fitting_size,
    part_orientations,
)

__all__ = [
    "AUTO_ORDER",
    "nesting_choice",
    "MERGE_PATIENCE",
    "ROLL_IMPROVEMENTS",
    "nest_parts",
    "MERGE_ATTEMPTS",
    "nest_roll",
    "nesting_search",
]

#: The true-shape nesters ``nesting = "auto"`` tries, the first installed one used. compas_nest
#: comes first: measured (docs/fabrication.md) on the vault, the cone, the dome preset and the
#: 22-plate dome it used 5, 2, 10 and 16 sheets against spyrrow's 5, 2, 9 and 19, in 1/20 to
#: 1/60 of the time (the vault: 3.2 s against 57 s), with a 5 - 54 % longer textile roll; and it
#: has wheels for Python 3.9 (Rhino 8), where spyrrow has none.
AUTO_ORDER = ("compas_nest", "spyrrow")

#: What each nester needs installed.
_INSTALL = {
    "compas_nest": "pip install 'compas_ccu[fab]'",
    "spyrrow": "pip install 'compas_ccu[fab]'; it has no wheel for Python 3.9",
}


def _installed(nester: str) -> bool:
    return importlib.util.find_spec(nester) is not None


def nesting_choice(requested: str) -> tuple:
    """The nesting to use for ``[fabrication] nesting = requested`` and the warning to give.

    ``"auto"`` is the first installed nester of :data:`AUTO_ORDER`; a nester named but not
    installed is replaced by the first installed one, with a warning; without any, the parts
    are nested by shelves of bounding boxes, with a warning (it wastes sheets). ``"shelf"`` is
    itself.

    Returns
    -------
    tuple
        ``(nesting, warning)``: ``"compas_nest"``, ``"spyrrow"`` or ``"shelf"``, and the
        warning's text or None.

    Examples
    --------
    >>> nesting_choice("shelf")
    ('shelf', None)
    """
    if requested == "shelf" or (requested != "auto" and _installed(requested)):
        return requested, None
    if requested not in ("auto", *AUTO_ORDER):
        raise ValueError(f"nesting must be auto, compas_nest, spyrrow or shelf, got {requested!r}")
    found = next((n for n in AUTO_ORDER if _installed(n)), None)
    if requested == "auto" and found is not None:
        return found, None
    missing = (
        f"{requested} is not installed ({_INSTALL[requested]})"
        if requested != "auto"
        else "no true-shape nester is installed (compas_nest or spyrrow: "
        "pip install 'compas_ccu[fab]')"
    )
    if found is not None:
        return found, f"{missing}: the parts are nested with {found} instead"
    return "shelf", (
        f"{missing}: the parts are nested by shelves of bounding boxes, which wastes sheets"
    )


def _resolved(options: WorkshopOptions) -> WorkshopOptions:
    """``options`` with ``nesting = "auto"`` replaced by the nester it chooses (a warning when
    that is the shelves)."""
    if options.nesting != "auto":
        return options
    nesting, warning = nesting_choice("auto")
    if warning is not None:
        warnings.warn(warning, CCUWarning, stacklevel=3)
    return replace(options, nesting=nesting)


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


def _nfp_pack(shapes, orientations, options, log, **kwargs) -> SheetPacking:
    """:func:`~compas_ccu.fabrication.nfp_packing.sheet_pack` with the options' seed,
    generations and time limit; ``log`` collects the packing."""
    packing = sheet_pack(
        shapes,
        orientations,
        gap=options.spacing * MM,
        seed=options.nesting_seed,
        generations=options.nesting_generations,
        time_limit=options.nesting_time,
        **kwargs,
    )
    if log is not None:
        log.append(packing)
    return packing


def _nfp_sheets(shapes, orientations, length, width, options, log) -> list:
    """Every part packed onto sheets by compas_nest: one ``name -> (rotation, translation,
    points)`` per sheet (mm, the sheet's origin at its usable area's corner). Parts the engine
    leaves unplaced are packed again onto more sheets; one it cannot place on an empty sheet
    (its curve tolerance grows the outline a little) gets a sheet of its own by shelves (it
    fits: :func:`~compas_ccu.fabrication.splices.fitting_size`)."""
    out, left = [], sorted(shapes)
    while left:
        rest = {m: shapes[m] for m in left}
        packing = _nfp_pack(rest, {m: orientations[m] for m in left}, options, log,
                            length=length, width=width)  # fmt: skip
        for sheet in packing.sheets:
            out.append({m: (rot, t, _moved(shapes[m], rot, t)) for m, (rot, t) in sheet.items()})
        left = list(packing.unplaced)
        if left and not packing.sheets:  # none placed: the largest alone, by shelves
            m = max(left, key=lambda n: (_area(shapes[n]), n))
            out.append(_shelf_sheet({m: shapes[m]}, orientations, length, width, 0.0))
            left.remove(m)
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
    options = _resolved(options)
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
        if options.nesting == "spyrrow":  # one strip of every part, cut into sheet lengths
            windows = _window_sheets(shapes, orient, length, width, options, log)
        elif options.nesting == "compas_nest":  # every part onto sheets at once
            windows = _nfp_sheets(shapes, orient, length, width, options, log)
        while left:
            if options.nesting == "shelf":
                rest = {m: shapes[m] for m in left}
                on = _shelf_sheet(rest, orient, length, width, options.spacing * MM)
            else:  # the nester places every part: the windows hold them all
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
        if options.nesting == "spyrrow":
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


def nest_roll(strips, options: WorkshopOptions, *, log=None) -> RollNesting:
    """The hinge strips strip-packed on the textile roll, each along the roll (0 or 180 deg
    after turning its chord along it): :class:`~compas_ccu.fabrication.plan.RollNesting`
    ``width``, ``length`` (m used), ``strips`` (per crease: length of its centre line, m).
    ``log`` (a list) collects the packing."""
    options = _resolved(options)
    if not strips:
        return RollNesting(options.roll_width, 0.0, {})
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
        return RollNesting(options.roll_width, used / MM + 2.0 * options.margin, lengths)
    if options.nesting == "compas_nest":
        used = _nfp_roll(shapes, orient, height, options, log)
    else:
        _, used = _strip_pack(shapes, orient, height, options.spacing * MM, options, log,
                              improvements=ROLL_IMPROVEMENTS)  # fmt: skip
    return RollNesting(options.roll_width, used / MM + 2.0 * options.margin, lengths)


def _nfp_roll(shapes, orientations, height, options, log) -> float:
    """The length of roll (mm) compas_nest packs the hinge strips into: one sheet as long as
    the strips laid end to end (with room for the engine's own offset, about 8 x its curve
    tolerance on every side, measured), of which the strips use the part up to the last one's
    end."""
    gap = options.spacing * MM
    room = sum(float(np.ptp(s[:, 0])) + gap + 40.0 * ROLL_TOLERANCE for s in shapes.values())
    packing = _nfp_pack(shapes, orientations, options, log, length=room, width=height, sheets=1,
                        tolerance=ROLL_TOLERANCE)  # fmt: skip
    if packing.unplaced:
        raise GeometryError(
            f"compas_nest could not place the hinge strips {', '.join(packing.unplaced)} on "
            f"the roll ({options.roll_width:g} m less margins); nesting = 'spyrrow' or "
            "'shelf' places them"
        )
    pts = [_moved(shapes[m], *packing.sheets[0][m]) for m in shapes]
    return max(float(p[:, 0].max()) for p in pts) - min(float(p[:, 0].min()) for p in pts)


def nesting_search(options: WorkshopOptions, packings: list) -> NestingSearch:
    """What the nesting searched (:class:`~compas_ccu.fabrication.plan.NestingSearch`;
    ``fabrication.json`` ``workshop.nesting_search``): the solver
    and its version, the seed, the steps per packing, the time limit (a safety limit only), the
    packings and the steps they searched. The shelf packing searches nothing (only ``solver``
    is set); compas_nest records its generations, population and curve tolerances and the part
    orders it placed (``layouts_searched``) instead of steps."""
    options = _resolved(options)
    if options.nesting == "compas_nest":
        return NestingSearch(
            solver="compas_nest",
            version=nester_version(),
            seed=int(options.nesting_seed),
            generations=int(options.nesting_generations),
            population=POPULATION,
            part_tolerance=NFP_PART_TOLERANCE,
            roll_tolerance=ROLL_TOLERANCE,
            time_limit=float(options.nesting_time),
            packings=len(packings),
            layouts_searched=int(sum(p.layouts for p in packings)),
        )
    if options.nesting == "shelf":
        return NestingSearch(solver="shelf", packings=0, steps_searched=0)
    return NestingSearch(
        solver=SOLVER,
        version=solver_version(),
        seed=int(options.nesting_seed),
        steps=int(options.nesting_steps),
        roll_improvements=ROLL_IMPROVEMENTS,
        patience=PATIENCE,
        merge_patience=MERGE_PATIENCE,
        time_limit=float(options.nesting_time),
        packings=len(packings),
        steps_searched=int(sum(p.steps for p in packings)),
    )
