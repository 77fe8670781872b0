"""Parametric cubic spline profile through control points."""

from __future__ import annotations

import numpy as np

from compas_ccu.curves.base import Profile, require_points
from compas_ccu.curves.funicular_arc_length import (
    MAX_BISECTIONS,
    NEWTON_MAX_ITERATIONS,
    NEWTON_TOLERANCE,
    QUADRATURE_TOLERANCE,
    gauss_legendre_rule,
)
from compas_ccu.errors import ProfileError

__all__ = ["SplineProfile"]

#: End conditions accepted for the spline (``"clamped"`` is excluded: it stops the curve).
BOUNDARY_CONDITIONS = ("natural", "not-a-knot")


class SplineProfile(Profile):
    """Smooth parametric cubic spline through control points, evaluated by arc length.

    The spline ``c(t) = (x(t), y(t))`` interpolates the points at the chord-length parameter
    ``t_i = sum_j<i |p_{j+1} - p_j|`` (:class:`scipy.interpolate.CubicSpline`). The arc length
    ``S(t) = int |c'|`` is computed by adaptive 16-point Gauss-Legendre quadrature (the spline
    pieces are bisected until each cell is integrated to about 1e-14 of the length). Arc
    lengths are mapped to parameters by safeguarded Newton iterations on ``S(t) - s`` to 1e-14
    relative. The curvature is the exact curvature of the spline,
    ``(x' y'' - y' x'') / |c'|^3``; it may change sign (inflection points) and is continuous,
    while its derivative jumps at the control points. Hence the discrete (Menger) curvature of
    ``sample(n)`` converges to it at second order only at samples whose two neighbours lie on
    the same spline piece; where a control point lies between the neighbours the error is of
    first order in ``length / n``.

    Parameters
    ----------
    points : (n, 2) array_like of float
        Control points, m, n >= 3, consecutive points distinct, in the order of traversal.
    bc_type : {"natural", "not-a-knot"}, optional
        End conditions of the spline; ``"natural"`` (default) gives zero curvature at the ends.

    Raises
    ------
    ProfileError
        If the points are not a finite (n, 2) array with n >= 3 and distinct consecutive
        points, or if ``bc_type`` is not allowed.

    Examples
    --------
    >>> spline = SplineProfile([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]])
    >>> round(spline.length, 6), spline.point(spline.length / 2).round(6).tolist()
    (2.914479, [1.0, 1.0])
    >>> s = [0.0, spline.length / 2, spline.length]
    >>> [round(float(k), 6) + 0.0 for k in spline.curvature(s)]
    [0.0, -3.0, 0.0]
    """

    name = "spline"

    def __init__(self, points: object, *, bc_type: str = "natural"):
        from scipy.interpolate import CubicSpline

        if not isinstance(bc_type, str) or bc_type not in BOUNDARY_CONDITIONS:
            raise ProfileError(
                f"bc_type must be one of {', '.join(map(repr, BOUNDARY_CONDITIONS))}, "
                f"got {bc_type!r}"
            )
        self._points = require_points(points)
        self._bc_type = bc_type
        chords = np.linalg.norm(np.diff(self._points, axis=0), axis=1)
        self._knots = np.concatenate([[0.0], np.cumsum(chords)])
        self._spline = CubicSpline(self._knots, self._points, bc_type=bc_type, axis=0)
        self._first_derivative = self._spline.derivative(1)
        self._second_derivative = self._spline.derivative(2)
        self._breaks, self._break_lengths = self._arc_length_table()

    # -- properties ---------------------------------------------------------------------------

    @property
    def control_points(self) -> np.ndarray:
        """(n, 2) float: the control points (a copy), m."""
        return self._points.copy()

    @property
    def bc_type(self) -> str:
        """End conditions of the spline."""
        return self._bc_type

    @property
    def spline(self):
        """The :class:`scipy.interpolate.CubicSpline` ``c(t)`` on the chord-length parameter."""
        return self._spline

    @property
    def knots(self) -> np.ndarray:
        """(n,) float: chord-length parameters of the control points, m."""
        return self._knots.copy()

    @property
    def length(self) -> float:
        """Arc length of the spline, m."""
        return float(self._break_lengths[-1])

    @property
    def start_point(self) -> np.ndarray:
        """(2,) float: the first control point, m."""
        return self._points[0].copy()

    @property
    def end_point(self) -> np.ndarray:
        """(2,) float: the last control point, m."""
        return self._points[-1].copy()

    def parameters(self) -> dict:
        """``{"points": [[x, y], ...], "bc_type": str}``."""
        return {"points": self._points.tolist(), "bc_type": self._bc_type}

    # -- arc length <-> parameter -------------------------------------------------------------

    def speed(self, t: object) -> np.ndarray:
        """Speed ``|c'(t)|`` of the spline at parameters ``t`` (any shape), dimensionless."""
        derivative = self._first_derivative(np.asarray(t, dtype=float))
        return np.hypot(derivative[..., 0], derivative[..., 1])

    def arc_length_at_parameter(self, t: object) -> np.ndarray:
        """Arc length ``S(t)`` from the start to the spline parameters ``t``.

        Parameters
        ----------
        t : (k,) array_like of float
            Spline parameters in ``[0, knots[-1]]`` (clipped).

        Returns
        -------
        (k,) float
            Arc lengths, m.
        """
        t = np.clip(np.asarray(t, dtype=float), 0.0, self._breaks[-1])
        return self._arc_length_in_cell(self._cell_of(t, self._breaks), t)

    def parameter_at(self, s: object) -> np.ndarray:
        """Spline parameters ``t`` with ``S(t) = s``, accurate to about 1e-14 relative.

        Parameters
        ----------
        s : (k,) array_like of float
            Arc lengths in ``[0, length]``, m.

        Returns
        -------
        (k,) float
            Spline parameters.
        """
        s = self._checked_s(s)
        breaks, break_lengths = self._breaks, self._break_lengths
        cell = self._cell_of(s, break_lengths)
        lower, upper = breaks[cell], breaks[cell + 1]
        fraction = (s - break_lengths[cell]) / (break_lengths[cell + 1] - break_lengths[cell])
        t = lower + fraction * (upper - lower)
        tolerance = NEWTON_TOLERANCE * self.length
        for _ in range(NEWTON_MAX_ITERATIONS):
            residual = self._arc_length_in_cell(cell, t) - s
            active = np.abs(residual) > tolerance
            if not active.any():
                break
            # S is increasing: keep a bracket [lower, upper] and bisect when Newton leaves it.
            upper = np.where(residual > 0.0, t, upper)
            lower = np.where(residual < 0.0, t, lower)
            with np.errstate(divide="ignore", invalid="ignore"):
                newton = t - residual / self.speed(t)
            inside = (newton >= lower) & (newton <= upper)
            t = np.where(active, np.where(inside, newton, 0.5 * (lower + upper)), t)
        return t

    def _arc_length_table(self) -> tuple:
        """Cells ``[breaks[j], breaks[j+1]]`` of the parameter and the arc lengths at ``breaks``.

        Adaptive bisection, vectorised over all cells of one level: starting from the spline
        pieces, a cell is accepted (as its two halves) when the Gauss-Legendre integral of the
        speed over the whole cell agrees with the sum over its halves to
        ``QUADRATURE_TOLERANCE * length``; otherwise both halves are bisected further.
        """
        lower, upper = self._knots[:-1], self._knots[1:]
        tolerance = QUADRATURE_TOLERANCE * self._gauss_legendre(lower, upper).sum()
        accepted_lower, accepted_lengths = [], []
        for depth in range(MAX_BISECTIONS + 1):
            middle = 0.5 * (lower + upper)
            whole = self._gauss_legendre(lower, upper)
            left = self._gauss_legendre(lower, middle)
            right = self._gauss_legendre(middle, upper)
            done = np.abs(left + right - whole) <= tolerance
            if depth == MAX_BISECTIONS:  # (a cusp of the spline) accept what there is
                done[:] = True
            accepted_lower += [lower[done], middle[done]]
            accepted_lengths += [left[done], right[done]]
            lower = np.concatenate([lower[~done], middle[~done]])
            upper = np.concatenate([middle[~done], upper[~done]])
            if lower.size == 0:
                break
        cell_lower = np.concatenate(accepted_lower)
        order = np.argsort(cell_lower, kind="stable")
        breaks = np.append(cell_lower[order], self._knots[-1])
        cell_lengths = np.concatenate(accepted_lengths)[order]
        return breaks, np.concatenate([[0.0], np.cumsum(cell_lengths)])

    def _gauss_legendre(self, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
        """Integral of the speed over ``[lower, upper]`` (elementwise), Gauss-Legendre."""
        gauss_nodes, gauss_weights = gauss_legendre_rule()
        half = 0.5 * (upper - lower)
        nodes = (0.5 * (upper + lower))[..., None] + half[..., None] * gauss_nodes
        return half * (self.speed(nodes) @ gauss_weights)

    def _arc_length_in_cell(self, cell: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Arc length at parameters ``t`` lying in the sub-intervals ``cell``."""
        start = self._breaks[cell]
        return self._break_lengths[cell] + self._gauss_legendre(start, t)

    @staticmethod
    def _cell_of(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
        return np.clip(np.searchsorted(edges, values, side="right") - 1, 0, len(edges) - 2)

    # -- evaluation ---------------------------------------------------------------------------

    def _point(self, s: np.ndarray) -> np.ndarray:
        return self._spline(self.parameter_at(s))

    def _tangent_angle(self, s: np.ndarray) -> np.ndarray:
        derivative = self._first_derivative(self.parameter_at(s))
        return np.arctan2(derivative[..., 1], derivative[..., 0])

    def _curvature(self, s: np.ndarray) -> np.ndarray:
        t = self.parameter_at(s)
        first = self._first_derivative(t)
        second = self._second_derivative(t)
        cross = first[..., 0] * second[..., 1] - first[..., 1] * second[..., 0]
        return cross / np.linalg.norm(first, axis=-1) ** 3
