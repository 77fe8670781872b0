"""The shared geometry kernel: unit vectors, reflections, plane fits, frames and rigid alignment.

Pure functions over NumPy arrays, broadcasting over leading axes. Every layer of the package uses
these instead of writing its own (the curves, strips, kinematics, thickness, FE and fabrication
layers all reflect in planes and fit planes).

>>> import numpy as np
>>> unit(np.array([3.0, 4.0, 0.0])).tolist()
[0.6, 0.8, 0.0]
>>> reflect(np.array([[1.0, 2.0, 3.0]]), np.array([0.0, 0.0, 1.0])).tolist()
[[1.0, 2.0, -3.0]]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import DesignError
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = [
    "edge_fold_angles",
    "unit",
    "dot",
    "cross3",
    "norm3",
    "unit3",
    "coordinate_dot",
    "coordinate_cross",
    "coordinate_unit",
    "reflect",
    "reflect_points",
    "fit_planes",
    "plane_frame",
    "PlaneFrame",
    "rigid_align",
]


def unit(v: np.ndarray) -> np.ndarray:
    """Unit vectors along the last axis of ``v`` (..., d)."""
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot products of (..., d) arrays: (...,)."""
    return np.einsum("...i,...i", a, b)


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``numpy.cross`` of (..., 3) arrays: the same products and differences (the same values,
    bit for bit) without its axis juggling, which costs more than the arithmetic on small
    arrays."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def norm3(v: np.ndarray) -> np.ndarray:
    """``numpy.linalg.norm(v, axis=-1)`` of (..., 3) arrays: the same sum in the same order (the
    same values, bit for bit), several times faster than a reduction over a length-3 axis."""
    v0, v1, v2 = v[..., 0], v[..., 1], v[..., 2]
    return np.sqrt(v0 * v0 + v1 * v1 + v2 * v2)


def unit3(v: np.ndarray) -> np.ndarray:
    """:func:`unit` of (..., 3) arrays (the same values) by :func:`norm3`."""
    return v / norm3(v)[..., None]


def coordinate_dot(u: np.ndarray, v: np.ndarray, *, out=None, term=None) -> np.ndarray:
    """:func:`dot` of vectors stored coordinate by coordinate, (3, ...) arrays: the same values
    as :func:`dot` of contiguous (..., 3) vectors, whose ``einsum`` sums the three products as
    ``(0 + 2) + 1``, on long contiguous rows. With ``out`` and ``term`` (arrays of the result's
    shape, e.g. kept work arrays) written there, the same operations."""
    out = np.multiply(u[0], v[0], out=out)
    out += np.multiply(u[2], v[2], out=term)
    out += np.multiply(u[1], v[1], out=term)
    return out


def coordinate_cross(u: np.ndarray, v: np.ndarray, *, out=None, one=None, two=None) -> np.ndarray:
    """:func:`cross3` of vectors stored coordinate by coordinate, (3, ...) arrays; with ``out``
    (3, ...) and ``one``, ``two`` (arrays of the shape of ``out[0]``) written there."""
    if out is None:
        out = np.empty(np.broadcast_shapes(u.shape, v.shape))
    for i, j, c in ((1, 2, 0), (2, 0, 1), (0, 1, 2)):
        np.subtract(np.multiply(u[i], v[j], out=one), np.multiply(u[j], v[i], out=two), out=out[c])
    return out


def coordinate_unit(v: np.ndarray, *, in_place: bool = False, size=None, term=None) -> np.ndarray:
    """:func:`unit3` of vectors stored coordinate by coordinate, (3, ...) arrays; with
    ``in_place`` written over ``v`` (``size``, ``term``: arrays of the shape of ``v[0]``)."""
    size = np.multiply(v[0], v[0], out=size)
    size += np.multiply(v[1], v[1], out=term)
    size += np.multiply(v[2], v[2], out=term)
    return np.divide(v, np.sqrt(size, out=size), out=v if in_place else None)


