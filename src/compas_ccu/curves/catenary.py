"""Inverted catenary arch profile."""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.curves.base import SpanRiseProfile, require_positive
from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = ["CatenaryProfile"]


def _log_rise_ratio(t: float) -> float:
    """``log((cosh t - 1) / t)`` for ``t > 0``, without overflow or cancellation.

    ``cosh t - 1 = 2 sinh(t/2)^2`` and ``log sinh(x) = x + log(-expm1(-2x)) - log 2``.
    """
    half = 0.5 * t
    log_sinh_half = half + math.log(-math.expm1(-t)) - math.log(2.0)
    return math.log(2.0) + 2.0 * log_sinh_half - math.log(t)


def solve_catenary_parameter(*, span: float, rise: float) -> float:
    """Catenary parameter ``a`` with ``rise = a (cosh(span / (2 a)) - 1)``.

    Solves ``(cosh t - 1) / t = rise / (span/2)`` for ``t = span / (2 a)``; the left side
    increases monotonically from 0 to infinity, so there is exactly one root for any
    ``rise / span > 0``. The root is bracketed in ``[min(r, 1), 2 r]`` with ``r = 2 rise/span``
    (since ``t/2 <= (cosh t - 1)/t <= (t/2) cosh(t/2)^2``) and found by Brent's method on the
    logarithm, to about 1e-15 relative.

    Parameters
    ----------
    span : float
        Distance between the end points, m, > 0.
    rise : float
        Height of the apex, m, > 0.

    Returns
    -------
    float
        ``a``, m.
    """
    from scipy.optimize import brentq

    ratio = 2.0 * rise / span
    log_ratio = math.log(ratio)
    t = brentq(
        lambda t: _log_rise_ratio(t) - log_ratio,
        min(ratio, 1.0),
        2.0 * ratio,
        xtol=DIVISION_FLOOR,
        rtol=4.0 * np.finfo(float).eps,
        maxiter=500,
    )
    return 0.5 * span / t


class CatenaryProfile(SpanRiseProfile):
    """Inverted catenary arch ``y = rise - a (cosh(x/a) - 1)`` for ``x`` in ``[-span/2, span/2]``.

    The arc length measured from the apex is ``sigma = a sinh(x/a)``, so the profile is
    evaluated in closed form at any arc length ``s = sigma + length/2``::

        x = a asinh(sigma/a),  y = rise - sigma^2 / (a + sqrt(a^2 + sigma^2)),
        tangent angle = -atan(sigma/a),  curvature = -1/(a cosh(x/a)^2) = -a/(a^2 + sigma^2).

    Parameters
    ----------
    span : float
        Distance between the end points ``(-span/2, 0)`` and ``(span/2, 0)``, m, > 0.
    rise : float
        Height of the apex ``(0, rise)``, m, > 0.

    Raises
    ------
    ProfileError
        If ``span`` or ``rise`` is not a real finite number > 0.

    Examples
    --------
    >>> arch = CatenaryProfile(span=4.0, rise=1.0)
    >>> round(arch.length, 6), arch.point(arch.length / 2).round(6).tolist()  # length, apex
    (4.603164, [0.0, 1.0])
    >>> round(float(arch.curvature(arch.length / 2)), 6)  # -1 / a at the apex
    -0.465411
    """

    name = "catenary"

    def __init__(self, *, span: float, rise: float):
        self._span = require_positive("span", span)
        self._rise = require_positive("rise", rise)
        self._a = solve_catenary_parameter(span=self._span, rise=self._rise)
        self._length = 2.0 * self._a * math.sinh(0.5 * self._span / self._a)

    @property
    def a(self) -> float:
        """Catenary parameter ``a`` (radius of curvature at the apex), m."""
        return self._a

    def arc_length_at_x(self, x: object) -> np.ndarray:
        """Arc length from the start to the point of abscissa ``x``.

        Parameters
        ----------
        x : (k,) array_like of float
            Abscissae in ``[-span/2, span/2]``, m (not checked).

        Returns
        -------
        (k,) float
            ``a (sinh(x/a) + sinh(span/(2a)))``, m.
        """
        x = np.asarray(x, dtype=float)
        return self._a * np.sinh(x / self._a) + 0.5 * self._length

    # -- evaluation ---------------------------------------------------------------------------

    def _point(self, s: np.ndarray) -> np.ndarray:
        sigma = s - 0.5 * self._length
        a = self._a
        x = a * np.arcsinh(sigma / a)
        y = self._rise - sigma * sigma / (a + np.hypot(a, sigma))
        return np.stack([x, y], axis=-1)

    def _tangent_angle(self, s: np.ndarray) -> np.ndarray:
        return -np.arctan((s - 0.5 * self._length) / self._a)

    def _curvature(self, s: np.ndarray) -> np.ndarray:
        sigma = s - 0.5 * self._length
        return -self._a / (self._a * self._a + sigma * sigma)
