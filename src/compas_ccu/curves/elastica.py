"""Euler elastica profile with pinned ends (first buckling mode)."""

from __future__ import annotations

import functools
import math

import numpy as np

from compas_ccu.curves.base import SpanRiseProfile, require_positive
from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = ["ElasticaProfile"]

_EPS = float(np.finfo(float).eps)


@functools.lru_cache(maxsize=1)
def largest_modulus() -> float:
    """Elliptic modulus ``k_max`` (~0.9089) where ``2 E(k) = K(k)``: the ends touch (span 0)."""
    from scipy.optimize import brentq
    from scipy.special import ellipe, ellipk

    return brentq(
        lambda k: 2.0 * ellipe(k * k) - ellipk(k * k),
        0.5,
        0.99,
        xtol=DIVISION_FLOOR,
        rtol=4.0 * _EPS,
    )


def solve_elastica_modulus(*, span: float, rise: float) -> float:
    """Elliptic modulus ``k`` of the pinned elastica of the given span and rise.

    Solves ``rise / span = k / (2 E(k) - K(k))`` (complete elliptic integrals of modulus
    ``k``), whose right side increases monotonically from 0 at ``k = 0`` to infinity at
    ``k = k_max`` (see :func:`largest_modulus`), so there is one root for any ``rise/span > 0``.

    Returns
    -------
    float
        ``k = sin(theta0 / 2)`` with ``theta0`` the tangent angle at the left end.
    """
    from scipy.optimize import brentq
    from scipy.special import ellipe, ellipk

    ratio = rise / span
    return brentq(
        lambda k: k - ratio * (2.0 * ellipe(k * k) - ellipk(k * k)),
        0.0,
        largest_modulus(),
        xtol=DIVISION_FLOOR,
        rtol=4.0 * _EPS,
        maxiter=500,
    )


class ElasticaProfile(SpanRiseProfile):
    """Euler elastica with pinned ends: the first buckling mode of an inextensible rod.

    The curvature vanishes at the end points ``(-span/2, 0)``, ``(span/2, 0)`` and is
    proportional to the height above the chord, ``curvature = -wavenumber**2 * y``. With the
    elliptic modulus ``k = sin(theta0 / 2)`` (``theta0`` the tangent angle at the left end),
    the wavenumber ``lambda`` and ``u = K(k) - lambda s``::

        x(s) = ((2 E(k) - K(k)) - (2 E(am u, k) - u)) / lambda - span/2
             = (u - 2 E(am u, k)) / lambda
        y(s) = (2 k / lambda) cn(u, k)
        sin(theta(s) / 2) = k sn(u, k),     curvature(s) = -2 k lambda cn(u, k)

    so that ``span = 2 (2 E(k) - K(k)) / lambda``, ``rise = 2 k / lambda`` and
    ``length = 2 K(k) / lambda``. ``k`` follows from ``rise / span = k / (2 E(k) - K(k))``.
    Any ``rise / span > 0`` is reachable; for ``rise/span`` above about 0.835 the tangent angle
    at the ends exceeds 90 degrees (the arch bulges beyond its end points), and
    ``theta0 -> 130.7`` degrees as ``rise/span -> infinity``.

    Parameters
    ----------
    span : float
        Distance between the end points, m, > 0.
    rise : float
        Height of the apex ``(0, rise)``, m, > 0.

    Raises
    ------
    ProfileError
        If ``span`` or ``rise`` is not a real finite number > 0.

    Examples
    --------
    >>> rod = ElasticaProfile(span=4.0, rise=1.0)
    >>> round(rod.length, 6), rod.point(rod.length / 2).round(6).tolist()
    (4.584788, [0.0, 1.0])
    >>> [round(float(k), 6) + 0.0 for k in rod.curvature([0.0, rod.length / 2])]  # 0 at the pins
    [0.0, -0.501793]
    """

    name = "elastica"

    def __init__(self, *, span: float, rise: float):
        from scipy.special import ellipe, ellipk

        self._span = require_positive("span", span)
        self._rise = require_positive("rise", rise)
        k = solve_elastica_modulus(span=self._span, rise=self._rise)
        m = k * k
        self._modulus = k
        self._complete_k = float(ellipk(m))
        self._complete_e = float(ellipe(m))
        # lambda from the span, so the end points are exact; the rise is exact to the solver.
        self._wavenumber = 2.0 * (2.0 * self._complete_e - self._complete_k) / self._span
        self._length = 2.0 * self._complete_k / self._wavenumber

    @property
    def modulus(self) -> float:
        """Elliptic modulus ``k = sin(theta0 / 2)`` in ``(0, k_max)``, ``k_max ~ 0.9089``."""
        return self._modulus

    @property
    def wavenumber(self) -> float:
        """``lambda``, 1/m; ``lambda**2`` is the axial load over the bending stiffness, P/EI."""
        return self._wavenumber

    @property
    def end_angle(self) -> float:
        """Tangent angle ``theta0 = 2 asin(k)`` at the left end, radians (-theta0 at the right)."""
        return 2.0 * math.asin(self._modulus)

    # -- evaluation ---------------------------------------------------------------------------

    def _jacobi(self, s: np.ndarray) -> tuple:
        """``(u, sn(u), cn(u), dn(u))`` at arc lengths ``s``, using the symmetry in ``u``."""
        from scipy.special import ellipj

        u = self._complete_k - self._wavenumber * s
        sign = np.where(u < 0.0, -1.0, 1.0)
        sn, cn, dn, _ = ellipj(np.abs(u), self._modulus**2)
        # cn >= 0 on |u| <= K; clip the round-off at the ends so y and curvature are not < 0.
        return u, sign * sn, np.maximum(cn, 0.0), dn

    def _epsilon(self, sn: np.ndarray, cn: np.ndarray, dn: np.ndarray) -> np.ndarray:
        """Jacobi epsilon ``E(am u, k)`` for ``|u| <= K`` from ``sn, cn, dn`` of ``u``.

        Carlson form ``E(phi, m) = sin(phi) R_F(c, d, 1) - (m/3) sin(phi)^3 R_D(c, d, 1)``
        with ``sin(phi) = sn``, ``c = cos(phi)^2 = cn^2`` and ``d = 1 - m sin(phi)^2 = dn^2``.
        (``scipy.special.ellipeinc`` is avoided: it jumps at some arguments, scipy issue 19498.)
        """
        from scipy.special import elliprd, elliprf

        c, d = cn * cn, dn * dn
        m = self._modulus**2
        return sn * elliprf(c, d, 1.0) - (m / 3.0) * sn**3 * elliprd(c, d, 1.0)

    def _point(self, s: np.ndarray) -> np.ndarray:
        u, sn, cn, dn = self._jacobi(s)
        x = (u - 2.0 * self._epsilon(sn, cn, dn)) / self._wavenumber
        y = (2.0 * self._modulus / self._wavenumber) * cn
        return np.stack([x, y], axis=-1)

    def _tangent_angle(self, s: np.ndarray) -> np.ndarray:
        _, sn, _, _ = self._jacobi(s)
        return 2.0 * np.arcsin(np.clip(self._modulus * sn, -1.0, 1.0))

    def _curvature(self, s: np.ndarray) -> np.ndarray:
        _, _, cn, _ = self._jacobi(s)
        return -2.0 * self._modulus * self._wavenumber * cn
