"""Circular arc profile."""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.curves.base import SpanRiseProfile, require_positive, require_real
from compas_ccu.errors import ProfileError

__all__ = ["ArcProfile"]


class ArcProfile(SpanRiseProfile):
    """Circular arc through ``(-span/2, 0)``, ``(0, rise)`` and ``(span/2, 0)``.

    The arc is traversed from left to right, so it turns clockwise: its curvature is
    ``-1/radius`` everywhere. A rise larger than ``span/2`` gives a major arc (central angle
    larger than 180 degrees), whose tangent angle exceeds 90 degrees near the ends.

    Parameters
    ----------
    span : float
        Distance between the two end points, m, > 0.
    rise : float
        Height of the apex above the chord, m, > 0.

    Raises
    ------
    ProfileError
        If ``span`` or ``rise`` is not a real finite number > 0.

    Examples
    --------
    >>> arc = ArcProfile(span=2.0, rise=1.0)  # a half circle of radius 1 m
    >>> round(arc.length, 12) == round(math.pi, 12)
    True
    """

    name = "arc"

    def __init__(self, *, span: float, rise: float):
        span = require_positive("span", span)
        rise = require_positive("rise", rise)
        half_span = 0.5 * span
        # Inscribed angle: the chord end sees the apex under atan(rise / half_span), which is
        # a quarter of the central angle. Valid for minor and major arcs alike.
        half_angle = 2.0 * math.atan2(rise, half_span)
        radius = (half_span * half_span + rise * rise) / (2.0 * rise)
        self._setup(span=span, rise=rise, radius=radius, half_angle=half_angle)
        self._defining = {"span": span, "rise": rise}

    @classmethod
    def from_radius_angle(cls, *, radius: float, angle: float) -> ArcProfile:
        """Arc of a given radius and central angle, symmetric about x = 0, ends on y = 0.

        Parameters
        ----------
        radius : float
            Radius, m, > 0.
        angle : float
            Central angle, DEGREES, 0 < angle < 360.

        Returns
        -------
        ArcProfile
            The arc; its :meth:`parameters` are ``{"radius": ..., "angle": ...}``.

        Raises
        ------
        ProfileError
            If ``radius`` is not > 0 or ``angle`` is not in (0, 360) degrees.
        """
        radius = require_positive("radius", radius)
        angle_degrees = require_real("angle", angle, unit="degrees")
        if not 0.0 < angle_degrees < 360.0:
            raise ProfileError(
                f"angle must be in (0, 360) degrees (exclusive), got {angle_degrees!r}"
            )
        half_angle = 0.5 * math.radians(angle_degrees)
        profile = cls.__new__(cls)
        profile._setup(
            span=2.0 * radius * math.sin(half_angle),
            rise=2.0 * radius * math.sin(0.5 * half_angle) ** 2,
            radius=radius,
            half_angle=half_angle,
        )
        profile._defining = {"radius": radius, "angle": angle_degrees}
        return profile

    def _setup(self, *, span: float, rise: float, radius: float, half_angle: float) -> None:
        self._span = span
        self._rise = rise
        self._radius = radius
        self._half_angle = half_angle
        self._length = 2.0 * radius * half_angle

    # -- properties ---------------------------------------------------------------------------

    @property
    def radius(self) -> float:
        """Radius, m."""
        return self._radius

    @property
    def angle(self) -> float:
        """Central angle, RADIANS, in (0, 2 pi)."""
        return 2.0 * self._half_angle

    @property
    def center(self) -> np.ndarray:
        """(2,) float: centre of the circle, ``(0, rise - radius)``, m."""
        return np.array([0.0, self._rise - self._radius])

    def parameters(self) -> dict:
        """``{"span", "rise"}`` or, if built by :meth:`from_radius_angle`, ``{"radius", "angle"}``
        (angle in degrees)."""
        return dict(self._defining)

    # -- evaluation ---------------------------------------------------------------------------

    def _polar_angle(self, s: np.ndarray) -> np.ndarray:
        """Angle from the apex direction, seen from the centre, positive to the right."""
        return (s - 0.5 * self._length) / self._radius

    def _point(self, s: np.ndarray) -> np.ndarray:
        phi = self._polar_angle(s)
        x = self._radius * np.sin(phi)
        y = self._rise - 2.0 * self._radius * np.sin(0.5 * phi) ** 2
        return np.stack([x, y], axis=-1)

    def _tangent_angle(self, s: np.ndarray) -> np.ndarray:
        return -self._polar_angle(s)

    def _curvature(self, s: np.ndarray) -> np.ndarray:
        return np.full(s.shape, -1.0 / self._radius)
