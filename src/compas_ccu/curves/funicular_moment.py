"""The bending moment of a simply supported beam under vertical loads, as a piecewise cubic.

:class:`BeamMoment` is the shape of a funicular arch
(:class:`~compas_ccu.curves.funicular.FunicularProfile`: ``y = rise M / max M``): ``M(x)`` in
closed form (no integration of the loads), with breaks at the load positions. Pieces left of
``x = 0`` are expanded about their left end from the left reaction, pieces right of it about
their right end from the right reaction, which keeps ``M`` accurate near both supports.
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.errors import ProfileError

__all__ = ["BeamMoment", "coefficients_from_left", "quadratic_roots"]


class BeamMoment:
    """``M(x)`` of the simply supported beam on ``[-span/2, span/2]`` under the loads.

    The loads are divided by the load unit (the largest point load or load resultant), so
    that the moment's numbers are of order one whatever the loads' unit; :attr:`load_unit`
    takes them back.

    Parameters
    ----------
    points : (n, 2) float
        Point loads ``[x, P]`` (F), positions snapped (:func:`.funicular_loads.snap_positions`).
    distributed : (m, 4) float
        Distributed loads ``[x0, x1, q0, q1]`` (F/m), positions snapped.
    span : float
        m.

    Attributes
    ----------
    load_unit : float
        F: the loads of the moment are the given ones divided by it.
    total_load : float
        The sum of the loads, in load units.
    reactions : (2,) float
        Left and right support reactions, in load units.
    breaks : (b,) float
        The ends of the cubic pieces: the supports, mid-span and every load position, m.
    origins : (b - 1,) float
        The abscissa each piece's cubic is expanded about, m.
    coefficients : (b - 1, 4) float
        ``c0 .. c3`` of ``M(origin + t)`` of every piece.
    max_moment : float
        The largest ``M`` (load units times m).
    apex_x : float
        Where ``M`` is largest, m.
    kink_x : (k,) float
        The distinct point-load positions, sorted, m.

    Raises
    ------
    ProfileError
        The total load is not finite or is zero, or ``M`` is not positive inside the span.

    Examples
    --------
    A point load at the middle of a 4 m beam: ``M = P L / 4`` (one load unit times 1 m):

    >>> import numpy as np
    >>> moment = BeamMoment(np.array([[0.0, 10.0]]), np.zeros((0, 4)), 4.0)
    >>> moment.load_unit, moment.reactions.tolist(), moment.max_moment, moment.apex_x
    (10.0, [0.5, 0.5], 1.0, 0.0)
    >>> moment.breaks.tolist(), moment.kink_x.tolist()
    ([-2.0, 0.0, 2.0], [0.0])
    """

    def __init__(self, points: np.ndarray, distributed: np.ndarray, span: float):
        self.span = span
        half = 0.5 * span
        points, distributed, resultants = self._normalise(points, distributed)
        self._set_reactions(points, distributed, resultants, half)
        self._set_pieces(points, distributed, half)
        values = self._set_maximum()
        self._guard(half, values)
        self.kink_x = np.unique(points[:, 0])

    def _normalise(self, points: np.ndarray, distributed: np.ndarray) -> tuple:
        """Check the total load and divide the loads by the load unit."""
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
        self.load_unit = unit
        points = points * np.array([1.0, 1.0 / unit])
        distributed = distributed * np.array([1.0, 1.0, 1.0 / unit, 1.0 / unit])
        resultants = resultants / unit
        return points, distributed, resultants

    def _set_reactions(self, points, distributed, resultants, half: float) -> None:
        """The total load and the support reactions (moments about the supports)."""
        # centroid of a trapezoid of intensities q0, q1 over [x0, x1]
        widths = distributed[:, 1] - distributed[:, 0]
        sums = distributed[:, 2] + distributed[:, 3]
        centroids = distributed[:, 0] + widths * (distributed[:, 2] + 2.0 * distributed[:, 3]) / (
            3.0 * sums
        )
        self.total_load = float(points[:, 1].sum() + resultants.sum())
        left = (points[:, 1] @ (half - points[:, 0]) + resultants @ (half - centroids)) / self.span
        right = (points[:, 1] @ (half + points[:, 0]) + resultants @ (half + centroids)) / self.span
        self.reactions = np.array([left, right])

    def _set_pieces(self, points, distributed, half: float) -> None:
        """The breaks and the cubic of every piece: from the left reaction left of mid-span,
        from the right one (the loads mirrored) right of it."""
        left, right = self.reactions
        breaks = np.unique(
            np.concatenate([[-half, 0.0, half], points[:, 0], distributed[:, :2].ravel()])
        )
        self.breaks = breaks
        lower, upper = breaks[:-1], breaks[1:]
        from_right = lower >= 0.0
        origins = np.where(from_right, upper, lower)
        coefficients = coefficients_from_left(origins, points, distributed, left, half)
        mirrored_points = points * np.array([-1.0, 1.0])
        mirrored_distributed = distributed[:, [1, 0, 3, 2]] * np.array([-1.0, -1.0, 1.0, 1.0])
        mirrored = coefficients_from_left(
            -origins, mirrored_points, mirrored_distributed, right, half
        )
        mirrored *= np.array([1.0, -1.0, 1.0, -1.0])  # t' = -t
        self.origins = origins
        self.coefficients = np.where(from_right[:, None], mirrored, coefficients)

    def _set_maximum(self) -> np.ndarray:
        """``max M`` and its place: at a break or where ``M' = 0`` inside a piece (``M`` is
        concave for loads >= 0); returns the moments at the candidates."""
        lower, upper = self.breaks[:-1], self.breaks[1:]
        candidates_x, candidates_piece = [], []
        for piece in range(len(lower)):
            candidates_x += [lower[piece], upper[piece]]
            candidates_piece += [piece, piece]
            c1, c2, c3 = self.coefficients[piece, 1:]
            for root in quadratic_roots(3.0 * c3, 2.0 * c2, c1):
                x = self.origins[piece] + root
                if lower[piece] < x < upper[piece]:
                    candidates_x.append(x)
                    candidates_piece.append(piece)
        candidates_x = np.array(candidates_x)
        values = self.value(candidates_x, np.array(candidates_piece))
        best = int(np.argmax(values))
        self.max_moment = float(values[best])
        self.apex_x = float(candidates_x[best])
        return values[best]

    def _guard(self, half: float, best) -> None:
        """Refuse a moment that is not positive at the breaks and the middles of the pieces
        strictly inside the span (``best``: the largest moment found)."""
        lower, upper = self.breaks[:-1], self.breaks[1:]
        where = np.concatenate([upper[:-1], 0.5 * (lower + upper)])
        where_piece = np.concatenate([np.arange(len(upper) - 1), np.arange(len(lower))])
        strictly_inside = (where > -half) & (where < half)
        where, where_piece = where[strictly_inside], where_piece[strictly_inside]
        inner = self.value(where, where_piece)
        if not (self.max_moment > 0.0 and math.isfinite(self.max_moment)) or not np.all(
            inner > 0.0
        ):
            index = int(np.argmin(inner)) if inner.size else 0
            bad_x, bad_m = (where[index], inner[index]) if inner.size else (self.apex_x, best)
            raise ProfileError(
                "the bending moment of the loads must be > 0 inside the span, got "
                f"M = {float(bad_m) * self.load_unit!r} at x = {float(bad_x)!r} m"
            )

    def value(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """``M`` (load units times m) at ``x`` evaluated with the cubic of ``piece``."""
        c = self.coefficients[piece]
        t = x - self.origins[piece]
        return ((c[..., 3] * t + c[..., 2]) * t + c[..., 1]) * t + c[..., 0]

    def derivative(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """``M'`` at ``x`` with the cubic of ``piece``."""
        c = self.coefficients[piece]
        t = x - self.origins[piece]
        return (3.0 * c[..., 3] * t + 2.0 * c[..., 2]) * t + c[..., 1]

    def second_derivative(self, x: np.ndarray, piece: np.ndarray) -> np.ndarray:
        """``M''`` at ``x`` with the cubic of ``piece`` (minus the load intensity there)."""
        c = self.coefficients[piece]
        t = x - self.origins[piece]
        return 6.0 * c[..., 3] * t + 2.0 * c[..., 2]


