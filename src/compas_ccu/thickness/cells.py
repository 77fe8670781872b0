"""The cells of a thick plate: the half-spaces of every quad cell and the tests on them.

A thick plate is the union of its quad *cells*: cell ``j`` is bounded by the two offset planes
of quad ``j`` (``|d| ≤ t/2`` along the quad normal), the two ruling-side planes (through ruling
``j`` and its offset vector ν_j, and the same for ``j + 1``) and the planes through the
crease-side and far-side edges that contain the quad normal. :func:`plate_cells` gives these
planes, :func:`plane_heights` the signed distances of points from them (one batched matrix
product), :func:`in_footprint` whether a point's foot lies inside a cell's footprint, and
:func:`point_gaps` the gap of any points over one plate; :func:`accepted_from` turns a lateral
test ``fl(h - offset) >= -tol`` into a comparison with the lowest float that passes. The
contact test of two plates (:mod:`compas_ccu.thickness.collision`) and its candidate search
(:mod:`compas_ccu.thickness.candidate_search`) are built on them.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.geometry import dot
from compas_ccu.thickness.work_arrays import (
    array_maker,
    cross_into,
    dot_into,
    slot_maker,
    unit_into,
)
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["plate_cells", "plane_heights", "in_footprint", "accepted_from", "point_gaps"]


def plate_cells(mid_near, mid_far, offsets, work=None):
    """Half-space description of the cells of plates (..., n cells): ``centre, normal, (a,
    s0), (b, s1), (a, e_near), (d, e_far)``, each (..., n, 3), the planes as (point, unit
    normal) with the cell on their positive side.

    Computed coordinate by coordinate (long contiguous rows; the same operations as on the
    vectors, dots in the order of :func:`compas_ccu.geometry.dot`, so the same values).
    ``work``: a :class:`compas_ccu.thickness.work_arrays.WorkArrays` whose arrays hold the
    temporaries and the six arrays returned (overwritten by the next call), or None (new
    arrays)."""
    near, far, nu = (np.moveaxis(x, -1, 0) for x in (mid_near, mid_far, offsets))
    a, b = near[..., :-1], near[..., 1:]
    c, d = far[..., 1:], far[..., :-1]
    new, kept = slot_maker(work), array_maker(work, "cells.")
    cell, row = a.shape, near.shape  # (3, ..., n), (3, ..., n + 1)
    one, two = new("one", row[1:]), new("two", row[1:])
    one_c, two_c = one.reshape(-1)[: a[0].size].reshape(cell[1:]), new("two_c", cell[1:])
    part = new("part", cell)
    normal = cross_into(
        np.subtract(c, a, out=part),
        np.subtract(d, b, out=new("part_2", cell)),
        new("normal", cell),
        one_c,
        two_c,
    )
    unit_into(normal, one_c, two_c)
    side = np.subtract(far, near, out=new("side", row))  # plane of ruling j and ν_j
    side = cross_into(unit_into(side, one, two), nu, new("rulings", row), one, two)
    unit_into(side, one, two)
    # orient the side planes so that the cell is on their positive side
    centre = np.add(a, b, out=new("centre", cell))
    centre += c
    centre += d
    centre *= 0.25
    sign = one_c

    def oriented(plane, point, out):  # plane * sign((centre - point) . plane)
        dot_into(np.subtract(centre, point, out=part), plane, sign, two_c)
        return np.multiply(plane, np.sign(sign, out=sign), out=out)

    s0 = oriented(side[..., :-1], a, new("s0", cell))
    s1 = oriented(side[..., 1:], b, new("s1", cell))
    edges = []
    for name, (u, v, point) in (("e_near", (b, a, a)), ("e_far", (c, d, d))):
        edge = cross_into(normal, np.subtract(u, v, out=part), new(name, cell), one_c, two_c)
        unit_into(edge, one_c, two_c)
        edges.append(oriented(edge, point, edge))
    e_near, e_far = edges
    names = ("centre", "normal", "s0", "s1", "e_near", "e_far")
    centre, normal, s0, s1, e_near, e_far = (
        _rows_last(x, kept(name, x.shape[1:] + (3,)))
        for x, name in zip((centre, normal, s0, s1, e_near, e_far), names)
    )
    a, b = mid_near[..., :-1, :], mid_near[..., 1:, :]
    d = mid_far[..., :-1, :]
    return centre, normal, (a, s0), (b, s1), (a, e_near), (d, e_far)


def _rows_last(x, out):
    """``x`` (3, ...) as (..., 3) rows written to ``out``."""
    out[...] = np.moveaxis(x, 0, -1)
    return out


def plane_heights(points, base, normal):
    """(K, P, n) signed distances ``(p - base_j) . normal_j`` of points (K, P, 3) from the
    planes (K, n, 3): one batched matrix product (BLAS) instead of a (K, P, n, 3) temporary."""
    return points @ np.swapaxes(normal, -1, -2) - dot(base, normal)[..., None, :]


def in_footprint(points, cells, tol):
    """(..., P, n) True where a point's foot lies inside a cell's footprint."""
    _, _, *planes = cells
    inside = None
    for base, normal in planes:
        ok = plane_heights(points, base, normal) >= -tol
        inside = ok if inside is None else inside & ok
    return inside


def point_gaps(points, mid_near, mid_far, offsets, thickness, *, tol=EXACT_RELATIVE):
    """Gap of points over one plate in every state: ``|d| - t/2`` over the cell whose footprint
    holds the point's foot (the smallest over such cells), inf where none does.

    Negative: the point lies inside the plate by that depth. The brute force of
    :func:`_contacts_all` (every point against every cell) for points that are not a plate's
    face vertices, e.g. sample points of a splice plate (:mod:`compas_ccu.thickness.splices`).

    Parameters
    ----------
    points : (k, P, 3) float
    mid_near, mid_far, offsets : (k, n + 1, 3) float
        The plate's mid-surface boundaries (with the crease corrections) and face offsets.
    thickness : float
        The plate's, m.
    tol : float
        Lateral tolerance of the footprint test, m.

    Returns
    -------
    (k, P) float

    Examples
    --------
    A 1 x 1 plate 8 mm thick in z = 0 and points 1 mm and 10 mm above it, and one beside it:

    >>> near = np.array([[[0.0, 0, 0], [1, 0, 0]]])
    >>> far = near + [0, 1, 0]
    >>> nu = np.broadcast_to([0.0, 0, 1], near.shape)
    >>> pts = np.array([[[0.5, 0.5, 0.001], [0.5, 0.5, 0.01], [2.0, 0.5, 0.0]]])
    >>> np.round(point_gaps(pts, near, far, nu, 0.008), 9).tolist()
    [[-0.003, 0.006, inf]]
    """
    cells = plate_cells(mid_near, mid_far, offsets)
    centre, normal = cells[0], cells[1]
    lateral = in_footprint(points, cells, tol)  # (k, P, n)
    d = plane_heights(points, centre, normal)
    return np.where(lateral, np.abs(d) - 0.5 * thickness, np.inf).min(axis=2)


def accepted_from(offset, tol, work=None):
    """The lowest height ``h`` (a float) with ``h - offset >= -tol`` in floating point, for
    every ``offset``: a lateral test of the brute force, ``fl(h - offset) >= -tol``, is ``h >=
    accepted`` (NaN where no height passes), the same booleans without the subtraction.

    ``fl(h - offset)`` grows with ``h`` (rounding is monotone), so the heights that pass are
    those from one float up. Where ``|offset| >= 4 tol`` the subtraction is exact for every
    ``h`` near ``offset - tol`` (Sterbenz), so that float is ``x = fl(offset - tol)`` if ``x``
    passes, else the next float up (``x`` is the nearest float to ``offset - tol``). Else a
    step or two from ``x``, or a bisection over the floats, finds it. ``work``: a
    :class:`compas_ccu.thickness.work_arrays.WorkArrays` whose array is returned (overwritten
    by the next such call), or None (a new array).
    """
    offset = np.asarray(offset, dtype=float)
    new = array_maker(work, "accepted.")
    with np.errstate(invalid="ignore", over="ignore"):
        out = np.subtract(offset, tol, out=new("out", offset.shape))
        size = np.abs(offset, out=new("size", offset.shape))
        exact = (size >= 4.0 * tol) & (size <= np.finfo(float).max)
        up = np.flatnonzero(exact & (np.subtract(out, offset, out=size) < -tol))
        if len(up):  # the next float up of a finite x, 0 < |x| (tol > 0 here)
            bits = out.reshape(-1)[up].view(np.int64)
            out.reshape(-1)[up] = (bits + np.where(bits >= 0, 1, -1)).view(np.float64)
        rest = np.flatnonzero(~exact)
        if len(rest):
            out.reshape(-1)[rest] = _near_zero(offset.reshape(-1)[rest], tol)
    return out


def _near_zero(offset, tol):
    """:func:`accepted_from` of offsets (m,) that are not finite or within ``4 tol`` of 0."""
    out = np.full(offset.shape, np.nan)
    out[offset == -np.inf] = np.nextafter(-np.inf, 0.0)  # every finite height passes
    work = np.flatnonzero(np.isfinite(offset))
    off = offset[work]
    low = off - tol
    for _ in range(2):  # one step down or up from fl(offset - tol)
        passes = (low - off) >= -tol
        below = np.nextafter(low, -np.inf)
        down = passes & ((below - off) >= -tol)
        done = passes & ~down
        out[work[done]] = low[done]
        low = np.where(down, below, np.nextafter(low, np.inf))[~done]
        work, off = work[~done], off[~done]
    if len(work):
        out[work] = _bisected(off, tol)
    return out


def _ordered(x):
    """int64 keys of floats in their order (-0.0 and 0.0 both 0)."""
    bits = x.view(np.int64)
    return np.where(bits < 0, -(bits & np.int64(0x7FFFFFFFFFFFFFFF)), bits)


def _unordered(key):
    """The floats of :func:`_ordered` keys."""
    bits = np.where(key < 0, (-key) | np.int64(-0x8000000000000000), key)
    return bits.view(np.float64)


def _bisected(off, tol):
    """:func:`accepted_from` of finite offsets by bisection over the floats."""
    lo = _ordered(np.full(off.shape, -np.inf))  # fails
    hi = _ordered(off.copy())  # passes: fl(offset - offset) = 0
    while True:
        open_ = hi > lo + 1
        if not open_.any():
            return _unordered(hi)
        mid = (lo >> 1) + (hi >> 1) + (lo & hi & 1)
        with np.errstate(invalid="ignore", over="ignore"):
            passes = (_unordered(mid) - off) >= -tol
        hi = np.where(open_ & passes, mid, hi)
        lo = np.where(open_ & ~passes, mid, lo)
