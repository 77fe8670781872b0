"""Which plate is which, and which vertex row of a plate is which: the plate index.

Every plate is a planar-quad strip of ``n`` quads between two polylines of ``n + 1`` vertices: the
*near* boundary (the crease it hangs on; for the leading plate, the leading crease) and the *far*
boundary. Arrays of a plate's vertices list the near row ``0 .. n``, then the far row
``n + 1 .. 2n + 1``; quad ``j`` is ``j, j + 1, n + 2 + j, n + 1 + j`` and ruling ``j`` joins
vertex ``j`` and vertex ``n + 1 + j`` (docs/structure-json.md).

Plates have two orders: the *mechanism* order (the leading plate first, every plate after the
plate it hangs on: the order of :class:`compas_ccu.kinematics.mechanism.Mechanism`) and the
*output* order (by plate id, as written to files). :class:`PlateIndex` answers both, and which
boundary of which plate every crease joins, so that no other module does row arithmetic.

>>> index = PlateIndex(segments=2, ids=(1, 0), crease_plates=((0, 1),), crease_boundaries=("near",))
>>> index.quads.tolist()
[[0, 1, 4, 3], [1, 2, 5, 4]]
>>> index.order.tolist(), index.output_ids
([1, 0], [0, 1])
>>> index.crease_rows(0)[0].tolist()
[0, 1, 2]
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compas_ccu.geometry import unit

__all__ = [
    "PlateIndex",
    "boundary_rows",
    "hinge_and_rulings",
    "stack_rows",
    "plate_quads",
    "plate_rulings",
]


def plate_quads(n: int) -> np.ndarray:
    """(n, 4) int: quad ``j`` of a plate of ``n`` quads is ``j, j + 1, n + 2 + j, n + 1 + j``.

    Examples
    --------
    >>> plate_quads(2).tolist()
    [[0, 1, 4, 3], [1, 2, 5, 4]]
    """
    j = np.arange(n)
    return np.c_[j, j + 1, n + 2 + j, n + 1 + j]


def plate_rulings(n: int) -> np.ndarray:
    """(n + 1, 2) int: ruling ``j`` of a plate of ``n`` quads joins ``j`` and ``n + 1 + j``.

    Examples
    --------
    >>> plate_rulings(2).tolist()
    [[0, 3], [1, 4], [2, 5]]
    """
    j = np.arange(n + 1)
    return np.c_[j, n + 1 + j]


def boundary_rows(near: np.ndarray, far: np.ndarray, boundary: str):
    """The rows of ``boundary`` and of the other boundary: ``(row, other)``.

    Parameters
    ----------
    near, far : (..., n + 1, 3) float
    boundary : {"near", "far"}

    Examples
    --------
    >>> import numpy as np
    >>> near, far = np.zeros((3, 3)), np.ones((3, 3))
    >>> row, other = boundary_rows(near, far, "far")
    >>> row[0].tolist(), other[0].tolist()
    ([1.0, 1.0, 1.0], [0.0, 0.0, 0.0])
    """
    if boundary == "near":
        return near, far
    if boundary == "far":
        return far, near
    raise ValueError(f"a plate boundary is 'near' or 'far', got {boundary!r}")


def hinge_and_rulings(near: np.ndarray, far: np.ndarray, boundary: str):
    """A plate's crease row on ``boundary`` and its unit ruling directions away from it.

    Parameters
    ----------
    near, far : (..., n + 1, 3) float
        One plate's boundaries.
    boundary : {"near", "far"}

    Returns
    -------
    row, away : (..., n + 1, 3) float

    Examples
    --------
    >>> import numpy as np
    >>> near = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    >>> far = near + [0.0, 2.0, 0.0]
    >>> row, away = hinge_and_rulings(near, far, "far")
    >>> row.tolist(), away.tolist()
    ([[0.0, 2.0, 0.0], [1.0, 2.0, 0.0]], [[0.0, -1.0, 0.0], [0.0, -1.0, 0.0]])
    """
    row, other = boundary_rows(near, far, boundary)
    return row, unit(other - row)


def stack_rows(near: np.ndarray, far: np.ndarray) -> np.ndarray:
    """Plate vertex arrays ``(..., 2n + 2, 3)`` from the two boundaries ``(..., n + 1, 3)``.

    Examples
    --------
    >>> import numpy as np
    >>> near = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    >>> stack_rows(near, near + [0.0, 2.0, 0.0])[:, :2].tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 2.0], [1.0, 2.0]]
    """
    return np.concatenate([near, far], axis=-2)


@dataclass(frozen=True)
class PlateIndex:
    """The plates of a mechanism: ids, both orders, vertex rows and crease boundaries.

    Parameters
    ----------
    segments : int
        ``n``, quads per plate.
    ids : tuple of int
        Output id of mechanism plate ``i``.
    crease_plates : tuple of (int, int)
        Mechanism indices of plates ``a`` and ``b`` of every crease.
    crease_boundaries : tuple of str
        The boundary (``"near"`` / ``"far"``) of plate ``a`` that each crease lies on; plate
        ``b`` always hangs on a crease by its near boundary.

    Examples
    --------
    Two plates of two quads; plate 1 is output first:

    >>> index = PlateIndex(2, ids=(1, 0), crease_plates=((0, 1),), crease_boundaries=("near",))
    >>> index.order.tolist(), index.output_ids
    ([1, 0], [0, 1])
    >>> index.quads.tolist()
    [[0, 1, 4, 3], [1, 2, 5, 4]]
    """

    segments: int
    ids: tuple
    crease_plates: tuple
    crease_boundaries: tuple
    order: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "ids", tuple(int(i) for i in self.ids))
        object.__setattr__(self, "order", np.argsort(self.ids))

    @classmethod
    def from_mechanism(cls, mechanism, ids) -> PlateIndex:
        """The index of a :class:`~compas_ccu.kinematics.mechanism.Mechanism` with plate ids."""
        return cls(
            segments=mechanism.segments,
            ids=tuple(ids),
            crease_plates=tuple((c.plate_a, c.plate_b) for c in mechanism.creases),
            crease_boundaries=tuple(c.boundary_a for c in mechanism.creases),
        )

    # -- one plate's vertex layout -------------------------------------------------------------
    @property
    def count(self) -> int:
        """Number of plates."""
        return len(self.ids)

    @property
    def vertex_count(self) -> int:
        """Vertices of one plate, ``2n + 2``."""
        return 2 * self.segments + 2

    @property
    def near_rows(self) -> np.ndarray:
        """(n + 1,) int: the near boundary's vertex indices."""
        return np.arange(self.segments + 1)

    @property
    def far_rows(self) -> np.ndarray:
        """(n + 1,) int: the far boundary's vertex indices."""
        return np.arange(self.segments + 1, 2 * self.segments + 2)

    def rows(self, boundary: str) -> np.ndarray:
        """(n + 1,) int: the vertex indices of ``boundary`` (``"near"`` or ``"far"``)."""
        return boundary_rows(self.near_rows, self.far_rows, boundary)[0]

    @property
    def quads(self) -> np.ndarray:
        """(n, 4) int: quad ``j`` is ``j, j + 1, n + 2 + j, n + 1 + j`` (not oriented)."""
        return plate_quads(self.segments)

    @property
    def rulings(self) -> np.ndarray:
        """(n + 1, 2) int: ruling ``j`` joins vertex ``j`` and vertex ``n + 1 + j``."""
        return plate_rulings(self.segments)

    # -- plate orders ----------------------------------------------------------------------------
    @property
    def output_ids(self) -> list:
        """Plate ids in output order."""
        return [self.ids[i] for i in self.order]

    def output_id(self, plate: int) -> int:
        """Output id of mechanism plate ``plate``."""
        return self.ids[plate]

    def to_output(self, values: np.ndarray, *, axis: int = 0) -> np.ndarray:
        """``values`` indexed by mechanism plate along ``axis``, reordered by plate id."""
        return np.take(values, self.order, axis=axis)

    def output_positions(self) -> np.ndarray:
        """(p,) int: the output position of every mechanism plate."""
        positions = np.empty(self.count, dtype=int)
        positions[self.order] = np.arange(self.count)
        return positions

    # -- creases ---------------------------------------------------------------------------------
    def crease_ids(self, crease: int) -> tuple:
        """Output ids of plates ``a`` and ``b`` of ``crease``."""
        a, b = self.crease_plates[crease]
        return self.ids[a], self.ids[b]

    def crease_rows(self, crease: int) -> tuple:
        """Vertex indices of ``crease`` in plate ``a`` and plate ``b``, in the same order."""
        return self.rows(self.crease_boundaries[crease]), self.near_rows

    def crease_boundary(self, crease: int, near: np.ndarray, far: np.ndarray):
        """Plate ``a``'s crease row and its other row, from mechanism-order arrays.

        Parameters
        ----------
        near, far : (..., p, n + 1, 3) float
            Boundaries of every plate in mechanism order.

        Returns
        -------
        row, other : (..., n + 1, 3) float
            ``other - row`` are plate ``a``'s rulings, pointing away from the crease.
        """
        a = self.crease_plates[crease][0]
        return boundary_rows(near[..., a, :, :], far[..., a, :, :], self.crease_boundaries[crease])
