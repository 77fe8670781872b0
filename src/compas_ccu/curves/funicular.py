"""Funicular arch profile: the thrust line of vertical loads (paper Fig. 9d).

The loads are checked by :mod:`.funicular_loads`, the bending moment they give is
:class:`~compas_ccu.curves.funicular_moment.BeamMoment` and the arc length of the arch is
:class:`~compas_ccu.curves.funicular_arc_length.ArcLengthTable`; this module is the profile.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.curves.base import SpanRiseProfile, require_positive, require_segments
from compas_ccu.curves.funicular_arc_length import ArcLengthTable, cell_of
from compas_ccu.curves.funicular_loads import (
    KINK_TOLERANCE,
    require_distributed_loads,
    require_point_loads,
    snap_positions,
)
from compas_ccu.curves.funicular_moment import BeamMoment
from compas_ccu.errors import ProfileError

__all__ = ["FunicularProfile"]


class FunicularProfile(SpanRiseProfile):
    """Funicular arch (thrust line) of vertical loads, from ``(-span/2, 0)`` to ``(span/2, 0)``.

    The arch carries the given vertical loads in pure compression: its height is proportional
    to the bending moment ``M(x)`` of the simply supported beam of the same span under the same
    loads, scaled so that the highest point has height ``rise``::

        y(x) = rise * M(x) / max M,   thrust H = max M / rise,   H y(x) = M(x).

    Loads point downwards and are positive; their unit is free (point loads ``P`` in a force
    unit F, distributed intensities ``q`` in F/m), only their ratios shape the arch.
    :attr:`thrust` (F) and :attr:`reactions` (F) are in that unit, :meth:`moment` in F m.
    Without any load argument the arch carries a uniform load of intensity 1 over the whole
    span: the parabola ``y = rise (1 - (2 x / span)^2)``.

    ``M`` is a piecewise cubic polynomial in ``x``, with breaks at the load positions, built in
    closed form (no integration of the loads). Pieces left of ``x = 0`` are expanded about
    their left end from the left reaction, pieces right of it about their right end from the
    right reaction, which keeps ``M`` accurate near both supports. The arc length
    ``int sqrt(1 + y'^2) dx`` is computed by adaptive 16-point Gauss-Legendre quadrature on each
    smooth piece (cells are bisected until each is integrated to about 1e-14 of the length)
    and inverted by safeguarded Newton iterations on ``x`` to 1e-14 relative.

    A point load makes a kink (the funicular polygon): the slope jumps there. The kinks'
    arc lengths are :attr:`kinks`; :meth:`sample_s` puts every kink exactly on a sample vertex
    (kinks closer than 1e-12 of the length to each other or to an end share one).
    :meth:`tangent_angle` and :meth:`curvature` are those of the smooth pieces (one-sided): at a
    kink they are the values of the piece that starts there (the outgoing piece), and the
    curvature does not contain the kink's concentrated turning. Between point loads the
    curvature is ``y'' / (1 + y'^2)^(3/2)`` with ``y'' = -q rise / max M``: zero on unloaded
    stretches (straight pieces), and it jumps where a distributed load starts or ends.

    **Kinks are curvature peaks of the plates.** The thrust line turns by a finite angle at a
    point load (the slope jumps by ``P / H``), all of it at one crease vertex. The plates of a
    curved-crease structure are developable and follow the crease: they turn with it along the
    ruling through that vertex, a bend concentrated in the one quad row beside it instead of
    spread along the crease, so the plates' discrete curvature there is about the turn over the
    row's width and grows as the segments get shorter (a fold line along the ruling in the
    limit). On catalog Fig. 9d (48 segments) the crease turns by 18.7 deg at the kink against
    at most 2.4 deg at any other vertex, and the plates' curvature peaks at 5.18 1/m there
    against 0.07-1.00 1/m elsewhere: the kinematic bending check reads that peak (``ccu info``
    says when it does). Spread a real point load over a width (``distributed_loads``: no kink)
    or put a hinge or a cut along that ruling (docs/shape-control.md).

    Parameters
    ----------
    span : float
        Distance between the end points ``(-span/2, 0)`` and ``(span/2, 0)``, m, > 0.
    rise : float
        Height of the highest point above the chord, m, > 0.
    point_loads : (n, 2) array_like of float, optional
        Point loads ``[x, P]``: position ``-span/2 < x < span/2`` (m) and load ``P > 0`` (F).
        Loads at the same position add up.
    distributed_loads : (n, 4) array_like of float, optional
        Linearly varying loads ``[x0, x1, q0, q1]``: intensity ``q0`` at ``x0`` to ``q1`` at
        ``x1`` (F/m), with ``-span/2 <= x0 < x1 <= span/2``, ``q0, q1 >= 0``, not both 0.

    Raises
    ------
    ProfileError
        If ``span`` or ``rise`` is not a real finite number > 0; if a load is not a list of
        the right length of real finite numbers, lies outside the span or is negative (the
        message names the load by its index and gives the value); if load lists are given but
        the total load is zero, or if it is not finite; if the bending moment is not positive
        inside the span.

    Examples
    --------
    A central point load gives a triangle with one kink at the apex:

    >>> arch = FunicularProfile(span=4.0, rise=1.0, point_loads=[[0.0, 10.0]])
    >>> arch.thrust  # H = (P span / 4) / rise
    10.0
    >>> arch.reactions.tolist()
    [5.0, 5.0]
    >>> arch.kinks.tolist() == [0.5 * arch.length]
    True
    >>> arch.point(arch.kinks).tolist()
    [[0.0, 1.0]]

    Without loads, a uniform load: the parabola ``y = rise (1 - (2 x / span)^2)``:

    >>> parabola = FunicularProfile(span=4.0, rise=1.0)
    >>> round(float(parabola.moment(1.0)) / parabola.thrust, 12)
    0.75
    """

    name = "funicular"

    def __init__(
        self,
        *,
        span: float,
        rise: float,
        point_loads: object = None,
        distributed_loads: object = None,
    ):
        self._span = require_positive("span", span)
        self._rise = require_positive("rise", rise)
        half = 0.5 * self._span
        self._given_points = None if point_loads is None else require_point_loads(point_loads, half)
        self._given_distributed = (
            None
            if distributed_loads is None
            else require_distributed_loads(distributed_loads, half)
        )
        if self._given_points is None and self._given_distributed is None:
            points = np.zeros((0, 2))
            distributed = np.array([[-half, half, 1.0, 1.0]])
        else:
            points = np.zeros((0, 2)) if self._given_points is None else self._given_points
            distributed = (
                np.zeros((0, 4)) if self._given_distributed is None else self._given_distributed
            )
        points, distributed = snap_positions(points, distributed, half)
        self._beam = BeamMoment(points, distributed, self._span)
        self._table = ArcLengthTable(self._beam.breaks, self._speed)
        # the kinks are cell breaks: their arc lengths are table entries (exact sample vertices)
        self._length = self._table.length
        self._kink_s = self._table.cell_s[np.searchsorted(self._table.cell_x, self._beam.kink_x)]

    # -- properties ---------------------------------------------------------------------------

    @property
    def point_loads(self) -> np.ndarray:
        """(n, 2) float: the point loads ``[x, P]`` as given (a copy; empty if none), m and F."""
        return np.zeros((0, 2)) if self._given_points is None else self._given_points.copy()

    @property
    def distributed_loads(self) -> np.ndarray:
        """(n, 4) float: the distributed loads ``[x0, x1, q0, q1]`` (a copy), m and F/m.

        ``[[-span/2, span/2, 1, 1]]`` (the implied uniform load) if no load was given.
        """
        if self._given_points is None and self._given_distributed is None:
            return np.array([[-0.5 * self._span, 0.5 * self._span, 1.0, 1.0]])
        if self._given_distributed is None:
            return np.zeros((0, 4))
        return self._given_distributed.copy()

    @property
    def total_load(self) -> float:
        """Sum of all vertical loads, F."""
        return self._beam.total_load * self._beam.load_unit

    @property
    def reactions(self) -> np.ndarray:
        """(2,) float: vertical support reactions (left, right), F; they add up to the load."""
        return self._beam.reactions * self._beam.load_unit

    @property
    def thrust(self) -> float:
        """Horizontal thrust ``H = max M / rise``, F, the same at both supports."""
        return self._beam.max_moment * self._beam.load_unit / self._rise

    @property
    def apex(self) -> np.ndarray:
        """(2,) float: the highest point ``(x, rise)`` (where ``M`` is largest), m."""
        return np.array([self._beam.apex_x, self._rise])

    @property
    def kinks(self) -> np.ndarray:
        """(k,) float: arc lengths of the kinks (the point loads, sorted, distinct), m."""
        return self._kink_s.copy()

    def parameters(self) -> dict:
        """``{"span", "rise"}`` plus the load lists that were given (as lists of lists)."""
        parameters = {"span": self._span, "rise": self._rise}
        if self._given_points is not None:
            parameters["point_loads"] = self._given_points.tolist()
        if self._given_distributed is not None:
            parameters["distributed_loads"] = self._given_distributed.tolist()
        return parameters

    # -- bending moment -----------------------------------------------------------------------

    def moment(self, x: object) -> np.ndarray:
        """Bending moment ``M(x)`` of the simply supported beam under the loads.

        Parameters
        ----------
        x : (k,) array_like of float
            Abscissae in ``[-span/2, span/2]``, m (clipped). At a point load both pieces give
            the same value.

        Returns
        -------
        (k,) float
            ``M(x) = H y(x)``, F m (sagging positive).
        """
        x = np.clip(np.asarray(x, dtype=float), -0.5 * self._span, 0.5 * self._span)
        return self._beam.value(x, cell_of(x, self._beam.breaks)) * self._beam.load_unit

    def arc_length_at_x(self, x: object) -> np.ndarray:
        """Arc length from the start to the point of abscissa ``x``.

        Parameters
        ----------
        x : (k,) array_like of float
            Abscissae in ``[-span/2, span/2]``, m (clipped).

        Returns
        -------
        (k,) float
            Arc lengths, m.
        """
        x = np.clip(np.asarray(x, dtype=float), -0.5 * self._span, 0.5 * self._span)
        return self._table.arc_length_at_x(x)

    def _slope_in_piece(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """``y' = rise M' / max M`` at ``x`` with the cubic of ``piece``."""
        return self._rise * (self._beam.derivative(x, piece) / self._beam.max_moment)

    def _speed(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """``ds/dx = sqrt(1 + y'^2)`` at ``x`` on ``piece``."""
        return np.hypot(1.0, self._slope_in_piece(x, piece))

    # -- sampling -----------------------------------------------------------------------------

    def sample_s(self, segments: int) -> np.ndarray:
        """Arc lengths of ``segments + 1`` samples with every kink on a sample.

        Without point loads the samples are equally spaced, ``s_i = i * length / segments``.
        With point loads the curve is cut at its kinks into pieces, which share the segments in
        proportion to their lengths: each gets ``floor(segments * piece / length)`` but at least
        one, and the difference to ``segments`` is made up one segment at a time by the piece
        with the longest step (or taken from the one whose step stays shortest). The samples
        are equally spaced within each piece.

        Parameters
        ----------
        segments : int
            Number of segments, >= 2 and >= the number of pieces between kinks.

        Returns
        -------
        (segments + 1,) float
            Increasing arc lengths, m; the first is exactly 0, the last exactly :attr:`length`,
            and the kinks' arc lengths :attr:`kinks` are among them exactly (kinks closer than
            1e-12 of the length to each other or to an end share one sample, the first).

        Raises
        ------
        ProfileError
            If ``segments`` is not an integer >= 2 or is smaller than the number of pieces.
        """
        segments = require_segments(segments)
        # kinks closer than round-off to each other or to an end share one sample
        tolerance = KINK_TOLERANCE * self._length
        bounds = [0.0]
        for kink in self._kink_s:
            if kink - bounds[-1] > tolerance and self._length - kink > tolerance:
                bounds.append(float(kink))
        if len(bounds) == 1:
            return super().sample_s(segments)
        bounds = np.array(bounds + [self._length])
        lengths = np.diff(bounds)
        pieces = len(lengths)
        if segments < pieces:
            raise ProfileError(
                f"segments must be >= {pieces} to put a sample on each of the "
                f"{pieces - 1} kinks (point loads), got {segments}"
            )
        # proportional shares (at least one each), then one segment at a time to or from the
        # piece whose step is longest (or would stay shortest): at most ``pieces`` corrections
        counts = np.maximum(1, np.floor(segments * lengths / self._length)).astype(int)
        while counts.sum() < segments:
            counts[np.argmax(lengths / counts)] += 1
        while counts.sum() > segments:
            with np.errstate(divide="ignore"):
                steps = np.where(counts > 1, lengths / (counts - 1), np.inf)
            counts[np.argmin(steps)] -= 1
        parts = [np.linspace(bounds[i], bounds[i + 1], counts[i] + 1)[:-1] for i in range(pieces)]
        return np.concatenate(parts + [[self._length]])

    def __repr__(self) -> str:
        fields = [f"span={self._span!r}", f"rise={self._rise!r}"]
        for key in ("point_loads", "distributed_loads"):
            loads = self.parameters().get(key)
            if loads is not None:
                fields.append(f"{key}=<{len(loads)} load{'' if len(loads) == 1 else 's'}>")
        return f"{type(self).__name__}({', '.join(fields)})"

    # -- evaluation ---------------------------------------------------------------------------

    def _point(self, s: np.ndarray) -> np.ndarray:
        x, piece = self._table.x_at(s)
        y = self._rise * (self._beam.value(x, piece) / self._beam.max_moment)
        return np.stack([x, y], axis=-1)

    def _tangent_angle(self, s: np.ndarray) -> np.ndarray:
        x, piece = self._table.x_at(s)
        return np.arctan(self._slope_in_piece(x, piece))

    def _curvature(self, s: np.ndarray) -> np.ndarray:
        x, piece = self._table.x_at(s)
        slope = self._slope_in_piece(x, piece)
        second = self._rise * (self._beam.second_derivative(x, piece) / self._beam.max_moment)
        return second / (1.0 + slope * slope) ** 1.5
