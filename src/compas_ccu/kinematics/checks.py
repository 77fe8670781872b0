"""Validity checks of placed states: creases that overlap themselves in their plane."""

from __future__ import annotations

import numpy as np

__all__ = ["total_turning", "self_intersecting"]


def total_turning(points: np.ndarray) -> np.ndarray:
    """Total absolute turning angle of polylines, radians.

    Parameters
    ----------
    points : (k, m, 3) float

    Returns
    -------
    (k,) float
    """
    e = np.diff(points, axis=1)
    cross = np.linalg.norm(np.cross(e[:, :-1], e[:, 1:]), axis=-1)
    dot = np.einsum("kmi,kmi->km", e[:, :-1], e[:, 1:])
    return np.arctan2(cross, dot).sum(axis=1)


def self_intersecting(points: np.ndarray, origins: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Which planar polylines overlap themselves.

    A polyline whose total absolute turning is at most pi cannot intersect itself, which settles
    almost every state at the cost of one vectorised pass; the others are projected onto their
    plane and tested with GEOS (shapely), O(m log m).

    Parameters
    ----------
    points : (k, m, 3) float
    origins, normals : (k, 3) float
        Planes of the polylines.

    Returns
    -------
    (k,) bool
    """
    out = np.zeros(len(points), dtype=bool)
    suspects = np.flatnonzero(total_turning(points) > np.pi)
    if suspects.size == 0:
        return out
    import shapely

    for k in suspects:
        n = normals[k]
        x = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        x /= np.linalg.norm(x)
        y = np.cross(n, x)
        rel = points[k] - origins[k]
        line = shapely.linestrings(np.c_[rel @ x, rel @ y])
        out[k] = not shapely.is_simple(line)
    return out
