"""The exact tests of the collision check on the block pairs of its candidate search.

:func:`exact_tests` runs the brute force's tests of
:func:`compas_ccu.thickness.collision.plate_contacts` on one batch of the block pairs that
:func:`compas_ccu.thickness.candidate_search.block_pairs` keeps (why no contact is lost, and
why the numbers are the brute force's bit for bit: the docstring of
:mod:`compas_ccu.thickness.candidate_search`); :func:`all_exact_tests` on all of them, in
batches of about :data:`BATCH` block pairs.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import dot
from compas_ccu.thickness.broad_phase import PairTable
from compas_ccu.thickness.candidate_search import CELLS, RULINGS, Blocks

__all__ = ["BATCH", "Found", "exact_tests", "all_exact_tests"]

#: Block pairs per batch of the exact tests (bounds the temporaries: ~1 MB per 100 pairs).
BATCH = 512


class Found(NamedTuple):
    """What the exact tests of one batch of block pairs found."""

    key: np.ndarray  # (N,) state * pairs + pair of every gap within the reach
    vertex: np.ndarray  # (N,) the vertex of b of the smallest gap of its block pair
    gap: np.ndarray  # (N,) that gap, m
    crossing: np.ndarray  # (C,) state * pairs + pair of every crossing found


def exact_tests(
    blocks: Blocks, table: PairTable, pair, cell_id, ruling_id, half, reach, tol, *, row=None
):
    """The brute force's exact tests on one batch of block pairs (module docstring).

    Parameters
    ----------
    blocks : Blocks
    table : PairTable
    pair, cell_id, ruling_id : (N,) int
        From :func:`block_pairs`.
    half, reach, tol : float
        Half the thickness, the contact reach and the lateral tolerance, m.
    row : {None, 0, 1}
        None: both rows of the vertex blocks; 0 (near) or 1 (far): that row only, for pairs
        joined by a hinge on the other row (left out of their tests, no crossing test).

    Returns
    -------
    Found
        Keys over the chunk's states (``state * len(table.pairs) + pair``).
    """
    p, npairs = blocks.plates, len(table.pairs)
    ni, nj = len(blocks.local), len(blocks.cell_block)
    count = len(pair)
    kb = cell_id // nj // p  # state
    ib = ruling_id % ni
    hinge = table.hinge[pair]  # -1: the all-False last row of the masks
    mask = np.where(hinge < 0, len(table.masks) - 1, hinge) * ni + ib
    if row is None:
        vertices, skip = blocks.local[ib], blocks.skip.reshape(-1, 4 * RULINGS).take(mask, axis=0)
        x = blocks.points.take(ruling_id, axis=0)  # (N, 4 RULINGS, 3)
    else:  # both faces of one row, the vertex numbers still growing
        columns = np.arange(4 * RULINGS).reshape(2, 2, RULINGS)[:, row].reshape(-1)
        vertices = blocks.local.reshape(-1).take(ib[:, None] * (4 * RULINGS) + columns)
        skip = blocks.skip.reshape(-1).take(mask[:, None] * (4 * RULINGS) + columns)
        at = ruling_id[:, None] * (4 * RULINGS) + columns
        x = blocks.points.reshape(-1, 3).take(at, axis=0)  # (N, 2 RULINGS, 3)
    # heights (N, plane, cell, vertex) by the same matrix products as the brute force
    # (the points transposed into a contiguous operand: the same BLAS kernel, faster packing)
    heights = blocks.normals.take(cell_id, axis=0) @ np.ascontiguousarray(x.swapaxes(1, 2))
    heights = heights.reshape(count, 5, CELLS, x.shape[1])
    # inside every lateral half-space (all four heights minus their offsets >= -tol, as the
    # brute force's lowest of the four; NaN: not inside): every height at least the lowest
    # one each test accepts (``accepted_from``, the same booleans without the
    # subtractions); outside where any is not, or the vertex is on the hinge
    up = heights[:, 1:] >= blocks.accepted.take(cell_id, axis=0)  # (N, 4 planes, cell, vertex)
    outside = up[:, 0] & up[:, 1]
    outside &= up[:, 2]
    outside &= up[:, 3]
    np.logical_not(outside, out=outside)
    outside |= skip[:, None]
    # the heights over the mid planes; the smallest |d| - t/2 over the lateral cells: the
    # smallest |d| (rounding is monotone)
    d = heights[:, 0] - blocks.offsets.take(cell_id, axis=0)  # (N, cell, vertex)
    size = np.abs(d)
    np.copyto(size, np.inf, where=outside)
    gap = np.minimum(size[:, 0], size[:, 1])
    for cell in range(2, CELLS):
        np.minimum(gap, size[:, cell], out=gap)
    gap -= half
    best = gap.argmin(axis=1)  # the first of the smallest gaps: the lowest vertex number
    rows = np.arange(count)
    value = gap[rows, best]
    near = value <= reach
    keys = kb * npairs + pair
    found = Found(keys[near], vertices[rows, best][near], value[near], keys[:0])
    test = hinge < 0
    if row is not None or not test.any():
        return found
    if not test.all():
        d, x, cell_id, keys = d[test], x[test], cell_id[test], keys[test]
    return found._replace(crossing=_crossings(blocks, d, x, cell_id, keys, tol))


def _crossings(blocks: Blocks, d, x, cell_id, keys, tol):
    """The keys of the block pairs in which a ruling of b (near row -> far row) passes through
    a's mid plane inside a cell: heights ``d`` (N, cell, 4 RULINGS) over the mid planes of
    the cells ``cell_id`` (N,) of the vertices ``x`` (N, 4 RULINGS, 3)."""
    # d0 * d1 < 0 of the near and far vertex of every ruling: the products of the heights
    # RULINGS apart in one contiguous pass (the near rows' ones are those of the rulings)
    flat = np.ascontiguousarray(d).reshape(-1)
    product = np.zeros(flat.shape)
    np.multiply(flat[:-RULINGS], flat[RULINGS:], out=product[:-RULINGS])
    at = np.flatnonzero(product < 0.0)
    at = at[at // RULINGS % 2 == 0]  # of a near row: (N, cell, face, near row, ruling)
    if not len(at):
        return keys[:0]
    p, nj = blocks.plates, len(blocks.cell_block)
    d0, d1 = flat[at], flat[at + RULINGS]
    nb, c, f, _, r = np.unravel_index(at, (len(d), CELLS, 2, 2, RULINGS))
    xs = x.reshape(-1, 2, 2, RULINGS, 3)
    x0, x1 = xs[nb, f, 0, r], xs[nb, f, 1, r]
    s = d0 / (d0 - d1)
    point = x0 + s[:, None] * (x1 - x0)
    cell = blocks.cell_block[cell_id % nj][nb, c]
    ks, as_ = np.divmod(cell_id // nj, p)
    ks, as_ = ks[nb], as_[nb]
    inside = np.ones(len(s), dtype=bool)
    for base, plane in blocks.planes:
        inside &= dot(point - base[ks, as_, cell], plane[ks, as_, cell]) >= tol
    return keys[nb][inside]


def all_exact_tests(blocks: Blocks, table: PairTable, pair, cell_id, ruling_id, half, reach, tol):
    """:func:`exact_tests` of every block pair of :func:`block_pairs` in batches of about
    :data:`BATCH` block pairs of both rows, those of a hinged pair that meets one row of the
    vertex blocks only on that row (``row``; twice as many in a batch): a list of Found."""
    row = blocks.row_box[table.hinge][pair]  # the tree walked: 0 both rows, 1 near, 2 far
    found = []
    for tree, size in ((0, BATCH), (1, 2 * BATCH), (2, 2 * BATCH)):
        at = np.flatnonzero(row == tree)
        for part in (at[i : i + size] for i in range(0, len(at), size)):
            found.append(
                exact_tests(
                    blocks,
                    table,
                    pair[part],
                    cell_id[part],
                    ruling_id[part],
                    half,
                    reach,
                    tol,
                    row=None if tree == 0 else tree - 1,
                )
            )
    return found
