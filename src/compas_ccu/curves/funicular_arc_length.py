"""Arc length of a piecewise smooth graph ``y(x)`` and its inverse, for the funicular arch.

:class:`ArcLengthTable` integrates the speed ``ds/dx = sqrt(1 + y'^2)`` by adaptive 16-point
Gauss-Legendre quadrature on each smooth piece (cells are bisected until each is integrated to
about 1e-14 of the length) and inverts the arc length by safeguarded Newton iterations on
``x`` to 1e-14 relative (:class:`~compas_ccu.curves.funicular.FunicularProfile`). The rule and
its tolerances are shared with :class:`~compas_ccu.curves.spline.SplineProfile`.
"""

from __future__ import annotations

import functools

import numpy as np

from compas_ccu.tolerances import ROUND_OFF

__all__ = [
    "ArcLengthTable",
    "cell_of",
    "gauss_legendre_rule",
    "GAUSS_ORDER",
    "MAX_BISECTIONS",
    "QUADRATURE_TOLERANCE",
    "NEWTON_TOLERANCE",
    "NEWTON_MAX_ITERATIONS",
]

#: The arc-length quadrature and its Newton inverse, shared by the funicular and the spline
#: profiles: Gauss-Legendre points per cell, bisections of a cell at most, the cells' and the
#: inversion's tolerance (relative to the length) and Newton's iterations at most.

GAUSS_ORDER = 16
MAX_BISECTIONS = 40
QUADRATURE_TOLERANCE = ROUND_OFF
NEWTON_TOLERANCE = ROUND_OFF
NEWTON_MAX_ITERATIONS = 60


@functools.lru_cache(maxsize=1)
def gauss_legendre_rule() -> tuple:
    """Nodes and weights of the Gauss-Legendre rule on [-1, 1], ``(GAUSS_ORDER,)`` each.

    Examples
    --------
    >>> nodes, weights = gauss_legendre_rule()
    >>> nodes.shape, round(float(weights.sum()), 12)
    ((16,), 2.0)
    """
    return np.polynomial.legendre.leggauss(GAUSS_ORDER)


