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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.tolerances import ZERO_LENGTH

__all__ = ["BlockTables", "block_tables", "sided_blocks"]


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


def block_tables(g, quad_block, local, excluded) -> BlockTables:
    """The :class:`BlockTables` of geometry ``g`` (the arrays of the run of states), quad blocks
    ``quad_block`` (J, B), vertex blocks ``local`` (I, V) and hinge vertices ``excluded`` (p,
    p, 2n + 2) bool."""
    k, p, n = g.offset.shape
    margin = ZERO_LENGTH * float(np.abs(g.vertices).max())
    masks = excluded[:, :, local].reshape(-1, local.shape[1])  # (p * p * I, V)
    codes = masks @ (1 << np.arange(local.shape[1], dtype=np.int64))
    _, first, pattern = np.unique(codes, return_index=True, return_inverse=True)
    masks = masks[first]  # (P, V)
    points = g.vertices[:, :, local]  # (k, p, I, V, 3)
    boxes = np.full((4, k, p, len(local), len(masks), 3), np.nan)  # bound lo, hi; lo, hi
    for i, mask in enumerate(masks):
        on = points[:, :, :, ~mask]
        if on.shape[3]:  # the bound skips a vertex that is not finite, as the heights do
            boxes[0, :, :, :, i], boxes[1, :, :, :, i] = (
                np.fmin.reduce(on, 3),
                np.fmax.reduce(on, 3),
            )
            boxes[2, :, :, :, i], boxes[3, :, :, :, i] = on.min(axis=3), on.max(axis=3)
    normal = g.normal[:, :, quad_block]  # (k, p, J, B, 3)
    return BlockTables(
        normal=np.moveaxis(normal, -1, 0).reshape(3, -1, quad_block.shape[1]),
        offset=g.offset[:, :, quad_block].reshape(-1, quad_block.shape[1]),
        touch=(g.touch[:, :, quad_block] - margin).reshape(-1, quad_block.shape[1]),
        bounds=boxes[:2].reshape(2, -1, 3),
        lo=boxes[2].reshape(-1, 3),
        hi=boxes[3].reshape(-1, 3),
        masks=masks,
        pattern=pattern.reshape(p, p, len(local)),
        margin=margin,
    )


def _box_bound(t, quads, verts):
    """(M, B) bool twice: a vertex of the box ``verts`` (rows of the box tables) may lie above
    (below) the plane of quad ``b`` of the quad blocks ``quads`` by more than the touch tolerance
    loosened by twice the margin: its box's extreme height ``n . c - offset ± |n| . e`` does."""
    lo, hi = np.take(t.bounds, verts, axis=1)
    c, e = 0.5 * (lo + hi), 0.5 * (hi - lo)
    nx, ny, nz = np.take(t.normal, quads, axis=1)  # (M, B) each
    mid = nx * c[:, 0:1] + ny * c[:, 1:2] + nz * c[:, 2:3] - np.take(t.offset, quads, axis=0)
    half = np.abs(nx) * e[:, 0:1] + np.abs(ny) * e[:, 1:2] + np.abs(nz) * e[:, 2:3]
    loose = np.take(t.touch, quads, axis=0) - t.margin
    return mid + half > loose, mid - half < -loose


def _heights(g, t, blocks, quad_block, local):
    """(M, B) bool twice: a vertex of the vertex blocks of ``blocks`` ((state, a, J, b, I)
    index arrays, off the hinge) above (below) the plane of quad ``b`` of their quad blocks by
    more than the touch tolerance loosened by the margin: every height, the vertex axis first
    (V, M, B), so that its extremes are quick."""
    s, ba, bj, bb, bi = blocks
    k, p, n = g.offset.shape
    quads = (s * p + ba) * len(quad_block) + bj
    at = (s * p + bb)[:, None] * (2 * n + 2) + local[bi]
    x = np.take(g.vertices.reshape(-1, 3), at, axis=0)  # (M, V, 3)
    x[t.masks[t.pattern[ba, bb, bi]]] = np.nan  # on the hinge: neither side (fmax, fmin skip it)
    nx, ny, nz = np.take(t.normal, quads, axis=1)
    nrm = np.stack([nx, ny, nz], axis=-1)  # (M, B, 3)
    h = np.empty((x.shape[1], len(s), quad_block.shape[1]))
    np.matmul(x, nrm.swapaxes(1, 2), out=h.transpose(1, 0, 2))
    off = np.take(t.offset, quads, axis=0)
    limit = np.take(t.touch, quads, axis=0)
    return np.fmax.reduce(h, axis=0) > off + limit, np.fmin.reduce(h, axis=0) < off - limit


