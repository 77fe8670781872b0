"""Bending curvature of deployed planar-quad strips.

A developable plate bends about its rulings only: its one non-zero principal curvature lies
across the rulings. On the planar-quad discretisation the bending is concentrated in the fold
angle ``θ_j`` between the quads on either side of ruling ``j``; spread over the width of the
strip it covers, from the middle of one quad to the middle of the next, it gives the discrete
principal curvature at the two ends of that ruling::

    κ_j = θ_j / ((d_j⁻ + d_j⁺) / 2)

where ``d_j^±`` are the distances of the neighbouring boundary vertices from the line of ruling
``j``. The estimate is second-order accurate in the segment length (a cylinder of radius ρ with
rulings ``φ`` apart gives ``κ = φ / (2ρ sin(φ/2))``); for the cone of the ultra-special case it
reproduces ``κ = tan α / ρ`` at distance ρ from the apex.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.geometry import unit

__all__ = ["plate_curvature"]


def _distance_to_lines(points: np.ndarray, base: np.ndarray, direction: np.ndarray) -> np.ndarray:
    d = points - base
    return np.linalg.norm(d - np.einsum("...i,...i", d, direction)[..., None] * direction, axis=-1)


def plate_curvature(vertices) -> np.ndarray:
    """Signed principal (bending) curvature at every vertex of planar-quad strips.

    Parameters
    ----------
    vertices : (..., 2n + 2, 3) float
        Plates in the vertex order of :mod:`compas_ccu.model`: the near boundary
        ``0 .. n`` then the far boundary ``n + 1 .. 2n + 1``; ruling ``j`` joins vertex ``j``
        and ``n + 1 + j``.

    Returns
    -------
    (..., 2n + 2) float
        Curvature in 1/m, positive where the plate bends away from the normal of its quads
        (``(far_{j+1} - near_j) x (far_j - near_{j+1})``): that normal then points to the convex
        side (the extrados). The end rulings, which have a quad on
        one side only, take the value of their neighbour. A single-quad strip is flat (0).

    Examples
    --------
    >>> import numpy as np
    >>> phi = np.linspace(0.0, np.pi / 2, 33)
    >>> ring = np.c_[2 * np.cos(phi), 2 * np.sin(phi), np.zeros_like(phi)]
    >>> cylinder = np.concatenate([ring, ring + [0.0, 0.0, 0.5]])
    >>> k = plate_curvature(cylinder)
    >>> bool(np.allclose(np.abs(k), 0.5, rtol=1e-3))
    True
    """
    v = np.asarray(vertices, dtype=float)
    if v.ndim < 2 or v.shape[-1] != 3 or v.shape[-2] % 2 or v.shape[-2] < 4:
        raise ValueError(f"vertices must have shape (..., 2n + 2, 3) with n >= 1, got {v.shape}")
    n = v.shape[-2] // 2 - 1
    near, far = v[..., : n + 1, :], v[..., n + 1 :, :]
    out = np.zeros(v.shape[:-1])
    if n < 2:
        return out
    a, b, c, d = near[..., :-1, :], near[..., 1:, :], far[..., 1:, :], far[..., :-1, :]
    normals = unit(np.cross(c - a, d - b))  # (..., n, 3)
    ruling = unit(far - near)  # (..., n + 1, 3)
    n0, n1, r = normals[..., :-1, :], normals[..., 1:, :], ruling[..., 1:-1, :]
    theta = np.arctan2(np.einsum("...i,...i", np.cross(n0, n1), r), np.einsum("...i,...i", n0, n1))
    kappa = []
    for side in (near, far):
        base = side[..., 1:-1, :]
        width = 0.5 * (
            _distance_to_lines(side[..., :-2, :], base, r)
            + _distance_to_lines(side[..., 2:, :], base, r)
        )
        with np.errstate(divide="ignore", invalid="ignore"):
            k = theta / width
        kappa.append(np.concatenate([k[..., :1], k, k[..., -1:]], axis=-1))
    out[..., : n + 1] = kappa[0]
    out[..., n + 1 :] = kappa[1]
    return out
