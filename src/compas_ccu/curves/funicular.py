"""Funicular arch profile: the thrust line of vertical loads (paper Fig. 9d)."""

from __future__ import annotations

import functools
import math

import numpy as np

from compas_ccu.curves.base import (
    SpanRiseProfile,
    require_positive,
    require_real,
    require_segments,
    short_repr,
)
from compas_ccu.errors import ProfileError
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = ["FunicularProfile"]

_GAUSS_ORDER = 16
_MAX_BISECTIONS = 40
_QUADRATURE_TOLERANCE = 1e-14
_NEWTON_TOLERANCE = 1e-14
_NEWTON_MAX_ITERATIONS = 60
#: Kinks closer than this fraction of the length (to each other or to an end) share a sample.
_KINK_TOLERANCE = ZERO_LENGTH


@functools.lru_cache(maxsize=1)
def _gauss_legendre_rule() -> tuple:
    """Nodes and weights of the Gauss-Legendre rule on [-1, 1], ``(_GAUSS_ORDER,)`` each."""
    return np.polynomial.legendre.leggauss(_GAUSS_ORDER)


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
        self._given_points = (
            None if point_loads is None else _require_point_loads(point_loads, half)
        )
        self._given_distributed = (
            None
            if distributed_loads is None
            else _require_distributed_loads(distributed_loads, half)
        )
        if self._given_points is None and self._given_distributed is None:
            points = np.zeros((0, 2))
            distributed = np.array([[-half, half, 1.0, 1.0]])
        else:
            points = np.zeros((0, 2)) if self._given_points is None else self._given_points
            distributed = (
                np.zeros((0, 4)) if self._given_distributed is None else self._given_distributed
            )
        self._setup_moment(points, distributed)
        self._setup_arc_length()

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
        return self._total_load * self._load_unit

    @property
    def reactions(self) -> np.ndarray:
        """(2,) float: vertical support reactions (left, right), F; they add up to the load."""
        return self._reactions * self._load_unit

    @property
    def thrust(self) -> float:
        """Horizontal thrust ``H = max M / rise``, F, the same at both supports."""
        return self._max_moment * self._load_unit / self._rise

    @property
    def apex(self) -> np.ndarray:
        """(2,) float: the highest point ``(x, rise)`` (where ``M`` is largest), m."""
        return np.array([self._apex_x, self._rise])

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
        return self._moment_in_piece(x, self._piece_of(x)) * self._load_unit

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
        cell = _cell_of(x, self._cell_x)
        return self._arc_length_in_cell(cell, x)

    def _setup_moment(self, points: np.ndarray, distributed: np.ndarray) -> None:
        """Normalise the loads, build the cubic pieces of ``M``, find ``max M`` and its place."""
        half = 0.5 * self._span
        points, distributed = _snap_positions(points, distributed, half)
        with np.errstate(over="ignore"):
            resultants = 0.5 * (distributed[:, 2] + distributed[:, 3])
            resultants = resultants * (distributed[:, 1] - distributed[:, 0])
            total = float(points[:, 1].sum() + resultants.sum())
        if not math.isfinite(total):
            raise ProfileError(f"the total load must be finite, got {total!r}")
        if not total > 0.0:
            raise ProfileError(
                "the total load is zero: give at least one load, or give neither "
                "point_loads nor distributed_loads for a uniform load"
            )
        unit = float(max(points[:, 1].max(initial=0.0), resultants.max(initial=0.0)))
        self._load_unit = unit
        points = points * np.array([1.0, 1.0 / unit])
        distributed = distributed * np.array([1.0, 1.0, 1.0 / unit, 1.0 / unit])
        resultants = resultants / unit
        # centroid of a trapezoid of intensities q0, q1 over [x0, x1]
        widths = distributed[:, 1] - distributed[:, 0]
        sums = distributed[:, 2] + distributed[:, 3]
        centroids = distributed[:, 0] + widths * (distributed[:, 2] + 2.0 * distributed[:, 3]) / (
            3.0 * sums
        )
        self._total_load = float(points[:, 1].sum() + resultants.sum())
        left = (points[:, 1] @ (half - points[:, 0]) + resultants @ (half - centroids)) / self._span
        right = (
            points[:, 1] @ (half + points[:, 0]) + resultants @ (half + centroids)
        ) / self._span
        self._reactions = np.array([left, right])

        breaks = np.unique(
            np.concatenate([[-half, 0.0, half], points[:, 0], distributed[:, :2].ravel()])
        )
        self._breaks = breaks
        lower, upper = breaks[:-1], breaks[1:]
        from_right = lower >= 0.0
        origins = np.where(from_right, upper, lower)
        coefficients = _coefficients_from_left(origins, points, distributed, left, half)
        mirrored_points = points * np.array([-1.0, 1.0])
        mirrored_distributed = distributed[:, [1, 0, 3, 2]] * np.array([-1.0, -1.0, 1.0, 1.0])
        mirrored = _coefficients_from_left(
            -origins, mirrored_points, mirrored_distributed, right, half
        )
        mirrored *= np.array([1.0, -1.0, 1.0, -1.0])  # t' = -t
        self._origins = origins
        self._coefficients = np.where(from_right[:, None], mirrored, coefficients)

        # max M: at a break or where M' = 0 inside a piece (M is concave for loads >= 0)
        candidates_x, candidates_piece = [], []
        for piece in range(len(lower)):
            candidates_x += [lower[piece], upper[piece]]
            candidates_piece += [piece, piece]
            c1, c2, c3 = self._coefficients[piece, 1:]
            for root in _quadratic_roots(3.0 * c3, 2.0 * c2, c1):
                x = origins[piece] + root
                if lower[piece] < x < upper[piece]:
                    candidates_x.append(x)
                    candidates_piece.append(piece)
        candidates_x = np.array(candidates_x)
        values = self._moment_in_piece(candidates_x, np.array(candidates_piece))
        best = int(np.argmax(values))
        self._max_moment = float(values[best])
        self._apex_x = float(candidates_x[best])
        # guard, at the breaks and the middles of the pieces strictly inside the span
        where = np.concatenate([upper[:-1], 0.5 * (lower + upper)])
        where_piece = np.concatenate([np.arange(len(upper) - 1), np.arange(len(lower))])
        strictly_inside = (where > -half) & (where < half)
        where, where_piece = where[strictly_inside], where_piece[strictly_inside]
        inner = self._moment_in_piece(where, where_piece)
        if not (self._max_moment > 0.0 and math.isfinite(self._max_moment)) or not np.all(
            inner > 0.0
        ):
            index = int(np.argmin(inner)) if inner.size else 0
            bad_x, bad_m = (
                (where[index], inner[index]) if inner.size else (self._apex_x, values[best])
            )
            raise ProfileError(
                "the bending moment of the loads must be > 0 inside the span, got "
                f"M = {float(bad_m) * unit!r} at x = {float(bad_x)!r} m"
            )
        self._kink_x = np.unique(points[:, 0])

    def _piece_of(self, x: np.ndarray) -> np.ndarray:
        """Index of the piece containing ``x``; at a break, the piece that starts there."""
        return _cell_of(x, self._breaks)

    def _moment_in_piece(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """Normalised ``M`` at ``x`` evaluated with the cubic of ``piece``."""
        c = self._coefficients[piece]
        t = x - self._origins[piece]
        return ((c[..., 3] * t + c[..., 2]) * t + c[..., 1]) * t + c[..., 0]

    def _slope_in_piece(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """``y' = rise M' / max M`` at ``x`` with the cubic of ``piece``."""
        c = self._coefficients[piece]
        t = x - self._origins[piece]
        derivative = (3.0 * c[..., 3] * t + 2.0 * c[..., 2]) * t + c[..., 1]
        return self._rise * (derivative / self._max_moment)

    def _second_derivative_in_piece(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """``y'' = rise M'' / max M`` at ``x`` with the cubic of ``piece``."""
        c = self._coefficients[piece]
        t = x - self._origins[piece]
        return self._rise * ((6.0 * c[..., 3] * t + 2.0 * c[..., 2]) / self._max_moment)

    # -- arc length <-> x ---------------------------------------------------------------------

    def _setup_arc_length(self) -> None:
        """Adaptive Gauss-Legendre table of cells ``[cell_x[j], cell_x[j+1]]`` and their lengths.

        Vectorised over all cells of one level: starting from the pieces of ``M``, a cell is
        accepted (as its two halves) when the integral of the speed over the whole cell agrees
        with the sum over its halves to ``_QUADRATURE_TOLERANCE * length``; otherwise both
        halves are bisected further.
        """
        lower, upper = self._breaks[:-1], self._breaks[1:]
        piece = np.arange(len(lower))
        tolerance = _QUADRATURE_TOLERANCE * self._gauss_legendre(lower, upper, piece).sum()
        accepted_lower, accepted_lengths, accepted_piece = [], [], []
        for depth in range(_MAX_BISECTIONS + 1):
            middle = 0.5 * (lower + upper)
            whole = self._gauss_legendre(lower, upper, piece)
            left = self._gauss_legendre(lower, middle, piece)
            right = self._gauss_legendre(middle, upper, piece)
            done = np.abs(left + right - whole) <= tolerance
            if depth == _MAX_BISECTIONS:
                done[:] = True
            accepted_lower += [lower[done], middle[done]]
            accepted_lengths += [left[done], right[done]]
            accepted_piece += [piece[done], piece[done]]
            lower = np.concatenate([lower[~done], middle[~done]])
            upper = np.concatenate([middle[~done], upper[~done]])
            piece = np.concatenate([piece[~done], piece[~done]])
            if lower.size == 0:
                break
        cell_lower = np.concatenate(accepted_lower)
        order = np.argsort(cell_lower, kind="stable")
        self._cell_x = np.append(cell_lower[order], self._breaks[-1])
        self._cell_piece = np.concatenate(accepted_piece)[order]
        cell_lengths = np.concatenate(accepted_lengths)[order]
        self._cell_s = np.concatenate([[0.0], np.cumsum(cell_lengths)])
        self._length = float(self._cell_s[-1])
        # the kinks are cell breaks: their arc lengths are table entries (exact sample vertices)
        self._kink_s = self._cell_s[np.searchsorted(self._cell_x, self._kink_x)]

    def _speed(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """``ds/dx = sqrt(1 + y'^2)`` at ``x`` on ``piece``."""
        return np.hypot(1.0, self._slope_in_piece(x, piece))

    def _gauss_legendre(self, lower: np.ndarray, upper: np.ndarray, piece: np.ndarray):
        """Integral of the speed over ``[lower, upper]`` on ``piece`` (elementwise)."""
        gauss_nodes, gauss_weights = _gauss_legendre_rule()
        half = 0.5 * (upper - lower)
        nodes = (0.5 * (upper + lower))[..., None] + half[..., None] * gauss_nodes
        return half * (self._speed(nodes, np.asarray(piece)[..., None]) @ gauss_weights)

    def _arc_length_in_cell(self, cell: np.ndarray, x: np.ndarray) -> np.ndarray:
        """Arc length at abscissae ``x`` lying in the cells ``cell``."""
        start = self._cell_x[cell]
        return self._cell_s[cell] + self._gauss_legendre(start, x, self._cell_piece[cell])

    def _x_at(self, s: np.ndarray) -> tuple:
        """Abscissae ``x`` with arc length ``s`` (checked) and their pieces, to 1e-14 relative.

        An ``s`` at a cell break (a kink, for instance) maps exactly to the break's ``x``, with
        the piece that starts there.
        """
        cell_x, cell_s = self._cell_x, self._cell_s
        cell = _cell_of(s, cell_s)
        lower, upper = cell_x[cell], cell_x[cell + 1]
        cell_length = cell_s[cell + 1] - cell_s[cell]  # 0 only for a cell below round-off
        fraction = (s - cell_s[cell]) / np.where(cell_length > 0.0, cell_length, 1.0)
        fraction = np.clip(np.where(cell_length > 0.0, fraction, 0.0), 0.0, 1.0)
        x = lower + fraction * (upper - lower)
        piece = self._cell_piece[cell]
        tolerance = _NEWTON_TOLERANCE * self._length
        for _ in range(_NEWTON_MAX_ITERATIONS):
            residual = self._arc_length_in_cell(cell, x) - s
            # the arc length increases with x: keep a bracket and bisect when Newton leaves it
            upper = np.where(residual > 0.0, x, upper)
            lower = np.where(residual < 0.0, x, lower)
            newton = x - residual / self._speed(x, piece)
            inside = (newton >= lower) & (newton <= upper)
            x = np.where(inside, newton, 0.5 * (lower + upper))
            if np.all(np.abs(residual) <= tolerance):
                break  # after one more Newton step, which squares the last error
        return x, piece

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
        tolerance = _KINK_TOLERANCE * self._length
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
        x, piece = self._x_at(s)
        y = self._rise * (self._moment_in_piece(x, piece) / self._max_moment)
        return np.stack([x, y], axis=-1)

    def _tangent_angle(self, s: np.ndarray) -> np.ndarray:
        x, piece = self._x_at(s)
        return np.arctan(self._slope_in_piece(x, piece))

    def _curvature(self, s: np.ndarray) -> np.ndarray:
        x, piece = self._x_at(s)
        slope = self._slope_in_piece(x, piece)
        return self._second_derivative_in_piece(x, piece) / (1.0 + slope * slope) ** 1.5


def _snap_positions(points: np.ndarray, distributed: np.ndarray, half: float):
    """Load positions closer than round-off (ZERO_LENGTH of the span) to each other, to the
    supports or to mid-span made equal (the first of each cluster; the supports and mid-span
    first), so that no piece of the thrust line has a length of round-off (a degenerate piece
    would put several crease vertices on one point)."""
    tolerance = _KINK_TOLERANCE * 2.0 * half
    points, distributed = points.copy(), distributed.copy()
    xs = np.concatenate([points[:, 0], distributed[:, :2].ravel()])
    if not xs.size:
        return points, distributed
    anchors = [-half, 0.0, half]
    snapped = np.empty_like(xs)
    for i in np.argsort(xs, kind="stable"):
        near = [a for a in anchors if abs(a - xs[i]) <= tolerance]
        if near:
            snapped[i] = near[0]
        else:
            snapped[i] = xs[i]
            anchors.append(xs[i])
    points[:, 0] = snapped[: len(points)]
    distributed[:, :2] = snapped[len(points) :].reshape(-1, 2)
    return points, distributed


def _cell_of(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Index ``j`` with ``edges[j] <= value < edges[j+1]``, clipped to the cells."""
    return np.clip(np.searchsorted(edges, values, side="right") - 1, 0, len(edges) - 2)


def _coefficients_from_left(
    origins: np.ndarray,
    points: np.ndarray,
    distributed: np.ndarray,
    reaction: float,
    half: float,
) -> np.ndarray:
    """Cubic coefficients ``c0..c3`` of ``M(origin + t)`` from the loads left of each origin.

    ``M(x) = R (x + half) - sum P (x - a) - int q(xi) (x - xi) dxi`` over the loads left of
    ``x``. Valid on a piece ``[origin, next break]`` (the load positions are breaks).
    """
    coefficients = np.zeros((len(origins), 4))
    coefficients[:, 0] = reaction * (origins + half)
    coefficients[:, 1] = reaction
    for position, load in points:
        active = position <= origins
        coefficients[:, 0] -= np.where(active, load * (origins - position), 0.0)
        coefficients[:, 1] -= np.where(active, load, 0.0)
    for x0, x1, q0, q1 in distributed:
        width = x1 - x0
        resultant = 0.5 * (q0 + q1) * width
        centroid = x0 + width * (q0 + 2.0 * q1) / (3.0 * (q0 + q1))
        past = origins >= x1
        inside = (origins >= x0) & ~past
        slope = (q1 - q0) / width
        d = np.where(inside, origins - x0, 0.0)
        # int_0^(d + t) (q0 + k xi) (d + t - xi) dxi = q0 (d + t)^2 / 2 + k (d + t)^3 / 6
        coefficients[:, 0] -= np.where(
            past,
            resultant * (origins - centroid),
            np.where(inside, (0.5 * q0 + slope * d / 6.0) * d * d, 0.0),
        )
        coefficients[:, 1] -= np.where(
            past, resultant, np.where(inside, (q0 + 0.5 * slope * d) * d, 0.0)
        )
        coefficients[:, 2] -= np.where(inside, 0.5 * (q0 + slope * d), 0.0)
        coefficients[:, 3] -= np.where(inside, slope / 6.0, 0.0)
    return coefficients


def _quadratic_roots(a: float, b: float, c: float) -> list:
    """Real roots of ``a t^2 + b t + c`` (cancellation-free), none if it is constant."""
    if a == 0.0:
        return [] if b == 0.0 else [-c / b]
    discriminant = b * b - 4.0 * a * c
    if discriminant < 0.0:
        return []
    q = -0.5 * (b + math.copysign(math.sqrt(discriminant), b))
    return [q / a] if q == 0.0 else [q / a, c / q]


def _require_point_loads(loads: object, half: float) -> np.ndarray:
    """Check a list of point loads ``[x, P]``; return (n, 2) float."""
    rows = _require_rows(loads, "point_loads", ("x", "P"), "[x, P]")
    for index, (x, load) in enumerate(rows):
        if not -half < x < half:
            raise ProfileError(
                f"point_loads[{index}]: x must lie inside the span, {-half!r} < x < {half!r} m, "
                f"got {x!r}"
            )
        if not load > 0.0:
            raise ProfileError(f"point_loads[{index}]: P must be > 0, got {load!r}")
    return np.array(rows, dtype=float).reshape(len(rows), 2)


def _require_distributed_loads(loads: object, half: float) -> np.ndarray:
    """Check a list of distributed loads ``[x0, x1, q0, q1]``; return (n, 4) float."""
    rows = _require_rows(loads, "distributed_loads", ("x0", "x1", "q0", "q1"), "[x0, x1, q0, q1]")
    for index, (x0, x1, q0, q1) in enumerate(rows):
        if not -half <= x0 < x1 <= half:
            raise ProfileError(
                f"distributed_loads[{index}]: need {-half!r} <= x0 < x1 <= {half!r} m, "
                f"got x0 = {x0!r}, x1 = {x1!r}"
            )
        for key, value in (("q0", q0), ("q1", q1)):
            if not value >= 0.0:
                raise ProfileError(f"distributed_loads[{index}]: {key} must be >= 0, got {value!r}")
        if q0 == 0.0 and q1 == 0.0:
            raise ProfileError(f"distributed_loads[{index}]: q0 and q1 are both 0 (no load)")
    return np.array(rows, dtype=float).reshape(len(rows), 4)


def _require_rows(loads: object, name: str, keys: tuple, form: str) -> list:
    """Check a list of equal-length rows of real finite numbers; return lists of floats."""
    if isinstance(loads, np.ndarray):
        loads = loads.tolist() if loads.ndim == 2 else loads
    if not isinstance(loads, (list, tuple)):
        raise ProfileError(f"{name} must be a list of {form} lists, got {short_repr(loads)}")
    rows = []
    for index, row in enumerate(loads):
        if not isinstance(row, (list, tuple, np.ndarray)) or len(row) != len(keys):
            raise ProfileError(f"{name}[{index}] must be a list {form}, got {short_repr(row)}")
        units = ["m" if key.startswith("x") else "load units" for key in keys]
        rows.append(
            [
                require_real(f"{name}[{index}] {key}", value, unit=unit)
                for key, value, unit in zip(keys, row, units)
            ]
        )
    return rows
