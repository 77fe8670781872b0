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

Everything is vectorised over states, vertices and cells; plate pairs whose bounding boxes are
further apart than ``reach`` are skipped.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import unit
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["Contact", "plate_contacts"]


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
    normal = unit(np.cross(c - a, d - b))
    ruling = unit(mid_far - mid_near)
    side = unit(np.cross(ruling, offsets))  # plane of ruling j and ν_j
    # orient the side planes so that the cell is on their positive side
    centre = 0.25 * (a + b + c + d)
    s0 = side[..., :-1, :]
    s0 = s0 * np.sign(_dot(centre - a, s0))[..., None]
    s1 = side[..., 1:, :]
    s1 = s1 * np.sign(_dot(centre - b, s1))[..., None]
    e_near = unit(np.cross(normal, b - a))
    e_near = e_near * np.sign(_dot(centre - a, e_near))[..., None]
    e_far = unit(np.cross(normal, c - d))
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
):
    """Worst contact of every ordered plate pair in every state.

    Parameters
    ----------
    mid_near, mid_far, offsets : (k, p, n + 1, 3) float
        Mid-surface boundaries (with the crease corrections) and face-offset vectors.
    faces : (k, p, 2, 2n + 2, 3) float
        Lower and upper face vertices of every plate.
    thickness : float
    pairs : list of (int, int)
        Ordered plate pairs ``(a, b)`` to test: vertices of ``b`` against the cells of ``a``.
    hinged : list of (P,) bool or None, optional
        Per pair: vertices of ``b`` on the hinge it shares with ``a`` (both faces), or None.
        They are left out (their mismatch is the hinge gap, reported apart), and so is the
        crossing test: two plates joined by a hinge only pass through each other by a negative
        fold angle, which the kinematics excludes.
    reach : float
        Pairs whose bounding boxes are further apart than this (m) in a state are skipped:
        their clearance is reported as inf.
    tol : float
        Lateral tolerance of the footprint test, m.

    Returns
    -------
    depth, clearance : (k, len(pairs)) float
    crossing : (k, len(pairs)) bool
    where : (k, len(pairs)) int
        Vertex of ``b`` with the largest depth (or, without penetration, the smallest clearance).
    """
    k = mid_near.shape[0]
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
        skip = None if hinged is None else hinged[q]
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