def reflect(v: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Directions ``v`` (m, 3) mirrored in a plane with unit ``normal`` (3,)."""
    return v - 2.0 * (v @ normal)[:, None] * normal


def reflect_points(points: np.ndarray, origin: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Points (..., m, 3) mirrored in the planes ``origin, normal`` (..., 3), one plane per row
    set (e.g. (k, m, 3) points and (k, 3) planes: one plane per state)."""
    distance = dot(points - origin[..., None, :], normal[..., None, :])
    return points - 2.0 * distance[..., None] * normal[..., None, :]


def fit_planes(points: np.ndarray, orient: np.ndarray):
    """Least-squares planes of ``(..., m, 3)`` point sets.

    Returns origins ``(..., 3)``, unit normals ``(..., 3)`` with ``normal @ orient >= 0`` and
    the largest point-plane distance ``(...,)``. ``orient`` is one direction ``(3,)`` for all
    the point sets or one per set (``(..., 3)``, broadcast against the sets).

    >>> import numpy as np
    >>> pts = np.array([[[0.0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]]])
    >>> origin, normal, deviation = fit_planes(pts, np.array([0.0, 0, 1]))
    >>> normal.round(12).tolist(), float(deviation[0])
    ([[0.0, 0.0, 1.0]], 0.0)
    """
    lead, m = points.shape[:-2], points.shape[-2]
    points = points.reshape(-1, m, 3)  # one stack of point sets: the same operations per set
    if orient.ndim > 1:
        if orient.shape[:-1] != lead:
            orient = np.broadcast_to(orient, (*lead, 3))
        orient = orient.reshape(-1, 3)
    origin = np.add.reduce(points, axis=1)  # points.mean(axis=1): its sum, then its division
    origin /= m
    centred = points - origin[:, None, :]
    # the last right singular vector of the centred points, not the eigenvector of their
    # covariance: squaring the points squares the condition, and an almost straight crease row
    # (sagitta 1e-3 of its length) would turn its plane by 1e-10 rad instead of 1e-13
    if np.isfinite(centred).all():  # the usual case, without the masking below
        normal = np.linalg.svd(centred, full_matrices=m < 3)[2][:, -1, :].copy()
    else:
        finite = np.isfinite(centred).all(axis=(1, 2))
        safe = np.where(finite[:, None, None], centred, 0.0)
        _, _, vt = np.linalg.svd(safe, full_matrices=m < 3)
        normal = np.where(finite[:, None], vt[:, -1, :], np.nan)
    towards = normal @ orient if orient.ndim == 1 else dot(normal, orient)
    np.negative(normal, out=normal, where=(towards < 0.0)[:, None])  # oriented like ``orient``
    deviation = np.maximum.reduce(np.abs(np.einsum("kni,ki->kn", centred, normal)), axis=1)
    return origin.reshape(*lead, 3), normal.reshape(*lead, 3), deviation.reshape(lead)


def _direction(vector, key: str) -> np.ndarray:
    """A unit direction from a vector of any finite non-zero size (scaled before the norm, so
    neither 1e-200 nor 1e200 under- or overflows)."""
    v = np.asarray(vector, dtype=float)
    scale = float(np.abs(v).max()) if v.size else 0.0
    if not (np.all(np.isfinite(v)) and scale > 0.0):
        raise DesignError(f"must be a finite non-zero direction, got {list(vector)}", key=key)
    return unit(v / scale)


def plane_frame(origin, xaxis, yaxis):
    """World frame of a plane: origin (3,) and the rows x, y, normal (3, 3).

    ``yaxis`` is made orthogonal to ``xaxis``.

    Raises
    ------
    DesignError
        An axis is zero or not finite, or ``yaxis`` is parallel to ``xaxis`` (names the key).
    """
    x = _direction(xaxis, "plane.xaxis")
    y = _direction(yaxis, "plane.yaxis")
    y = y - (y @ x) * x
    if np.linalg.norm(y) < ZERO_LENGTH:
        raise DesignError(
            f"must not be parallel to plane.xaxis, got {list(yaxis)}", key="plane.yaxis"
        )
    y = unit(y)
    return np.asarray(origin, dtype=float), np.array([x, y, np.cross(x, y)])


@dataclass(frozen=True)
class PlaneFrame:
    """The world frame of the leading crease plane.

    Local coordinates: profile x, profile y (times ``flip``), distance from the plane.

    Attributes
    ----------
    origin : (3,) float
    axes : (3, 3) float
        Rows: x axis, y axis, plane normal (world).
    flip : float
        +1 if the leading plate lies left of the profile, -1 if right (the local frame mirrors
        profile y then).
    """

    origin: np.ndarray
    axes: np.ndarray
    flip: float

    def to_world(self, local: np.ndarray) -> np.ndarray:
        """World points from local points (..., 3)."""
        return self.origin + self.vector_to_world(local)

    def vector_to_world(self, local: np.ndarray) -> np.ndarray:
        """World vectors from local vectors (..., 3)."""
        return (local * np.array([1.0, self.flip, 1.0])) @ self.axes


def rigid_align(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``source`` moved by the rotation and translation that best fit it to ``target`` (Kabsch).

    Parameters
    ----------
    source, target : (m, 3) float
        Corresponding points.

    Returns
    -------
    (m, 3) float

    Examples
    --------
    >>> import numpy as np
    >>> p = np.random.default_rng(0).normal(size=(10, 3))
    >>> c, s = np.cos(0.3), np.sin(0.3)
    >>> q = p @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]).T + [1.0, 2.0, 3.0]
    >>> bool(np.allclose(rigid_align(p, q), q))
    True
    """
    cs, ct = source.mean(axis=0), target.mean(axis=0)
    h = (source - cs).T @ (target - ct)
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    rot = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
    return (source - cs) @ rot.T + ct


def edge_fold_angles(crease: np.ndarray, side_a: np.ndarray, side_b: np.ndarray) -> np.ndarray:
    """The angle between two planar-quad strips across every edge of their shared boundary.

    Measured from the geometry alone, edge by edge (docs/geometry.md, "Fold angles"): within
    each quad, the direction from the crease edge towards the quad's far edge, perpendicular to
    the crease edge; the fold angle is the angle between the two strips' directions (0: folded
    flat onto each other, 180: one plane). For two mirror-image strips it is twice the
    reflection angle of the edge, whatever the per-vertex angles read at a kink or an
    inflection of the crease.

    Parameters
    ----------
    crease : (..., n + 1, 3) float
        The shared boundary.
    side_a, side_b : (..., n + 1, 3) float
        The other boundary of each strip (its rulings end there).

    Returns
    -------
    (..., n) float
        Degrees.

    Examples
    --------
    Two strips at right angles across a straight crease along x:

    >>> crease = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    >>> up, out = crease + [0.0, 0.0, 1.0], crease + [0.0, 1.0, 0.0]
    >>> edge_fold_angles(crease, up, out).round(12).tolist()
    [90.0, 90.0]
    """
    p = np.asarray(crease, dtype=float)
    e = unit3(p[..., 1:, :] - p[..., :-1, :])
    mid = 0.5 * (p[..., 1:, :] + p[..., :-1, :])

    def across(side):
        q = np.asarray(side, dtype=float)
        d = 0.5 * (q[..., 1:, :] + q[..., :-1, :]) - mid
        return unit3(d - dot(d, e)[..., None] * e)

    ua, ub = across(side_a), across(side_b)
    # atan2 of |cross| and dot: accurate near 0 and 180 degrees, where arccos is not
    return np.degrees(np.arctan2(norm3(cross3(ua, ub)), dot(ua, ub)))
