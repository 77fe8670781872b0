"""Explicit polyline profile."""

from __future__ import annotations

import numpy as np

from compas_ccu.curves.base import Profile, require_points, require_segments
from compas_ccu.curves.discrete import discrete_curvature

__all__ = ["PolylineProfile"]


class PolylineProfile(Profile):
    """An explicit polyline, evaluated by arc length along its straight edges.

    ``point(s)`` interpolates linearly along the edges. Its ``curvature(s)`` is DISCRETE: the
    signed Menger curvature (inverse circumradius of a vertex and its two neighbours, see
    :func:`~compas_ccu.curves.discrete.discrete_curvature`) at the interior vertices, the end
    vertices taking the value of their neighbour, linearly interpolated in arc length between
    the vertices. It is not the curvature of the polyline itself, which is zero on the edges
    and singular at the vertices.

    Parameters
    ----------
    points : (n, 2) array_like of float
        Vertices, m, n >= 3, consecutive vertices distinct, in the order of traversal.

    Raises
    ------
    ProfileError
        If the points are not a finite (n, 2) array with n >= 3 and distinct consecutive
        points.

    Examples
    --------
    >>> roof = PolylineProfile([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]])
    >>> round(roof.length, 6), roof.point(roof.length / 2).tolist()
    (2.828427, [1.0, 1.0])
    >>> roof.curvature([0.0, roof.length]).round(6).tolist()  # the circle through the 3 vertices
    [-1.0, -1.0]
    """

    name = "polyline"

    def __init__(self, points: object):
        self._vertices = require_points(points)
        edge_lengths = np.linalg.norm(np.diff(self._vertices, axis=0), axis=1)
        self._vertex_s = np.concatenate([[0.0], np.cumsum(edge_lengths)])
        curvature = discrete_curvature(self._vertices)
        curvature[0], curvature[-1] = curvature[1], curvature[-2]
        self._vertex_curvature = curvature

    @property
    def vertices(self) -> np.ndarray:
        """(n, 2) float: the given vertices (a copy), m."""
        return self._vertices.copy()

    @property
    def vertex_s(self) -> np.ndarray:
        """(n,) float: arc lengths of the vertices along the polyline, m."""
        return self._vertex_s.copy()

    @property
    def vertex_curvature(self) -> np.ndarray:
        """(n,) float: discrete (Menger) curvature at the vertices, ends copied, 1/m."""
        return self._vertex_curvature.copy()

    @property
    def length(self) -> float:
        """Total length of the edges, m."""
        return float(self._vertex_s[-1])

    @property
    def start_point(self) -> np.ndarray:
        """(2,) float: the first vertex, m."""
        return self._vertices[0].copy()

    @property
    def end_point(self) -> np.ndarray:
        """(2,) float: the last vertex, m."""
        return self._vertices[-1].copy()

    def parameters(self) -> dict:
        """``{"points": [[x, y], ...]}``."""
        return {"points": self._vertices.tolist()}

    def sample_s(self, segments: int | None = None) -> np.ndarray:
        """Arc lengths of equally spaced samples, or of the vertices if ``segments`` is None.

        Parameters
        ----------
        segments : int or None, optional
            Number of segments, >= 2; None (default) for the given vertices.

        Returns
        -------
        (segments + 1,) or (n,) float
            Arc lengths, m.
        """
        if segments is None:
            return self.vertex_s
        return super().sample_s(segments)

    def sample(self, segments: int | None = None) -> np.ndarray:
        """Points resampled at equal arc length along the polyline, or the given vertices.

        Parameters
        ----------
        segments : int or None, optional
            Number of segments, >= 2; None (default) returns the given vertices unchanged.

        Returns
        -------
        (segments + 1, 2) or (n, 2) float
            Points on the polyline, m. Resampled points lie on the edges, so the polyline
            through them cuts the corners of the given one unless they fall on its vertices.

        Raises
        ------
        ProfileError
            If ``segments`` is neither None nor an integer >= 2.
        """
        if segments is None:
            return self.vertices
        return self.point(self.sample_s(require_segments(segments)))

    # -- evaluation ---------------------------------------------------------------------------

    def _edge_of(self, s: np.ndarray) -> np.ndarray:
        """Index of the edge containing ``s``; at a vertex, the edge that starts there."""
        edges = np.searchsorted(self._vertex_s, s, side="right") - 1
        return np.clip(edges, 0, len(self._vertices) - 2)

    def _point(self, s: np.ndarray) -> np.ndarray:
        x = np.interp(s, self._vertex_s, self._vertices[:, 0])
        y = np.interp(s, self._vertex_s, self._vertices[:, 1])
        return np.stack([x, y], axis=-1)

    def _tangent_angle(self, s: np.ndarray) -> np.ndarray:
        """Angle of the edge containing ``s`` (at an interior vertex, of the outgoing edge)."""
        edge_vectors = np.diff(self._vertices, axis=0)
        edge_angles = np.arctan2(edge_vectors[:, 1], edge_vectors[:, 0])
        return edge_angles[self._edge_of(s)]

    def _curvature(self, s: np.ndarray) -> np.ndarray:
        return np.interp(s, self._vertex_s, self._vertex_curvature)
