"""Interpenetration of thick plates: penetration depth, clearance and crossings.

A thick plate is the union of its quad *cells*: cell ``j`` is bounded by the two offset planes
of quad ``j`` (``|d| ≤ t/2`` along the quad normal), the two ruling-side planes (through ruling
``j`` and its offset vector ν_j, and the same for ``j + 1``) and the planes through the
crease-side and far-side edges that contain the quad normal. For another plate's face vertices
the test gives

* the **penetration depth** ``t/2 - |d|`` of every vertex that lies inside a cell (two solids
  that touch along a hinge or lie face on face in the flat stack have depth 0, not > 0);
* the **clearance** ``|d| - t/2`` of every vertex whose foot lies on the cell (over the plate);
* a **crossing**: a ruling of the other plate whose ends lie on opposite sides of a cell's mid
  plane with the crossing point inside the cell's footprint (plates that pass through each other
  without a vertex inside).

Per ordered plate pair and state the worst contact is kept: the largest depth, or without
penetration the smallest clearance, and its vertex (the lowest vertex number on a tie). Plate
pairs whose bounding boxes are further apart than ``reach`` are skipped, and a smallest gap
larger than ``reach`` is no contact (clearance inf): the clearance is measured within the reach.

**Broad phase.** The pairs whose boxes are further apart than ``reach`` are found without
testing all ``p (p - 1)`` pairs: per state the plates' axis-aligned boxes, widened by half the
reach on every side, are sorted along one axis and swept, and only the overlapping pairs go on
(:mod:`compas_ccu.thickness.broad_phase`). The test
that keeps a pair is the one the brute force applies to every pair, so no pair is lost; the
work per state is O(p log p) plus the overlapping pairs, which in a deployed state are the
neighbours of each plate (in the flat-folded stack: the plates within the reach above and
below). The states are checked in chunks of about :data:`CHUNK_CELLS` cells.

**Candidate search** (``method="cells"``, the default). Testing every vertex against every cell
costs O(n²) per pair while a vertex lies over one or two cells; so the cells of a plate are
grouped in blocks of ``CELLS`` consecutive cells and the face vertices of a plate in blocks of
``RULINGS`` consecutive rulings (both rows, both faces: the vertices and the rulings between
them), and the exact tests run only on block pairs that can meet. What a block pair can miss:

* *What a cell accepts.* The lateral test accepts, at height ``h`` over the cell's mid plane,
  the quadrilateral cut from that plane by the four lateral half-spaces (each moved out by
  ``tol``). Every plane keeps its direction in the cut, so the cut's corners lie on the four
  lines where adjacent lateral planes meet, ``X(h) = X(0) + h w``, and every vertex of the cut,
  even where the two side lines cross, lies on a segment between two such corners. A vertex
  whose gap counts (``|d| - t/2 <= reach``) has ``|h| <= t/2 + reach``, so it lies in the convex
  hull of the eight points ``X(±(t/2 + reach))`` of the cell (:func:`_cell_hulls`; a corner line
  parallel to the mid plane gives infinite points: that cell meets everything). A crossing
  point lies on the mid plane (``h = 0`` up to round-off) inside the footprint, so in the same
  hull, and on its ruling, so in the hull of the ruling block's vertices.
* *Blocks.* A cell block is boxed in the frame of its middle cell around the hulls of its
  cells, a ruling block in the frame of its plate's middle cell around its vertices (both
  widened by ``1e-9`` of the coordinates plus ``tol`` for round-off). Along each plate the
  blocks form a binary tree whose nodes are boxed around their children's boxes; for every pair
  and state a walk from the two roots keeps the node pairs whose boxes overlap (the separating
  axis test on the six face axes) down to the leaf blocks. Two plates joined by a hinge leave
  out its row of vertices and the crossing test, so for them the leaf box of the ruling
  block's other row stands in. No accepted vertex, counted gap or crossing is outside both
  boxes of its block pair, nor of any node pair above it, so none is lost: every contact within
  the reach, and every crossing at any distance, is found.
* *The same numbers.* On the remaining block pairs the heights are the same BLAS matrix
  products as in the brute force (one product of the ``4 RULINGS`` vertices with the ``5 CELLS``
  plane normals per block pair: BLAS sums the three terms of every entry the same way whatever
  the shape of the product, which the tests check) minus the same plane offsets, and the
  tests, minima and crossing points are the brute force's element-wise operations. The results
  equal those of ``method="all"`` (the brute force, kept as :func:`_contacts_all`) bit for bit;
  the tests compare the two on many layouts. (Plates of a single cell go to the brute force:
  their heights are matrix-vector products, which BLAS rounds differently.)

The work is linear in the segments: a block meets a bounded number of blocks of every plate
within the reach, and the walk tests a bounded number of node pairs per kept pair on every
level (docs/benchmarks.md: the vault from 32 to 512 segments). A k-d tree over balls around the
blocks, tried first, keeps pairs up to the plate width plus the reach apart along the strip:
their number grows with the square of the segments.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import cross3, norm3, unit3
from compas_ccu.thickness.broad_phase import (
    PairTable,
    box_pairs,
    candidate_pairs,
    pair_table,
    plate_boxes,
)
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "Contact",
    "PairTable",
    "pair_table",
    "plate_boxes",
    "box_pairs",
    "candidate_pairs",
    "Blocks",
    "plate_blocks",
    "block_pairs",
    "Found",
    "exact_tests",
    "plate_contacts",
    "point_gaps",
]


def _dot(a, b):
    return np.einsum("...i,...i", a, b)


class Contact(NamedTuple):
    """Worst contact between one ordered pair of plates in one state.

    ``depth`` > 0 means interpenetration (m); ``clearance`` is the smallest gap of a vertex over
    the other plate (inf if none lies over it); ``crossing`` is True if a ruling passes through.
    ``vertex`` is the index (in plate ``b``'s face vertices, ``0 .. 4n + 3``: lower face then
    upper face) of the deepest or closest vertex, ``point`` its coordinates.
    """

    depth: float
    clearance: float
    crossing: bool
    vertex: int
    point: np.ndarray


def _cells(mid_near, mid_far, offsets):
    """Half-space description of the cells of plates (..., n cells)."""
    a, b = mid_near[..., :-1, :], mid_near[..., 1:, :]
    c, d = mid_far[..., 1:, :], mid_far[..., :-1, :]
    normal = unit3(cross3(c - a, d - b))
    ruling = unit3(mid_far - mid_near)
    side = unit3(cross3(ruling, offsets))  # plane of ruling j and ν_j
    # orient the side planes so that the cell is on their positive side
    centre = 0.25 * (a + b + c + d)
    s0 = side[..., :-1, :]
    s0 = s0 * np.sign(_dot(centre - a, s0))[..., None]
    s1 = side[..., 1:, :]
    s1 = s1 * np.sign(_dot(centre - b, s1))[..., None]
    e_near = unit3(cross3(normal, b - a))
    e_near = e_near * np.sign(_dot(centre - a, e_near))[..., None]
    e_far = unit3(cross3(normal, c - d))
    e_far = e_far * np.sign(_dot(centre - d, e_far))[..., None]
    return centre, normal, (a, s0), (b, s1), (a, e_near), (d, e_far)


def _heights(points, base, normal):
    """(K, P, n) signed distances ``(p - base_j) . normal_j`` of points (K, P, 3) from the
    planes (K, n, 3): one batched matrix product (BLAS) instead of a (K, P, n, 3) temporary."""
    return points @ np.swapaxes(normal, -1, -2) - _dot(base, normal)[..., None, :]


def _lateral(points, cells, tol):
    """(..., P, n) True where a point's foot lies inside a cell's footprint."""
    _, _, *planes = cells
    inside = None
    for base, normal in planes:
        ok = _heights(points, base, normal) >= -tol
        inside = ok if inside is None else inside & ok
    return inside


def _cell_hulls(cells, tol, height):
    """(..., n, 8, 3) points whose convex hull holds every point that the lateral test of a cell
    accepts at a distance of up to ``height`` from the cell's mid plane (module docstring).

    In the planes parallel to the mid plane each lateral plane leaves a line of fixed direction;
    the accepted set is bounded by the four corners where adjacent lines meet if, along each
    line, its two neighbours bound it from opposite sides. Where that fails, or a corner line
    never meets those planes (a degenerate cell), the points are infinite.
    """
    centre, normal, (a, s0), (b, s1), (_, e_near), (d, e_far) = cells
    near, far, side0, side1 = (a, e_near), (d, e_far), (a, s0), (b, s1)
    oc = _dot(centre, normal)[..., None]
    out = []
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for (ba, na), (bb, nb) in ((near, side0), (side0, far), (far, side1), (side1, near)):
            oa = _dot(ba, na)[..., None] - tol  # the lateral half-spaces, moved out by tol
            ob = _dot(bb, nb)[..., None] - tol
            axis = cross3(na, nb)
            det = _dot(normal, axis)[..., None]
            x0 = (oa * cross3(nb, normal) + ob * cross3(normal, na) + oc * axis) / det
            out += [x0 - height * axis / det, x0 + height * axis / det]
    out = np.stack(out, axis=-2)
    bounded = np.ones(out.shape[:-2], dtype=bool)
    for (_, line), (_, one), (_, other) in (
        (near, side0, side1),
        (far, side0, side1),
        (side0, near, far),
        (side1, near, far),
    ):
        u = cross3(normal, line)  # the line's direction in the planes parallel to the mid plane
        bounded &= _dot(one, u) * _dot(other, u) < 0.0
    out[~bounded] = np.inf
    return out


def _frames(mid_near, normal, cell):
    """(k, p, c, 3, 3) orthonormal frames (columns: edge, ruling side, normal) of cells
    ``cell`` (c,) of every plate."""
    t = mid_near[:, :, cell + 1] - mid_near[:, :, cell]  # the crease-side edge b - a
    nrm = normal[:, :, cell]
    t = unit3(t - _dot(t, nrm)[..., None] * nrm)
    return np.stack([t, cross3(nrm, t), nrm], axis=-1)


def _box(points, axes, tol):
    """Oriented boxes around point sets (..., s, 3) in the frames ``axes`` (..., 3, 3): centres
    (..., 3), the axes and the half-extents (..., 3), widened for round-off (inf where a point
    is not finite)."""
    x, y, z = (points[..., i] for i in range(3))
    lo, hi = [], []
    with np.errstate(invalid="ignore", over="ignore"):
        for c in range(3):  # coordinates along axis c
            a = axes[..., c]
            along = x * a[..., 0, None] + y * a[..., 1, None] + z * a[..., 2, None]
            lo.append(along.min(axis=-1))
            hi.append(along.max(axis=-1))
        lo, hi = np.stack(lo, axis=-1), np.stack(hi, axis=-1)
        mid = 0.5 * (lo + hi)
        half = 0.5 * (hi - lo) + 1e-9 * (np.abs(lo) + np.abs(hi)) + tol
    bad = ~np.isfinite(half).all(axis=-1)
    mid[bad], half[bad] = 0.0, np.inf
    centre = np.einsum("...ij,...j->...i", axes, mid)
    return centre, axes, half


def _pack(box):
    """Boxes as columns ``(centre, axes (row by row), half-extents)`` of 15 numbers: (15, ...),
    so that the separating-axis test runs on contiguous rows."""
    centre, axes, half = box
    rows = np.concatenate([centre, axes.reshape(*axes.shape[:-2], 9), half], axis=-1)
    return np.moveaxis(rows, -1, 0)


def _separated(box_a, box_b):
    """(N,) bool: packed boxes ``a`` and ``b`` (15, N) are disjoint by a face axis of either
    (the separating axis test on those six axes; False where undecided)."""
    d = box_b[:3] - box_a[:3]
    a, b = box_a[3:12], box_b[3:12]  # axes[row, column] at 3 row + column
    ha, hb = box_a[12:], box_b[12:]
    # |a_i . b_j| and the projections of d on the axes a_i and b_j
    r = [
        [np.abs(a[i] * b[j] + a[3 + i] * b[3 + j] + a[6 + i] * b[6 + j]) for j in range(3)]
        for i in range(3)
    ]
    da = [np.abs(a[i] * d[0] + a[3 + i] * d[1] + a[6 + i] * d[2]) for i in range(3)]
    db = [np.abs(b[j] * d[0] + b[3 + j] * d[1] + b[6 + j] * d[2]) for j in range(3)]
    with np.errstate(invalid="ignore"):
        slack = 1e-9 * (norm3(d.T) + ha.sum(axis=0) + hb.sum(axis=0))
        out = np.zeros(d.shape[1], dtype=bool)
        for i in range(3):
            out |= da[i] > ha[i] + r[i][0] * hb[0] + r[i][1] * hb[1] + r[i][2] * hb[2] + slack
        for j in range(3):
            out |= db[j] > hb[j] + r[0][j] * ha[0] + r[1][j] * ha[1] + r[2][j] * ha[2] + slack
    return out


def _blocks(count, size):
    """(blocks, size) indices ``0 .. count - 1`` in consecutive blocks (the last one padded
    with its last index)."""
    blocks = -(-count // size)
    return np.minimum(np.arange(blocks * size).reshape(blocks, size), count - 1)


def _corners(box):
    """(..., 8, 3) corners of boxes."""
    centre, axes, half = box
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    with np.errstate(invalid="ignore"):
        offsets = np.einsum("...ij,...cj->...ci", axes, signs * half[..., None, :])
    return centre[..., None, :] + offsets


def _tree(box, middle, frame, tol):
    """Boxes of a binary tree over the leaf boxes of every plate (leaves along axis 2).

    ``middle(level, node)`` is the cell whose frame a node takes, ``frame(cells)`` the frames
    of cells; a parent's box holds the corners of its children's boxes. Leaves are padded to a
    power of two with empty ones. Returns the levels from the leaves up, each the packed boxes
    (15, states x plates x nodes) and which nodes are not padding.
    """
    count = box[0].shape[2]
    size = 1 << max(count - 1, 0).bit_length()
    pad = size - count
    valid = np.r_[np.ones(count, dtype=bool), np.zeros(pad, dtype=bool)]
    box = tuple(np.concatenate([x, np.repeat(x[:, :, -1:], pad, axis=2)], axis=2) for x in box)
    levels = [(box, valid)]
    level = 0
    while size > 1:
        size //= 2
        level += 1
        corners = _corners(box)  # (k, p, 2 size, 8, 3)
        pair = valid.reshape(size, 2)
        # an empty child takes its sibling's corners (a parent of two empty ones is empty)
        corners = corners.reshape(*corners.shape[:2], size, 2, 8, 3)
        corners = np.where(pair[:, :, None, None], corners, corners[:, :, :, ::-1])
        corners = corners.reshape(*corners.shape[:2], size, 16, 3)
        box = _box(corners, frame(middle(level, np.arange(size))), tol)
        valid = pair.any(axis=1)
        levels.append((box, valid))
    return [(_pack(box).reshape(15, -1), valid) for box, valid in levels]


#: Cells per cell block and rulings per vertex block of the candidate search.
CELLS = 4
RULINGS = 8
#: Block pairs per batch of the exact tests (bounds the temporaries: ~1 MB per 100 pairs).
BATCH = 512
#: Cells (states x plates x cells) whose blocks are boxed at once: the states are checked in
#: chunks of about this many cells, so the temporaries stay small whatever the plate count.
CHUNK_CELLS = 16384


class Blocks(NamedTuple):
    """The blocks of cells and of face vertices of every plate in a chunk of states, their
    boxes and trees (:func:`plate_blocks`). Flat arrays run over (state, plate, block)."""

    plates: int  # p
    cell_block: np.ndarray  # (J, CELLS) cells of every cell block
    local: np.ndarray  # (I, 4 RULINGS) face vertices of every vertex block
    planes: list  # the four lateral planes (base, normal), each (k, p, n, 3)
    normals: np.ndarray  # (k p J, 5 CELLS, 3) plane normals of every cell block
    offsets: np.ndarray  # (k p J, 5, CELLS, 1) and their offsets
    points: np.ndarray  # (k p I, 4 RULINGS, 3) the vertices of every vertex block
    cell_tree: list  # levels of packed boxes over the cell blocks, leaves first
    ruling_tree: list  # the same over the vertex blocks
    rows: np.ndarray  # (15, 3 k p I) packed leaf boxes: both rows, near rows, far rows
    row_box: np.ndarray  # (H + 1,) which leaf box a hinged pair meets (-1: none)
    skip: np.ndarray  # (H + 1, I, 4 RULINGS) bool: hinge vertices left out, per hinge


def plate_blocks(mid_near, mid_far, offsets, faces, table: PairTable, tol, height) -> Blocks:
    """Blocks, boxes and trees of the candidate search (module docstring).

    Parameters
    ----------
    mid_near, mid_far, offsets : (k, p, n + 1, 3) float
    faces : (k, p, 2, 2n + 2, 3) float
    table : PairTable
    tol : float
        Lateral tolerance, m.
    height : float
        Largest distance from a cell's mid plane that counts (``t/2 + reach``), m.
    """
    k, p, m = mid_near.shape[:3]
    n = m - 1
    # cells and their five planes (mid plane, then the lateral ones), every state and plate
    cells = _cells(mid_near, mid_far, offsets)
    centre, normal, planes = cells[0], cells[1], cells[2:]
    normals = np.stack([normal] + [nrm for _, nrm in planes], axis=-2)  # (k, p, n, 5, 3)
    plane_offsets = np.stack(
        [_dot(centre, normal)] + [_dot(base, nrm) for base, nrm in planes], axis=-1
    )  # (k, p, n, 5)

    # cell blocks: a box (in the frame of the middle cell) around the hull of what their
    # lateral tests accept up to the reach
    cell_block = _blocks(n, CELLS)  # (J, CELLS)
    nj = len(cell_block)
    hull = _cell_hulls(cells, tol, height)[:, :, cell_block].reshape(k, p, nj, -1, 3)
    cell_box = _box(hull, _frames(mid_near, normal, cell_block[:, CELLS // 2]), tol)
    # the five planes of the cells of every block: normals (plane, cell) and offsets
    block_normals = normals[:, :, cell_block].swapaxes(3, 4).reshape(-1, 5 * CELLS, 3)
    block_offsets = plane_offsets[:, :, cell_block].swapaxes(3, 4)[..., None]

    # vertex blocks: RULINGS consecutive rulings of a plate, both faces (lower / upper face,
    # near / far row, then the ruling): the vertices and the rulings between them (vertex
    # numbers grow along a block); a box in the frame of the middle cell
    column = _blocks(m, RULINGS)  # (I, RULINGS)
    ni = len(column)
    nv = 2 * faces.shape[3]
    local = np.arange(2)[:, None, None] * (2 * m) + np.arange(2)[None, :, None] * m
    local = (local[None] + column[:, None, None, :]).reshape(ni, 4 * RULINGS)
    points = faces.reshape(k, p, nv, 3)
    block_points = points[:, :, local]  # (k, p, I, 4 RULINGS, 3)
    frames = _frames(mid_near, normal, np.minimum(column[:, RULINGS // 2], n - 1))
    vertex_box = _box(block_points, frames, tol)
    # a pair whose one row is all on their hinge meets the other row only (no crossing test):
    # boxes of the near rows and of the far rows too, and which box each hinge meets
    rows = local.reshape(ni, 2, 2, RULINGS)
    boxes = [vertex_box] + [
        _box(points[:, :, rows[:, :, r].reshape(ni, -1)], frames, tol) for r in (0, 1)
    ]
    boxes = [np.stack(parts).reshape(-1, *parts[0].shape[3:]) for parts in zip(*boxes)]
    masks = table.masks
    on_hinge = [masks[:, rows[:, :, r].reshape(-1)].all(axis=1) for r in (0, 1)]
    row_box = np.select([on_hinge[0] & on_hinge[1], on_hinge[0], on_hinge[1]], [-1, 2, 1], 0)

    def frame(cells):
        return _frames(mid_near, normal, np.minimum(cells, n - 1))

    def middle(size):  # the middle cell of node ``node`` of ``level`` over blocks of ``size``
        return lambda level, node: ((2 * node + 1) << level) * size // 2

    return Blocks(
        plates=p,
        cell_block=cell_block,
        local=local,
        planes=planes,
        normals=block_normals,
        offsets=block_offsets.reshape(-1, 5, CELLS, 1),
        points=block_points.reshape(-1, 4 * RULINGS, 3),
        cell_tree=_tree(cell_box, middle(CELLS), frame, tol),
        ruling_tree=_tree(vertex_box, middle(RULINGS), frame, tol),
        rows=_pack(tuple(boxes)).reshape(15, -1),
        row_box=row_box,
        skip=masks[:, local],
    )


def block_pairs(blocks: Blocks, table: PairTable, state, pair):
    """The block pairs that can meet: a walk down the two trees of boxes of every candidate
    pair and state, from their roots to the leaf blocks, keeping the node pairs whose boxes
    overlap.

    Parameters
    ----------
    blocks : Blocks
    table : PairTable
    state, pair : (N,) int
        Candidate (state, pair) of the chunk (:func:`candidate_pairs`).

    Returns
    -------
    pair : (M,) int
    cell_id, ruling_id : (M,) int
        Flat (state, plate, block) indices of the cell block of ``a`` and the vertex block of
        ``b``.
    """
    p = blocks.plates
    cell_tree, ruling_tree = blocks.cell_tree, blocks.ruling_tree
    nj, ni = len(cell_tree[0][1]), len(ruling_tree[0][1])  # leaves, with the padding
    row_box = blocks.row_box[table.hinge]  # -1 -> the last row: no hinge, both rows
    keep = row_box[pair] >= 0
    qq = pair[keep]
    node_a = state[keep] * p + table.pairs[qq, 0]  # (state, plate, node) at the current levels
    node_b = state[keep] * p + table.pairs[qq, 1]
    la, lb = len(cell_tree) - 1, len(ruling_tree) - 1
    rows = blocks.rows
    kpi = rows.shape[1] // 3
    while True:
        (box_a, valid_a), (box_b, valid_b) = cell_tree[la], ruling_tree[lb]
        keep = valid_a[node_a % len(valid_a)] & valid_b[node_b % len(valid_b)]  # not padding
        qq, node_a, node_b = qq[keep], node_a[keep], node_b[keep]
        if la == 0 and lb == 0:  # the leaves: for hinged pairs, the box of the free row
            plate_b, ii = np.divmod(node_b, ni)
            b_of = rows.take(row_box[qq] * kpi + plate_b * len(blocks.local) + ii, axis=1)
        else:
            b_of = box_b.take(node_b, axis=1)
        keep = ~_separated(box_a.take(node_a, axis=1), b_of)
        qq, node_a, node_b = qq[keep], node_a[keep], node_b[keep]
        if la == 0 and lb == 0:
            break
        split_a, split_b = la >= lb, lb >= la  # the deeper tree first, both if level
        fan = (2 if split_a else 1) * (2 if split_b else 1)
        qq, node_a, node_b = (np.repeat(x, fan) for x in (qq, node_a, node_b))
        child = np.tile(np.arange(fan), len(qq) // fan)
        if split_a:
            node_a = 2 * node_a + child % 2
        if split_b:
            node_b = 2 * node_b + (child // 2 if split_a else child)
        la, lb = la - split_a, lb - split_b
    plate_a, jj = np.divmod(node_a, nj)
    plate_b, ii = np.divmod(node_b, ni)
    cell_id = plate_a * len(blocks.cell_block) + jj  # (state, plate, block) without padding
    ruling_id = plate_b * len(blocks.local) + ii
    return qq, cell_id, ruling_id


class Found(NamedTuple):
    """What the exact tests of one batch of block pairs found."""

    key: np.ndarray  # (N,) state * pairs + pair of every gap within the reach
    vertex: np.ndarray  # (N,) the vertex of b of the smallest gap of its block pair
    gap: np.ndarray  # (N,) that gap, m
    crossing: np.ndarray  # (C,) state * pairs + pair of every crossing found


def exact_tests(blocks: Blocks, table: PairTable, pair, cell_id, ruling_id, half, reach, tol):
    """The brute force's exact tests on one batch of block pairs (module docstring).

    Parameters
    ----------
    blocks : Blocks
    table : PairTable
    pair, cell_id, ruling_id : (N,) int
        From :func:`block_pairs`.
    half, reach, tol : float
        Half the thickness, the contact reach and the lateral tolerance, m.

    Returns
    -------
    Found
        Keys over the chunk's states (``state * len(table.pairs) + pair``).
    """
    p, npairs = blocks.plates, len(table.pairs)
    ni, nj = len(blocks.local), len(blocks.cell_block)
    count = len(pair)
    kb, ab = np.divmod(cell_id // nj, p)  # state and plate a
    ib = ruling_id % ni
    vertices = blocks.local[ib]  # (N, 4 RULINGS)
    x = blocks.points.take(ruling_id, axis=0)  # (N, 4 RULINGS, 3)
    # heights (N, plane, cell, vertex) by the same matrix products as the brute force
    heights = blocks.normals.take(cell_id, axis=0) @ x.swapaxes(1, 2)
    heights = heights.reshape(count, 5, CELLS, 4 * RULINGS)
    heights -= blocks.offsets.take(cell_id, axis=0)
    lateral = heights[:, 1] >= -tol
    for plane in (2, 3, 4):
        lateral &= heights[:, plane] >= -tol
    hinge = table.hinge[pair]  # -1: the all-False last row of the masks
    lateral &= ~blocks.skip.reshape(-1, 4 * RULINGS).take(
        np.where(hinge < 0, len(table.masks) - 1, hinge) * ni + ib, axis=0
    )[:, None]
    # the smallest |d| - t/2 over the lateral cells: the smallest |d| (rounding is monotone)
    size = np.abs(heights[:, 0])
    size[~lateral] = np.inf
    gap = size.min(axis=1) - half
    best = gap.argmin(axis=1)  # the first of the smallest gaps: the lowest vertex number
    rows = np.arange(count)
    value = gap[rows, best]
    near = value <= reach
    keys = kb * npairs + pair
    found = Found(keys[near], vertices[rows, best][near], value[near], keys[:0])
    # crossings: a ruling of b (near row -> far row) through a's mid plane inside the cell
    test = hinge < 0
    if not test.any():
        return found
    d = heights[test, 0].reshape(-1, CELLS, 2, 2, RULINGS)  # (N, cell, face, row, ruling)
    d0, d1 = d[:, :, :, 0], d[:, :, :, 1]
    change = np.nonzero((d0 * d1) < 0.0)  # (N, cell, face, ruling)
    if not len(change[0]):
        return found
    nb, c, f, r = change
    d0, d1 = d0[change], d1[change]
    xs = x[test].reshape(-1, 2, 2, RULINGS, 3)
    x0, x1 = xs[nb, f, 0, r], xs[nb, f, 1, r]
    s = d0 / (d0 - d1)
    point = x0 + s[:, None] * (x1 - x0)
    cell = blocks.cell_block[cell_id[test] % nj][nb, c]
    ks, as_ = kb[test][nb], ab[test][nb]
    inside = np.ones(len(s), dtype=bool)
    for base, plane in blocks.planes:
        inside &= _dot(point - base[ks, as_, cell], plane[ks, as_, cell]) >= tol
    return found._replace(crossing=keys[test][nb][inside])


def _smallest(found: list, depth, clearance, crossing, where):
    """Write the smallest gap of every (state, pair) of ``found`` (the first vertex on a tie)
    and its crossings into the (k, P) arrays."""
    for f in found:
        crossing.flat[f.crossing] = True
    key = np.concatenate([f.key for f in found])
    vertex = np.concatenate([f.vertex for f in found])
    gap = np.concatenate([f.gap for f in found])
    first = np.lexsort((vertex, gap, key))
    first = first[np.r_[True, key[first][1:] != key[first][:-1]]] if len(first) else first
    value = gap[first]
    depth.flat[key[first]] = -value
    clearance.flat[key[first]] = np.where(value >= 0.0, value, 0.0)
    where.flat[key[first]] = vertex[first]


def _no_contacts(k: int, npairs: int):
    """(k, P) depth -inf, clearance inf, no crossing, vertex 0: nothing found yet."""
    depth = np.full((k, npairs), -np.inf)
    clearance = np.full((k, npairs), np.inf)
    crossing = np.zeros((k, npairs), dtype=bool)
    where = np.zeros((k, npairs), dtype=int)
    return depth, clearance, crossing, where


def _chunks(k: int, cells: int):
    """Slices of the states, about :data:`CHUNK_CELLS` cells each."""
    size = max(1, CHUNK_CELLS // max(cells, 1))
    return [slice(start, min(start + size, k)) for start in range(0, k, size)]


def plate_contacts(
    mid_near,
    mid_far,
    offsets,
    faces,
    thickness,
    *,
    pairs,
    hinged=None,
    reach=0.1,
    tol=EXACT_RELATIVE,
    method="cells",
):
    """Worst contact of every ordered plate pair in every state.

    Parameters
    ----------
    mid_near, mid_far, offsets : (k, p, n + 1, 3) float
        Mid-surface boundaries (with the crease corrections) and face-offset vectors.
    faces : (k, p, 2, 2n + 2, 3) float
        Lower and upper face vertices of every plate.
    thickness : float
    pairs : (P, 2) int or list of (int, int)
        Ordered plate pairs ``(a, b)`` to test: vertices of ``b`` against the cells of ``a``.
    hinged : list of (V,) bool or None, or dict, optional
        Per pair (a list of length P, None for a pair without a hinge) or per hinged pair (a
        dict ``{(a, b): mask}``): the vertices of ``b`` on the hinge it shares with ``a`` (both
        faces, ``V = 4n + 4``). They are left out (their mismatch is the hinge gap, reported
        apart), and so is the crossing test: two plates joined by a hinge only pass through
        each other by a negative fold angle, which the kinematics excludes.
    reach : float
        Contact reach, m: pairs whose bounding boxes are further apart than this in a state are
        skipped, and a smallest gap larger than this is no contact; both report clearance inf
        (depth -inf, vertex 0).
    tol : float
        Lateral tolerance of the footprint test, m.
    method : {"cells", "all"}
        "cells": a broad phase over the plates' boxes (:func:`box_pairs`, O(p log p) per
        state), then the exact tests only where a block of cells and a block of rulings can
        meet (module docstring), O(n) per pair; "all": every vertex against every cell of every
        pair whose boxes overlap, O(n^2) per pair (the reference). Both give the same results,
        bit for bit.

    Returns
    -------
    depth, clearance : (k, P) float
    crossing : (k, P) bool
    where : (k, P) int
        Vertex of ``b`` with the largest depth (or, without penetration, the smallest clearance).
    """
    if method not in ("cells", "all"):
        raise ValueError(f"method must be 'cells' or 'all', got {method!r}")
    k, p, m = mid_near.shape[:3]
    table = pair_table(pairs, hinged, p, 2 * faces.shape[3])
    if method == "all" or m < 3:  # one cell: its heights are matrix-vector products
        found = _contacts_all(
            mid_near, mid_far, offsets, faces, thickness, table.pairs, table, reach, tol
        )
        return _cut_off(*found, reach)
    depth, clearance, crossing, where = _no_contacts(k, len(table.pairs))
    if not (k and len(table.pairs)):
        return depth, clearance, crossing, where
    half = 0.5 * thickness
    lo, hi = plate_boxes(faces, reach)
    for states in _chunks(k, p * (m - 1)):
        state, pair = candidate_pairs(lo[states], hi[states], table, p)
        if not len(pair):
            continue
        chunk = (mid_near[states], mid_far[states], offsets[states], faces[states])
        blocks = plate_blocks(*chunk, table, tol, half + reach)
        qq, cell_id, ruling_id = block_pairs(blocks, table, state, pair)
        found = [
            exact_tests(blocks, table, qq[part], cell_id[part], ruling_id[part], half, reach, tol)
            for part in (slice(i, i + BATCH) for i in range(0, len(qq), BATCH))
        ]
        if found:
            out = (x[states] for x in (depth, clearance, crossing, where))
            _smallest(found, *out)
    return depth, clearance, crossing, where


def _cut_off(depth, clearance, crossing, where, reach):
    """A smallest gap larger than ``reach`` is no contact (as :func:`plate_contacts`)."""
    far = -depth > reach
    depth = np.where(far, -np.inf, depth)
    clearance = np.where(far, np.inf, clearance)
    where = np.where(far, 0, where)
    return depth, clearance, crossing, where


def _contacts_all(mid_near, mid_far, offsets, faces, thickness, pairs, hinged, reach, tol):
    """The brute force: every face vertex of ``b`` against every cell of ``a`` (O(n^2) per
    pair) of every pair whose boxes overlap (each pair tested on its own, no broad phase),
    without the clearance cut-off at ``reach``. The reference of the tests. ``hinged`` as
    :func:`plate_contacts` takes it, or a :class:`PairTable`."""
    k, p = mid_near.shape[:2]
    table = hinged if isinstance(hinged, PairTable) else None
    if table is None:
        table = pair_table(pairs, hinged, p, 2 * faces.shape[3])
    pairs = table.pairs
    npairs = len(pairs)
    depth = np.full((k, npairs), -np.inf)
    clearance = np.full((k, npairs), np.inf)
    crossing = np.zeros((k, npairs), dtype=bool)
    where = np.zeros((k, npairs), dtype=int)
    half = 0.5 * thickness
    lo = faces.min(axis=(2, 3)) - 0.5 * reach
    hi = faces.max(axis=(2, 3)) + 0.5 * reach
    m = mid_near.shape[2]
    for q, (pa, pb) in enumerate(pairs):
        apart = np.any((lo[:, pa] > hi[:, pb]) | (lo[:, pb] > hi[:, pa]), axis=1)
        ks = np.flatnonzero(~apart)
        if not len(ks):
            continue
        cells = _cells(mid_near[ks, pa], mid_far[ks, pa], offsets[ks, pa])
        centre, normal = cells[0], cells[1]
        pts = faces[ks, pb].reshape(len(ks), -1, 3)  # (K, P, 3)
        lateral = _lateral(pts, cells, tol)  # (K, P, n)
        skip = table.skip(q)
        if skip is not None:
            lateral &= ~skip[None, :, None]
        d = _heights(pts, centre, normal)  # (K, P, n)
        gap = np.where(lateral, np.abs(d) - half, np.inf)
        best = gap.min(axis=2)  # (K, P): most negative = deepest
        worst = best.argmin(axis=1)
        value = best[np.arange(len(ks)), worst]
        depth[ks, q] = -value
        clearance[ks, q] = np.where(value >= 0.0, value, 0.0)
        where[ks, q] = worst
        # rulings of b (both faces) crossing a's mid planes inside a cell
        for face in (0, 1) if skip is None else ():
            x0 = faces[ks, pb, face, :m]
            x1 = faces[ks, pb, face, m:]
            d0 = _heights(x0, centre, normal)
            d1 = _heights(x1, centre, normal)
            sign_change = (d0 * d1) < 0.0
            if not sign_change.any():
                continue
            with np.errstate(divide="ignore", invalid="ignore"):
                s = np.where(sign_change, d0 / (d0 - d1), 0.0)
            hit = x0[:, :, None, :] + s[..., None] * (x1 - x0)[:, :, None, :]  # (K, m, n, 3)
            inside = np.ones(sign_change.shape, dtype=bool)
            for base, nrm in cells[2:]:
                inside &= _dot(hit - base[:, None], nrm[:, None]) >= tol
            crossing[ks, q] |= (sign_change & inside).any(axis=(1, 2))
    return depth, clearance, crossing, where


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
    cells = _cells(mid_near, mid_far, offsets)
    centre, normal = cells[0], cells[1]
    lateral = _lateral(points, cells, tol)  # (k, P, n)
    d = _heights(points, centre, normal)
    return np.where(lateral, np.abs(d) - 0.5 * thickness, np.inf).min(axis=2)
