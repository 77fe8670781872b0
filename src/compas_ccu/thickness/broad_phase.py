"""The broad phase of the collision check: which plate pairs can touch in which state.

:mod:`compas_ccu.thickness.collision` tests a pair of plates cell by cell only where their
axis-aligned boxes, widened by half the contact reach on every side, overlap. Per state the
boxes are sorted along one axis and swept (:func:`box_pairs`), so the work is O(p log p) plus
the overlapping pairs (a deployed plate's neighbours; in the flat-folded stack the plates within
the reach above and below) instead of all ``p (p - 1)`` ordered pairs. The test that keeps a
pair is the one the brute force applies to every pair, so no pair is lost
(``tests/test_thickness_broad_phase.py`` checks it against all pairs).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["PairTable", "pair_table", "plate_boxes", "box_pairs", "candidate_pairs"]


class PairTable(NamedTuple):
    """The ordered plate pairs of a check and the hinges between them.

    Attributes
    ----------
    pairs : (P, 2) int
        ``(a, b)``: the vertices of ``b`` against the cells of ``a``.
    hinge : (P,) int
        Row of ``masks`` with the vertices of ``b`` on the hinge it shares with ``a``; -1 for
        pairs without a hinge.
    masks : (H + 1, V) bool
        The hinge rows of the hinged pairs, then an all-False row (the row of ``hinge == -1``).
    """

    pairs: np.ndarray
    hinge: np.ndarray
    masks: np.ndarray

    def skip(self, q: int):
        """(V,) bool: the vertices of pair ``q``'s ``b`` left out, or None."""
        h = self.hinge[q]
        return None if h < 0 else self.masks[h]


def pair_table(pairs, hinged, plates: int, vertices: int) -> PairTable:
    """The pairs and hinges of :func:`plate_contacts` as arrays.

    Parameters
    ----------
    pairs : (P, 2) int or list of (int, int)
    hinged : list of (V,) bool or None, or dict, or None
        Per pair (a list of length P) or per hinged pair (a dict ``{(a, b): mask}``): the
        vertices of ``b`` on the hinge it shares with ``a`` (both faces).
    plates : int
        Plate count ``p`` (pairs are ``0 .. p - 1``).
    vertices : int
        Face vertices per plate ``V``.
    """
    pairs = np.asarray(pairs, dtype=np.intp).reshape(-1, 2)
    hinge = np.full(len(pairs), -1, dtype=np.intp)
    masks = []
    if isinstance(hinged, dict):
        keys = pairs[:, 0] * plates + pairs[:, 1]
        where = {int(key): q for q, key in enumerate(keys)} if len(hinged) else {}
        items = [(where.get(int(a) * plates + int(b)), mask) for (a, b), mask in hinged.items()]
    else:
        items = list(enumerate(() if hinged is None else hinged))
    for q, mask in items:
        if q is not None and mask is not None:
            hinge[q] = len(masks)
            masks.append(np.asarray(mask, dtype=bool).reshape(vertices))
    masks.append(np.zeros(vertices, dtype=bool))
    return PairTable(pairs, hinge, np.stack(masks))


def plate_boxes(faces, reach):
    """Axis-aligned boxes of every plate in every state, widened by half the reach on all
    sides: lower and upper corners (k, p, 3) each. Two plates whose boxes do not overlap are
    further apart than ``reach`` (the broad phase of :func:`plate_contacts`)."""
    flat = faces.reshape(faces.shape[0], faces.shape[1], -1, 3)
    # coordinate by coordinate: a reduction over a long strided axis, ten times faster than
    # one over the points with the coordinates innermost (the same values)
    lo = np.stack([flat[..., i].min(axis=-1) for i in range(3)], axis=-1)
    hi = np.stack([flat[..., i].max(axis=-1) for i in range(3)], axis=-1)
    return lo - 0.5 * reach, hi + 0.5 * reach


