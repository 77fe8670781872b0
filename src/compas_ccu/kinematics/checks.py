"""Validity checks: cut patterns whose rulings cross, creases that overlap themselves."""

from __future__ import annotations

import numpy as np

from compas_ccu.geometry import cross3, norm3

__all__ = ["total_turning", "self_intersecting", "planar_overlaps", "crossing_rulings"]


def crossing_rulings(patterns: np.ndarray, quads: np.ndarray):
    """The first quad of a cut pattern whose two rulings cross (the pattern folds over itself).

    Parameters
    ----------
    patterns : (p, v, 2) float
        Cut patterns of ``p`` plates.
    quads : (n, 4) int
        Quad ``j``'s vertices ``a, b, c, d`` with rulings ``a-d`` and ``b-c``.

    Returns
    -------
    (plate, quad) or None

    >>> import numpy as np
    >>> good = np.array([[[0.0, 0], [1, 0], [1, 1], [0, 1]]])
    >>> crossing_rulings(good, np.array([[0, 1, 2, 3]])) is None
    True
    >>> crossing_rulings(good[:, [0, 1, 3, 2]], np.array([[0, 1, 2, 3]]))
    (0, 0)
    """
    a, b, c, d = (patterns[:, quads[:, i]] for i in range(4))
    # rulings a-d and b-c of a quad must not meet: a + s (d - a) = b + t (c - b)
    u, v, w = d - a, c - b, b - a

    def cross(p, q):
        return p[..., 0] * q[..., 1] - p[..., 1] * q[..., 0]

    den = cross(u, v)
    with np.errstate(divide="ignore", invalid="ignore"):
        s, t = cross(w, v) / den, cross(w, u) / den
    bad = np.argwhere((den != 0.0) & (s > 0.0) & (s <= 1.0) & (t > 0.0) & (t <= 1.0))
    if bad.size == 0:
        return None
    return int(bad[0, 0]), int(bad[0, 1])


def total_turning(points: np.ndarray) -> np.ndarray:
    """Total absolute turning angle of polylines, radians.

    Parameters
    ----------
    points : (k, m, 3) float

    Returns
    -------
    (k,) float

    Examples
    --------
    A right angle and a straight line:

    >>> import numpy as np
    >>> bent = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]
    >>> straight = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
    >>> np.degrees(total_turning(np.array([bent, straight]))).round(6).tolist()
    [90.0, 0.0]
    """
    e = np.diff(points, axis=1)
    cross = norm3(cross3(e[:, :-1], e[:, 1:]))
    dot = np.einsum("kmi,kmi->km", e[:, :-1], e[:, 1:])
    return np.arctan2(cross, dot).sum(axis=1)


def self_intersecting(points: np.ndarray, origins: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Which planar polylines overlap themselves.

    A polyline whose total absolute turning is at most pi cannot intersect itself, which settles
    almost every state at the cost of one vectorised pass; the others are projected onto their
    plane and tested with GEOS (shapely), O(m log m), all in one vectorised call.

    Parameters
    ----------
    points : (k, m, 3) float
    origins, normals : (k, 3) float
        Planes of the polylines.

    Returns
    -------
    (k,) bool

    Examples
    --------
    A square spiral whose last edge crosses its first, and an open square:

    >>> import numpy as np
    >>> spiral = [[0, 0, 0], [2, 0, 0], [2, 2, 0], [1, 2, 0], [1, -1, 0]]
    >>> square = [[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [0, 1, 0]]
    >>> points = np.array([spiral, square], dtype=float)
    >>> self_intersecting(points, np.zeros((2, 3)), np.array([[0.0, 0.0, 1.0]] * 2)).tolist()
    [True, False]
    """
    out = np.zeros(len(points), dtype=bool)
    suspects = np.flatnonzero(total_turning(points) > np.pi)
    if suspects.size:
        out[suspects] = planar_overlaps(points[suspects], origins[suspects], normals[suspects])
    return out


def planar_overlaps(points: np.ndarray, origins: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Which planar polylines overlap themselves, by GEOS alone: each projected onto its plane,
    all tested in one vectorised call (:func:`self_intersecting` asks it for the polylines that
    turn by more than pi; each polyline's answer is its own, whichever are tested together).
    Parameters and result as :func:`self_intersecting`'s.
    """
    import shapely

    n = normals
    helper = np.where(
        (np.abs(n[:, 0]) < 0.9)[:, None], np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    )
    x = cross3(n, helper)  # numpy.cross and numpy.linalg.norm's values, bit for bit
    x /= norm3(x)[:, None]
    y = cross3(n, x)
    rel = points - origins[:, None]
    xy = np.stack([np.einsum("kmi,ki->km", rel, x), np.einsum("kmi,ki->km", rel, y)], axis=-1)
    return ~shapely.is_simple(shapely.linestrings(xy))
