"""Oriented boxes and binary trees of boxes: the bounding volumes of the candidate search.

:mod:`compas_ccu.thickness.candidate_search` boxes blocks of cells and blocks of face vertices
and walks two trees of boxes down to the block pairs that can meet. Here: the corner lines of
what a cell's lateral test accepts (:func:`cell_corners`) and their hull up to a height
(:func:`cell_hulls`), the frames of cells (:func:`cell_frames`), the extents of point sets
(:func:`point_bounds`), of those hulls (:func:`hull_bounds`, without the hull's points) and of
boxes (:func:`box_bounds`) along such frames, boxes from extents (:func:`bounded_boxes`) or
around point sets (:func:`oriented_boxes`), packed as columns (:func:`pack_boxes`) for the
separating axis test (:func:`separated`), the blocks of consecutive indices
(:func:`index_blocks`) and the trees over the leaf boxes of every plate (:func:`box_tree`),
refitted level by level from their children's boxes. Every product runs on whole stacks of
boxes (one batched BLAS product, or term by term on arrays, no per-box Python).

**Layout.** Points, centres and extents are stored coordinate by coordinate, (3, ...) arrays
(long contiguous rows: NumPy is several times slower on many short rows of three); frames stay
(..., 3, 3) matrices, the operands of BLAS. Sums of three products are written term by term
in the order of the ``einsum`` they replace (:func:`compas_ccu.geometry.coordinate_dot`), so
every box is the same bit for bit as with vectors in rows.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.geometry import cross3, dot, norm3, unit3
from compas_ccu.thickness.work_arrays import array_maker, cross_into, dot_into, slot_maker
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "cell_corners",
    "cell_hulls",
    "hull_bounds",
    "cell_frames",
    "point_bounds",
    "bounded_boxes",
    "oriented_boxes",
    "box_bounds",
    "pack_boxes",
    "separated",
    "index_blocks",
    "box_tree",
]


def _components(vectors, out=None):
    """(3, r, ...) the coordinates of r vector arrays (..., 3), coordinate by coordinate."""
    if out is None:
        out = np.empty((3, len(vectors)) + vectors[0].shape[:-1])
    for r, v in enumerate(vectors):
        out[:, r] = np.moveaxis(v, -1, 0)
    return out


def cell_corners(cells, tol, work=None):
    """The corner lines of what the lateral test of a cell accepts: points ``X(0)`` (3, 4, ...,
    n) in the mid plane and directions ``w`` (3, 4, ..., n), coordinate by coordinate and
    corner by corner, the corner at height ``h`` over the mid plane being ``X(0) + h w``
    (:func:`cell_hulls`; ``X(0)`` infinite where the cell is unbounded). ``work``: a
    :class:`compas_ccu.thickness.work_arrays.WorkArrays` whose arrays are written and returned
    (overwritten by the next call), or None (new arrays)."""
    centre, normal, (a, s0), (b, s1), (_, e_near), (d, e_far) = cells
    new = slot_maker(work)
    flat = normal.shape[:-1]
    big, small = (3, 4) + flat, (4,) + flat
    term, one, two = new("term", big), new("one", small), new("two", small)
    # the lateral planes in turn round the cell (near, side 0, far, side 1), the next one and
    # the one before each: each one's offset moved out by tol and its line's direction in the
    # planes parallel to the mid plane; corner i where the lines of planes i and i + 1 meet
    plane = _components([e_near, s0, e_far, s1], new("plane", big))
    turn, back = [1, 2, 3, 0], [3, 0, 1, 2]
    after = np.take(plane, turn, axis=1, out=new("after", big), mode="wrap")
    before = np.take(plane, back, axis=1, out=new("before", big), mode="wrap")
    offset = dot_into(_components([a, a, d, b], term), plane, new("offset", small), one)
    offset -= tol  # (4, ..., n)
    up = new("up", (3,) + flat)
    up[...] = np.moveaxis(normal, -1, 0)
    up = up[:, None]  # (3, 1, ..., n)
    line = cross_into(up, plane, new("line", big), one, two)
    x0, w = new("x0", big), new("w", big)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        axis = cross_into(plane, after, new("axis", big), one, two)
        det = dot_into(up, axis, new("det", small), one)
        # cross3(next, normal) = -line of the next plane, exactly
        np.multiply(np.take(offset, turn, axis=0, out=one, mode="wrap"), line, out=x0)
        x0 -= np.multiply(offset, np.take(line, turn, axis=1, out=term, mode="wrap"), out=term)
        height = dot_into(np.moveaxis(centre, -1, 0), up[:, 0], new("height", flat), two[0])
        x0 += np.multiply(height, axis, out=term)
        x0 /= det
        np.divide(axis, det, out=w)
    # each line bounded from opposite sides by the lines of its two neighbours
    bounded = np.multiply(
        dot_into(after, line, one, term[0]), dot_into(before, line, two, term[0]), out=one
    )
    bounded = bounded < 0.0
    x0[:, :, ~bounded.all(axis=0)] = np.inf
    return x0, w


def cell_hulls(cells, tol, height):
    """(..., n, 8, 3) points whose convex hull holds every point that the lateral test of a cell
    accepts at a distance of up to ``height`` from the cell's mid plane
    (:mod:`compas_ccu.thickness.candidate_search`): ``X(±height)`` of :func:`cell_corners`.

    In the planes parallel to the mid plane each lateral plane leaves a line of fixed direction;
    the accepted set is bounded by the four corners where adjacent lines meet if, along each
    line, its two neighbours bound it from opposite sides. Where that fails, or a corner line
    never meets those planes (a degenerate cell), the points are infinite.
    """
    x0, w = (np.moveaxis(x, (0, 1), (-1, -2)) for x in cell_corners(cells, tol))
    with np.errstate(invalid="ignore", over="ignore"):
        step = (np.reshape(height, (-1, 1, 1, 1, 1)) if np.ndim(height) else height) * w
        out = np.stack([x0 - step, x0 + step], axis=-2)  # (..., 4 corners, 2, 3)
    return out.reshape(*out.shape[:-3], 8, 3)


def hull_bounds(corners, directions, axes, height, work=None):
    """The lowest and highest coordinates (3, ...) each of the hulls of cell corners (..., 3,
    s) with their directions (..., 3, s) up to ``height`` (:func:`cell_corners`) along the
    columns of ``axes`` (..., 3, 3): the segment ``X(0) + h w``, ``|h| <= height``, spans
    ``X(0) . u ± height |w . u|`` (the hull's points, without the points). ``work``: as
    :func:`cell_corners` takes it, for the temporaries."""
    turn = np.swapaxes(axes, -1, -2)
    new = slot_maker(work)
    shape = np.broadcast_shapes(turn.shape[:-1] + corners.shape[-1:], corners.shape)
    mid, size = new("mid", shape), new("size", shape)
    with np.errstate(invalid="ignore", over="ignore"):
        np.matmul(turn, corners, out=mid)  # (..., 3, s)
        np.abs(np.matmul(turn, directions, out=size), out=size)
        size *= height
        ends = new("ends", shape)
        lo = _lowest(np.subtract(mid, size, out=ends), np.minimum)
        hi = _lowest(np.add(mid, size, out=ends), np.maximum)
    return np.moveaxis(lo, -1, 0), np.moveaxis(hi, -1, 0)


def cell_frames(mid_near, normal, cell):
    """(k, p, c, 3, 3) orthonormal frames (columns: edge, ruling side, normal) of cells
    ``cell`` (c,) of every plate."""
    t = mid_near[:, :, cell + 1] - mid_near[:, :, cell]  # the crease-side edge b - a
    nrm = normal[:, :, cell]
    t = unit3(t - dot(t, nrm)[..., None] * nrm)
    return np.stack([t, cross3(nrm, t), nrm], axis=-1)


def point_bounds(points, axes, work=None):
    """The lowest and highest coordinates (3, ...) each of point sets (..., s, 3) along the
    columns of the frames ``axes`` (..., 3, 3) (non-finite where a point is not finite): one
    batched product of the transposed frames with the transposed points. ``work``: as
    :func:`cell_corners` takes it, for the temporaries."""
    turn, columns = np.swapaxes(axes, -1, -2), np.swapaxes(points, -1, -2)
    shape = np.broadcast_shapes(turn.shape[:-1] + columns.shape[-1:], columns.shape)
    along = array_maker(work, "point_bounds.")("along", shape)
    with np.errstate(invalid="ignore", over="ignore"):
        np.matmul(turn, columns, out=along)  # (..., 3, s)
    lo, hi = _lowest(along, np.minimum), _lowest(along, np.maximum)
    return np.moveaxis(lo, -1, 0), np.moveaxis(hi, -1, 0)


def _lowest(values, lower):
    """The lowest of ``values`` (..., s) along the last axis by ``lower`` (np.minimum, or
    np.maximum for the highest), column by column: the reduction's values (NaN where one is
    NaN) without its short rows."""
    out = values[..., 0].copy()
    for i in range(1, values.shape[-1]):
        lower(out, values[..., i], out=out)
    return out


def _rows(axes, out=None):
    """(3, 3, ...) frames (..., 3, 3) entry by entry: ``[i, j]`` row i, column j (written to
    ``out`` if given)."""
    if out is None:
        return np.ascontiguousarray(np.moveaxis(axes, (-2, -1), (0, 1)))
    out[...] = np.moveaxis(axes, (-2, -1), (0, 1))
    return out


def bounded_boxes(lo, hi, axes, tol, work=None):
    """Oriented boxes from the coordinates ``lo``, ``hi`` (3, t, ..., s) they span along the
    columns of ``axes`` (..., s, 3, 3; the same for every ``t``): centres (3, t, ..., s), the
    axes and the half-extents (3, t, ..., s), widened by ``1e-9`` of the coordinates plus
    ``tol`` for round-off (inf where not finite). Boxes hold their centres and half-extents
    coordinate by coordinate (long contiguous rows), their axes as frames (for BLAS).
    ``work``: ``(WorkArrays, prefix)`` whose arrays hold the centres and half-extents returned
    (overwritten by the next call with that prefix), or None (new arrays)."""
    new = array_maker(*work) if work else array_maker(None, "")
    shape = np.broadcast_shapes(lo.shape, hi.shape)
    mid, half, term = new("mid", shape), new("half", shape), new("term", shape)
    with np.errstate(invalid="ignore", over="ignore"):
        np.multiply(0.5, np.add(lo, hi, out=mid), out=mid)
        np.multiply(0.5, np.subtract(hi, lo, out=half), out=half)
        size = np.add(np.abs(lo, out=term), np.abs(hi, out=new("centre", shape)), out=term)
        half += np.multiply(EXACT_RELATIVE, size, out=term)
        half += tol
    bad = ~np.isfinite(half).all(axis=0)
    mid[:, bad], half[:, bad] = 0.0, np.inf
    # axes @ mid in the order of einsum's contiguous sums of three, (0 + 2) + 1
    rows = _rows(axes, new("rows", (3, 3) + axes.shape[:-2]))[:, :, None]  # (3, 3, 1, ..., s)
    centre = np.multiply(rows[:, 0], mid[0], out=new("centre", shape))
    centre += np.multiply(rows[:, 2], mid[2], out=term)
    centre += np.multiply(rows[:, 1], mid[1], out=term)
    return centre, axes, half


def oriented_boxes(points, axes, tol):
    """Oriented boxes around point sets (..., s, 3) in the frames ``axes`` (..., 3, 3): centres
    (3, 1, ...), the axes and the half-extents (3, 1, ...), widened for round-off (inf where
    a point is not finite; :func:`point_bounds`, :func:`bounded_boxes`)."""
    lo, hi = point_bounds(points, axes)
    return bounded_boxes(lo[:, None], hi[:, None], axes, tol)


def box_bounds(box, axes, work=None):
    """The lowest and highest coordinates (3, t, ...) each of oriented boxes (centres and
    half-extents (3, t, ...), axes (..., 3, 3)) along the columns of the frames ``axes``
    (..., 3, 3): the support of a box along a unit vector ``u`` is ``centre . u ± sum_j
    half_j |axis_j . u|`` (the extreme corners, without the corners). ``work``: as
    :func:`bounded_boxes` takes it, for the two arrays returned and the temporaries."""
    centre, box_axes, half = box
    new = array_maker(*work) if work else array_maker(None, "")
    frames = (3, 3) + axes.shape[:-2]
    rows = _rows(axes, new("rows", frames))[:, :, None]  # (3, 3, 1, ...)
    shape = np.broadcast_shapes(rows.shape[1:], centre.shape[1:])
    term = new("term", shape)
    with np.errstate(invalid="ignore", over="ignore"):
        mid = np.multiply(rows[0], centre[0], out=new("mid", shape))  # axes^T @ centre, term
        mid += np.multiply(rows[1], centre[1], out=term)  # by term
        mid += np.multiply(rows[2], centre[2], out=term)
        along = np.matmul(np.swapaxes(axes, -1, -2), box_axes, out=new("along", axes.shape))
        size = _rows(np.abs(along, out=along), new("size", frames))[:, :, None]  # |u_c . axis_j|
        reach = np.multiply(size[:, 0], half[0], out=new("reach", shape))
        reach += np.multiply(size[:, 1], half[1], out=term)
        reach += np.multiply(size[:, 2], half[2], out=term)
        return np.subtract(mid, reach, out=new("lo", shape)), np.add(mid, reach, out=mid)


def pack_boxes(box, out=None):
    """Boxes as columns ``(centre, axes (row by row), half-extents)`` of 15 numbers: (15, t x
    k x p x nodes) from centres and half-extents (3, t, k, p, nodes) and axes (k, p, nodes,
    3, 3), the same for every ``t``, so that the separating-axis test runs on contiguous rows
    (written to ``out`` (15, t, k, p, nodes) if given)."""
    centre, axes, half = box
    if out is None:
        out = np.empty((15,) + centre.shape[1:])
    out[:3] = centre
    out[3:12] = _rows(axes).reshape((9, 1) + axes.shape[:-2])
    out[12:] = half
    return out.reshape(15, -1)


def separated(box_a, box_b, work=None):
    """(N,) bool: packed boxes ``a`` and ``b`` (15, N) are disjoint by a face axis of either
    (the separating axis test on those six axes; False where undecided). ``work``: as
    :func:`cell_corners` takes it, for the temporaries."""
    new = slot_maker(work)
    n = box_a.shape[1]
    d = np.subtract(box_b[:3], box_a[:3], out=new("d", (3, n)))
    a, b = box_a[3:12].reshape(3, 3, -1), box_b[3:12].reshape(3, 3, -1)  # [row, column]
    ha, hb = box_a[12:], box_b[12:]
    # |a_i . b_j| (3, 3, N) and the projections of d on the axes a_i and b_j (3, N), every
    # one the sum of its three products in turn
    r, nine, three = new("r", (3, 3, n)), new("nine", (3, 3, n)), new("three", (3, n))
    np.multiply(a[0][:, None], b[0][None], out=r)
    r += np.multiply(a[1][:, None], b[1][None], out=nine)
    r += np.multiply(a[2][:, None], b[2][None], out=nine)
    np.abs(r, out=r)
    da = np.multiply(a[0], d[0], out=new("da", (3, n)))
    db = np.multiply(b[0], d[0], out=new("db", (3, n)))
    for x, y in ((a, da), (b, db)):
        y += np.multiply(x[1], d[1], out=three)
        y += np.multiply(x[2], d[2], out=three)
        np.abs(y, out=y)
    with np.errstate(invalid="ignore"):
        slack = EXACT_RELATIVE * (norm3(d.T) + ha.sum(axis=0) + hb.sum(axis=0))
        # the half-extents' reach along a_i (3, N) and along b_j (3, N), left to right
        ra = np.add(ha, np.multiply(r[:, 0], hb[0], out=three), out=new("ra", (3, n)))
        rb = np.add(hb, np.multiply(r[0], ha[0], out=three), out=new("rb", (3, n)))
        for c in (1, 2):
            ra += np.multiply(r[:, c], hb[c], out=three)
            rb += np.multiply(r[c], ha[c], out=three)
        ra += slack
        rb += slack
        return (da > ra).any(axis=0) | (db > rb).any(axis=0)


def index_blocks(count, size):
    """(blocks, size) indices ``0 .. count - 1`` in consecutive blocks (the last one padded
    with its last index)."""
    blocks = -(-count // size)
    return np.minimum(np.arange(blocks * size).reshape(blocks, size), count - 1)


def box_tree(box, frames, tol, work=None):
    """Boxes of binary trees over the leaf boxes of every plate.

    Parameters
    ----------
    box : tuple
        The leaf boxes (:func:`bounded_boxes`): centres (3, t, k, p, c) of ``t`` trees, their
        axes (k, p, c, 3, 3), the same for every tree, and half-extents (3, t, k, p, c).
    frames : callable
        ``frames(level)``: the axes (k, p, nodes, 3, 3) of the nodes of ``level`` (1 above the
        leaves), the same for every tree.
    tol : float

    A parent's box holds its children's boxes (their extents along its axes,
    :func:`box_bounds`: the trees are refitted level by level, O(nodes) array operations; the
    children's axes along the parent's, ``|u . axis_j|``, are the same for every tree). Leaves
    are padded to a power of two with empty ones, and a parent of one empty child spans its
    other child alone. Returns the levels from the leaves up, each the packed boxes (15,
    trees x states x plates x nodes) and which nodes are not padding. ``work``: ``(WorkArrays,
    prefix)`` whose arrays hold the levels returned and the temporaries (overwritten by the
    next call with that prefix), or None (new arrays).
    """
    new = array_maker(*work) if work else array_maker(None, "")
    prefix = work[1] if work else ""
    count = box[1].shape[2]
    size = 1 << max(count - 1, 0).bit_length()
    pad = size - count
    valid = np.r_[np.ones(count, dtype=bool), np.zeros(pad, dtype=bool)]
    if pad:  # empty leaves: copies of the last one (never looked at)
        centre, axes, half = box
        centre, half = (
            _padded(x, -1, pad, new(name, x.shape[:-1] + (size,)))
            for x, name in ((centre, "pad.centre"), (half, "pad.half"))
        )
        shape = axes.shape[:2] + (size,) + axes.shape[3:]
        box = centre, _padded(axes, 2, pad, new("pad.axes", shape)), half
    levels = [(pack_boxes(box, new("packed.0", (15,) + box[0].shape[1:])), valid)]
    level = 0
    while size > 1:
        size //= 2
        level += 1
        parent = frames(level)  # (k, p, size, 3, 3)
        twice = new("twice", parent.shape[:3] + (2,) + parent.shape[3:])
        twice[...] = parent[:, :, :, None]  # np.repeat(parent, 2, axis=2)
        twice = twice.reshape(parent.shape[:2] + (2 * size,) + parent.shape[3:])
        within = (work[0], prefix + "bounds.") if work else None
        lo, hi = box_bounds(box, twice, within)  # (3, t, k, p, 2 size)
        lo_box = np.minimum(
            lo[..., 0::2], lo[..., 1::2], out=new("lo_box", lo.shape[:-1] + (size,))
        )
        hi_box = np.maximum(hi[..., 0::2], hi[..., 1::2], out=new("hi_box", lo_box.shape))
        pair = valid.reshape(size, 2)
        alone = np.flatnonzero(pair[:, 0] & ~pair[:, 1])  # the second child empty
        lo_box[..., alone], hi_box[..., alone] = lo[..., 2 * alone], hi[..., 2 * alone]
        # the boxes of a level are read while those of the next one are written
        within = (work[0], f"{prefix}box.{level % 2}.") if work else None
        box = bounded_boxes(lo_box, hi_box, parent, tol, within)
        valid = pair.any(axis=1)
        levels.append((pack_boxes(box, new(f"packed.{level}", (15,) + box[0].shape[1:])), valid))
    return levels


def _padded(x, axis, pad, out):
    """``x`` with ``pad`` copies of its last entry along ``axis`` appended, written to ``out``."""
    count = x.shape[axis]
    at = (slice(None),) * (axis % x.ndim)
    out[at + (slice(0, count),)] = x
    out[at + (slice(count, None),)] = x[at + (slice(count - 1, count),)]
    return out
