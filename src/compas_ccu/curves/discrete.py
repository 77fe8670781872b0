"""Discrete (Menger) curvature of planar polylines."""

from __future__ import annotations

import numpy as np

from compas_ccu.curves.base import require_points

__all__ = ["discrete_curvature"]


def discrete_curvature(points: object) -> np.ndarray:
    """Signed Menger curvature at the interior vertices of a planar polyline.

    At vertex ``i`` this is the inverse radius of the circle through ``points[i - 1]``,
    ``points[i]`` and ``points[i + 1]``::

        kappa_i = 2 cross(p_i - p_{i-1}, p_{i+1} - p_i) / (|p_i - p_{i-1}| |p_{i+1} - p_i|
                                                           |p_{i+1} - p_{i-1}|)

    positive where the polyline turns counter-clockwise (left). On a smooth curve sampled at
    equal arc-length spacing ``h`` it approximates the curvature with an ``O(h^2)`` error.

    Parameters
    ----------
    points : (n, 2) array_like of float
        Polyline vertices, m, n >= 3, consecutive vertices distinct.

    Returns
    -------
    (n,) float
        Signed curvature, 1/m; NaN at the two end vertices.

    Raises
    ------
    compas_ccu.errors.ProfileError
        If ``points`` is not a finite (n, 2) array with n >= 3 and distinct consecutive points.

    Examples
    --------
    Three points of the unit circle, traversed counter-clockwise (turning left):

    >>> kappa = discrete_curvature([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]])
    >>> kappa.shape, round(float(kappa[1]), 6)
    ((3,), 1.0)
    """
    vertices = require_points(points)
    incoming = vertices[1:-1] - vertices[:-2]
    outgoing = vertices[2:] - vertices[1:-1]
    across = vertices[2:] - vertices[:-2]
    cross = incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0]
    denominator = (
        np.linalg.norm(incoming, axis=1)
        * np.linalg.norm(outgoing, axis=1)
        * np.linalg.norm(across, axis=1)
    )
    curvature = np.full(len(vertices), np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        # A vertex whose neighbours coincide (a hairpin) has an undefined circle: NaN.
        curvature[1:-1] = np.where(denominator > 0.0, 2.0 * cross / denominator, np.nan)
    return curvature