def _both_sides(up, down, before, after):
    """(N, B) bool: for each candidate (its blocks ``before`` and ``after`` the step, rows of
    ``up`` and ``down``), a vertex above and one below a quad's plane in the state after the
    step (a crossing), or above in one state and below in the other (a pass-through)."""
    up0, down0, up1, down1 = up[before], down[before], up[after], down[after]
    return (up1 & down1) | (up0 & down1) | (down0 & up1)


def _near(g, t, blocks, box, steps, quad_block):
    """(R, B) bool: the centres of the quads of ``blocks`` ((state, a, J) index arrays, the
    states after the steps ``steps``) within their circumradius, the step's reach and the margin
    of the boxes ``box`` (rows of the box tables) of their vertex blocks."""
    s, ba, bj = blocks
    p, n = g.offset.shape[1:]
    at = (s * p + ba)[:, None] * n + quad_block[bj]  # (R, B) into (k, p, n)
    centre = np.take(g.centre.reshape(-1, 3), at, axis=0)  # (R, B, 3)
    lo = np.take(t.lo, box, axis=0)[:, None]
    hi = np.take(t.hi, box, axis=0)[:, None]
    gap = np.maximum(lo - centre, 0.0) + np.maximum(centre - hi, 0.0)
    reach = np.sqrt(np.take(g.radius2, at)) + g.reach[steps][:, None] + t.margin
    return (gap**2).sum(axis=-1) <= reach**2


def sided_blocks(g, candidates, shape, quad_block, local, excluded):
    """(N,) bool: the candidate block pairs (state, a, J, b, I) of
    :func:`~compas_ccu.kinematics.interference_events.path_events` that may hold an event: for
    some quad, a vertex of the block strictly above its plane and one strictly below it (in the
    state after the step for a crossing, in either state for a pass-through), the crossing
    point or the vertex near the quad. Only these need the full tests: the others have none.

    Each block's bound and heights are computed once for both steps it belongs to, and compared
    with the touch tolerance loosened by far more than their rounding, so no block with an event
    is left out whatever the order of the arithmetic (module docstring)."""
    ks, a, jb, b, ib = candidates
    live = np.zeros(len(ks), dtype=bool)
    if not len(ks):
        return live
    t = block_tables(g, quad_block, local, excluded)
    shape = (shape[0] + 1,) + shape[1:]  # (k, p, J, p, I): the blocks in every state
    before = np.ravel_multi_index((ks, a, jb, b, ib), shape)
    after = np.ravel_multi_index((ks + 1, a, jb, b, ib), shape)
    needed = np.zeros(int(np.prod(shape)), dtype=bool)
    needed[before] = needed[after] = True
    blocks = np.flatnonzero(needed)
    where = np.zeros(len(needed), dtype=np.intp)
    where[blocks] = np.arange(len(blocks))
    before, after = where[before], where[after]
    s, ba, bj, bb, bi = np.unravel_index(blocks, shape)
    p, count_j, count_i = shape[1], shape[2], shape[4]
    quads = (s * p + ba) * count_j + bj  # rows of the quad tables
    box = ((s * p + bb) * count_i + bi) * len(t.masks) + t.pattern[ba, bb, bi]  # of the boxes
    # 1. the box bound, 2. the heights of the blocks of the candidate pairs it keeps
    rows = np.flatnonzero(_both_sides(*_box_bound(t, quads, box), before, after).any(axis=1))
    if not len(rows):
        return live
    kept = np.unique(np.concatenate([before[rows], after[rows]]))
    up = np.zeros((len(blocks), quad_block.shape[1]), dtype=bool)
    down = np.zeros_like(up)
    up[kept], down[kept] = _heights(
        g, t, (s[kept], ba[kept], bj[kept], bb[kept], bi[kept]), quad_block, local
    )
    sided = _both_sides(up, down, before[rows], after[rows])  # (R, B)
    # and near the quad: a crossing point (on an edge of the block's vertices off the hinge)
    # within the quad's circumradius of its centre, a vertex passing through within that and
    # the step's reach (in the state after the step): the centre within that of their box
    block = after[rows]
    sided &= _near(g, t, (s[block], ba[block], bj[block]), box[block], ks[rows], quad_block)
    live[rows] = sided.any(axis=1)
    return live
