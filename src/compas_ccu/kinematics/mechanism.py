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
from compas_ccu.kinematics.generations import DefaultPlacement, placement_batches
from compas_ccu.kinematics.leading import LeadingStrip
from compas_ccu.kinematics.plates import boundary_rows
from compas_ccu.strips.intrinsics import StripIntrinsics

__all__ = [
    "PlateLink",
    "CreaseLink",
    "CreasePlanes",
    "CreaseSelection",
    "Mechanism",
    "MechanismStates",
]


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

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> link = load_model("examples/cone.toml").mechanism.plates[1]  # the leading plate's partner
    >>> link.parent, link.boundary, link.relation, link.crease
    (0, 'near', 'ccu', 0)
    >>> link.intrinsics.ruling_lengths[:2].round(6).tolist()
    [0.4, 0.4]
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

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> crease = load_model("examples/vault.toml").mechanism.creases[1]
    >>> crease.plate_a, crease.boundary_a, crease.plate_b, crease.relation, crease.fixed
    (1, 'far', 2, 'ccu', False)
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

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> states = load_model("examples/cone.toml").mechanism.deploy(np.radians([20.0, 40.0]))
    >>> states.near.shape, states.plane_normals.shape, states.tilts.shape
    ((2, 2, 49, 3), (2, 1, 3), (2, 48))
    >>> np.degrees(states.tilts).round(4).max(axis=1).tolist()
    [20.0028, 40.0064]
    """

    near: np.ndarray
    far: np.ndarray
    plane_origins: np.ndarray
    plane_normals: np.ndarray
    planarity: np.ndarray
    tilts: np.ndarray


class CreaseSelection:
    """What a set of creases reads from the placed plates, worked out once per mechanism.

    :meth:`Mechanism.crease_selection` makes (and keeps) one per set of crease indices, so a
    placement does not redo the index work for every generation of plates in every call.

    Attributes
    ----------
    creases : (g,) int
        The crease indices.
    positions : (g,) int
        Their places in the set this one was taken from (``arange(g)`` for a whole set).
    plates : (g,) int
        Plate ``a`` of every crease.
    side : bool or None
        True when every crease is its plate ``a``'s far boundary, False when every one is the
        near boundary, None when they differ (then ``on_far`` says which, shape (1, g, 1, 1)).
    normals : (g, 3) float
        Design normals that orient the fitted planes.
    fixed, free : CreaseSelection or None
        The fixed (leading plane) and the free creases of the set; both None when no crease of
        the set is fixed.
    """

    def __init__(self, mechanism: Mechanism, creases: np.ndarray, positions=None, split=True):
        self.creases = creases
        self.positions = np.arange(len(creases)) if positions is None else positions
        self.plates = mechanism.crease_plate_a[creases]
        on_far = mechanism.crease_far[creases]
        self.side = bool(on_far[0]) if len(on_far) and (on_far == on_far[0]).all() else None
        if not len(on_far):
            self.side = True
        self.on_far = on_far[None, :, None, None]
        self.normals = mechanism.crease_normals[creases]
        self._normals_one = self.normals[None]  # (1, g, 3): the shape of one state's planes
        fixed = mechanism.crease_fixed[creases]
        self.fixed = self.free = None
        if split and fixed.any():
            at, free_at = np.flatnonzero(fixed), np.flatnonzero(~fixed)
            self.fixed = CreaseSelection(mechanism, creases[at], at, split=False)
            self.free = CreaseSelection(mechanism, creases[free_at], free_at, split=False)

    def orient(self, states: int) -> np.ndarray:
        """The design normals for ``states`` states of planes: (g, 3), or (1, g, 3) for one."""
        return self._normals_one if states == 1 else self.normals


class CreasePlanes:
    """The plane each crease is mirrored in while the mechanism is placed (the default strategy).

    The leading crease plane is fixed (local ``z = 0``); every other crease plane is the
    least-squares plane of the crease, oriented like the design normal. The child plate's crease
    row is the parent's row itself (the hinge is shared exactly).

    A strategy is any object with the methods :meth:`begin` and :meth:`planes` and the
    attribute ``mirror_rows``; :class:`compas_ccu.thickness.axis_shift.HingePlanes` is the one
    of thick plates. :meth:`Mechanism.place` asks :meth:`planes` for all the creases of one
    generation of plates at once.

    Examples
    --------
    The creases of ``examples/vault.toml`` lie in parallel planes (local ``z`` = const):

    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> mechanism = load_model("examples/vault.toml").mechanism
    >>> states = mechanism.deploy(np.radians([10.0, 30.0]))
    >>> origins, normals, planarity = CreasePlanes().plane(mechanism, 1, states.near, states.far)
    >>> (normals.round(6) + 0.0).tolist(), bool(planarity.max() < 1e-12)
    ([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]], True)
    """

    #: False: a child plate shares its parent's crease row; True: it gets the row's mirror image.
    mirror_rows = False

    def begin(self, states: int, creases: int, vertices: int) -> None:
        """Called once before a placement of ``states`` states (for strategies that record)."""

    def planes(self, mechanism: Mechanism, creases: np.ndarray, near: np.ndarray, far: np.ndarray):
        """The planes of several creases whose plates ``a`` are placed.

        Parameters
        ----------
        mechanism : Mechanism
        creases : (g,) int
            Crease indices.
        near, far : (k, p, n + 1, 3) float
            The placed plates so far (plate ``a`` of every crease in ``creases`` is placed).

        Returns
        -------
        origins, normals : (k, g, 3) float
            Points on the planes and their unit normals (oriented like the design normals).
        planarity : (k, g) float
            Largest distance of a crease vertex from its plane.
        """
        pick = mechanism.crease_selection(creases)
        k = near.shape[0]
        if pick.free is None:  # best-fit planes only (every crease but the leading one)
            return fit_planes(mechanism.selected_rows(pick, near, far), pick.orient(k))
        g = len(pick.creases)
        origins = np.zeros((k, g, 3))
        normals = np.zeros((k, g, 3))
        planarity = np.zeros((k, g))
        fixed, free = pick.fixed, pick.free
        normals[:, fixed.positions] = (0.0, 0.0, 1.0)  # the leading plane, local z = 0
        row = mechanism.selected_rows(fixed, near, far)
        planarity[:, fixed.positions] = np.abs(row[..., 2]).max(axis=-1)
        if len(free.positions):
            at = free.positions
            fit = fit_planes(mechanism.selected_rows(free, near, far), free.orient(k))
            origins[:, at], normals[:, at], planarity[:, at] = fit
        return origins, normals, planarity

    def plane(self, mechanism: Mechanism, crease: int, near: np.ndarray, far: np.ndarray):
        """:meth:`planes` of one crease: origins, unit normals (k, 3) and planarity (k,)."""
        origins, normals, planarity = self.planes(mechanism, np.array([crease]), near, far)
        return origins[:, 0], normals[:, 0], planarity[:, 0]


class Mechanism:
    """Deployable CCU structure with one degree of freedom.

    Parameters
    ----------
    leading : LeadingStrip
        Kinematics of plate 0.
    plates : list of PlateLink
        Plate 0 is the leading plate; every other plate comes after its parent.
    creases : list of CreaseLink

    Attributes
    ----------
    generations : list of (g,) int
        The plates in placement order, one array per generation: plate 0, then the plates whose
        parent (and the plate ``a`` of whose crease) is in an earlier generation.
    crease_plate_a : (c,) int
        Plate ``a`` of every crease.
    crease_far : (c,) bool
        True where the crease is plate ``a``'s far boundary.
    crease_fixed : (c,) bool
        The fixed leading crease plane.
    crease_normals : (c, 3) float
        Design normals that orient the fitted planes.

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> mechanism = load_model("examples/vault.toml").mechanism
    >>> len(mechanism.plates), len(mechanism.creases), mechanism.segments
    (10, 9, 64)
    >>> [g.tolist() for g in mechanism.generations]  # plate 0, then its neighbours outwards
    [[0], [1, 5], [2, 6], [3, 7], [4, 8], [9]]
    >>> states = mechanism.deploy(np.radians([10.0, 30.0]))
    >>> states.near.shape, bool(states.planarity.max() < 1e-12)
    ((2, 10, 65, 3), True)
    >>> round(float(np.degrees(mechanism.alpha_limit)), 4)
    88.9538
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
        self.crease_plate_a = np.array([c.plate_a for c in self.creases], dtype=np.intp)
        self.crease_far = np.array([c.boundary_a == "far" for c in self.creases], dtype=bool)
        self.crease_fixed = np.array([bool(c.fixed) for c in self.creases], dtype=bool)
        self.crease_normals = np.array(
            [c.design_normal for c in self.creases], dtype=float
        ).reshape(-1, 3)
        for c in self.creases:
            boundary_rows(None, None, c.boundary_a)  # a known boundary name
        self.generations, self._batches = placement_batches(self.plates, self.creases)
        placed = np.zeros(len(self.creases), dtype=bool)
        for batch in self._batches:
            placed[batch.creases] = True
        self._closing = np.flatnonzero(~placed)  # creases that attach no plate (close a loop)
        self._found_order = np.concatenate(
            [b.creases for b in self._batches] + [self._closing]
        ).astype(np.intp)
        # where every crease is found once, the planes are put in crease order by one take (none
        # when they are found in that order) instead of zeros and a scatter
        self._found_inverse = self._found_take = None
        if np.array_equal(np.sort(self._found_order), np.arange(len(self.creases))):
            self._found_inverse = np.argsort(self._found_order)
            self._found_take = not np.array_equal(self._found_order, np.arange(len(self.creases)))
        # the crease sets of the generations and of the closing creases, kept for good (a
        # 200-plate chain has ~100 generations); other sets read from outside, up to a bound
        self._kept = {}
        for creases in [b.creases for b in self._batches] + [self._closing]:
            creases = np.asarray(creases, dtype=np.intp)
            self._kept[_selection_key(creases)] = CreaseSelection(self, creases.copy())
        self._selections = {}
        self._default = DefaultPlacement(self, self._batches, self._closing)

    @property
    def segments(self) -> int:
        return self.leading.n

    def crease_rows(self, creases: np.ndarray, near: np.ndarray, far: np.ndarray) -> np.ndarray:
        """Plate ``a``'s crease row at ``creases`` (g,): (k, g, n + 1, 3).

        Parameters
        ----------
        creases : (g,) int
        near, far : (k, p, n + 1, 3) float
        """
        return self.selected_rows(self.crease_selection(creases), near, far)

    def crease_selection(self, creases) -> CreaseSelection:
        """The :class:`CreaseSelection` of crease indices ``creases`` (g,), made once and kept."""
        creases = np.asarray(creases, dtype=np.intp)
        key = _selection_key(creases)
        pick = self._kept.get(key) or self._selections.get(key)
        if pick is None:
            if len(self._selections) >= _SELECTIONS_KEPT:
                self._selections.clear()
            pick = self._selections[key] = CreaseSelection(self, creases.copy())
        return pick

    @staticmethod
    def selected_rows(pick: CreaseSelection, near: np.ndarray, far: np.ndarray) -> np.ndarray:
        """Plate ``a``'s crease row of every crease of ``pick``: (k, g, n + 1, 3).

        Parameters
        ----------
        pick : CreaseSelection
        near, far : (k, p, n + 1, 3) float
        """
        if pick.side is None:
            return np.where(pick.on_far, far[:, pick.plates], near[:, pick.plates])
        return (far if pick.side else near)[:, pick.plates]

    def crease_boundaries(self, creases: np.ndarray, near: np.ndarray, far: np.ndarray):
        """Plate ``a``'s crease row and its other row at ``creases`` (g,): (k, g, n + 1, 3) each.

        Parameters
        ----------
        creases : (g,) int
        near, far : (k, p, n + 1, 3) float
        """
        pick = self.crease_selection(creases)
        near_a, far_a = near[:, pick.plates], far[:, pick.plates]
        if pick.side is None:
            return np.where(pick.on_far, far_a, near_a), np.where(pick.on_far, near_a, far_a)
        return (far_a, near_a) if pick.side else (near_a, far_a)

    def place(self, s0, *, planes: CreasePlanes | None = None) -> MechanismStates:
        """Place every plate for values of the degree of freedom ``s0`` (see LeadingStrip).

        The plates of one generation (:attr:`generations`) are placed together: their crease
        planes in one call of the strategy, their reflections as one array operation.

        Parameters
        ----------
        s0 : float or (k,) float
        planes : CreasePlanes, optional
            The strategy that gives the planes of creases from the placed parent plates
            (default: the fixed leading plane and the best-fit planes of the other creases,
            placed by :class:`compas_ccu.kinematics.generations.DefaultPlacement`: the same
            numbers as this loop, bit for bit, at less dispatch; rows that are not finite are
            left to this loop).
        """
        if type(s0) is not np.ndarray or s0.ndim != 1 or s0.dtype != np.float64:
            s0 = np.atleast_1d(np.asarray(s0, dtype=float))
        if planes is None or type(planes) is CreasePlanes:
            placed = self._default.place_s0(s0)
            if placed is not None:
                return MechanismStates(*placed)
        lead = self.leading.place(s0)
        planes = _DEFAULT_PLANES if planes is None else planes
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
        planes.begin(k, c, m)
        found = []  # the planes of every generation's creases, stored once at the end
        for batch in self._batches:
            found.append(planes.planes(self, batch.creases, near, far))
            origin, normal, _ = found[-1]
            # the parents' crease rows and their rulings away from them; where all plates of
            # the generation hang on the same boundary (or fold alike) without the masks
            if batch.side is None:
                on_far = batch.from_far[None, :, None, None]
                hinge = np.where(on_far, far[:, batch.parents], near[:, batch.parents])
                ray = rays[:, batch.parents]
                away = np.where(on_far, -ray, ray)
            else:
                hinge = (far if batch.side else near)[:, batch.parents]  # (k, g, n + 1, 3)
                away = -rays[:, batch.parents] if batch.side else rays[:, batch.parents]
            normal = normal[:, :, None]
            mirrored = away - 2.0 * dot(away, normal)[..., None] * normal
            if batch.flip is None:
                mirrored = np.where(batch.ccf[None, :, None, None], -mirrored, mirrored)
            elif batch.flip:
                mirrored = -mirrored
            if planes.mirror_rows:
                hinge = reflect_points(hinge, origin, normal[:, :, 0])
            near[:, batch.target] = hinge
            far[:, batch.target] = hinge + batch.scale * mirrored
            rays[:, batch.target] = mirrored
        if len(self._closing):  # creases that attach no plate (closing a loop)
            found.append(planes.planes(self, self._closing, near, far))
        return MechanismStates(near, far, *self._found_planes(found, k), lead.tilts)

    def _found_planes(self, found: list, k: int):
        """Origins, normals (k, c, 3) and planarity (k, c) in crease order from the planes of
        :meth:`place` in the order they were found (``found``: (k, g, ...) parts)."""
        if found and self._found_inverse is not None:
            joined = [np.concatenate(part, axis=1) for part in zip(*found)]
            if self._found_take:
                joined = [part[:, self._found_inverse] for part in joined]
            return joined
        c = len(self.creases)
        origins = np.zeros((k, c, 3))
        normals = np.zeros((k, c, 3))
        planarity = np.zeros((k, c))
        if found:
            at = self._found_order
            origins[:, at], normals[:, at], planarity[:, at] = (
                np.concatenate(part, axis=1) for part in zip(*found)
            )
        return origins, normals, planarity

    def crease_planes(self, near: np.ndarray, far: np.ndarray):
        """Planes of every crease of placed plates ``near, far`` (k, p, n + 1, 3).

        Returns origins, normals (k, c, 3) and the planarity deviation (k, c).
        """
        return _DEFAULT_PLANES.planes(self, np.arange(len(self.creases)), near, far)

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
#: crease selections a mechanism keeps besides those of its generations (sets read from outside)
_SELECTIONS_KEPT = 64


def _selection_key(creases: np.ndarray) -> tuple:
    return creases.shape, creases.tobytes()
