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

**Candidate search** (``method="cells"``, the default): the exact tests run only where a block
of cells of one plate and a block of rulings of the other can meet
(:mod:`compas_ccu.thickness.candidate_search`, which says why no contact is lost); the results
equal those of ``method="all"`` (the brute force, kept as :func:`_contacts_all`) bit for bit.
The cells and their tests: :mod:`compas_ccu.thickness.cells`.

**What a report needs** (``smallest``, as
:func:`compas_ccu.thickness.collision_check.path_collisions` asks): per state the candidate
search looks only as far as an upper bound of the state's smallest clearance, which a few
probes give (:mod:`compas_ccu.thickness.report_pairs`); the report is the same bit for bit,
the other pairs' gaps are not all measured.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import dot
from compas_ccu.thickness.block_tests import Found, all_exact_tests, exact_tests
from compas_ccu.thickness.broad_phase import (
    PairTable,
    box_pairs,
    candidate_pairs,
    pair_table,
    plate_boxes,
)
from compas_ccu.thickness.candidate_search import Blocks, block_pairs, plate_blocks, with_planes
from compas_ccu.thickness.cells import in_footprint, plane_heights, plate_cells, point_gaps
from compas_ccu.thickness.report_pairs import report_heights
from compas_ccu.thickness.work_arrays import work_arrays
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


#: Cells (states x plates x cells) whose blocks are boxed at once: the states are checked in
#: chunks of about this many cells, so the temporaries stay small whatever the plate count.
CHUNK_CELLS = 16384


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
    smallest=None,
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
        meet (:mod:`.candidate_search`), O(n) per pair; "all": every vertex against every cell
        of every pair whose boxes overlap, O(n^2) per pair (the reference). Both give the same
        results, bit for bit.
    smallest : (P,) bool, optional
        Only what a collision report needs (:mod:`.report_pairs`; ``method="cells"`` only):
        every pair that can penetrate or cross is tested, and of the pairs marked here only
        those that can hold the smallest clearance of their state; the others report no
        contact. The largest depth, any crossing, the smallest clearance over the marked pairs
        per state and the first pair and vertex of each are those of the full check, bit for
        bit. None (default): every pair.

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
        height, cells = half + reach, plate_cells(*chunk[:3], work=work_arrays)
        if smallest is not None:  # only what a report needs: a height per state
            height = report_heights(cells, chunk[3], table, state, pair, smallest, half, reach)
        blocks = plate_blocks(*chunk, table, tol, height, cells, planes=False, work=work_arrays)
        qq, cell_id, ruling_id = block_pairs(blocks, table, state, pair, work_arrays)
        if len(qq):  # the planes and points of the exact tests, only where they run
            blocks = with_planes(blocks, cells, chunk[3], tol, work_arrays)
        found = all_exact_tests(blocks, table, qq, cell_id, ruling_id, half, reach, tol)
        if found:
            out = (x[states] for x in (depth, clearance, crossing, where))
            _smallest(found, *out)
    redo = np.flatnonzero(crossing.any(axis=1)) if smallest is not None else []
    if len(redo):  # a crossing pair's depth counts whatever its gap: these states in full
        again = (x[redo] for x in (mid_near, mid_far, offsets, faces))
        full = plate_contacts(*again, thickness, pairs=table.pairs, hinged=hinged, reach=reach)
        for whole, part in zip((depth, clearance, crossing, where), full):
            whole[redo] = part
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
        cells = plate_cells(mid_near[ks, pa], mid_far[ks, pa], offsets[ks, pa])
        centre, normal = cells[0], cells[1]
        pts = faces[ks, pb].reshape(len(ks), -1, 3)  # (K, P, 3)
        lateral = in_footprint(pts, cells, tol)  # (K, P, n)
        skip = table.skip(q)
        if skip is not None:
            lateral &= ~skip[None, :, None]
        d = plane_heights(pts, centre, normal)  # (K, P, n)
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
            d0 = plane_heights(x0, centre, normal)
            d1 = plane_heights(x1, centre, normal)
            sign_change = (d0 * d1) < 0.0
            if not sign_change.any():
                continue
            with np.errstate(divide="ignore", invalid="ignore"):
                s = np.where(sign_change, d0 / (d0 - d1), 0.0)
            hit = x0[:, :, None, :] + s[..., None] * (x1 - x0)[:, :, None, :]  # (K, m, n, 3)
            inside = np.ones(sign_change.shape, dtype=bool)
            for base, nrm in cells[2:]:
                inside &= dot(hit - base[:, None], nrm[:, None]) >= tol
            crossing[ks, q] |= (sign_change & inside).any(axis=(1, 2))
    return depth, clearance, crossing, where