def box_pairs(lo, hi):
    """Every pair of overlapping boxes in every state, by sort and sweep.

    Two boxes overlap unless one's lower corner lies above the other's upper corner along an
    axis (``lo_a > hi_b`` or ``lo_b > hi_a``; a NaN coordinate separates nothing along its axis).
    Per state the boxes are sorted by their lower corner along the axis on which the fewest
    pairs overlap, each box is paired with the boxes that start before it ends along that axis
    (a box with a NaN coordinate with every box), and those pairs are kept whose boxes overlap
    along all three axes: O(p log p + pairs).

    Parameters
    ----------
    lo, hi : (k, p, 3) float

    Returns
    -------
    state, a, b : (N,) int
        The overlapping pairs, ``a < b``.
    """
    k, p = lo.shape[:2]
    found = []
    for s in range(k):
        low, high = lo[s], hi[s]
        wild = np.isnan(low).any(axis=1) | np.isnan(high).any(axis=1)
        tame = np.flatnonzero(~wild)
        best = None
        for axis in range(3):
            order = tame[np.argsort(low[tame, axis], kind="stable")]
            start = low[order, axis]
            end = np.searchsorted(start, high[order, axis], side="right")
            count = np.maximum(end - np.arange(len(order)) - 1, 0)
            if best is None or count.sum() < best[2].sum():
                best = order, np.arange(len(order)), count
        order, rank, count = best
        first = np.repeat(rank, count)
        step = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
        a, b = order[first], order[first + 1 + step]
        if wild.any():  # a NaN corner: that axis separates nothing, the others may
            others = np.flatnonzero(wild)
            a = np.concatenate([a, np.repeat(others, p)])
            b = np.concatenate([b, np.tile(np.arange(p), len(others))])
            keep = (a != b) & ~(wild[a] & wild[b] & (a > b))  # each wild pair once
            a, b = a[keep], b[keep]
        apart = np.zeros(len(a), dtype=bool)
        for lo_c, hi_c in zip(low.T, high.T):  # axis by axis (the same test)
            apart |= lo_c[a] > hi_c[b]
            apart |= lo_c[b] > hi_c[a]
        keep = ~apart
        a, b = a[keep], b[keep]
        found.append((np.full(len(a), s), np.minimum(a, b), np.maximum(a, b)))
    if not found:
        return tuple(np.zeros(0, dtype=np.intp) for _ in range(3))
    state, a, b = (np.concatenate(parts).astype(np.intp) for parts in zip(*found))
    return state, a, b


def candidate_pairs(lo, hi, table: PairTable, plates: int):
    """The (state, pair) of ``table``'s pairs whose plate boxes overlap (:func:`box_pairs`;
    a pair of a plate with itself always).

    Returns
    -------
    state, pair : (N,) int
        Sorted by state, then pair.
    """
    k = lo.shape[0]
    state, a, b = box_pairs(lo, hi)
    state = np.concatenate([state, state])
    key = np.concatenate([a * plates + b, b * plates + a])  # both orders
    wanted = table.pairs[:, 0] * plates + table.pairs[:, 1]
    order = np.argsort(wanted, kind="stable")
    wanted = wanted[order]
    left = np.searchsorted(wanted, key, side="left")
    if len(wanted) and (wanted[1:] > wanted[:-1]).all():  # every pair once: found or not
        count = (wanted[np.minimum(left, len(wanted) - 1)] == key).astype(np.intp)
    else:
        count = np.searchsorted(wanted, key, side="right") - left
    step = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
    pair = order[np.repeat(left, count) + step]  # every pair of the table with that key
    state = np.repeat(state, count)
    same = np.flatnonzero(table.pairs[:, 0] == table.pairs[:, 1])
    if len(same):
        state = np.concatenate([state, np.repeat(np.arange(k), len(same))])
        pair = np.concatenate([pair, np.tile(same, k)])
    first = np.lexsort((pair, state))
    return state[first].astype(np.intp), pair[first].astype(np.intp)
