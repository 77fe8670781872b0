"""The candidate search of the collision check: the cell blocks and ruling blocks that can meet.

:func:`compas_ccu.thickness.collision.plate_contacts` with ``method="cells"`` (the default)
runs the exact tests of :mod:`compas_ccu.thickness.cells` only on the block pairs found here:
:func:`plate_blocks` (the blocks, their boxes and trees, :mod:`compas_ccu.thickness.box_trees`),
:func:`block_pairs` (the walk down the trees); the tests on a batch of block pairs:
:mod:`compas_ccu.thickness.block_tests`.

**Why no contact is lost.** Testing every vertex against every cell
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
  hull of the eight points ``X(±(t/2 + reach))`` of the cell (:func:`cell_hulls`; a corner line
  parallel to the mid plane gives infinite points: that cell meets everything; a box spans
  the hull where it spans the ends of the four segments, :func:`hull_bounds`). A crossing
  point lies on the mid plane (``h = 0`` up to round-off) inside the footprint, so in the same
  hull, and on its ruling, so in the hull of the ruling block's vertices.
* *Blocks.* A cell block is boxed in the frame of its middle cell around the hulls of its
  cells, a ruling block in the frame of its plate's middle cell around its vertices (both
  widened by ``1e-9`` of the coordinates plus ``tol`` for round-off). Along each plate the
  blocks form a binary tree whose nodes are boxed around their children's boxes; for every pair
  and state a walk from the two roots keeps the node pairs whose boxes overlap (the separating
  axis test on the six face axes) down to the leaf blocks. Two plates joined by a hinge leave
  out its row of vertices and the crossing test, so for them the tree over the ruling
  blocks' other rows stands in (three ruling trees per plate: both rows, the near rows, the
  far rows, whose leaves hold the vertices of those rows). No accepted vertex, counted gap or
  crossing is outside both boxes of its block pair, nor of any node pair above it, so none is
  lost: every contact within the reach, and every crossing at any distance, is found.
* *The same numbers.* On the remaining block pairs the heights are the same BLAS matrix
  products as in the brute force (one product of the ``4 RULINGS`` vertices with the ``5 CELLS``
  plane normals per block pair, of the ``2 RULINGS`` vertices of its free row for a hinged pair
  that meets one row only: BLAS sums the three terms of every entry the same way whatever the
  shape of the product, which the tests check). The mid planes' heights are minus the same
  offsets; a lateral test ``fl(h - offset) >= -tol`` is ``h >= accepted``, the lowest float
  that passes (:func:`compas_ccu.thickness.cells.accepted_from`: the same booleans without the
  subtractions); the minima and crossing points are the brute force's element-wise
  operations. The results equal those of ``method="all"`` (the brute force of
  :func:`plate_contacts`) bit for bit; the tests compare the two on many layouts. (Plates of a
  single cell go to the brute force: their heights are matrix-vector products, which BLAS
  rounds differently.)

The work is linear in the segments: a block meets a bounded number of blocks of every plate
within the reach, and the walk tests a bounded number of node pairs per kept pair on every
level (docs/benchmarks.md: the vault from 32 to 512 segments). A k-d tree over balls around the
blocks, tried first, keeps pairs up to the plate width plus the reach apart along the strip:
their number grows with the square of the segments.

Given ``work`` (:class:`compas_ccu.thickness.work_arrays.WorkArrays`, as
:func:`compas_ccu.thickness.collision.plate_contacts` passes it), the blocks, boxes, trees and
the walk's temporaries are written into arrays kept per thread between calls, not mapped
afresh (and faulted in) on every call: the same operations on the same operands, so the same
numbers; the blocks returned then hold arrays that the next such call overwrites.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import dot
from compas_ccu.thickness.box_trees import (
    bounded_boxes,
    box_tree,
    cell_corners,
    cell_frames,
    hull_bounds,
    index_blocks,
    point_bounds,
    separated,
)
from compas_ccu.thickness.broad_phase import PairTable
from compas_ccu.thickness.cells import accepted_from, plate_cells
from compas_ccu.thickness.work_arrays import array_maker

__all__ = [
    "CELLS",
    "RULINGS",
    "Blocks",
    "plate_blocks",
    "with_planes",
    "block_pairs",
]

#: Cells per cell block and rulings per vertex block of the candidate search.
CELLS = 4
RULINGS = 8
#: Node pairs per batch of the walk's box tests (bounds the temporaries).
WALK = 16384


class Blocks(NamedTuple):
    """The blocks of cells and of face vertices of every plate in a chunk of states, their
    boxes and trees (:func:`plate_blocks`). Flat arrays run over (state, plate, block)."""

    plates: int  # p
    cell_block: np.ndarray  # (J, CELLS) cells of every cell block
    local: np.ndarray  # (I, 4 RULINGS) face vertices of every vertex block
    planes: list  # the four lateral planes (base, normal), each (k, p, n, 3)
    normals: np.ndarray  # (k p J, 5 CELLS, 3) plane normals of every cell block
    offsets: np.ndarray  # (k p J, CELLS, 1) the mid planes' offsets
    accepted: np.ndarray  # (k p J, 4, CELLS, 1) the lowest heights the lateral tests accept
    points: np.ndarray  # (k p I, 4 RULINGS, 3) the vertices of every vertex block (these
    # four None until :func:`with_planes`)
    cell_tree: list  # levels of packed boxes over the cell blocks, leaves first
    ruling_tree: list  # the same over the vertex blocks: both rows, near rows, far rows
    row_box: np.ndarray  # (H + 1,) which ruling tree a hinged pair meets (-1: none)
    skip: np.ndarray  # (H + 1, I, 4 RULINGS) bool: hinge vertices left out, per hinge


def plate_blocks(
    mid_near,
    mid_far,
    offsets,
    faces,
    table: PairTable,
    tol,
    height,
    cells=None,
    *,
    planes=True,
    work=None,
) -> Blocks:
    """Blocks, boxes and trees of the candidate search (module docstring).

    Parameters
    ----------
    mid_near, mid_far, offsets : (k, p, n + 1, 3) float
    faces : (k, p, 2, 2n + 2, 3) float
    table : PairTable
    tol : float
        Lateral tolerance, m.
    height : float or (k, 1, 1, 1) float
        Largest distance from a cell's mid plane that counts (``t/2 + reach``; per state, a
        collision report's, :mod:`compas_ccu.thickness.report_pairs`), m.
    cells : tuple, optional
        :func:`compas_ccu.thickness.cells.plate_cells` of the plates, if already computed.
    planes : bool
        False: without the planes and points of the exact tests (``normals``, ``offsets``,
        ``accepted`` and ``points`` None), for a walk that may keep no block pair;
        :func:`with_planes` adds them.
    work : compas_ccu.thickness.work_arrays.WorkArrays, optional
        Kept work arrays for the temporaries and the boxes of the trees (then the blocks
        returned hold arrays that the next such call overwrites: for a caller that is done
        with them before); None (default): new arrays.
    """
    k, p, m = mid_near.shape[:3]
    n = m - 1
    # cells and their five planes (mid plane, then the lateral ones), every state and plate
    if cells is None:
        cells = plate_cells(mid_near, mid_far, offsets)
    normal = cells[1]

    # cell blocks: a box (in the frame of the middle cell) around the hull of what their
    # lateral tests accept up to the reach
    cell_block = index_blocks(n, CELLS)  # (J, CELLS)
    nj = len(cell_block)
    column = index_blocks(m, RULINGS)  # (I, RULINGS)
    ni = len(column)
    frame = _frames(mid_near, normal, nj, ni)
    cell_box = _cell_boxes(cells, cell_block, frame(CELLS, 0), tol, height, work)

    # vertex blocks: RULINGS consecutive rulings of a plate, both faces (lower / upper face,
    # near / far row, then the ruling): the vertices and the rulings between them (vertex
    # numbers grow along a block); a box in the frame of the middle cell
    nv = 2 * faces.shape[3]
    local = np.arange(2)[:, None, None] * (2 * m) + np.arange(2)[None, :, None] * m
    local = (local[None] + column[:, None, None, :]).reshape(ni, 4 * RULINGS)
    points = faces.reshape(k, p, nv, 3)
    frames = frame(RULINGS, 0)
    # a pair whose one row is all on their hinge meets the other row only (no crossing test):
    # boxes of the near rows and of the far rows too, and which box each hinge meets; the
    # box of both rows spans the union of their extents (the same frame)
    rows = local.reshape(ni, 2, 2, RULINGS)
    new = array_maker(work, "blocks.")
    near, far = (
        point_bounds(
            _taken(points, rows[:, :, r].reshape(ni, -1), partial(new, f"row.{r}")), frames, work
        )
        for r in (0, 1)
    )
    lo, hi = new("lo", (3, 3) + near[0].shape[1:]), new("hi", (3, 3) + near[0].shape[1:])
    for x, lower, i in ((lo, np.minimum, 0), (hi, np.maximum, 1)):  # both rows, near, far
        lower(near[i], far[i], out=x[:, 0])  # (3, 3, k, p, I)
        x[:, 1], x[:, 2] = near[i], far[i]
    masks = table.masks
    on_hinge = [masks[:, rows[:, :, r].reshape(-1)].all(axis=1) for r in (0, 1)]
    row_box = np.select([on_hinge[0] & on_hinge[1], on_hinge[0], on_hinge[1]], [-1, 2, 1], 0)
    blocks = Blocks(
        plates=p,
        cell_block=cell_block,
        local=local,
        planes=cells[2:],
        normals=None,
        offsets=None,
        accepted=None,
        points=None,
        cell_tree=box_tree(cell_box, lambda level: frame(CELLS, level), tol, _named(work, "cell")),
        ruling_tree=box_tree(
            bounded_boxes(lo, hi, frames, tol, _named(work, "ruling_leaves")),
            lambda level: frame(RULINGS, level),
            tol,
            _named(work, "ruling"),
        ),
        row_box=row_box,
        skip=masks[:, local],
    )
    return with_planes(blocks, cells, faces, tol, work) if planes else blocks


def _named(work, name):
    """``(work, prefix)`` of the arrays of ``name`` (:func:`box_tree`), or None."""
    return None if work is None else (work, f"search.{name}.")


def _cell_boxes(cells, cell_block, axes, tol, height, work=None):
    """The boxes (one tree, :func:`bounded_boxes`) of the cell blocks ``cell_block`` (J,
    CELLS) in the frames ``axes`` (k, p, J, 3, 3) around the hulls of what their cells'
    lateral tests accept up to ``height`` (:func:`hull_bounds`)."""
    k, p, nj = axes.shape[:3]
    corners, directions = cell_corners(cells, tol, work)  # (3, 4, k, p, n) each
    if corners.shape[-1] % CELLS:
        corners, directions = corners[..., cell_block], directions[..., cell_block]
    shape = (k, p, nj, 3, 4 * CELLS)
    new = array_maker(work, "cell_boxes.")
    corners, directions = (  # (k, p, J, 3, 4 corners x CELLS cells) matrices
        _copied(
            x.reshape(3, 4, k, p, nj, CELLS).transpose(2, 3, 4, 0, 1, 5),
            new(name, (k, p, nj, 3, 4, CELLS)),
        )
        for x, name in ((corners, "corners"), (directions, "directions"))
    )
    corners, directions = corners.reshape(shape), directions.reshape(shape)
    up_to = np.reshape(height, (-1, 1, 1, 1, 1)) if np.ndim(height) else height
    lo, hi = hull_bounds(corners, directions, axes, up_to, work)
    return bounded_boxes(lo[:, None], hi[:, None], axes, tol, _named(work, "cell_leaves"))


def _taken(points, index, new):
    """``points.take(index, axis=2)`` (``points`` (k, p, v, 3), ``index`` (I, s)) written to
    ``new(shape)``."""
    out = new(points.shape[:2] + index.shape + (3,))
    return np.take(points, index, axis=2, out=out, mode="wrap")  # every index valid


def _copied(x, out):
    """``x`` written to ``out`` (``numpy.ascontiguousarray`` into ``out``)."""
    out[...] = x
    return out


def _frames(mid_near, normal, nj, ni):
    """``frame(size, level)``: the frames (k, p, nodes, 3, 3) of the middle cells of the nodes
    of ``level`` of the trees over blocks of ``size`` cells or rulings (``nj`` cell blocks, ``ni``
    ruling blocks), every frame computed once (:func:`cell_frames`)."""
    n = normal.shape[2]

    def middle(size, level):  # the middle cells of the nodes of ``level`` (padding above 0)
        leaves = nj if size == CELLS else ni
        nodes = (1 << max(leaves - 1, 0).bit_length()) >> level if level else leaves
        return np.minimum(((2 * np.arange(nodes) + 1) << level) * size // 2, n - 1)

    tops = [(1 << max(x - 1, 0).bit_length()).bit_length() for x in (nj, ni)]
    every = np.unique(
        np.concatenate(
            [
                middle(size, level)
                for size, top in zip((CELLS, RULINGS), tops)
                for level in range(top)
            ]
        )
    )
    table = cell_frames(mid_near, normal, every)

    def frame(size, level):
        return table[:, :, np.searchsorted(every, middle(size, level))]

    return frame


def with_planes(blocks: Blocks, cells, faces, tol, work=None) -> Blocks:
    """``blocks`` with the planes and points of the exact tests: the five planes of the cells
    of every cell block, normals (plane, cell), the offsets of the mid planes and the lowest
    heights the lateral tests accept
    (:func:`compas_ccu.thickness.cells.accepted_from`), and the face vertices of every
    vertex block.

    Parameters
    ----------
    blocks : Blocks
    cells : tuple
        :func:`compas_ccu.thickness.cells.plate_cells` of the (k, p, n) cells.
    faces : (k, p, 2, 2n + 2, 3) float
    tol : float
        Lateral tolerance, m.
    work : compas_ccu.thickness.work_arrays.WorkArrays, optional
        As :func:`plate_blocks` takes it.
    """
    centre, normal, planes = cells[0], cells[1], cells[2:]
    new = array_maker(work, "planes.")
    k, p, n = normal.shape[:3]
    cell_block = blocks.cell_block
    nj = len(cell_block)

    def by_block(x):  # (k, p, n, ...) -> (k, p, J, CELLS, ...), a view where no cell repeats
        if n % CELLS:
            return x[:, :, cell_block]
        return x.reshape(k, p, nj, CELLS, *x.shape[3:])

    normals = np.stack(
        [by_block(x) for x in [normal] + [nrm for _, nrm in planes]],
        axis=3,
        out=new("normals", (k, p, nj, 5, CELLS, 3)),
    )
    lateral = np.stack(
        [by_block(dot(base, nrm)) for base, nrm in planes],
        axis=3,
        out=new("lateral", (k, p, nj, 4, CELLS)),
    )
    vertices = faces.reshape(*faces.shape[:2], -1, 3)
    points = new("points", vertices.shape[:2] + blocks.local.shape + (3,))  # (k, p, I, 4R, 3)
    np.take(vertices, blocks.local, axis=2, out=points, mode="wrap")  # every index valid
    return blocks._replace(
        normals=normals.reshape(-1, 5 * CELLS, 3),  # (k, p, J, 5, CELLS, 3)
        offsets=by_block(dot(centre, normal)).reshape(-1, CELLS, 1),
        accepted=accepted_from(lateral, tol, work).reshape(-1, 4, CELLS, 1),
        points=points.reshape(-1, 4 * RULINGS, 3),
    )


def block_pairs(blocks: Blocks, table: PairTable, state, pair, work=None):
    """The block pairs that can meet: a walk down the two trees of boxes of every candidate
    pair and state, from their roots to the leaf blocks, keeping the node pairs whose boxes
    overlap.

    Parameters
    ----------
    blocks : Blocks
    table : PairTable
    state, pair : (N,) int
        Candidate (state, pair) of the chunk (:func:`candidate_pairs`).
    work : compas_ccu.thickness.work_arrays.WorkArrays, optional
        Kept work arrays for the temporaries of the box tests (None: new arrays).

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
    kp = cell_tree[-1][0].shape[1]  # states x plates: one root each
    # the tree of both rows, or for a hinged pair the tree of its free row
    node_b = row_box[qq] * kp + state[keep] * p + table.pairs[qq, 1]
    la, lb = len(cell_tree) - 1, len(ruling_tree) - 1
    new = array_maker(work, "walk.")
    while True:
        (box_a, valid_a), (box_b, valid_b) = cell_tree[la], ruling_tree[lb]
        keep = None  # not padding
        for valid, node in ((valid_a, node_a), (valid_b, node_b)):
            if not valid.all():
                ok = valid[node % len(valid)]
                keep = ok if keep is None else keep & ok
        if keep is not None:
            qq, node_a, node_b = qq[keep], node_a[keep], node_b[keep]
        keep = np.empty(len(qq), dtype=bool)
        tested = ((box_a, node_a, "a"), (box_b, node_b, "b"))
        for at in (slice(i, i + WALK) for i in range(0, len(qq), WALK)):
            boxes = (_taken_boxes(x, node[at], partial(new, name)) for x, node, name in tested)
            keep[at] = ~separated(*boxes, work)
        at = np.flatnonzero(keep)
        qq, node_a, node_b = qq[at], node_a[at], node_b[at]
        if la == 0 and lb == 0:
            break
        # the children: (a0, b0), (a1, b0), (a0, b1), (a1, b1) of every pair, the deeper tree
        # first (both if level)
        split_a, split_b = la >= lb, lb >= la
        child_a, child_b = _CHILDREN[split_a, split_b]
        fan = len(child_a)
        qq = np.repeat(qq, fan)
        node_a = ((1 + split_a) * node_a[:, None] + child_a).reshape(-1)
        node_b = ((1 + split_b) * node_b[:, None] + child_b).reshape(-1)
        la, lb = la - split_a, lb - split_b
    plate_a, jj = np.divmod(node_a, nj)
    plate_b, ii = np.divmod(node_b, ni)
    plate_b %= kp  # (state, plate) whatever the tree of rows
    cell_id = plate_a * len(blocks.cell_block) + jj  # (state, plate, block) without padding
    ruling_id = plate_b * len(blocks.local) + ii
    return qq, cell_id, ruling_id


def _taken_boxes(box, node, new):
    """``box.take(node, axis=1)`` (packed boxes (15, N)) written to ``new(shape)``."""
    return np.take(box, node, axis=1, out=new((15, len(node))), mode="wrap")  # valid nodes


#: The children (of a, of b) of a node pair by which trees split: every pair of children.
_CHILDREN = {
    (True, True): (np.array([0, 1, 0, 1]), np.array([0, 0, 1, 1])),
    (True, False): (np.array([0, 1]), np.array([0, 0])),
    (False, True): (np.array([0, 0]), np.array([0, 1])),
}
