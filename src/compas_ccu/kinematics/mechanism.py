"""The one-degree-of-freedom mechanism of a CCU structure: leading strip plus reflected plates.

docs/geometry.md §2, multi-crease: the leading strip follows the exact closed form of
:mod:`compas_ccu.kinematics.leading`; every other plate hangs off a crease of an already placed
plate (its *parent*) and is the mirror image of the parent's ruling lines across the plane of
that crease:

* ``relation = "ccu"``: the plate lies on the same in-plane side of the crease as the parent and
  on the other side of its plane (direction ``M(q)``, ``q`` the parent's ruling direction away
  from the crease, ``M`` the reflection in the crease plane);
* ``relation = "ccf"``: the curved-crease-folding continuation, rulings collinear in the pattern
  (direction ``-M(q)``).

The leading crease plane is fixed. The plane of every other crease is fitted to its vertices
(least squares) in each state; its largest distance to the crease is reported as the planarity
deviation. Where it is zero (parallel planes with cylindrical or conical strips) the reflected
plates are exact isometries of their cut patterns; elsewhere the reflection is taken across the
best-fit plane and the isometry error is reported, not hidden.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import dot, fit_planes, reflect_points
from compas_ccu.kinematics.leading import LeadingStrip
from compas_ccu.kinematics.plates import boundary_rows
from compas_ccu.strips.intrinsics import StripIntrinsics

__all__ = ["PlateLink", "CreaseLink", "CreasePlanes", "Mechanism", "MechanismStates"]


@dataclass(frozen=True)
class PlateLink:
    """How a plate is attached in the mechanism.

    Attributes
    ----------
    intrinsics : StripIntrinsics
        Isometry invariants (only ``ruling_lengths`` is used for non-leading plates).
    parent : int or None
        Index of the parent plate; None for the leading plate (index 0).
    boundary : str
        ``"near"`` or ``"far"``: which boundary of the parent is the shared crease.
    relation : str
        ``"ccu"`` (mirror partner) or ``"ccf"`` (folded continuation).
    crease : int or None
        Index of the shared crease.
    """

    intrinsics: StripIntrinsics
    parent: int | None = None
    boundary: str = "near"
    relation: str = "ccu"
    crease: int | None = None


@dataclass(frozen=True)
class CreaseLink:
    """A crease between plate ``a`` (boundary ``boundary_a``) and plate ``b`` (its near boundary).

    ``fixed`` is True for the leading crease plane (local ``z = 0``). ``design_normal`` orients
    the fitted plane normals consistently (local frame).
    """

    plate_a: int
    boundary_a: str
    plate_b: int
    relation: str
    fixed: bool
    design_normal: tuple


class MechanismStates(NamedTuple):
    """Placed geometry for ``k`` states, local frame of the leading crease plane.

    Attributes
    ----------
    near, far : (k, p, n + 1, 3) float
        Near and far boundary of every plate.
    plane_origins, plane_normals : (k, c, 3) float
        Crease planes (fixed or best fit).
    planarity : (k, c) float
        Largest distance of a crease vertex from its plane.
    tilts : (k, n) float
        Reflection angle of every segment of the leading crease.
    """

    near: np.ndarray
    far: np.ndarray
    plane_origins: np.ndarray
    plane_normals: np.ndarray
    planarity: np.ndarray
    tilts: np.ndarray


class CreasePlanes:
    """The plane each crease is mirrored in while the mechanism is placed (the default strategy).

    The leading crease plane is fixed (local ``z = 0``); every other crease plane is the
    least-squares plane of the crease, oriented like the design normal. The child plate's crease
    row is the parent's row itself (the hinge is shared exactly).

    A strategy is any object with these methods and the attribute ``mirror_rows``;
    :class:`compas_ccu.thickness.axis_shift.HingePlanes` is the one of thick plates.
    """

    #: False: a child plate shares its parent's crease row; True: it gets the row's mirror image.
    mirror_rows = False

    def begin(self, states: int, creases: int, vertices: int) -> None:
        """Called once before a placement of ``states`` states (for strategies that record)."""

    def plane(self, mechanism: Mechanism, crease: int, near: np.ndarray, far: np.ndarray):
        """Origins, unit normals (k, 3) and planarity deviation (k,) of ``crease``'s plane.

        Parameters
        ----------
        near, far : (k, p, n + 1, 3) float
            The placed plates so far (plate ``a`` of ``crease`` is placed).
        """
        link = mechanism.creases[crease]
        row = boundary_rows(near[:, link.plate_a], far[:, link.plate_a], link.boundary_a)[0]
        if link.fixed:
            k = len(row)
            normal = np.zeros((k, 3))
            normal[:, 2] = 1.0
            return np.zeros((k, 3)), normal, np.abs(row[:, :, 2]).max(axis=1)
        return fit_planes(row, np.asarray(link.design_normal))


class Mechanism:
    """Deployable CCU structure with one degree of freedom.

    Parameters
    ----------
    leading : LeadingStrip
        Kinematics of plate 0.
    plates : list of PlateLink
        Plate 0 is the leading plate; every other plate comes after its parent.
    creases : list of CreaseLink
    """

    def __init__(self, leading: LeadingStrip, plates: list, creases: list):
        if plates[0].parent is not None:
            raise ValueError("plate 0 must be the leading plate")
        for i, plate in enumerate(plates[1:], start=1):
            if plate.parent is None or not 0 <= plate.parent < i:
                raise ValueError(f"plate {i} must come after its parent, got {plate.parent}")
        self.leading = leading
        self.plates = list(plates)
        self.creases = list(creases)
        self._ruling_lengths = [p.intrinsics.ruling_lengths for p in self.plates]

    @property
    def segments(self) -> int:
        return self.leading.n

    def place(self, s0, *, planes: CreasePlanes | None = None) -> MechanismStates:
        """Place every plate for values of the degree of freedom ``s0`` (see LeadingStrip).

        Parameters
        ----------
        s0 : float or (k,) float
        planes : CreasePlanes, optional
            The strategy that gives the plane of every crease from the placed parent plate
            (default: the fixed leading plane and the best-fit planes of the other creases).
        """
        planes = _DEFAULT_PLANES if planes is None else planes
        lead = self.leading.place(s0)
        k, m = lead.near.shape[0], lead.near.shape[1]
        p, c = len(self.plates), len(self.creases)
        near = np.empty((k, p, m, 3))
        far = np.empty((k, p, m, 3))
        near[:, 0], far[:, 0] = lead.near, lead.far
        # unit ruling directions near -> far of every placed plate: a child's rulings mirror its
        # parent's directions as placed, not the difference of the parent's boundaries, whose
        # round-off a short ruling (crease planes that almost meet) would magnify
        rays = np.empty((k, p, m, 3))
        rays[:, 0] = lead.rulings
        origins = np.zeros((k, c, 3))
        normals = np.zeros((k, c, 3))
        planarity = np.zeros((k, c))
        placed = np.zeros(c, dtype=bool)
        planes.begin(k, c, m)
        for i, plate in enumerate(self.plates[1:], start=1):
            j, ci = plate.parent, plate.crease
            hinge = boundary_rows(near[:, j], far[:, j], plate.boundary)[0]
            away = rays[:, j] if plate.boundary == "near" else -rays[:, j]
            # the parent is placed, so the crease (its boundary) is known
            origin, normal, planarity[:, ci] = planes.plane(self, ci, near, far)
            origins[:, ci], normals[:, ci] = origin, normal
            mirrored = away - 2.0 * dot(away, normal[:, None])[..., None] * normal[:, None]
            if plate.relation == "ccf":
                mirrored = -mirrored
            if planes.mirror_rows:
                hinge = reflect_points(hinge, origin, normal)
            near[:, i] = hinge
            far[:, i] = hinge + self._ruling_lengths[i][None, :, None] * mirrored
            rays[:, i] = mirrored
            placed[ci] = True
        for ci in np.flatnonzero(~placed):  # creases that attach no plate (closing a loop)
            origins[:, ci], normals[:, ci], planarity[:, ci] = planes.plane(self, ci, near, far)
        return MechanismStates(near, far, origins, normals, planarity, lead.tilts)

    def crease_planes(self, near: np.ndarray, far: np.ndarray):
        """Planes of every crease of placed plates ``near, far`` (k, p, n + 1, 3).

        Returns origins, normals (k, c, 3) and the planarity deviation (k, c).
        """
        k, c = near.shape[0], len(self.creases)
        origins = np.zeros((k, c, 3))
        normals = np.zeros((k, c, 3))
        planarity = np.zeros((k, c))
        for ci in range(c):
            origins[:, ci], normals[:, ci], planarity[:, ci] = _DEFAULT_PLANES.plane(
                self, ci, near, far
            )
        return origins, normals, planarity

    def refit(self, states: MechanismStates, near: np.ndarray, far: np.ndarray) -> MechanismStates:
        """States with plates replaced by ``near, far`` (k, p, n + 1, 3) and planes refitted.

        Used for geometry that did not come from :meth:`place`, e.g. a relaxation.
        """
        origins, normals, planarity = self.crease_planes(near, far)
        return MechanismStates(near, far, origins, normals, planarity, states.tilts)

    def deploy(self, alpha) -> MechanismStates:
        """Place every plate at reference reflection angles ``alpha`` (radians, scalar or (k,)).

        Raises
        ------
        DeploymentLimitError
            An angle is negative or beyond the deployment limit.
        """
        return self.place(self.leading.s0_for_alpha(alpha))

    @property
    def alpha_limit(self) -> float:
        """Largest reachable reference reflection angle, radians."""
        return self.leading.alpha_limit


_DEFAULT_PLANES = CreasePlanes()
