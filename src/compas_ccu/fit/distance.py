"""Deployed plates as triangles and the exact distance from points to them (docs/fit.md).

:class:`PlateSurface` holds the triangles of every plate of one state (each planar quad split
along a diagonal) and a sampling of them (a lattice on every triangle, at most ``spacing``
apart). :meth:`PlateSurface.query` finds, for every point, candidate triangles among those of
its nearest samples (scipy's cKDTree) and the exact closest point on them
(:func:`closest_on_triangles`). The candidates are complete — the result is the exact
point-to-plates distance, to rounding — whenever the ``k``-th nearest sample lies further than
the best exact distance plus the sampling's covering radius: every triangle point lies within
that radius of a sample of its own triangle, so no triangle left out can be closer. Points where
this does not hold are queried again with 4 times as many candidates, up to ``max_candidates``;
beyond that (points far from every plate, many times the covering radius) the distance is exact
to within the covering radius (``Distances.exact`` says which).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from compas_ccu.errors import GeometryError

__all__ = ["PlateSurface", "Distances", "closest_on_triangles", "plate_triangles", "lattice_plan"]


def plate_triangles(vertices, faces):
    """The triangles of every plate: each quad ``(a, b, c, d)`` as ``(a, b, c)`` and
    ``(a, c, d)``.

    Parameters
    ----------
    vertices : (p, m, 3) float
        Plate vertices (``Structure.deployed`` or ``CCUModel.vertices(alpha)[0]``).
    faces : (p, n, 4) or (n, 4) int
        Quads of every plate, indices into its vertex rows (``CCUModel.faces``).

    Returns
    -------
    triangles : (p * 2n, 3, 3) float64
    plate : (p * 2n,) int
        Row of the plate (0 .. p - 1) of every triangle.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    p = v.shape[0]
    if f.ndim == 2:
        f = np.broadcast_to(f, (p, *f.shape))
    tri = np.concatenate([f[..., [0, 1, 2]], f[..., [0, 2, 3]]], axis=1)  # (p, 2n, 3)
    rows = np.arange(p)[:, None, None]
    triangles = v[rows, tri]  # (p, 2n, 3, 3)
    plate = np.repeat(np.arange(p), tri.shape[1])
    return triangles.reshape(-1, 3, 3), plate


def closest_on_triangles(points, triangles):
    """The closest point of each triangle to each point (Ericson's region test, vectorised).

    Parameters
    ----------
    points : (..., 3) float
    triangles : (..., 3, 3) float
        Broadcast against ``points``.

    Returns
    -------
    (..., 3) float64
    """
    p = np.asarray(points, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.float64)
    a, b, c = t[..., 0, :], t[..., 1, :], t[..., 2, :]
    ab, ac = b - a, c - a
    ap, bp, cp = p - a, p - b, p - c
    d1 = (ab * ap).sum(-1)
    d2 = (ac * ap).sum(-1)
    d3 = (ab * bp).sum(-1)
    d4 = (ac * bp).sum(-1)
    d5 = (ab * cp).sum(-1)
    d6 = (ac * cp).sum(-1)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2

    def safe(x):
        return np.where(np.abs(x) > 0.0, x, 1.0)

    denom = safe(va + vb + vc)
    v_in, w_in = vb / denom, vc / denom
    out = a + v_in[..., None] * ab + w_in[..., None] * ac  # inside the face
    # edges and vertices, lowest priority first so that the first region of the test wins
    e_bc = (d4 - d3) / safe((d4 - d3) + (d5 - d6))
    m = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)
    out = np.where(m[..., None], b + e_bc[..., None] * (c - b), out)
    e_ac = d2 / safe(d2 - d6)
    m = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    out = np.where(m[..., None], a + e_ac[..., None] * ac, out)
    m = (d6 >= 0) & (d5 <= d6)
    out = np.where(m[..., None], c, out)
    e_ab = d1 / safe(d1 - d3)
    m = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    out = np.where(m[..., None], a + e_ab[..., None] * ab, out)
    m = (d3 >= 0) & (d4 <= d3)
    out = np.where(m[..., None], b, out)
    m = (d1 <= 0) & (d2 <= 0)
    out = np.where(m[..., None], a, out)
    return out


