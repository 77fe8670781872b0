"""The deployable model of a design: :class:`CCUModel`, the one object that carries a design.

It owns the validated :class:`~compas_ccu.design.Design`, the design-state geometry and the
mechanism (:func:`compas_ccu.design.build.build`), the plate index
(:class:`~compas_ccu.kinematics.plates.PlateIndex`: ids, orders, vertex rows) and the world frame
of the leading crease plane, and it builds the deployed states
(:class:`~compas_ccu.structure.Structure`) with the output conventions of
docs/structure-json.md (plate and crease ids, vertex order, world frame, units).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from compas.data import Data

from compas_ccu.design import Design, load_design
from compas_ccu.design.build import build
from compas_ccu.errors import GeometryError
from compas_ccu.geometry import PlaneFrame, plane_frame
from compas_ccu.kinematics.interference import PathCertificate
from compas_ccu.kinematics.invariants import (
    InvariantErrors,
    invariant_errors,
    overlap_limit,
    overlapping_creases,
)
from compas_ccu.kinematics.plates import PlateIndex, stack_rows
from compas_ccu.kinematics.relations import crease_relations
from compas_ccu.model.checks import check_design, check_path, check_size
from compas_ccu.model.records import path_structures, state_structure
from compas_ccu.model.relaxed import relaxed_structure
from compas_ccu.model.self_intersection import (
    PathLimits,
    check_interference,
    check_overlap,
    collision_free_alpha,
    path_certificate,
)
from compas_ccu.strips.intrinsics import quad_lengths
from compas_ccu.structure import Structure

__all__ = ["CCUModel", "load_model"]


class CCUModel(Data):
    """A design, built: deploy it to any reflection angle.

    Parameters
    ----------
    design : compas_ccu.design.Design

    Attributes
    ----------
    design : compas_ccu.design.Design
    geometry : compas_ccu.design.build.DesignGeometry
        The design state and the profile, local frame, mechanism order.
    mechanism : compas_ccu.kinematics.mechanism.Mechanism
    plates : compas_ccu.kinematics.plates.PlateIndex
        Plate ids, output order, vertex rows, crease boundaries.
    frame : PlaneFrame
        World frame of the leading crease plane.
    reference_lengths : (p, n, 6) float
        Side and diagonal lengths of every quad at the design state (mechanism order): the
        reference of the isometry invariant.
    size : float
        Diagonal of the bounding box of the design state, m: the scale of relative invariants.

    Raises
    ------
    GeometryError
        The cut pattern folds over itself (rulings cross inside a plate).
    DeploymentLimitError
        A cut-pattern design whose design angle its pattern cannot reach.
    SelfIntersectionError
        A crease overlaps itself at the design state.

    Examples
    --------
    >>> model = load_model("examples/cone.toml")
    >>> structure = model.deploy(30.0)
    >>> structure.alpha, len(structure.plate_ids), structure.max_invariant_error < 1e-12
    (30.0, 2, True)
    """

    def __init__(self, design: Design):
        super().__init__(name=design.name)
        check_size(design)
        self.design = design
        self.geometry = build(design)
        self.mechanism = self.geometry.mechanism
        self.plates = PlateIndex.from_mechanism(self.mechanism, self.geometry.plate_ids)
        plane = design.plane
        origin, axes = plane_frame(plane.origin, plane.xaxis, plane.yaxis)
        self.frame = PlaneFrame(origin, axes, self.geometry.flip)
        g = self.geometry
        self.reference_lengths = quad_lengths(g.design_near[None], g.design_far[None])[0]
        corners = self.frame.to_world(stack_rows(g.design_near, g.design_far))
        self.size = float(np.linalg.norm(np.ptp(corners.reshape(-1, 3), axis=0)))
        self._flat = None
        self._kinds = None
        #: Measured path limits, kept between models of the same geometry (adopt_limits)
        self.limits = PathLimits()
        self._faces = None
        self._check_design()

    # -- COMPAS data ---------------------------------------------------------------------------
    @property
    def __data__(self) -> dict:
        return {"design": self.design.__data__}

    @classmethod
    def __from_data__(cls, data: dict) -> CCUModel:
        return cls(Design.__from_data__(data["design"]))

    def __repr__(self) -> str:
        return (
            f"CCUModel({self.name!r}, plates={self.plates.count}, segments={self.segments}, "
            f"alpha={self.alpha_design:g} deg)"
        )

    # -- the design facts ----------------------------------------------------------------------
    @property
    def segments(self) -> int:
        """``n``: quads per plate."""
        return self.mechanism.segments

    @property
    def plate_ids(self) -> list:
        """Plate ids in output order."""
        return self.plates.output_ids

    @property
    def order(self) -> np.ndarray:
        """(p,) int: the mechanism plate at every output position."""
        return self.plates.order

    @property
    def origin(self) -> np.ndarray:
        """(3,) float: world origin of the leading crease plane."""
        return self.frame.origin

    @property
    def axes(self) -> np.ndarray:
        """(3, 3) float: rows x, y, normal of the leading crease plane (world)."""
        return self.frame.axes

    @property
    def flip(self) -> float:
        """+1 if the leading plate lies left of the profile, -1 if right."""
        return self.frame.flip

    @property
    def alpha_design(self) -> float:
        """Design reflection angle, degrees."""
        return self.design.alpha

    @property
    def alpha_limit(self) -> float:
        """Deployment limit: largest reachable reference reflection angle, degrees."""
        return math.degrees(self.mechanism.alpha_limit)

    @property
    def limit_vertex(self) -> int:
        """Leading-crease segment that stands perpendicular to its plane at the limit."""
        return self.mechanism.leading.limit_segment

    @property
    def reference(self) -> int:
        """The reference crease vertex whose reflection angle names the actuation."""
        return self.geometry.reference

    @property
    def planes(self):
        """The crease planes of a multi-crease layout at the design state, or None.

        :class:`compas_ccu.design.layouts.PlaneLayout` in the local frame of the leading plane.
        """
        return self.geometry.planes

    @property
    def target_fit(self):
        """The planes solved for ``[target]`` curves and the remaining miss, or None."""
        return self.geometry.target_fit

    def to_world(self, local: np.ndarray) -> np.ndarray:
        """World points from points (..., 3) in the local frame of the leading crease plane."""
        return self.frame.to_world(local)

    def flat(self) -> np.ndarray:
        """(p, 2n + 2, 3) cut patterns in plane coordinates (z = 0): the flat-folded stack."""
        if self._flat is None:
            st = self.mechanism.place(0.0)
            local = self.plates.to_output(stack_rows(st.near[0], st.far[0]))
            self._flat = local * np.array([1.0, self.flip, 0.0])
        return self._flat

    @property
    def faces(self) -> np.ndarray:
        """(p, n, 4) quads of every plate, counter-clockwise in its cut pattern."""
        if self._faces is None:
            flat = self.flat()
            q = self.plates.quads
            a, b, d = flat[:, q[:, 0], :2], flat[:, q[:, 1], :2], flat[:, q[:, 3], :2]
            area = ((b - a)[..., 0] * (d - a)[..., 1] - (b - a)[..., 1] * (d - a)[..., 0]).sum(1)
            self._faces = np.where((area < 0.0)[:, None, None], q[:, ::-1], q[None])
        return self._faces

    def relations(self, states, k: int, crease: int):
        """Sector angles, kinds and the smooth relations of ``crease`` in state ``k``.

        Parameters
        ----------
        states : compas_ccu.kinematics.mechanism.MechanismStates
        k : int
        crease : int

        Returns
        -------
        compas_ccu.kinematics.relations.CreaseRelations
        """
        link = self.mechanism.creases[crease]
        hinge, other = self.plates.crease_boundary(crease, states.near[k], states.far[k])
        rb = states.far[k, link.plate_b] - states.near[k, link.plate_b]
        return crease_relations(
            hinge, other - hinge, rb, states.plane_normals[k, crease], relation=link.relation
        )

    def all_relations(self, states, ks=slice(None)):
        """:meth:`relations` of every crease in every state ``ks`` in one vectorised call.

        Parameters
        ----------
        states : compas_ccu.kinematics.mechanism.MechanismStates
        ks : slice or (k,) int, optional
            The states; default: all.

        Returns
        -------
        compas_ccu.kinematics.relations.CreaseRelations
            Arrays (k, c, ...): entry ``[i, ci]`` is the same as ``relations(states, ks[i],
            ci)`` (bit for bit); ``kinds`` nested lists ``[i][ci]``.
        """
        creases = self.mechanism.creases
        a = np.array([c.plate_a for c in creases], dtype=int)
        b = np.array([c.plate_b for c in creases], dtype=int)
        on_far = np.array([c.boundary_a == "far" for c in creases], dtype=bool)[:, None, None]
        near, far = states.near[ks], states.far[ks]
        near_a, far_a = near[:, a], far[:, a]
        hinge = np.where(on_far, far_a, near_a)
        other = np.where(on_far, near_a, far_a)
        rb = far[:, b] - near[:, b]
        relation = np.array([c.relation for c in creases], dtype=object)
        return crease_relations(
            hinge, other - hinge, rb, states.plane_normals[ks], relation=relation
        )

    def crease_kinds(self) -> list:
        """Per crease: (kind, per-vertex kinds, sector angles) from the design state."""
        if self._kinds is None:
            g = self.geometry
            s0 = (
                self.mechanism.leading.s0_for_alpha(g.design_alpha)
                if g.state == "deployed"
                else 0.0
            )
            st = self.mechanism.place(s0)
            rel = self.all_relations(st, slice(0, 1))
            out = []
            for ci in range(len(self.mechanism.creases)):
                vertex_kinds = rel.kinds[0][ci]
                kinds = {k for k in vertex_kinds if k not in (None, "straight")}
                kind = kinds.pop() if len(kinds) == 1 else ("mixed" if kinds else "straight")
                out.append((kind, vertex_kinds, rel.sector_angles[0, ci]))
            self._kinds = out
        return self._kinds

    # -- checks --------------------------------------------------------------------------------
    def _check_design(self) -> None:
        check_design(self)

    def check_overlap(self, states, alphas) -> None:
        """Refuse placed ``states`` (at reference angles ``alphas``, degrees) in which a crease
        overlaps itself in its plane.

        Raises
        ------
        SelfIntersectionError
            Names the first such state, the crease and the largest alpha before any overlap.
        """
        check_overlap(self, states, alphas)

    def overlapping(self, states) -> np.ndarray:
        """(k, 1 + c) bool: the leading crease, then every crease, overlapping itself."""
        return overlapping_creases(self.mechanism, states)

    @property
    def overlap_alpha(self) -> float:
        """Largest reference alpha (degrees) before a crease overlaps itself (or the limit)."""
        return self.limits.measure(
            "overlap_alpha", lambda: math.degrees(overlap_limit(self.mechanism))
        )

    @property
    def certificate(self) -> PathCertificate:
        """The interpenetration certificate of the path from the flat stack to the limit
        (:class:`compas_ccu.kinematics.interference.PathCertificate`), scanned as far as asked;
        made once (kept in :attr:`limits`: a model of the same geometry shares it)."""
        return self.limits.measure("certificate", lambda: path_certificate(self))

    @property
    def interference(self):
        """The first state from the flat stack to the limit in which two plates (zero
        thickness, every pair) cross: :class:`compas_ccu.kinematics.interference.Interference`
        (its ``hit`` is None if they never do)."""
        return self.certificate.result()

    @property
    def collision_free_alpha(self) -> float:
        """Largest reference alpha (degrees) reached from the flat stack without any two plates
        (zero thickness, every pair) passing through each other: the first of the plates
        crossing (:attr:`interference`, certified to
        :data:`compas_ccu.kinematics.interference.ANGLE_TOLERANCE`, 1e-7 rad) and a crease
        overlapping itself (:attr:`overlap_alpha`: the two plates of that crease cross at their
        hinge); the deployment limit if neither happens."""
        return collision_free_alpha(self)

    def check_interference(self, alphas) -> None:
        """Refuse reference angles ``alphas`` (degrees) beyond the first state, on the path from
        the flat stack, in which two plates cross.

        Raises
        ------
        SelfIntersectionError
            Names the two plates, the alpha where they first meet and the largest alpha clear.
        """
        check_interference(self, alphas)

    def _check_states(self, count: int) -> None:
        check_path(self, count)

    def invariants(self, states) -> InvariantErrors:
        """Invariant errors of ``k`` placed states, metres, measured on the world coordinates
        that the structures and files hold (:func:`invariant_errors`)."""
        return invariant_errors(self.mechanism, states, self.reference_lengths, frame=self.frame)

    # -- deployment ----------------------------------------------------------------------------
    def deploy(self, alpha: float | None = None, *, check: bool = True) -> Structure:
        """Deploy to the reference reflection angle ``alpha`` (degrees; default: the design).

        Returns
        -------
        compas_ccu.structure.Structure

        Raises
        ------
        DeploymentLimitError
            ``alpha`` is negative or beyond the deployment limit.
        SelfIntersectionError
            A crease overlaps itself at ``alpha``, or two plates have crossed on the way from
            the flat stack (with ``check``).
        """
        alpha = self.alpha_design if alpha is None else float(alpha)
        return self.path([alpha], check=check)[0]

    def path(self, alphas, *, check: bool = True) -> list:
        """Deploy to several reference angles (degrees) in one vectorised call.

        Parameters
        ----------
        alphas : (k,) float
            Reference reflection angles, degrees.
        check : bool
            Refuse states in which a crease overlaps itself, or beyond the first state on the
            path from the flat stack in which two plates cross (:attr:`collision_free_alpha`):
            :class:`SelfIntersectionError`.

        Returns
        -------
        list of compas_ccu.structure.Structure
            Their crease records and metrics are computed when first read, for all the states
            of the call at once (:class:`compas_ccu.model.records.StateRecords`).

        Raises
        ------
        DeploymentLimitError, SelfIntersectionError
        """
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        self._check_states(len(alphas))
        states = self.mechanism.deploy(np.radians(alphas))
        if check:
            self.check_overlap(states, alphas)
            self.check_interference(alphas)
        return path_structures(self, states, alphas)

    def structure(self, states, k: int, alpha: float, invariants: dict | None = None) -> Structure:
        """The :class:`Structure` of state ``k`` of placed mechanism ``states`` at reference
        angle ``alpha`` (degrees): :func:`compas_ccu.model.records.state_structure`."""
        return state_structure(self, states, k, alpha, invariants)

    def vertices(self, alphas) -> np.ndarray:
        """(k, p, 2n + 2, 3) world vertices of every plate at reference angles ``alphas`` (deg).

        The plate vertices of :meth:`path` (same order as ``Structure.deployed``) without the
        metrics, checks and objects: for callers that need many states' geometry only.
        """
        alphas = np.atleast_1d(np.asarray(alphas, float))
        self._check_states(len(alphas))
        states = self.mechanism.deploy(np.radians(alphas))
        return self.state_vertices(states)

    def state_vertices(self, states, k: int | None = None) -> np.ndarray:
        """World vertices of placed mechanism states in output plate order.

        (k, p, 2n + 2, 3) for all states, or (p, 2n + 2, 3) for state ``k`` only.
        """
        if k is not None:
            local = self.plates.to_output(stack_rows(states.near[k], states.far[k]))
        else:
            local = self.plates.to_output(stack_rows(states.near, states.far), axis=1)
        return self.frame.to_world(local)

    def plane_curves(self, states) -> np.ndarray:
        """(k, m + 1, n + 1, 3) world coordinates of the curves on crease planes ``0 .. m``.

        Curve ``i`` is the boundary of plate ``i`` (or of plate ``m - 1`` for ``i = m``) that
        lies on plane ``i``: the creases in plane order with the two free boundaries at the
        ends. Only for multi-crease layouts.

        Parameters
        ----------
        states : compas_ccu.kinematics.MechanismStates

        Raises
        ------
        GeometryError
            A single-crease design.
        """
        planes = self.geometry.planes
        if planes is None:
            raise GeometryError("plane curves exist only for multi-crease layouts")
        k0 = planes.leading
        ids = np.asarray(self.plates.ids)
        lower = np.where((ids >= k0)[None, :, None, None], states.near, states.far)
        upper = np.where((ids >= k0)[None, :, None, None], states.far, states.near)
        order = self.plates.order
        curves = np.concatenate([lower[:, order], upper[:, order[-1:]]], axis=1)
        return self.frame.to_world(curves)

    def relax(self, alpha: float | None = None, *, planarity_weight: float = 1.0, **options):
        """Deploy to ``alpha`` and relax the plates by least squares (docs/shape-control.md).

        Where a crease leaves its plane, the mirror construction has no exact solution and the
        kinematic state is not an isometry. The relaxation
        (:func:`compas_ccu.kinematics.relaxation.relax`) holds the leading plate, keeps every
        hinge closed and minimises the quads' relative side and diagonal length errors plus
        their non-planarity, starting from the kinematic state. Where the kinematic state is
        exact it is returned unchanged.

        Returns
        -------
        structure : compas_ccu.structure.Structure
            The relaxed state; ``metrics["relaxation"]`` holds the residuals (strain, quad
            planarity, displacement from the kinematic state, convergence) and the invariants
            are measured on the relaxed geometry.
        relaxation : compas_ccu.kinematics.relaxation.Relaxation
        """
        alpha = self.alpha_design if alpha is None else float(alpha)
        return relaxed_structure(self, alpha, planarity_weight=planarity_weight, **options)

    def crease_planarity(self, alphas) -> np.ndarray:
        """(k, c) largest distance (m) of each crease's vertices from its fitted plane.

        Parameters
        ----------
        alphas : (k,) float
            Reference reflection angles, degrees.
        """
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        return self.mechanism.deploy(np.radians(alphas)).planarity


def load_model(path) -> CCUModel:
    """Load a design TOML file and build its model.

    Raises
    ------
    DesignError
        The file is missing, not TOML, or not a valid design (the message names the key).
    GeometryError, DeploymentLimitError, SelfIntersectionError
        The design cannot be built (see :class:`CCUModel`).

    Examples
    --------
    >>> load_model("examples/cone.toml")
    CCUModel('cone', plates=2, segments=48, alpha=40 deg)
    """
    return CCUModel(load_design(Path(path)))
