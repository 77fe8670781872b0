"""Global curvature class of a corrugated multi-crease structure, measured from its geometry.

Paper §5.5: although every plate stays monoclastic, the corrugated structure as a whole follows
a monoclastic, synclastic or anticlastic global surface. We measure it, not assume it:

1. The curves on the crease planes ``G_0 .. G_m`` (creases and the two free boundaries)
   alternate between ridge and valley. The period-2 filter ``(G_i + 2 G_{i+1} + G_{i+2}) / 4``
   removes the corrugation exactly for any alternating pattern of two offsets and leaves the
   global surface sampled on a grid (rows across the corrugation, columns along the creases).
2. Around the centre of that grid (the row at the leading plane, the middle column) the
   Gaussian curvature ``K`` is the angle defect ``2 pi - sum of corner angles`` summed over the
   window's vertices divided by their area (a quarter of each adjacent quad). It is exactly zero
   on a discrete developable, e.g. a grid whose rows follow the rulings of a cylinder or a cone,
   so monoclastic structures measure ``K = 0`` to rounding and not to a fitting error.
3. The mean curvature ``H`` comes from a least-squares quadratic height function
   ``h = c0 + c1 a + c2 b + (A a^2 + 2 B a b + C b^2) / 2`` in a local frame; the principal
   curvatures are ``H +- sqrt(H^2 - K)``.
4. The class is *monoclastic* when ``|K| <= tolerance * max|k|^2`` (the smaller principal
   curvature is below ``tolerance`` times the larger) and otherwise *synclastic* (``K > 0``) or
   *anticlastic* (``K < 0``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["GlobalCurvature", "global_curvature"]


@dataclass(frozen=True)
class GlobalCurvature:
    """Measured global curvature at the centre of a corrugated structure.

    Attributes
    ----------
    kind : str
        ``"synclastic"``, ``"anticlastic"`` or ``"monoclastic"``.
    principal : (2,) float
        Principal curvatures, 1/m, larger magnitude first; the sign is relative to the surface
        normal at the centre (same sign: synclastic).
    gaussian : float
        ``k1 * k2``, 1/m^2.
    ratio : float
        ``|K| / max|k|^2``, i.e. ``min |k| / max |k|``, compared with the tolerance.
    point : (3,) float
        Where it was measured (on the filtered global surface).
    """

    kind: str
    principal: np.ndarray
    gaussian: float
    ratio: float
    point: np.ndarray

    def summary(self) -> dict:
        """Plain JSON-able values."""
        return {
            "global_curvature": self.kind,
            "principal_curvatures": [float(v) for v in self.principal],
            "gaussian_curvature": float(self.gaussian),
            "curvature_ratio": float(self.ratio),
        }


def global_curvature(
    curves: np.ndarray, *, row: int | None = None, column: int | None = None, tolerance=1e-3
) -> GlobalCurvature:
    """Measure the global curvature class of a corrugated structure.

    Parameters
    ----------
    curves : (m + 1, n + 1, 3) float
        The curves on crease planes ``0 .. m`` in order, vertices in crease order (see
        :meth:`compas_ccu.model.CCUModel.plane_curves`); ``m >= 4``.
    row : int, optional
        Plane at which to measure, ``2 .. m - 2``; default: the middle plane.
    column : int, optional
        Crease vertex at which to measure; default: the middle vertex.
    tolerance : float
        Relative size of the smaller principal curvature below which the surface counts as
        monoclastic.

    Returns
    -------
    GlobalCurvature

    Examples
    --------
    A sphere of radius 2 sampled as a grid of meridians is synclastic with ``K = 1/4`` and
    mean curvature ``1/2`` (near an umbilic the split into ``k1, k2`` is sensitive):

    >>> import numpy as np
    >>> u, v = np.meshgrid(np.linspace(-0.4, 0.4, 9), np.linspace(-0.6, 0.6, 17), indexing="ij")
    >>> sphere = 2.0 * np.stack([np.cos(v) * np.sin(u), np.sin(v), np.cos(v) * np.cos(u)], -1)
    >>> g = global_curvature(sphere)
    >>> g.kind, round(g.gaussian, 3), round(float(g.principal.mean()), 2)
    ('synclastic', 0.25, 0.5)
    """
    g = np.asarray(curves, dtype=float)
    m = g.shape[0] - 1
    if g.ndim != 3 or g.shape[2] != 3 or m < 4 or g.shape[1] < 5:
        raise ValueError(
            "the global curvature needs at least 5 plane curves (4 plates) of at least 5 "
            f"vertices, got curves of shape {g.shape}"
        )
    smooth = 0.25 * (g[:-2] + 2.0 * g[1:-1] + g[2:])  # row i centred on plane i + 1
    r = (m // 2 if row is None else int(row)) - 1
    r = min(max(r, 1), len(smooth) - 2)
    n = g.shape[1] - 1
    j = n // 2 if column is None else int(column)
    w = max(2, n // 8)
    j = min(max(j, w), n - w)
    window = smooth[r - 1 : r + 2, j - w : j + w + 1].reshape(-1, 3)
    centre = smooth[r, j]
    u = smooth[r, j + 1] - smooth[r, j - 1]
    v = smooth[r + 1, j] - smooth[r - 1, j]
    normal = np.cross(u, v)
    normal /= np.linalg.norm(normal)
    u = u / np.linalg.norm(u)
    v = np.cross(normal, u)
    rel = window - centre
    a, b, h = rel @ u, rel @ v, rel @ normal
    basis = np.c_[np.ones_like(a), a, b, 0.5 * a * a, a * b, 0.5 * b * b]
    c0, c1, c2, big_a, big_b, big_c = np.linalg.lstsq(basis, h, rcond=None)[0]
    first = np.array([[1.0 + c1 * c1, c1 * c2], [c1 * c2, 1.0 + c2 * c2]])
    second = np.array([[big_a, big_b], [big_b, big_c]]) / np.sqrt(1.0 + c1 * c1 + c2 * c2)
    mean = 0.5 * float(np.trace(np.linalg.solve(first, second)))
    gaussian = _angle_defect_curvature(smooth[r - 1 : r + 2, j - w - 1 : j + w + 2])
    root = np.sqrt(max(mean * mean - gaussian, 0.0))
    k = np.array([mean + root, mean - root])
    k = k[np.argsort(-np.abs(k))]
    ratio = abs(gaussian) / float(k[0] * k[0]) if k[0] != 0.0 else 0.0
    if ratio <= tolerance:
        kind = "monoclastic"
    else:
        kind = "synclastic" if gaussian > 0.0 else "anticlastic"
    return GlobalCurvature(kind, k, gaussian, ratio, centre)


def _angle_defect_curvature(grid: np.ndarray) -> float:
    """Integrated angle defect of the interior vertices of a (3, q, 3) grid over their area."""

    def angle(p, a, b):
        u, v = a - p, b - p
        return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), np.einsum("...i,...i", u, v))

    p = grid[1, 1:-1]
    left, right = grid[1, :-2], grid[1, 2:]
    down, up = grid[0, 1:-1], grid[2, 1:-1]
    corners = angle(p, right, up) + angle(p, up, left) + angle(p, left, down)
    corners += angle(p, down, right)
    defect = 2.0 * np.pi - corners

    def tri(a, b):
        return 0.5 * np.linalg.norm(np.cross(a - p, b - p), axis=-1)

    # a quarter of each adjacent quad: half the triangle spanned by p and two neighbours
    area = 0.5 * (tri(right, up) + tri(up, left) + tri(left, down) + tri(down, right))
    return float(defect.sum() / area.sum())