@dataclass(frozen=True)
class Distances:
    """Distances from points to the plates.

    Attributes
    ----------
    distance : (n,) float64
        Unsigned distance to the nearest plate, m.
    signed : (n,) float64
        The same, signed by the side of the nearest triangle (its normal, counter-clockwise in
        the plate's cut pattern): smooth through the plate, the residual of the fits.
    plate : (n,) int
        Row of the nearest plate (0 .. p - 1, the order of ``CCUModel.plate_ids``).
    triangle : (n,) int
        Index of the nearest triangle.
    closest : (n, 3) float64
        Closest point on the plates.
    exact : (n,) bool
        The candidate search was complete (module docstring); else exact to the covering radius.
    """

    distance: np.ndarray
    signed: np.ndarray
    plate: np.ndarray
    triangle: np.ndarray
    closest: np.ndarray
    exact: np.ndarray


class PlateSurface:
    """The triangles of the plates of one state, sampled for the nearest-triangle search.

    Parameters
    ----------
    triangles : (t, 3, 3) float
    plate : (t,) int
        Plate row of every triangle.
    spacing : float
        Largest distance between neighbouring samples along a triangle's sides, m.
    plan : tuple, optional
        A :func:`lattice_plan` to reuse (another state of the same plates).

    Attributes
    ----------
    triangles, plate
    normals : (t, 3) float64
        Unit normals.
    areas : (t,) float64
    samples : (s, 3) float64
        The lattice points.
    sample_triangle : (s,) int
    sample_weight : (s,) float64
        Area each sample stands for (its triangle's area / its triangle's samples), m².
    spacing : float
    cover : float
        Covering radius: every triangle point lies within it of a sample of its triangle, m.

    Examples
    --------
    >>> tri = np.array([[[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]])
    >>> s = PlateSurface(tri, np.array([0]), spacing=0.25)
    >>> d = s.query(np.array([[0.2, 0.2, 0.5], [2.0, 0.0, 0.0]]))
    >>> d.distance.round(12).tolist(), d.signed.round(12).tolist()
    ([0.5, 1.0], [0.5, 1.0])
    """

    def __init__(self, triangles, plate, *, spacing: float, plan=None):
        t = np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3)
        if not len(t) or not np.isfinite(t).all():
            raise GeometryError("the plates have no finite triangles to measure distances to")
        if not spacing > 0.0:
            raise GeometryError(f"the sample spacing must be > 0, got {spacing!r}")
        self.triangles = t
        self.spacing = float(spacing)
        self.plate = np.asarray(plate, dtype=np.int64)
        cross = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        double = np.linalg.norm(cross, axis=1)
        self.areas = 0.5 * double
        self.normals = cross / np.where(double > 0.0, double, 1.0)[:, None]
        self.plan = lattice_plan(t, float(spacing)) if plan is None else plan
        self.samples, self.sample_triangle, self.cover = _lattice(t, self.plan)
        counts = np.bincount(self.sample_triangle, minlength=len(t))
        self.sample_weight = self.areas[self.sample_triangle] / counts[self.sample_triangle]
        self.tree = cKDTree(self.samples)

    @classmethod
    def from_vertices(cls, vertices, faces, *, spacing: float, plan=None) -> PlateSurface:
        """The surface of plate vertices ``(p, m, 3)`` with quads ``faces``
        (:func:`plate_triangles`)."""
        triangles, plate = plate_triangles(vertices, faces)
        return cls(triangles, plate, spacing=spacing, plan=plan)

    @property
    def count(self) -> int:
        """Number of plates."""
        return int(self.plate.max()) + 1

    def plate_areas(self) -> np.ndarray:
        """(p,) area of every plate, m²."""
        return np.bincount(self.plate, weights=self.areas, minlength=self.count)

    def query(
        self,
        points,
        *,
        candidates: int = 8,
        max_candidates: int = 512,
        chunk: int = 100_000,
    ) -> Distances:
        """Exact distances from ``points`` (n, 3) to the plates (module docstring).

        Parameters
        ----------
        points : (n, 3) float
        candidates : int
            Nearest samples whose triangles are tried first.
        max_candidates : int
            The most samples tried for a point.
        chunk : int
            Points per batch (at most 4e6 triangle tests per batch).

        Returns
        -------
        Distances
        """
        p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        n = len(p)
        best = np.full(n, np.inf)
        tri = np.zeros(n, dtype=np.int64)
        closest = np.zeros((n, 3))
        exact = np.zeros(n, dtype=bool)
        todo = np.arange(n)
        k = int(min(candidates, len(self.samples)))
        while len(todo):
            step = max(1, min(chunk, 4_000_000 // k))  # memory: step * k triangle tests
            for s in range(0, len(todo), step):
                idx = todo[s : s + step]
                d_s, i_s = self.tree.query(p[idx], k=k)
                d_s, i_s = d_s.reshape(len(idx), -1), i_s.reshape(len(idx), -1)
                cand = self.sample_triangle[i_s]  # (m, k)
                q = closest_on_triangles(p[idx, None, :], self.triangles[cand])
                dist = np.linalg.norm(q - p[idx, None, :], axis=-1)
                j = np.argmin(dist, axis=1)
                r = np.arange(len(idx))
                better = dist[r, j] < best[idx]
                sel = idx[better]
                best[sel] = dist[r, j][better]
                tri[sel] = cand[r, j][better]
                closest[sel] = q[r, j][better]
                exact[idx] = (d_s[:, -1] > best[idx] + self.cover) | (k >= len(self.samples))
            todo = todo[~exact[todo]]
            if k >= min(max_candidates, len(self.samples)):
                break
            k = int(min(4 * k, max_candidates, len(self.samples)))
        side = ((p - closest) * self.normals[tri]).sum(axis=1)
        signed = np.where(side < 0.0, -best, best)
        return Distances(best, signed, self.plate[tri], tri, closest, exact)


def lattice_plan(triangles, spacing: float):
    """How :class:`PlateSurface` samples triangles (t, 3, 3) at ``spacing``: the apex of every
    triangle (where its shortest side starts) and the steps ``nu, nv`` along its two sides from
    there. Reusing one plan for several states of the same plates keeps the samples continuous
    in the geometry (the fits' finite differences need that)."""
    t = np.asarray(triangles, dtype=np.float64)
    sides = np.linalg.norm(t[:, [1, 2, 0]] - t[:, [0, 1, 2]], axis=-1)  # ab, bc, ca
    apex = np.argmin(sides, axis=1)
    order = np.stack([apex, (apex + 1) % 3, (apex + 2) % 3], axis=1)
    t = np.take_along_axis(t, order[:, :, None], axis=1)
    lu = np.linalg.norm(t[:, 1] - t[:, 0], axis=1)
    lv = np.linalg.norm(t[:, 2] - t[:, 0], axis=1)
    nu = np.maximum(1, np.ceil(lu / spacing)).astype(np.int64)
    nv = np.maximum(1, np.ceil(lv / spacing)).astype(np.int64)
    return order, nu, nv


def _lattice(t: np.ndarray, plan):
    """Samples on every triangle: ``a + (i / nu) (b - a) + (j / nv) (c - a)``, ``i / nu +
    j / nv <= 1`` (the apex ``a`` at the shortest side, so that slivers get few samples).
    Returns the samples, their triangle and the covering radius (the longest cell diagonal)."""
    order, nu, nv = plan
    t = np.take_along_axis(t, order[:, :, None], axis=1)
    eu, ev = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    du, dv = eu / nu[:, None], ev / nv[:, None]
    cover = float(max(np.linalg.norm(du + dv, axis=1).max(), np.linalg.norm(du - dv, axis=1).max()))
    points, owner = [], []
    for a, b in sorted({(int(x), int(y)) for x, y in zip(nu, nv)}):  # one lattice per class
        members = np.flatnonzero((nu == a) & (nv == b))
        i, j = np.meshgrid(np.arange(a + 1), np.arange(b + 1), indexing="ij")
        keep = i * b + j * a <= a * b
        u, v = i[keep] / a, j[keep] / b
        pts = t[members, 0, None] + u[None, :, None] * eu[members, None]
        pts = pts + v[None, :, None] * ev[members, None]
        points.append(pts.reshape(-1, 3))
        owner.append(np.repeat(members, len(u)))
    order = np.argsort(np.concatenate(owner), kind="stable")
    return np.concatenate(points)[order], np.concatenate(owner)[order], cover