def coefficients_from_left(
    origins: np.ndarray,
    points: np.ndarray,
    distributed: np.ndarray,
    reaction: float,
    half: float,
) -> np.ndarray:
    """Cubic coefficients ``c0..c3`` of ``M(origin + t)`` from the loads left of each origin.

    ``M(x) = R (x + half) - sum P (x - a) - int q(xi) (x - xi) dxi`` over the loads left of
    ``x``. Valid on a piece ``[origin, next break]`` (the load positions are breaks).

    Returns
    -------
    (len(origins), 4) float

    Examples
    --------
    A unit load at mid-span of a 4 m beam (reaction 0.5): ``M = 0.5 t`` from the left support,
    ``M = 1 - 0.5 t`` from mid-span:

    >>> import numpy as np
    >>> points = np.array([[0.0, 1.0]])
    >>> coefficients_from_left(np.array([-2.0, 0.0]), points, np.zeros((0, 4)), 0.5, 2.0).tolist()
    [[0.0, 0.5, 0.0, 0.0], [1.0, -0.5, 0.0, 0.0]]
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


def quadratic_roots(a: float, b: float, c: float) -> list:
    """Real roots of ``a t^2 + b t + c`` (cancellation-free), none if it is constant.

    Examples
    --------
    >>> quadratic_roots(1.0, -3.0, 2.0), quadratic_roots(0.0, 2.0, -1.0), quadratic_roots(1, 0, 1)
    ([2.0, 1.0], [0.5], [])
    """
    if a == 0.0:
        return [] if b == 0.0 else [-c / b]
    discriminant = b * b - 4.0 * a * c
    if discriminant < 0.0:
        return []
    q = -0.5 * (b + math.copysign(math.sqrt(discriminant), b))
    return [q / a] if q == 0.0 else [q / a, c / q]
