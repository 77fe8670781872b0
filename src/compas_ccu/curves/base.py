"""Base class of planar crease profiles and shared input checks.

A profile is a planar curve in the (x, y) plane, in metres, traversed from left to right and
parametrised by its arc length ``s`` in ``[0, length]``.
"""

from __future__ import annotations

import math
import numbers
from abc import ABC, abstractmethod

import numpy as np

from compas_ccu.errors import ProfileError
from compas_ccu.tolerances import ARC_PARAMETER, ZERO_LENGTH

__all__ = ["Profile"]

#: Relative tolerance on arc-length arguments slightly outside ``[0, length]`` (round-off).
_S_TOLERANCE = ARC_PARAMETER


def require_real(name: str, value: object, *, unit: str = "m") -> float:
    """Return ``value`` as a float if it is a real finite number (``bool`` is not a number).

    Raises
    ------
    ProfileError
        If ``value`` is not a real finite number.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ProfileError(f"{name} must be a real finite number ({unit}), got {value!r}")
    number = float(value)
    if not math.isfinite(number):
        raise ProfileError(f"{name} must be a real finite number ({unit}), got {number!r}")
    return number


def require_positive(name: str, value: object, *, unit: str = "m") -> float:
    """Return ``value`` as a float if it is a real finite number > 0.

    Raises
    ------
    ProfileError
        If ``value`` is not a real finite number or is not > 0.
    """
    number = require_real(name, value, unit=unit)
    if not number > 0.0:
        raise ProfileError(f"{name} must be > 0 {unit}, got {number!r}")
    return number


def require_points(points: object, *, name: str = "points", min_points: int = 3) -> np.ndarray:
    """Return ``points`` as a new ``(n, 2)`` float array after checking it.

    Parameters
    ----------
    points : (n, 2) array_like of float
        Point coordinates, m.
    name : str, optional
        Name of the parameter, used in error messages.
    min_points : int, optional
        Smallest allowed ``n``.

    Returns
    -------
    (n, 2) float
        A copy of the points.

    Raises
    ------
    ProfileError
        If the points are not numbers, not of shape (n, 2), fewer than ``min_points``,
        not finite, or if two consecutive points coincide.
    """
    raw = None
    if not isinstance(points, (str, bytes)):
        try:
            raw = np.asarray(points)
        except (TypeError, ValueError):  # ragged nested sequences
            raw = None
    if raw is None or raw.dtype.kind not in "iuf":
        raise ProfileError(
            f"{name} must be an (n, 2) array of real numbers (m), got {short_repr(points)}"
        )
    coordinates = np.array(raw, dtype=float)
    if coordinates.ndim != 2 or coordinates.shape[1] != 2:
        raise ProfileError(f"{name} must have shape (n, 2), got shape {coordinates.shape}")
    count = coordinates.shape[0]
    if count < min_points:
        raise ProfileError(f"{name} must contain at least {min_points} points, got {count}")
    finite = np.isfinite(coordinates).all(axis=1)
    if not finite.all():
        index = int(np.flatnonzero(~finite)[0])
        raise ProfileError(
            f"{name} must be finite, got {name}[{index}] = {coordinates[index].tolist()}"
        )
    edge_lengths = np.linalg.norm(np.diff(coordinates, axis=0), axis=1)
    extent = float(np.ptp(coordinates, axis=0).max())
    repeated = edge_lengths <= ZERO_LENGTH * extent
    if repeated.any():
        index = int(np.flatnonzero(repeated)[0])
        raise ProfileError(
            f"consecutive {name} must be distinct, got {name}[{index}] = "
            f"{coordinates[index].tolist()} and {name}[{index + 1}] = "
            f"{coordinates[index + 1].tolist()}"
        )
    return coordinates


def require_segments(segments: object) -> int:
    """Return ``segments`` as an int if it is an integer >= 2.

    Raises
    ------
    ProfileError
        If ``segments`` is not an integer >= 2.
    """
    if isinstance(segments, (bool, np.bool_)) or not isinstance(segments, numbers.Integral):
        raise ProfileError(f"segments must be an integer >= 2, got {segments!r}")
    if segments < 2:
        raise ProfileError(f"segments must be an integer >= 2, got {int(segments)}")
    return int(segments)


def short_repr(value: object, limit: int = 60) -> str:
    """``repr(value)``, cut to ``limit`` characters with "..." (for error messages)."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


