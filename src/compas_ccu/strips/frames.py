"""Discrete frames of a crease polyline lying in its plane (local ``z = 0``)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.errors import GeometryError
from compas_ccu.tolerances import DIVISION_FLOOR, ROUND_OFF

__all__ = ["CreaseFrames", "crease_frames", "signed_menger_curvature"]


class CreaseFrames(NamedTuple):
    """Per-edge and per-vertex frames of a planar crease polyline.

    Attributes
    ----------
    edges : (n, 2) float
        Unit edge directions ``u_j``.
    lengths : (n,) float
        Edge lengths.
    tangents : (n + 1, 2) float
        Discrete tangent ``T_i``: bisector of the adjacent edge directions; at the two ends the
        end edge turned back by half the turning angle of its neighbouring vertex, which is the
        circle's tangent for a circular polyline.
    normals : (n + 1, 2) float
        ``N_i``: ``T_i`` turned by +90 degrees (towards the left side).
    turns : (n + 1,) float
        Signed turning angle at each vertex (+ = to the left), 0 at the ends.

    Examples
    --------
    >>> import numpy as np
    >>> frames = crease_frames(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]))
    >>> frames.lengths.tolist(), np.degrees(frames.turns).tolist()
    ([1.0, 1.0], [0.0, 90.0, 0.0])
    >>> frames.tangents[1].round(6).tolist()  # the bisector of the two edges
    [0.707107, 0.707107]
    """

    edges: np.ndarray
    lengths: np.ndarray
    tangents: np.ndarray
    normals: np.ndarray
    turns: np.ndarray


def crease_frames(points: np.ndarray) -> CreaseFrames:
    """Frames of a planar polyline.

    Parameters
    ----------
    points : (n + 1, 2) or (n + 1, 3) float
        Polyline vertices; only x and y are used.

    Examples
    --------
    >>> import numpy as np
    >>> f = crease_frames(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]))
    >>> np.degrees(f.turns).tolist(), f.normals[1].round(6).tolist()
    ([0.0, 90.0, 0.0], [-0.707107, 0.707107])
    """
    p = np.asarray(points, dtype=float)[:, :2]
    d = np.diff(p, axis=0)
    lengths = np.hypot(d[:, 0], d[:, 1])
    if np.any(lengths <= ROUND_OFF * max(lengths.sum(), DIVISION_FLOOR)):
        raise GeometryError(f"crease edge {int(np.argmin(lengths))} has zero length")
    u = d / lengths[:, None]
    turns = np.zeros(len(p))
    turns[1:-1] = np.arctan2(
        u[:-1, 0] * u[1:, 1] - u[:-1, 1] * u[1:, 0], np.einsum("ij,ij->i", u[:-1], u[1:])
    )
    t = np.empty_like(p)
    mid = u[:-1] + u[1:]
    t[1:-1] = mid / np.linalg.norm(mid, axis=1)[:, None]
    t[0], t[-1] = u[0], u[-1]
    if len(u) >= 2:  # ends: the edge turned back by half the neighbouring turn (2nd order)
        for end, edge, half in ((0, u[0], -0.5 * turns[1]), (-1, u[-1], 0.5 * turns[-2])):
            c, s = np.cos(half), np.sin(half)
            t[end] = [c * edge[0] - s * edge[1], s * edge[0] + c * edge[1]]
    normals = np.c_[-t[:, 1], t[:, 0]]
    return CreaseFrames(u, lengths, t, normals, turns)


def signed_menger_curvature(points: np.ndarray) -> np.ndarray:
    """(n + 1,) discrete curvature 1/circumradius of consecutive vertices, + when turning left.

    It equals Eq. 6/7 of the paper, ``cos(mu) / (|C| / 2)``, for equal edge lengths; NaN at the
    two end vertices.

    Examples
    --------
    Five vertices of a circle of radius 2 m, traversed clockwise (turning right):

    >>> import numpy as np
    >>> phi = np.linspace(0.75 * np.pi, 0.25 * np.pi, 5)
    >>> signed_menger_curvature(2.0 * np.c_[np.cos(phi), np.sin(phi)]).round(6).tolist()
    [nan, -0.5, -0.5, -0.5, nan]
    """
    p = np.asarray(points, dtype=float)[:, :2]
    f = crease_frames(p)
    k = np.full(len(p), np.nan)
    chord = np.linalg.norm(p[2:] - p[:-2], axis=1)
    k[1:-1] = 2.0 * np.sin(f.turns[1:-1]) / chord
    return k
