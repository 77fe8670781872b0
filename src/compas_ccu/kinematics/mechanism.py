"""The one-degree-of-freedom mechanism of a CCU structure: leading strip plus reflected plates.

SPEC §2, multi-crease: the leading strip follows the exact closed form of
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

from compas_ccu.kinematics.leading import LeadingStrip
from compas_ccu.strips.intrinsics import StripIntrinsics

__all__ = ["PlateLink", "CreaseLink", "Mechanism", "MechanismStates"]


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


def fit_planes(points: np.ndarray, orient: np.ndarray):
    """Least-squares planes of ``(k, m, 3)`` point sets.

    Returns origins ``(k, 3)``, unit normals ``(k, 3)`` with ``normal @ orient >= 0`` and the
    largest point-plane distance ``(k,)``.
    """
    origin = points.mean(axis=1)
    centred = points - origin[:, None, :]
    cov = np.einsum("kni,knj->kij", centred, centred)
    _, vectors = np.linalg.eigh(cov)
    normal = vectors[:, :, 0]
    normal *= np.where(normal @ orient < 0.0, -1.0, 1.0)[:, None]
    deviation = np.abs(np.einsum("kni,ki->kn", centred, normal)).max(axis=1)
    return origin, normal, deviation


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


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

    def place(self, s0) -> MechanismStates:
        """Place every plate for values of the degree of freedom ``s0`` (see LeadingStrip)."""
        lead = self.leading.place(s0)
        k, m = lead.near.shape[0], lead.near.shape[1]
        p, c = len(self.plates), len(self.creases)
        near = np.empty((k, p, m, 3))
        far = np.empty((k, p, m, 3))
        near[:, 0], far[:, 0] = lead.near, lead.far
        origins = np.zeros((k, c, 3))
        normals = np.zeros((k, c, 3))
        planarity = np.zeros((k, c))
        placed = np.zeros(c, dtype=bool)
        for i, plate in enumerate(self.plates[1:], start=1):
            j = plate.parent
            if plate.boundary == "near":
                hinge, away = near[:, j], _unit(far[:, j] - near[:, j])
            else:
                hinge, away = far[:, j], _unit(near[:, j] - far[:, j])
            # the parent is placed, so the crease (its boundary) is known
            origin, normal, dev = self._crease_plane(plate.crease, near, far)
            origins[:, plate.crease], planarity[:, plate.crease] = origin, dev
            normals[:, plate.crease] = normal
            mirrored = (
                away
                - 2.0 * np.einsum("kmi,ki->km", away, normal)[:, :, None] * (normal[:, None, :])
            )
            if plate.relation == "ccf":
                mirrored = -mirrored
            near[:, i] = hinge
            far[:, i] = hinge + self._ruling_lengths[i][None, :, None] * mirrored
            placed[plate.crease] = True
        for ci in np.flatnonzero(~placed):  # creases that attach no plate (closing a loop)
            origins[:, ci], normals[:, ci], planarity[:, ci] = self._crease_plane(ci, near, far)
        return MechanismStates(near, far, origins, normals, planarity, lead.tilts)

    def _crease_plane(self, ci: int, near: np.ndarray, far: np.ndarray):
        """Plane of crease ``ci`` in ``k`` states: origins, normals (k, 3), planarity (k,)."""
        crease = self.creases[ci]
        hinge = (near if crease.boundary_a == "near" else far)[:, crease.plate_a]
        if crease.fixed:
            k = len(hinge)
            normal = np.zeros((k, 3))
            normal[:, 2] = 1.0
            return np.zeros((k, 3)), normal, np.abs(hinge[:, :, 2]).max(axis=1)
        return fit_planes(hinge, np.asarray(crease.design_normal))

    def refit(self, states: MechanismStates, near: np.ndarray, far: np.ndarray) -> MechanismStates:
        """States with plates replaced by ``near, far`` (k, p, n + 1, 3) and planes refitted.

        Used for geometry that did not come from :meth:`place`, e.g. a relaxation.
        """
        k, c = near.shape[0], len(self.creases)
        origins = np.zeros((k, c, 3))
        normals = np.zeros((k, c, 3))
        planarity = np.zeros((k, c))
        for ci in range(c):
            origins[:, ci], normals[:, ci], planarity[:, ci] = self._crease_plane(ci, near, far)
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