def cell_of(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Index ``j`` with ``edges[j] <= value < edges[j+1]``, clipped to the cells.

    Examples
    --------
    >>> import numpy as np
    >>> cell_of(np.array([-1.0, 0.0, 0.5, 1.0, 2.5]), np.array([0.0, 1.0, 2.0])).tolist()
    [0, 0, 0, 1, 1]
    """
    return np.clip(np.searchsorted(edges, values, side="right") - 1, 0, len(edges) - 2)


class ArcLengthTable:
    """Adaptive Gauss-Legendre table of cells ``[cell_x[j], cell_x[j+1]]`` and their lengths.

    Vectorised over all cells of one level: starting from the smooth pieces, a cell is
    accepted (as its two halves) when the integral of the speed over the whole cell agrees
    with the sum over its halves to ``QUADRATURE_TOLERANCE * length``; otherwise both halves
    are bisected further. The breaks of the pieces are cell breaks: their arc lengths are
    table entries.

    Parameters
    ----------
    breaks : (b,) float
        The ends of the smooth pieces, increasing, m.
    speed : callable
        ``speed(x, piece) -> ds/dx`` at abscissae ``x`` on the pieces ``piece`` (broadcast).

    Attributes
    ----------
    cell_x : (c + 1,) float
        The cell breaks, m.
    cell_piece : (c,) int
        The piece of every cell.
    cell_s : (c + 1,) float
        The arc length at every cell break, m.
    length : float
        The whole arc length, m.

    Examples
    --------
    The parabola ``y = x^2`` on ``[0, 1]`` (one smooth piece), its length in closed form:

    >>> import math
    >>> import numpy as np
    >>> table = ArcLengthTable(np.array([0.0, 1.0]), lambda x, piece: np.sqrt(1.0 + 4.0 * x**2))
    >>> round(table.length, 12) == round(math.sqrt(5.0) / 2 + math.asinh(2.0) / 4, 12)
    True
    >>> x, piece = table.x_at(np.array([table.length / 2]))
    >>> round(float(x[0]), 6), piece.tolist()
    (0.610739, [0])
    """

    def __init__(self, breaks: np.ndarray, speed):
        self._speed = speed
        lower, upper = breaks[:-1], breaks[1:]
        piece = np.arange(len(lower))
        tolerance = QUADRATURE_TOLERANCE * self._gauss_legendre(lower, upper, piece).sum()
        accepted_lower, accepted_lengths, accepted_piece = [], [], []
        for depth in range(MAX_BISECTIONS + 1):
            middle = 0.5 * (lower + upper)
            whole = self._gauss_legendre(lower, upper, piece)
            left = self._gauss_legendre(lower, middle, piece)
            right = self._gauss_legendre(middle, upper, piece)
            done = np.abs(left + right - whole) <= tolerance
            if depth == MAX_BISECTIONS:
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
        self.cell_x = np.append(cell_lower[order], breaks[-1])
        self.cell_piece = np.concatenate(accepted_piece)[order]
        cell_lengths = np.concatenate(accepted_lengths)[order]
        self.cell_s = np.concatenate([[0.0], np.cumsum(cell_lengths)])
        self.length = float(self.cell_s[-1])

    def _gauss_legendre(self, lower: np.ndarray, upper: np.ndarray, piece: np.ndarray):
        """Integral of the speed over ``[lower, upper]`` on ``piece`` (elementwise)."""
        gauss_nodes, gauss_weights = gauss_legendre_rule()
        half = 0.5 * (upper - lower)
        nodes = (0.5 * (upper + lower))[..., None] + half[..., None] * gauss_nodes
        return half * (self._speed(nodes, np.asarray(piece)[..., None]) @ gauss_weights)

    def arc_length_at_x(self, x: np.ndarray) -> np.ndarray:
        """Arc lengths (m) at abscissae ``x`` inside the table's range."""
        return self.arc_length_in_cell(cell_of(x, self.cell_x), x)

    def arc_length_in_cell(self, cell: np.ndarray, x: np.ndarray) -> np.ndarray:
        """Arc length at abscissae ``x`` lying in the cells ``cell``."""
        start = self.cell_x[cell]
        return self.cell_s[cell] + self._gauss_legendre(start, x, self.cell_piece[cell])

    def x_at(self, s: np.ndarray) -> tuple:
        """Abscissae ``x`` with arc length ``s`` (in ``[0, length]``) and their pieces, to
        1e-14 relative.

        An ``s`` at a cell break (a kink, for instance) maps exactly to the break's ``x``, with
        the piece that starts there.
        """
        cell_x, cell_s = self.cell_x, self.cell_s
        cell = cell_of(s, cell_s)
        lower, upper = cell_x[cell], cell_x[cell + 1]
        cell_length = cell_s[cell + 1] - cell_s[cell]  # 0 only for a cell below round-off
        fraction = (s - cell_s[cell]) / np.where(cell_length > 0.0, cell_length, 1.0)
        fraction = np.clip(np.where(cell_length > 0.0, fraction, 0.0), 0.0, 1.0)
        x = lower + fraction * (upper - lower)
        piece = self.cell_piece[cell]
        tolerance = NEWTON_TOLERANCE * self.length
        for _ in range(NEWTON_MAX_ITERATIONS):
            residual = self.arc_length_in_cell(cell, x) - s
            # the arc length increases with x: keep a bracket and bisect when Newton leaves it
            upper = np.where(residual > 0.0, x, upper)
            lower = np.where(residual < 0.0, x, lower)
            newton = x - residual / self._speed(x, piece)
            inside = (newton >= lower) & (newton <= upper)
            x = np.where(inside, newton, 0.5 * (lower + upper))
            if np.all(np.abs(residual) <= tolerance):
                break  # after one more Newton step, which squares the last error
        return x, piece
