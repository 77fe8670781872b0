"""The candidate block pairs of the interpenetration certificate's scan that may hold an event
(:mod:`compas_ccu.kinematics.interference_events`, whose docstring defines the blocks and the
events): :func:`sided_blocks`.

An event needs, for one quad of a quad block, vertices of the vertex block strictly on both sides
of its plane (:func:`sided_blocks` says in which states). Two tests tell, the second only on what
the first keeps:

1. **the box bound**: the heights of a block's vertices over a quad's plane lie within those of
   its box (the box of its vertices off the hinge, in one state), ``n . c - offset ± |n| . e``
   for the box's centre ``c`` and half extents ``e``: a box wholly on one side of every quad's
   plane, in both states of the step, holds no event. One dot product per quad instead of one
   per vertex and quad, and no vertex gathered.
2. **the heights**: every vertex's height over every quad's plane, once per block and state.

Both compare with the touch tolerance loosened by far more than their rounding (the bound by
twice as much as the heights), so the bound keeps every block pair the heights keep, and the
heights every one with an event: the pairs kept are those of the heights alone, bit for bit
(tests/test_kinematics_interference_blocks.py), whatever the order of the arithmetic.

The scan runs on every edit of the studio: its large temporaries (a few MB, which glibc would
map afresh, page by page, on every call) are written (``out=``) into the work arrays kept per
thread in :data:`work_arrays` (:class:`compas_ccu.work_arrays.WorkArrays`): the tables of
:func:`block_tables` under their names, the temporaries of the bound, the heights and the
nearness test in shared slots (each function holds no other's while it runs). Every operation
is the one it replaces, on the same operands, and :func:`sided_blocks` returns a new array:
nothing it returns is kept (tests/test_kinematics_interference_blocks.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.tolerances import ZERO_LENGTH
from compas_ccu.work_arrays import WorkArrays, array_maker, slot_maker, take_into

__all__ = ["BlockTables", "block_tables", "sided_blocks", "work_arrays"]

#: The work arrays of the scan, kept per thread between calls (module docstring).
work_arrays = WorkArrays()


@dataclass(frozen=True)
class BlockTables:
    """The per-block arrays of one run of states that :func:`sided_blocks` gathers from.

    ``k`` states, ``p`` plates, ``J`` quad blocks of ``B`` quads, ``I`` vertex blocks of ``V``
    vertices, ``P`` hinge patterns (which of a vertex block's vertices lie on a hinge shared
    with the other plate of the pair: left out of both tests). Rows of the quad tables run over
    (state, plate, J), rows of the box tables over (state, plate, I, P).
    """

    normal: np.ndarray  # (3, k * p * J, B): the quads' unit normals, coordinate by coordinate
    offset: np.ndarray  # (k * p * J, B): their planes' offsets
    touch: np.ndarray  # (k * p * J, B): their touch tolerances, less the margin
    bounds: np.ndarray  # (2, k * p * I * P, 3): the boxes of the bound (its finite vertices)
    lo: np.ndarray  # (k * p * I * P, 3): the lower corners of the boxes (vertices off the hinge)
    hi: np.ndarray  # (k * p * I * P, 3): their upper corners (NaN if a vertex is not finite)
    masks: np.ndarray  # (P, V) bool: the vertices of each pattern on the hinge
    pattern: np.ndarray  # (p, p, I) int: the hinge pattern of plate b's block I against plate a
    margin: float  # >> the rounding of a height


def block_tables(g, quad_block, local, excluded, work=None) -> BlockTables:
    """The :class:`BlockTables` of geometry ``g`` (the arrays of the run of states), quad blocks
    ``quad_block`` (J, B), vertex blocks ``local`` (I, V) and hinge vertices ``excluded`` (p,
    p, 2n + 2) bool. Given ``work`` (a :class:`~compas_ccu.work_arrays.WorkArrays`), its
    large arrays are the kept arrays of ``work`` (overwritten by the next call), else new."""
    new = array_maker(work, "tables.")
    k, p, n = g.offset.shape
    count, size = local.shape
    margin = ZERO_LENGTH * float(np.abs(g.vertices).max())
    masks = excluded[:, :, local].reshape(-1, size)  # (p * p * I, V)
    codes = masks @ (1 << np.arange(size, dtype=np.int64))
    _, first, pattern = np.unique(codes, return_index=True, return_inverse=True)
    masks = masks[first]  # (P, V)
    # the vertices of the blocks, the vertex axis first (V, k, p, I, 3): their extremes are quick
    points = take_into(g.vertices, local, 2, new("points", (k, p, count, size, 3)))
    first = new("first", (size, k, p, count, 3))
    np.copyto(first, np.moveaxis(points, 3, 0))
    boxes = new("boxes", (4, k, p, count, len(masks), 3))  # bound lo, hi; lo, hi
    boxes.fill(np.nan)
    for i, mask in enumerate(masks):
        on = _off_hinge(first, np.flatnonzero(~mask), new)
        if len(on):  # the bound skips a vertex that is not finite, as the heights do
            boxes[0, :, :, :, i], boxes[1, :, :, :, i] = (
                np.fmin.reduce(on, 0),
                np.fmax.reduce(on, 0),
            )
            boxes[2, :, :, :, i], boxes[3, :, :, :, i] = on.min(axis=0), on.max(axis=0)
    rows, width = k * p * len(quad_block), quad_block.shape[1]
    normal = take_into(g.normal, quad_block, 2, new("normal", (k, p) + quad_block.shape + (3,)))
    moved = new("moved", (3, rows, width))
    np.copyto(moved.reshape(3, k, p, len(quad_block), width), np.moveaxis(normal, -1, 0))
    touch = take_into(g.touch, quad_block, 2, new("touch", (k, p) + quad_block.shape))
    return BlockTables(
        normal=moved,
        offset=take_into(g.offset, quad_block, 2, new("offset", (k, p) + quad_block.shape)).reshape(
            rows, width
        ),
        touch=np.subtract(touch, margin, out=touch).reshape(rows, width),
        bounds=boxes[:2].reshape(2, -1, 3),
        lo=boxes[2].reshape(-1, 3),
        hi=boxes[3].reshape(-1, 3),
        masks=masks,
        pattern=pattern.reshape(p, p, count),
        margin=margin,
    )


def _off_hinge(first, rows, new):
    """The vertices ``rows`` of ``first`` (V, ...): a slice if they are consecutive, else
    written to a work array of ``new``."""
    if not len(rows) or rows[-1] - rows[0] == len(rows) - 1:
        return first[rows[0] : rows[-1] + 1] if len(rows) else first[:0]
    return take_into(first, rows, 0, new("on", (len(rows),) + first.shape[1:]))


def _box_bound(t, quads, verts, new):
    """(M, B) bool twice: a vertex of the box ``verts`` (rows of the box tables) may lie above
    (below) the plane of quad ``b`` of the quad blocks ``quads`` by more than the touch tolerance
    loosened by twice the margin: its box's extreme height ``n . c - offset ± |n| . e`` does.
    ``new(name, shape, dtype)``: the arrays written (the results among them)."""
    m, b = len(quads), t.normal.shape[2]
    lo, hi = take_into(t.bounds, verts, 1, new("box", (2, m, 3)))
    c = np.add(lo, hi, out=new("c", (m, 3)))
    c *= 0.5
    e = np.subtract(hi, lo, out=new("e", (m, 3)))
    e *= 0.5
    nx, ny, nz = take_into(t.normal, quads, 1, new("normal", (3, m, b)))  # (M, B) each
    mid, half, term = new("mid", (m, b)), new("half", (m, b)), new("term", (m, b))
    np.multiply(nx, c[:, 0:1], out=mid)
    mid += np.multiply(ny, c[:, 1:2], out=term)
    mid += np.multiply(nz, c[:, 2:3], out=term)
    mid -= take_into(t.offset, quads, 0, term)
    np.multiply(np.abs(nx, out=term), e[:, 0:1], out=half)
    half += np.multiply(np.abs(ny, out=term), e[:, 1:2], out=term)
    half += np.multiply(np.abs(nz, out=term), e[:, 2:3], out=term)
    loose = take_into(t.touch, quads, 0, new("loose", (m, b)))
    loose -= t.margin
    up = np.greater(np.add(mid, half, out=term), loose, out=new("up", (m, b), bool))
    np.negative(loose, out=loose)
    return up, np.less(np.subtract(mid, half, out=term), loose, out=new("down", (m, b), bool))


def _heights(g, t, blocks, quad_block, local, new):
    """(M, B) bool twice: a vertex of the vertex blocks of ``blocks`` ((state, a, J, b, I)
    index arrays, off the hinge) above (below) the plane of quad ``b`` of their quad blocks by
    more than the touch tolerance loosened by the margin: every height, the vertex axis first
    (V, M, B), so that its extremes are quick. ``new(name, shape, dtype)``: the arrays
    written (the results among them)."""
    s, ba, bj, bb, bi = blocks
    k, p, n = g.offset.shape
    m, b, v = len(s), quad_block.shape[1], local.shape[1]
    quads = (s * p + ba) * len(quad_block) + bj
    at = take_into(local, bi, 0, new("at", (m, v), np.intp))
    at += ((s * p + bb) * (2 * n + 2))[:, None]
    x = take_into(g.vertices.reshape(-1, 3), at, 0, new("x", (m, v, 3)))  # (M, V, 3)
    on_hinge = t.masks[t.pattern[ba, bb, bi]][..., None]  # neither side (fmax, fmin skip it)
    np.copyto(x, np.nan, where=on_hinge)
    nrm = new("nrm", (m, b, 3))
    np.copyto(nrm, np.moveaxis(take_into(t.normal, quads, 1, new("normal", (3, m, b))), 0, -1))
    h = new("h", (v, m, b))
    np.matmul(x, nrm.swapaxes(1, 2), out=h.transpose(1, 0, 2))
    off = take_into(t.offset, quads, 0, new("off", (m, b)))
    limit = take_into(t.touch, quads, 0, new("limit", (m, b)))
    extreme, bound = new("extreme", (m, b)), new("bound", (m, b))
    up = np.greater(
        np.fmax.reduce(h, axis=0, out=extreme),
        np.add(off, limit, out=bound),
        out=new("up", (m, b), bool),
    )
    down = np.less(
        np.fmin.reduce(h, axis=0, out=extreme),
        np.subtract(off, limit, out=bound),
        out=new("down", (m, b), bool),
    )
    return up, down


def _both_sides(up, down, before, after):
    """(N, B) bool: for each candidate (its blocks ``before`` and ``after`` the step, rows of
    ``up`` and ``down``), a vertex above and one below a quad's plane in the state after the
    step (a crossing), or above in one state and below in the other (a pass-through)."""
    up0, down0, up1, down1 = up[before], down[before], up[after], down[after]
    return (up1 & down1) | (up0 & down1) | (down0 & up1)


def _near(g, t, blocks, box, steps, quad_block, new):
    """(R, B) bool: the centres of the quads of ``blocks`` ((state, a, J) index arrays, the
    states after the steps ``steps``) within their circumradius, the step's reach and the margin
    of the boxes ``box`` (rows of the box tables) of their vertex blocks (a new array;
    ``new(name, shape, dtype)``: the temporaries)."""
    s, ba, bj = blocks
    p, n = g.offset.shape[1:]
    r, b = len(s), quad_block.shape[1]
    at = take_into(quad_block, bj, 0, new("at", (r, b), np.intp))
    at += ((s * p + ba) * n)[:, None]  # (R, B) into (k, p, n)
    centre = take_into(g.centre.reshape(-1, 3), at, 0, new("centre", (r, b, 3)))  # (R, B, 3)
    lo = np.take(t.lo, box, axis=0)[:, None]
    hi = np.take(t.hi, box, axis=0)[:, None]
    gap, term = new("gap", (r, b, 3)), new("term", (r, b, 3))
    np.maximum(np.subtract(lo, centre, out=gap), 0.0, out=gap)
    gap += np.maximum(np.subtract(centre, hi, out=term), 0.0, out=term)
    reach = np.sqrt(
        take_into(g.radius2.reshape(-1), at, 0, new("reach", (r, b))), out=new("root", (r, b))
    )
    reach += g.reach[steps][:, None]
    reach += t.margin
    distance = np.square(gap, out=gap).sum(axis=-1, out=new("distance", (r, b)))
    return np.less_equal(distance, np.square(reach, out=reach))


def sided_blocks(g, candidates, shape, quad_block, local, excluded, work=work_arrays):
    """(N,) bool: the candidate block pairs (state, a, J, b, I) of
    :func:`~compas_ccu.kinematics.interference_events.path_events` that may hold an event: for
    some quad, a vertex of the block strictly above its plane and one strictly below it (in the
    state after the step for a crossing, in either state for a pass-through), the crossing
    point or the vertex near the quad. Only these need the full tests: the others have none.

    Each block's bound and heights are computed once for both steps it belongs to, and compared
    with the touch tolerance loosened by far more than their rounding, so no block with an event
    is left out whatever the order of the arithmetic (module docstring). The temporaries are
    the kept arrays of ``work`` (:data:`work_arrays`; None: new ones); the result is new."""
    ks, a, jb, b, ib = candidates
    live = np.zeros(len(ks), dtype=bool)
    if not len(ks):
        return live
    t = block_tables(g, quad_block, local, excluded, work=work)
    shape = (shape[0] + 1,) + shape[1:]  # (k, p, J, p, I): the blocks in every state
    before = np.ravel_multi_index((ks, a, jb, b, ib), shape)
    after = np.ravel_multi_index((ks + 1, a, jb, b, ib), shape)
    needed = np.zeros(int(np.prod(shape)), dtype=bool)
    needed[before] = needed[after] = True
    blocks = np.flatnonzero(needed)
    # the row of each block (read only at the blocks: the rest is left as it was)
    where = array_maker(work, "scan.")("where", len(needed), np.intp)
    where[blocks] = np.arange(len(blocks))
    before, after = where[before], where[after]
    s, ba, bj, bb, bi = np.unravel_index(blocks, shape)
    p, count_j, count_i = shape[1], shape[2], shape[4]
    quads = (s * p + ba) * count_j + bj  # rows of the quad tables
    box = ((s * p + bb) * count_i + bi) * len(t.masks) + t.pattern[ba, bb, bi]  # of the boxes
    # 1. the box bound, 2. the heights of the blocks of the candidate pairs it keeps
    bound = _box_bound(t, quads, box, slot_maker(work))
    rows = np.flatnonzero(_both_sides(*bound, before, after).any(axis=1))
    if not len(rows):
        return live
    kept = np.unique(np.concatenate([before[rows], after[rows]]))
    up = np.zeros((len(blocks), quad_block.shape[1]), dtype=bool)
    down = np.zeros_like(up)
    up[kept], down[kept] = _heights(
        g, t, (s[kept], ba[kept], bj[kept], bb[kept], bi[kept]), quad_block, local, slot_maker(work)
    )
    sided = _both_sides(up, down, before[rows], after[rows])  # (R, B)
    # and near the quad: a crossing point (on an edge of the block's vertices off the hinge)
    # within the quad's circumradius of its centre, a vertex passing through within that and
    # the step's reach (in the state after the step): the centre within that of their box
    block = after[rows]
    steps = ks[rows]
    sided &= _near(
        g, t, (s[block], ba[block], bj[block]), box[block], steps, quad_block, slot_maker(work)
    )
    live[rows] = sided.any(axis=1)
    return live
