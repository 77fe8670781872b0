"""Matching the creases of plate drawings (``ccu import``): a crease's vertices and rulings on
its plate (its cut pattern), the pairs of plates joined along one crease and the partner checks
(same crease, mirror-image rulings), and which plate of a pair leads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import DesignError
from compas_ccu.fabrication.plate_drawings import (
    SNAP,
    CreaseDrawing,
    PlateDrawing,
)
from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = [
    "PARTNER_TOLERANCE",
    "CreasePair",
    "distance_to_polyline",
    "crease_pattern",
    "pair_creases",
    "check_partner",
    "stack_upper_leads",
]

#: Relative tolerance of the partner checks: crease lengths, ruling lengths and angles.
PARTNER_TOLERANCE = 1e-6


@dataclass
class CreasePair:
    """A crease and its two plates (``a`` the leading one)."""

    key: str
    a: PlateDrawing
    crease_a: CreaseDrawing
    b: PlateDrawing
    crease_b: CreaseDrawing


def distance_to_polyline(points, polyline):
    """Distance of every point to a polyline, and the arc length of its nearest point."""
    a, b = polyline[:-1], polyline[1:]
    ab = b - a
    length2 = np.maximum((ab * ab).sum(axis=1), DIVISION_FLOOR)
    s_edges = np.r_[0.0, np.cumsum(np.sqrt(length2))]
    out_d, out_s = [], []
    for p in np.atleast_2d(points):
        t = np.clip(((p - a) * ab).sum(axis=1) / length2, 0.0, 1.0)
        q = a + t[:, None] * ab
        d = np.linalg.norm(q - p, axis=1)
        k = int(np.argmin(d))
        out_d.append(d[k])
        out_s.append(s_edges[k] + t[k] * math.sqrt(length2[k]))
    return np.array(out_d), np.array(out_s)


def _end_ruling(plate: PlateDrawing, crease: CreaseDrawing, end: np.ndarray, tol: float):
    """Far end of the end ruling at a crease end point: the outline's edge that leaves the
    crease there (followed while straight)."""
    outline = plate.outline
    d = np.linalg.norm(outline - end, axis=1)
    i = int(np.argmin(d))
    if d[i] > tol:
        raise DesignError(
            f"{plate.label} CREASE #{crease.handle}: its end point {np.round(end, 6).tolist()} "
            f"is not a vertex of the CUT outline #{plate.outline_handle} (nearest "
            f"{d[i]:.3g} m away): a crease lies on the outline"
        )
    m = len(outline)
    for step in (1, -1):
        j = (i + step) % m
        off, _ = distance_to_polyline(outline[j], crease.points)
        if off[0] > tol:
            direction = outline[j] - outline[i]
            direction /= np.linalg.norm(direction)
            # follow collinear vertices along the straight end edge
            while True:
                nxt = (j + step) % m
                v = outline[nxt] - outline[i]
                if (
                    np.linalg.norm(v) > 0
                    and abs(direction[0] * v[1] - direction[1] * v[0]) <= (tol)
                    and v @ direction > np.linalg.norm(outline[j] - outline[i])
                ):
                    j = nxt
                else:
                    break
            return outline[j]
    raise DesignError(  # pragma: no cover - a CUT outline equal to its crease
        f"{plate.label} CREASE #{crease.handle}: no outline edge leaves the crease end "
        f"{np.round(end, 6).tolist()}"
    )


def crease_pattern(plate: PlateDrawing, crease: CreaseDrawing):
    """The crease vertices and ruling ends of a plate at one of its creases.

    Returns
    -------
    near : (n + 1, 2) float
        Crease vertices: the crease's end points and the interior rulings' feet, in order.
    far : (n + 1, 2) float
        The other end of every ruling (the end rulings: the outline's edges at the ends).
    handles : list of str
        The ruling of every vertex (the outline's handle for the end rulings).

    Raises
    ------
    DesignError
        A ruling that touches the crease with neither end, two rulings from one crease point,
        rulings that cross (file and both handles named), a crease end off the outline.
    """
    tol = SNAP * plate.size
    line = crease.points
    feet, fars, handles, params = [], [], [], []
    for handle, seg in plate.rulings:
        d, s = distance_to_polyline(seg, line)
        if min(d) > tol:
            if (
                any(
                    min(distance_to_polyline(seg, c.points)[0]) <= tol
                    for c in plate.creases
                    if c is not crease
                )
                and len(plate.creases) > 1
            ):
                continue  # a ruling of another crease of this plate that ends elsewhere
            raise DesignError(
                f"{plate.label} RULING_SCORE #{handle}: the ruling does not start on the "
                f"crease #{crease.handle} (its ends are {min(d):.3g} m from it)"
            )
        k = int(np.argmin(d))
        feet.append(seg[k])
        fars.append(seg[1 - k])
        params.append(s[k])
        handles.append(handle)
    order = np.argsort(params)
    params = np.asarray(params)[order]
    total = crease.length
    if len(params) and (params[0] <= tol or params[-1] >= total - tol):
        k = 0 if params[0] <= tol else len(params) - 1
        raise DesignError(
            f"{plate.label} RULING_SCORE #{handles[order[k]]}: an interior ruling starts at an "
            f"end of the crease #{crease.handle} (the end rulings are the outline's edges)"
        )
    same = np.flatnonzero(np.diff(params) <= tol)
    if same.size:
        a, b = handles[order[same[0]]], handles[order[same[0] + 1]]
        raise DesignError(
            f"{plate.label} RULING_SCORE #{a} and #{b}: two rulings start at the same crease point"
        )
    start, end = line[0], line[-1]
    near = np.array([start, *[feet[k] for k in order], end])
    far = np.array(
        [
            _end_ruling(plate, crease, start, tol),
            *[fars[k] for k in order],
            _end_ruling(plate, crease, end, tol),
        ]
    )
    names = [f"{plate.outline_handle} (end ruling)"] + [handles[k] for k in order]
    names.append(f"{plate.outline_handle} (end ruling)")
    _check_crossings(plate, near, far, names, tol)
    return near, far, names


def _check_crossings(plate, near, far, names, tol) -> None:
    """Refuse rulings that cross inside the plate (a pattern that folds over itself)."""
    p, r = near, far - near
    n = len(p)
    for i in range(n - 1):
        q, s = p[i + 1 :], r[i + 1 :]
        denom = r[i, 0] * s[:, 1] - r[i, 1] * s[:, 0]
        qp = q - p[i]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (qp[:, 0] * s[:, 1] - qp[:, 1] * s[:, 0]) / denom
            u = (qp[:, 0] * r[i, 1] - qp[:, 1] * r[i, 0]) / denom
        lim = tol / max(float(np.linalg.norm(r[i])), DIVISION_FLOOR)
        hit = np.flatnonzero(
            (np.abs(denom) > 0) & (t > lim) & (t < 1 - lim) & (u > lim) & (u < 1 - lim)
        )
        if hit.size:
            j = i + 1 + int(hit[0])
            raise DesignError(
                f"{plate.label} RULING_SCORE #{names[i]} and #{names[j]}: the rulings cross "
                f"inside the plate (at crease vertices {i} and {j}); rulings of a developable "
                "plate never cross"
            )


def pair_creases(plates: list) -> list:
    """The creases of a folder of plates and their two plates.

    Creases with XDATA are paired by crease id; the others by length (a crease and the one
    crease of another plate with the same length).

    Raises
    ------
    DesignError
        Partner creases of different length (both plates, handles and lengths named), a crease
        id on more or fewer than two plates, a crease without a partner.
    """
    pairs, loose = [], []
    by_id: dict = {}
    for plate in plates:
        for crease in plate.creases:
            if crease.crease_id is not None:
                by_id.setdefault(crease.crease_id, []).append((plate, crease))
            else:
                loose.append((plate, crease))
    for cid, members in sorted(by_id.items()):
        if len(members) != 2:
            where = ", ".join(f"{p.label} #{c.handle}" for p, c in members)
            raise DesignError(f"crease {cid} is on {len(members)} plates ({where}), not 2")
        pairs.append(CreasePair(f"crease {cid}", members[0][0], members[0][1], *members[1]))
    while loose:
        plate, crease = loose.pop(0)
        others = [(p, c) for p, c in loose if p is not plate]
        if not others:
            raise DesignError(
                f"{plate.label} CREASE #{crease.handle}: no partner crease on another plate"
            )
        tol = PARTNER_TOLERANCE * max(crease.length, DIVISION_FLOOR)
        match = [(p, c) for p, c in others if abs(c.length - crease.length) <= tol]
        if not match:
            p, c = min(others, key=lambda pc: abs(pc[1].length - crease.length))
            raise DesignError(
                f"partner creases of different length: {plate.label} CREASE #{crease.handle} "
                f"is {crease.length:.9g} m long, {p.label} CREASE #{c.handle} "
                f"{c.length:.9g} m (difference {abs(c.length - crease.length):.3g} m); the two "
                "plates of a crease share it"
            )
        loose.remove(match[0])
        pairs.append(CreasePair(f"crease {plate.label} #{crease.handle}", plate, crease, *match[0]))
    for pair in pairs:
        la, lb = pair.crease_a.length, pair.crease_b.length
        if abs(la - lb) > PARTNER_TOLERANCE * la:
            raise DesignError(
                f"partner creases of different length ({pair.key}): {pair.a.label} CREASE "
                f"#{pair.crease_a.handle} is {la:.9g} m long, {pair.b.label} CREASE "
                f"#{pair.crease_b.handle} {lb:.9g} m (difference {abs(la - lb):.3g} m)"
            )
    return pairs


def _intrinsic(near, far):
    """Crease edge lengths, ruling lengths and the (unsigned) angles between them."""
    edges = np.linalg.norm(np.diff(near, axis=0), axis=1)
    r = far - near
    lengths = np.linalg.norm(r, axis=1)
    t = np.gradient(near, axis=0)
    cos = (t * r).sum(axis=1) / (np.linalg.norm(t, axis=1) * lengths)
    return edges, lengths, np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def check_partner(pair: CreasePair, a_pattern, b_pattern):
    """The partner must be the leading plate's mirror image (or the same pattern)."""
    near_a, far_a, _ = a_pattern
    near_b, far_b, names_b = b_pattern
    if len(near_a) != len(near_b):
        raise DesignError(
            f"{pair.b.label}: {len(near_b) - 2} interior rulings on CREASE "
            f"#{pair.crease_b.handle}, its partner in {pair.a.label} has {len(near_a) - 2}: the "
            "two plates of a crease have their rulings at the same crease points"
        )
    ea, la, ga = _intrinsic(near_a, far_a)
    best = None
    for flip in (False, True):
        nb, fb, nm = (
            (near_b[::-1], far_b[::-1], names_b[::-1]) if flip else (near_b, far_b, names_b)
        )
        eb, lb, gb = _intrinsic(nb, fb)
        if flip:
            gb = 180.0 - gb
        err = max(
            float(np.abs(ea - eb).max()) / max(float(ea.max()), DIVISION_FLOOR),
            float(np.abs(la - lb).max()) / max(float(la.max()), DIVISION_FLOOR),
        )
        if best is None or err < best[0]:
            best = (err, la, lb, ea, eb, nm, flip)
    err, la, lb, ea, eb, nm, flip = best
    if err > PARTNER_TOLERANCE:
        j = int(np.argmax(np.abs(la - lb)))
        if abs(la[j] - lb[j]) > PARTNER_TOLERANCE * la.max():
            raise DesignError(
                f"{pair.b.label} RULING_SCORE #{nm[j]}: the ruling at crease vertex {j} is "
                f"{lb[j]:.9g} m long, its partner in {pair.a.label} {la[j]:.9g} m: a design "
                "file holds one crease and a mirror partner of the same rulings, so this pair "
                "cannot be imported (docs/import.md)"
            )
        j = int(np.argmax(np.abs(ea - eb)))
        raise DesignError(
            f"{pair.b.label} CREASE #{pair.crease_b.handle}: its segment {j} is {eb[j]:.9g} m, "
            f"the partner's in {pair.a.label} {ea[j]:.9g} m: the rulings do not meet the two "
            "creases at the same points"
        )
    return err, flip


def stack_upper_leads(pair: CreasePair, patterns: dict, manifest: dict) -> CreasePair:
    """The pair with the plate higher in the flat-folded stack as plate ``a`` (``patterns``
    reordered with it): the drawings show the plates from the stack's top, so it rises towards
    the viewer as the leading plate does (+z); without fabrication.json, the first file leads
    and the structure may come out mirrored."""
    stack = manifest.get("stack_order")
    if stack and pair.a.plate_id in stack and pair.b.plate_id in stack:
        if stack.index(pair.a.plate_id) < stack.index(pair.b.plate_id):
            pair = CreasePair(pair.key, pair.b, pair.crease_b, pair.a, pair.crease_a)
            patterns[pair.key] = patterns[pair.key][::-1]
    return pair
