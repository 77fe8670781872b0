"""Intrinsic description of a planar-quad strip: what isometric deployment preserves.

A strip (docs/geometry.md §2) is a chain of planar quads between two polylines: the *near* boundary
``P_0 .. P_n`` (a crease, or the crease nearest to the leading crease) and the *far* boundary
``Q_0 .. Q_n`` (the next crease or a free edge). Quad ``j`` is ``P_j, P_{j+1}, Q_{j+1}, Q_j``;
the segments ``P_i Q_i`` are rulings. Every quad is rigid, so the strip is fixed by

* the crease edge lengths ``|P_{j+1} - P_j|``,
* at each crease vertex the two sector angles between the ruling and the crease edges,
* the ruling lengths ``|Q_i - P_i|``.

These are the numbers the kinematics needs; they are the same in the cut pattern and in every
deployed state.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.errors import GeometryError
from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE, ZERO_LENGTH

__all__ = ["StripIntrinsics", "strip_intrinsics", "sector_angles"]


class StripIntrinsics(NamedTuple):
    """Isometry invariants of a strip.

    Attributes
    ----------
    edge_lengths : (n,) float
        Crease edge lengths ``|P_{j+1} - P_j|``.
    sector_back : (n + 1,) float
        Angle at ``P_i`` between the backward crease edge ``P_{i-1} - P_i`` and the ruling
        (radians, on the plate's side); NaN at ``i = 0``.
    sector_forward : (n + 1,) float
        Angle at ``P_i`` between the forward crease edge ``P_{i+1} - P_i`` and the ruling;
        NaN at ``i = n``.
    ruling_lengths : (n + 1,) float
        ``|Q_i - P_i|``.

    Examples
    --------
    >>> import numpy as np
    >>> near = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> strip = strip_intrinsics(near, near + [0.0, 2.0])
    >>> isinstance(strip, StripIntrinsics), strip.ruling_lengths.tolist()
    (True, [2.0, 2.0, 2.0])
    """

    edge_lengths: np.ndarray
    sector_back: np.ndarray
    sector_forward: np.ndarray
    ruling_lengths: np.ndarray

    @property
    def segments(self) -> int:
        return len(self.edge_lengths)

    @property
    def plate_angles(self) -> np.ndarray:
        """(n + 1,) interior angle of the plate between the two crease edges, NaN at the ends."""
        return self.sector_back + self.sector_forward


#: Vertex pairs (quad corners a, b, c, d) of the six quad lengths: sides ab, bc, cd, da and
#: diagonals ac, bd. Six distances fix four points up to a rigid motion, planarity included.
QUAD_LENGTH_PAIRS = np.array([(0, 1), (1, 2), (2, 3), (3, 0), (0, 2), (1, 3)])


def quad_corners(near: np.ndarray, far: np.ndarray) -> np.ndarray:
    """(..., n, 4, 3) corners ``a, b, c, d`` of every quad; ``near, far`` are (..., n + 1, 3)."""
    return np.stack([near[..., :-1, :], near[..., 1:, :], far[..., 1:, :], far[..., :-1, :]], -2)


def quad_lengths(near: np.ndarray, far: np.ndarray) -> np.ndarray:
    """(..., n, 6) side and diagonal lengths of every quad (order of ``QUAD_LENGTH_PAIRS``)."""
    q = quad_corners(near, far)
    pairs = QUAD_LENGTH_PAIRS
    return np.linalg.norm(q[..., pairs[:, 1], :] - q[..., pairs[:, 0], :], axis=-1)


def _angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Unsigned angle between rows of ``a`` and ``b`` (any dimension), robust near 0 and pi."""
    if a.shape[-1] == 2:
        cross = np.abs(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])
    else:
        cross = np.linalg.norm(np.cross(a, b), axis=-1)
    return np.arctan2(cross, np.einsum("...i,...i->...", a, b))


def sector_angles(near: np.ndarray, far: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sector angles at the near-boundary vertices of a strip.

    Parameters
    ----------
    near, far : (n + 1, d) float
        Near boundary (crease) and far boundary points, ``d`` = 2 or 3.

    Returns
    -------
    sector_back, sector_forward : (n + 1,) float
        See :class:`StripIntrinsics`. Unsigned angles in [0, pi]; NaN where the edge is missing.

    Examples
    --------
    >>> import numpy as np
    >>> near = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> back, fwd = sector_angles(near, near + [0.0, 1.0])
    >>> np.degrees(fwd[:2]).round(6).tolist(), np.degrees(back[1:]).round(6).tolist()
    ([90.0, 90.0], [90.0, 90.0])
    """
    near = np.asarray(near, dtype=float)
    far = np.asarray(far, dtype=float)
    rulings = far - near
    edges = np.diff(near, axis=0)
    back = np.full(len(near), np.nan)
    fwd = np.full(len(near), np.nan)
    fwd[:-1] = _angle_between(edges, rulings[:-1])
    back[1:] = _angle_between(-edges, rulings[1:])
    return back, fwd


def strip_intrinsics(near: np.ndarray, far: np.ndarray) -> StripIntrinsics:
    """Isometry invariants of a strip given by its two boundaries (2D pattern or 3D state).

    Parameters
    ----------
    near, far : (n + 1, d) float
        Near (crease) and far boundary, ``n >= 1`` quads, ``d`` = 2 or 3.

    Raises
    ------
    GeometryError
        Zero-length crease edge or ruling, or a ruling along the crease (sector angle 0 or pi).

    Examples
    --------
    A strip of two quads with slanted rulings ``(0.5, 1)``:

    >>> import numpy as np
    >>> near = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> strip = strip_intrinsics(near, near + [0.5, 1.0])
    >>> strip.edge_lengths.tolist(), strip.ruling_lengths.round(6).tolist()
    ([1.0, 1.0], [1.118034, 1.118034, 1.118034])
    >>> np.degrees(strip.sector_forward).round(6).tolist()  # atan(2), NaN at the last vertex
    [63.434949, 63.434949, nan]
    """
    near = np.asarray(near, dtype=float)
    far = np.asarray(far, dtype=float)
    if near.shape != far.shape or near.ndim != 2 or near.shape[0] < 2:
        raise GeometryError(
            f"strip boundaries must be two (n + 1, d) arrays with n >= 1, got {near.shape} "
            f"and {far.shape}"
        )
    edge_lengths = np.linalg.norm(np.diff(near, axis=0), axis=1)
    ruling_lengths = np.linalg.norm(far - near, axis=1)
    scale = max(float(edge_lengths.sum()), DIVISION_FLOOR)
    bad = np.flatnonzero(edge_lengths <= ZERO_LENGTH * scale)
    if bad.size:
        raise GeometryError(f"crease edge {int(bad[0])} has zero length")
    bad = np.flatnonzero(ruling_lengths <= ZERO_LENGTH * scale)
    if bad.size:
        raise GeometryError(f"ruling at crease vertex {int(bad[0])} has zero length")
    back, fwd = sector_angles(near, far)
    tol = EXACT_RELATIVE
    degenerate = np.zeros(len(near), dtype=bool)
    degenerate[1:] |= (back[1:] < tol) | (back[1:] > np.pi - tol)
    degenerate[:-1] |= (fwd[:-1] < tol) | (fwd[:-1] > np.pi - tol)
    if degenerate.any():
        i = int(np.flatnonzero(degenerate)[0])
        raise GeometryError(f"the ruling at crease vertex {i} lies along the crease")
    return StripIntrinsics(edge_lengths, back, fwd, ruling_lengths)