class Profile(ABC):
    """A planar crease profile parametrised by arc length, traversed from left to right.

    Subclasses implement ``length``, ``start_point``, ``end_point``, ``parameters`` and the
    private evaluators ``_point``, ``_tangent_angle`` and ``_curvature``, which receive arc
    lengths already checked and clipped to ``[0, length]``.

    Attributes
    ----------
    name : str
        Name of the profile type, as used by :func:`compas_ccu.curves.profile_from_dict`.

    Examples
    --------
    Every profile type is a Profile; a half circle of radius 1 m:

    >>> from compas_ccu.curves import ArcProfile
    >>> arc = ArcProfile(span=2.0, rise=1.0)
    >>> isinstance(arc, Profile), arc.name, round(arc.length, 6)
    (True, 'arc', 3.141593)
    >>> arc.point([0.0, arc.length / 2]).round(6).tolist()  # the start point and the apex
    [[-1.0, 0.0], [0.0, 1.0]]
    """

    name: str = "profile"

    # -- to implement -----------------------------------------------------------------------

    @property
    @abstractmethod
    def length(self) -> float:
        """Total arc length of the profile, m."""

    @property
    @abstractmethod
    def start_point(self) -> np.ndarray:
        """(2,) float: the first point of the profile (s = 0), m."""

    @property
    @abstractmethod
    def end_point(self) -> np.ndarray:
        """(2,) float: the last point of the profile (s = length), m."""

    @abstractmethod
    def parameters(self) -> dict:
        """Return the defining parameters as a JSON-able dict (floats, lists, strings)."""

    @abstractmethod
    def _point(self, s: np.ndarray) -> np.ndarray:
        """Points at checked arc lengths ``s`` (any shape), shape ``s.shape + (2,)``."""

    @abstractmethod
    def _tangent_angle(self, s: np.ndarray) -> np.ndarray:
        """Tangent angles at checked arc lengths ``s`` (any shape)."""

    @abstractmethod
    def _curvature(self, s: np.ndarray) -> np.ndarray:
        """Signed curvatures at checked arc lengths ``s`` (any shape)."""

    # -- public evaluation --------------------------------------------------------------------

    def point(self, s: object) -> np.ndarray:
        """Points at arc lengths ``s``.

        Parameters
        ----------
        s : (k,) array_like of float
            Arc lengths from the start, in ``[0, length]``, m. Any shape is accepted; the
            result then has shape ``s.shape + (2,)``.

        Returns
        -------
        (k, 2) float
            Point coordinates, m. The points at ``s = 0`` and ``s = length`` are exactly
            :attr:`start_point` and :attr:`end_point`.
        """
        s = self._checked_s(s)
        points = self._point(s)
        points[s == 0.0] = self.start_point
        points[s == self.length] = self.end_point
        return points

    def tangent_angle(self, s: object) -> np.ndarray:
        """Angles of the unit tangent to the +x axis at arc lengths ``s``.

        Parameters
        ----------
        s : (k,) array_like of float
            Arc lengths from the start, in ``[0, length]``, m.

        Returns
        -------
        (k,) float
            Tangent angles, radians (counter-clockwise from +x). Continuous along the analytic
            arches (arc, catenary, elastica: in (-pi, pi), beyond +-pi/2 near the ends of tall
            arches); spline and polyline angles come from ``atan2`` and lie in (-pi, pi].
        """
        return self._tangent_angle(self._checked_s(s))

    def curvature(self, s: object) -> np.ndarray:
        """Signed curvature at arc lengths ``s``.

        The curvature is positive where the curve turns counter-clockwise (to the left) and
        negative where it turns clockwise, as ``d(tangent_angle)/ds``.

        Parameters
        ----------
        s : (k,) array_like of float
            Arc lengths from the start, in ``[0, length]``, m.

        Returns
        -------
        (k,) float
            Signed curvature, 1/m.
        """
        return self._curvature(self._checked_s(s))

    def sample_s(self, segments: int) -> np.ndarray:
        """Arc lengths of ``segments + 1`` equally spaced samples, ``s_i = i * length / segments``.

        Parameters
        ----------
        segments : int
            Number of segments, >= 2.

        Returns
        -------
        (segments + 1,) float
            Arc lengths, m; the first is exactly 0 and the last exactly :attr:`length`.

        Raises
        ------
        ProfileError
            If ``segments`` is not an integer >= 2.
        """
        segments = require_segments(segments)
        return np.linspace(0.0, self.length, segments + 1)

    def sample(self, segments: int) -> np.ndarray:
        """Points at equal arc-length spacing ``length / segments``.

        Parameters
        ----------
        segments : int
            Number of segments, >= 2.

        Returns
        -------
        (segments + 1, 2) float
            Points from :attr:`start_point` to :attr:`end_point` (both exact), m.

        Raises
        ------
        ProfileError
            If ``segments`` is not an integer >= 2.
        """
        return self.point(self.sample_s(segments))

    def __repr__(self) -> str:
        fields = []
        for key, value in self.parameters().items():
            if isinstance(value, list):
                fields.append(f"{key}=<{len(value)} points>")
            else:
                fields.append(f"{key}={value!r}")
        return f"{type(self).__name__}({', '.join(fields)})"

    # -- helpers ------------------------------------------------------------------------------

    def _checked_s(self, s: object) -> np.ndarray:
        """Return ``s`` as a float array clipped to ``[0, length]`` after checking it."""
        try:
            values = np.array(s, dtype=float)
        except (TypeError, ValueError):
            raise ProfileError(
                f"s must be real arc lengths in [0, length] m, got {short_repr(s)}"
            ) from None
        length = self.length
        if not np.isfinite(values).all():
            bad = float(values[~np.isfinite(values)].flat[0])
            raise ProfileError(f"s must be finite arc lengths in [0, {length!r}] m, got {bad!r}")
        tolerance = _S_TOLERANCE * length
        outside = (values < -tolerance) | (values > length + tolerance)
        if outside.any():
            bad = float(values[outside].flat[0])
            raise ProfileError(f"s must lie in [0, {length!r}] m (the profile length), got {bad!r}")
        return np.clip(values, 0.0, length)


class SpanRiseProfile(Profile):
    """A symmetric arch from ``(-span/2, 0)`` over ``(0, rise)`` to ``(span/2, 0)``.

    Subclasses set ``_span``, ``_rise`` and ``_length`` and implement the evaluation.
    """

    _span: float
    _rise: float
    _length: float

    @property
    def span(self) -> float:
        """Distance between the end points, m."""
        return self._span

    @property
    def rise(self) -> float:
        """Height of the apex above the chord, m."""
        return self._rise

    @property
    def length(self) -> float:
        """Arc length, m."""
        return self._length

    @property
    def start_point(self) -> np.ndarray:
        """(2,) float: ``(-span/2, 0)``, m."""
        return np.array([-0.5 * self._span, 0.0])

    @property
    def end_point(self) -> np.ndarray:
        """(2,) float: ``(span/2, 0)``, m."""
        return np.array([0.5 * self._span, 0.0])

    def parameters(self) -> dict:
        """``{"span": float, "rise": float}``."""
        return {"span": self._span, "rise": self._rise}
