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
from functools import lru_cache

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
        self.tree = cKDTree(self.samples, balanced_tree=False)  # built 2x faster, same answers
        ab, ac = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
        gram = np.stack([(ab * ab).sum(1), (ab * ac).sum(1), (ac * ac).sum(1)], axis=1)
        self._edges = (t[:, 0].copy(), ab, ac, gram)

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
        beyond: float = np.inf,
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
        beyond : float
            m: a point certainly farther from the plates (its ``k``-th sample lies beyond
            ``beyond`` plus the covering radius) is not searched further; its distance is
            exact to within the covering radius (``exact`` False).
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
        todo = _grid_order(p, 4.0 * self.spacing) if n > 20_000 else np.arange(n)
        k = int(min(candidates, len(self.samples)))
        while len(todo):
            step = max(1, min(chunk, 4_000_000 // k))  # memory: step * k triangle tests
            settled = np.zeros(n, dtype=bool)
            for s in range(0, len(todo), step):
                idx = todo[s : s + step]
                d_k, b_dist, b_tri, b_closest = self._nearest_of_candidates(p[idx], k)
                better = b_dist < best[idx]
                sel = idx[better]
                best[sel], tri[sel], closest[sel] = b_dist[better], b_tri[better], b_closest[better]
                exact[idx] = (d_k > best[idx] + self.cover) | (k >= len(self.samples))
                settled[idx] = exact[idx] | (d_k > beyond + self.cover)
            todo = todo[~settled[todo]]
            if k >= min(max_candidates, len(self.samples)):
                break
            k = int(min(4 * k, max_candidates, len(self.samples)))
        side = ((p - closest) * self.normals[tri]).sum(axis=1)
        signed = np.where(side < 0.0, -best, best)
        return Distances(best, signed, self.plate[tri], tri, closest, exact)

    def _nearest_of_candidates(self, p, k: int):
        """For points ``p`` (m, 3): the distance of the ``k``-th nearest sample, and the
        distance, triangle and closest point of the nearest of those samples' triangles."""
        d_s, i_s = self.tree.query(p, k=k)
        d_s, i_s = d_s.reshape(len(p), -1), i_s.reshape(len(p), -1)
        cand = self.sample_triangle[i_s]  # (m, k)
        # each candidate triangle once (the k samples of a point share few triangles)
        rows, cols = np.nonzero(_first_occurrences(cand))
        sq, uv = _closest_pairs(p[rows], cand[rows, cols], self._edges)
        dist = np.full(cand.shape, np.inf)
        dist[rows, cols] = np.sqrt(sq)
        at = np.zeros(cand.shape, dtype=np.int64)
        at[rows, cols] = np.arange(len(rows))
        r = np.arange(len(p))
        j = np.argmin(dist, axis=1)
        pick = at[r, j]
        t = cand[r, j]
        a, ab, ac, _ = self._edges
        closest = a[t] + uv[pick, :1] * ab[t] + uv[pick, 1:] * ac[t]
        return d_s[:, -1], dist[r, j], t, closest


def _grid_order(points, cell: float) -> np.ndarray:
    """Indices of ``points`` (n, 3) cell by cell of a grid (neighbours queried together: the
    tree's nodes stay in cache; each point's result is the same in any order)."""
    g = np.floor((points - points.min(axis=0)) / cell).astype(np.int64)
    return np.lexsort((g[:, 2], g[:, 1], g[:, 0]))


def _first_occurrences(cand: np.ndarray) -> np.ndarray:
    """(m, k) bool: the first column of every distinct value in each row of ``cand``."""
    order = np.argsort(cand, axis=1, kind="stable")
    ranked = np.take_along_axis(cand, order, axis=1)
    first = np.ones(cand.shape, dtype=bool)
    first[:, 1:] = ranked[:, 1:] != ranked[:, :-1]
    out = np.empty_like(first)
    np.put_along_axis(out, order, first, axis=1)
    return out


def _closest_pairs(points, tri, edges):
    """Squared distance and closest point's parameters ``(u, v)`` (``a + u ab + v ac``) of
    point ``i`` to triangle ``tri[i]``: the region test of :func:`closest_on_triangles` on
    flat pairs, from the triangles' corner ``a``, edges ``ab``, ``ac`` and Gram entries
    ``ab.ab, ab.ac, ac.ac`` (``edges``), the other dot products derived from two per pair.

    Returns
    -------
    sq : (n,) float64
    uv : (n, 2) float64
    """
    a, ab, ac, gram = edges
    e_ab, e_ac = ab[tri], ac[tri]
    ap = points - a[tri]
    d1 = np.einsum("ij,ij->i", e_ab, ap)
    d2 = np.einsum("ij,ij->i", e_ac, ap)
    g = gram[tri]
    d3, d4 = d1 - g[:, 0], d2 - g[:, 1]  # ab.bp, ac.bp
    d5, d6 = d1 - g[:, 1], d2 - g[:, 2]  # ab.cp, ac.cp
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2

    def safe(x):
        return np.where(np.abs(x) > 0.0, x, 1.0)

    denom = safe(va + vb + vc)
    u, v = vb / denom, vc / denom  # inside the face
    # edges and vertices, lowest priority first so that the first region of the test wins
    m = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)  # edge bc
    e = (d4 - d3) / safe((d4 - d3) + (d5 - d6))
    u, v = np.where(m, 1.0 - e, u), np.where(m, e, v)
    m = (vb <= 0) & (d2 >= 0) & (d6 <= 0)  # edge ac
    u, v = np.where(m, 0.0, u), np.where(m, d2 / safe(d2 - d6), v)
    m = (d6 >= 0) & (d5 <= d6)  # corner c
    u, v = np.where(m, 0.0, u), np.where(m, 1.0, v)
    m = (vc <= 0) & (d1 >= 0) & (d3 <= 0)  # edge ab
    u, v = np.where(m, d1 / safe(d1 - d3), u), np.where(m, 0.0, v)
    m = (d3 >= 0) & (d4 <= d3)  # corner b
    u, v = np.where(m, 1.0, u), np.where(m, 0.0, v)
    m = (d1 <= 0) & (d2 <= 0)  # corner a
    u, v = np.where(m, 0.0, u), np.where(m, 0.0, v)
    diff = ap - u[:, None] * e_ab - v[:, None] * e_ac
    return np.einsum("ij,ij->i", diff, diff), np.stack([u, v], axis=1)


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


def lattice_cover(du, dv) -> float:
    """Covering radius of the lattices of :func:`_lattice` with steps ``du``, ``dv`` (t, 3):
    every point of every triangle lies within it of a lattice point of its own triangle.

    A point of the triangle lies in a lattice cell whose corner ``A`` (nearest the apex) is a
    sample; of the other corners ``B = A + du``, ``C = A + dv``, ``D = A + du + dv`` the
    samples are (the triangle is closed downwards) all four, ``A, B, C``, ``A, B``, ``A, C``
    or ``A`` alone. The half cell ``A, B, C`` (and its point reflection ``B, C, D``) is within
    its circumradius of its corners (half its longest side if obtuse). The rest of a cell cut
    by the hypotenuse lies within ``max(|du|, |dv|)`` of ``B`` or ``C`` (``A, B, C`` kept),
    within ``sqrt(|du|^2 / 4 + |dv|^2)`` of ``A`` or ``B`` (``A, B``: the bisector of ``AB``
    is at most ``|dv|`` high in the cell), ``sqrt(|du|^2 + |dv|^2 / 4)`` likewise for ``A, C``,
    and ``max(|du|, |dv|)`` of ``A`` alone. The largest of these over all triangles.
    """
    lu = np.linalg.norm(du, axis=1)
    lv = np.linalg.norm(dv, axis=1)
    lw = np.linalg.norm(du - dv, axis=1)
    area2 = np.linalg.norm(np.cross(du, dv), axis=1)  # twice the half cell's area
    sides = np.sort(np.stack([lu, lv, lw], axis=1), axis=1)
    obtuse = sides[:, 2] ** 2 >= sides[:, 0] ** 2 + sides[:, 1] ** 2
    circum = lu * lv * lw / (2.0 * np.where(area2 > 0.0, area2, 1.0))
    half = np.where(obtuse | (area2 <= 0.0), 0.5 * sides[:, 2], circum)
    cut = np.sqrt(np.maximum(lu, lv) ** 2 + 0.25 * np.minimum(lu, lv) ** 2)
    return float(np.maximum(half, cut).max())


def _lattice(t: np.ndarray, plan):
    """Samples on every triangle: ``a + (i / nu) (b - a) + (j / nv) (c - a)``, ``i / nu +
    j / nv <= 1`` (the apex ``a`` at the shortest side, so that slivers get few samples).
    Returns the samples, their triangle and the covering radius (:func:`lattice_cover`)."""
    order, nu, nv = plan
    t = np.take_along_axis(t, order[:, :, None], axis=1)
    eu, ev = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    du, dv = eu / nu[:, None], ev / nv[:, None]
    cover = lattice_cover(du, dv)
    owner, u, v = _layout(np.ascontiguousarray(nu).tobytes(), np.ascontiguousarray(nv).tobytes())
    points = eu[owner]  # a + u (b - a) + v (c - a), in place (fresh arrays cost page faults)
    points *= u[:, None]
    points += t[owner, 0]
    along = ev[owner]
    along *= v[:, None]
    points += along
    return points, owner, cover


@lru_cache(maxsize=8)
def _layout(nu_bytes: bytes, nv_bytes: bytes):
    """The lattice coordinates of :func:`_lattice` for the steps ``nu, nv`` (int64 bytes):
    every sample's triangle and its ``u = i / nu``, ``v = j / nv``, by triangle. Cached: the
    fits deploy one plan at many states."""
    nu = np.frombuffer(nu_bytes, dtype=np.int64)
    nv = np.frombuffer(nv_bytes, dtype=np.int64)
    owner, us, vs = [], [], []
    for a, b in sorted({(int(x), int(y)) for x, y in zip(nu, nv)}):  # one lattice per class
        members = np.flatnonzero((nu == a) & (nv == b))
        i, j = np.meshgrid(np.arange(a + 1), np.arange(b + 1), indexing="ij")
        keep = i * b + j * a <= a * b
        u, v = i[keep] / a, j[keep] / b
        owner.append(np.repeat(members, len(u)))
        us.append(np.tile(u, len(members)))
        vs.append(np.tile(v, len(members)))
    order = np.argsort(np.concatenate(owner), kind="stable")
    out = tuple(np.concatenate(x)[order] for x in (owner, us, vs))
    for x in out:
        x.flags.writeable = False
    return out
