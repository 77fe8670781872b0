"""An independent oracle for plates passing through each other: brute-force triangle tests.

It shares no code with :mod:`compas_ccu` (only NumPy): every quad of every plate is split into
two triangles and every triangle edge of one plate is tested against every triangle of every
other plate (after a bounding-box cull) with orientation determinants. A crossing counts when the
edge's ends lie strictly on both sides of the triangle's plane (distances beyond ``eps`` of the
structure's size) and the crossing point lies in the closed triangle (within ``eps``: two mirror
images straddling their mirror plane meet exactly on their edges), so plates that only touch
(the flat stack, a hinge) do not count.
"""

from __future__ import annotations

import numpy as np


def _triangles(vertices):
    """(p, 2n, 3, 3) triangles of (p, 2n + 2, 3) plate vertices (near row, then far row)."""
    m = vertices.shape[1] // 2
    j = np.arange(m - 1)
    a, b, c, d = j, j + 1, m + j + 1, m + j
    tri = np.stack([np.stack([a, b, c], 1), np.stack([a, c, d], 1)], 1).reshape(-1, 3)
    return vertices[:, tri]


def quad_warp(vertices) -> np.ndarray:
    """(p, 2n) float: per triangle, the distance of its quad's fourth corner from the plane of
    the other three, m: how far the geometry itself is from planar quads (its two
    triangulations differ by that much)."""
    m = vertices.shape[1] // 2
    j = np.arange(m - 1)
    a, b, c, d = (vertices[:, idx] for idx in (j, j + 1, m + j + 1, m + j))
    normal = np.cross(b - a, c - a)
    area = np.linalg.norm(normal, axis=-1)
    height = np.abs(np.einsum("...i,...i->...", d - a, normal)) / np.where(area > 0, area, 1.0)
    return np.repeat(np.where(area > 0, height, 0.0), 2, axis=1)


def crossing_pairs(vertices, *, eps=1e-9, warp=2.0):
    """Plate pairs ``(a, b)``, a < b, whose triangles cross in one state.

    Parameters
    ----------
    vertices : (p, 2n + 2, 3) float
        Every plate's vertices, near row then far row (``Structure.deployed``).
    eps : float
        Relative to the structure's size: distances within it of a triangle, or within twice
        the warp of its quad (:func:`quad_warp`: where the quads are not exactly planar, their
        triangles and the quads differ by that much), count as zero.
    warp : float
        The multiple of a quad's warp that counts as zero.
    """
    vertices = np.asarray(vertices, float)
    size = float(np.linalg.norm(np.ptp(vertices.reshape(-1, 3), axis=0)))
    tol = eps * size
    face_tol = np.maximum(tol, warp * quad_warp(vertices))  # (p, 2n): per triangle
    tris = _triangles(vertices)  # (p, T, 3, 3)
    p = tris.shape[0]
    lo, hi = tris.min(axis=2), tris.max(axis=2)
    out = []
    for pa in range(p):
        for pb in range(pa + 1, p):
            if np.any(lo[pa].min(0) > hi[pb].max(0) + tol) or np.any(
                lo[pb].min(0) > hi[pa].max(0) + tol
            ):
                continue
            ia, ib = np.nonzero(
                np.all(lo[pa][:, None] <= hi[pb][None] + tol, axis=-1)
                & np.all(lo[pb][None] <= hi[pa][:, None] + tol, axis=-1)
            )
            if not len(ia):
                continue
            ta, tb = tris[pa][ia], tris[pb][ib]
            # a vertex that one plate shares with the other (a hinge) only touches it: the
            # edges from it are not tested
            va, vb = vertices[pa], vertices[pb]
            close = np.linalg.norm(va[:, None] - vb[None], axis=-1) < tol
            on_a = _on(ta, va[close.any(axis=1)], tol)
            on_b = _on(tb, vb[close.any(axis=0)], tol)
            fa, fb = face_tol[pa][ia], face_tol[pb][ib]
            if _edges_cross(ta, tb, fb, on_a) or _edges_cross(tb, ta, fa, on_b):
                out.append((pa, pb))
    return out


def _on(triangles, shared, tol):
    """(N, 3) bool: the corners of ``triangles`` (N, 3, 3) that are ``shared`` points."""
    if not len(shared):
        return np.zeros(triangles.shape[:2], dtype=bool)
    return (np.linalg.norm(triangles[:, :, None] - shared[None, None], axis=-1) < tol).any(-1)


def _edges_cross(ta, tb, tol, shared):
    """Any edge of a triangle of ``ta`` through its partner in ``tb``: its ends on both sides
    of the partner's plane by more than ``tol`` (distances, not volumes, so that a grazing
    crossing counts), the crossing point in the partner or within ``tol`` of it; edges with a
    ``shared`` end (N, 3) are not tested."""
    if not len(ta):
        return False
    tol = np.broadcast_to(tol, (len(tb),))
    a, b, c = tb[:, 0], tb[:, 1], tb[:, 2]
    normal = np.cross(b - a, c - a)
    area = np.linalg.norm(normal, axis=-1)
    ok = area > 0.0
    normal = normal / np.where(ok, area, 1.0)[:, None]
    for e0, e1 in ((0, 1), (1, 2), (2, 0)):
        p, q = ta[:, e0], ta[:, e1]
        hp = np.einsum("ij,ij->i", p - a, normal)
        hq = np.einsum("ij,ij->i", q - a, normal)
        sides = ok & (((hp > tol) & (hq < -tol)) | ((hp < -tol) & (hq > tol)))
        sides &= ~(shared[:, e0] | shared[:, e1])
        if not sides.any():
            continue
        s = hp[sides] / (hp[sides] - hq[sides])
        x = p[sides] + s[:, None] * (q[sides] - p[sides])
        inside = np.ones(len(x), dtype=bool)
        n = normal[sides]
        corners = (a[sides], b[sides], c[sides])
        for i in range(3):
            u, v = corners[i], corners[(i + 1) % 3]
            inward = np.cross(n, v - u)
            inward /= np.linalg.norm(inward, axis=-1, keepdims=True)
            inside &= np.einsum("ij,ij->i", x - u, inward) > -tol[sides]
        if inside.any():
            return True
    return False
