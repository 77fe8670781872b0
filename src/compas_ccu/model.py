"""The deployable model of a design and its deployed states.

:class:`CCUModel` wraps the mechanism of a design with the output conventions of SPEC §4 (plate
and crease ids, vertex order, world frame, units); :meth:`CCUModel.deploy` and
:meth:`CCUModel.path` return :class:`compas_ccu.structure.Structure` objects.

Plate vertex order (every plate has the same layout): crease-side (near) boundary
``0 .. n`` followed by the far boundary ``n + 1 .. 2n + 1``; quad ``j`` has the vertices
``j, j + 1, n + 2 + j, n + 1 + j``, listed counter-clockwise in the plate's cut pattern (so the
order is reversed for plates that lie on the other side of their crease).
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.errors import SelfIntersectionError
from compas_ccu.kinematics.checks import self_intersecting
from compas_ccu.kinematics.relations import crease_relations
from compas_ccu.strips.intrinsics import quad_lengths

__all__ = ["CCUModel"]


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def plane_frame(origin, xaxis, yaxis):
    """World frame of the leading crease plane: origin (3,) and rows x, y, normal (3, 3)."""
    x = _unit(np.asarray(xaxis, dtype=float))
    y = np.asarray(yaxis, dtype=float)
    y = y - (y @ x) * x
    if np.linalg.norm(y) < 1e-12:
        from compas_ccu.errors import DesignError

        raise DesignError(
            f"must not be parallel to plane.xaxis, got {list(yaxis)}", key="plane.yaxis"
        )
    y = _unit(y)
    return np.asarray(origin, dtype=float), np.array([x, y, np.cross(x, y)])


class CCUModel:
    """A design, built: deploy it to any reflection angle.

    Parameters
    ----------
    design : compas_ccu.design.Design

    Attributes
    ----------
    mechanism : compas_ccu.kinematics.Mechanism
    alpha_limit : float
        Deployment limit, degrees.
    """

    def __init__(self, design):
        from compas_ccu.design.build import build

        self.design = design
        self.built = build(design.values)
        self.mechanism = self.built.mechanism
        plane = design.values["plane"]
        self.origin, self.axes = plane_frame(plane["origin"], plane["xaxis"], plane["yaxis"])
        self.flip = self.built.flip
        b = self.built
        n = self.mechanism.segments
        self.segments = n
        # output order: by plate id
        self.order = np.argsort(b.plate_ids)
        self.plate_ids = [int(b.plate_ids[i]) for i in self.order]
        self._mech_to_out = {int(m): int(b.plate_ids[m]) for m in range(len(b.plate_ids))}
        j = np.arange(n)
        self._quads = np.c_[j, j + 1, n + 2 + j, n + 1 + j]
        # reference lengths of every quad (4 sides + 2 diagonals) at the design state
        self._reference_lengths = self._quad_lengths(b.design_near[None], b.design_far[None])[0]
        corners = self._to_world(np.concatenate([b.design_near, b.design_far], axis=1))
        self.size = float(np.linalg.norm(np.ptp(corners.reshape(-1, 3), axis=0)))
        self._flat = None
        self._kinds = None
        self._overlap_alpha = None
        self._faces = None
        self._check_design()

    def _check_design(self) -> None:
        """Refuse, before any deployment, designs whose pattern or design state is impossible.

        * rulings that cross inside a plate (a quad of the cut pattern folds over: the crease
          is curved too tightly for the plate's width there);
        * a flat-state design whose design angle lies beyond the deployment limit;
        * a crease that overlaps itself at the design state.
        """
        from compas_ccu.errors import DeploymentLimitError, GeometryError

        flat = self.flat()
        n = self.segments
        j = np.arange(n)
        a, b, d = flat[:, j, :2], flat[:, j + 1, :2], flat[:, n + 1 + j, :2]
        c = flat[:, n + 2 + j, :2]
        # rulings a-d and b-c of a quad must not meet: a + s (d - a) = b + t (c - b)
        u, v, w = d - a, c - b, b - a

        def cross(p, q):
            return p[..., 0] * q[..., 1] - p[..., 1] * q[..., 0]

        den = cross(u, v)
        with np.errstate(divide="ignore", invalid="ignore"):
            s_, t_ = cross(w, v) / den, cross(w, u) / den
        bad = np.argwhere((den != 0.0) & (s_ > 0.0) & (s_ <= 1.0) & (t_ > 0.0) & (t_ <= 1.0))
        if bad.size:
            p, q = (int(v) for v in bad[0])
            raise GeometryError(
                f"the rulings of plate {self.plate_ids[p]} cross between crease vertices {q} and "
                f"{q + 1}: its cut pattern folds over itself (the crease is curved too tightly "
                "there for the plate's width or the plane spacing); reduce the width / "
                "spacing, smooth the profile, or put the plate on the other side"
            )
        limit = self.alpha_limit
        if self.alpha_design > limit:
            raise DeploymentLimitError(
                f"the design alpha {self.alpha_design:.6g} deg cannot be reached: this cut "
                f"pattern unfolds at most to {limit:.6g} deg, where crease segment "
                f"{self.limit_vertex} of the leading crease stands perpendicular to its plane",
                alpha=self.alpha_design,
                alpha_limit=limit,
                vertex=self.limit_vertex,
            )
        self.deploy(check=True)  # raises SelfIntersectionError with the crease and the angle

    # -- frames ------------------------------------------------------------------------------
    def _to_world(self, local: np.ndarray) -> np.ndarray:
        return self.origin + (local * np.array([1.0, self.flip, 1.0])) @ self.axes

    def _vector_to_world(self, local: np.ndarray) -> np.ndarray:
        return (local * np.array([1.0, self.flip, 1.0])) @ self.axes

    @staticmethod
    def _quad_lengths(near: np.ndarray, far: np.ndarray) -> np.ndarray:
        """(k, p, n, 6) side and diagonal lengths of every quad."""
        return quad_lengths(near, far)

    # -- design facts --------------------------------------------------------------------------
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
        return self.built.reference

    def flat(self) -> np.ndarray:
        """(p, 2n + 2, 3) cut patterns in plane coordinates (z = 0): the flat-folded stack."""
        if self._flat is None:
            st = self.mechanism.place(0.0)
            local = np.concatenate([st.near[0], st.far[0]], axis=1)[self.order]
            flat = local * np.array([1.0, self.flip, 0.0])
            self._flat = flat
        return self._flat

    @property
    def faces(self) -> np.ndarray:
        """(p, n, 4) quads of every plate, counter-clockwise in its cut pattern."""
        if self._faces is None:
            flat = self.flat()
            q = self._quads
            a, b, d = flat[:, q[:, 0], :2], flat[:, q[:, 1], :2], flat[:, q[:, 3], :2]
            area = ((b - a)[..., 0] * (d - a)[..., 1] - (b - a)[..., 1] * (d - a)[..., 0]).sum(1)
            self._faces = np.where((area < 0.0)[:, None, None], q[:, ::-1], q[None])
        return self._faces

    def crease_kinds(self) -> list:
        """Per crease: (kind, per-vertex kinds, sector angles) from the design state."""
        if self._kinds is None:
            b = self.built
            st = self.mechanism.place(
                self.mechanism.leading.s0_for_alpha(b.design_alpha)
                if b.state == "deployed"
                else 0.0
            )
            out = []
            for ci in range(len(self.mechanism.creases)):
                rel = self._relations(st, 0, ci)
                kinds = {k for k in rel.kinds if k not in (None, "straight")}
                kind = kinds.pop() if len(kinds) == 1 else ("mixed" if kinds else "straight")
                out.append((kind, rel.kinds, rel.sector_angles))
            self._kinds = out
        return self._kinds

    def _relations(self, st, k: int, ci: int):
        crease = self.mechanism.creases[ci]
        a, b = crease.plate_a, crease.plate_b
        if crease.boundary_a == "near":
            hinge, ra = st.near[k, a], st.far[k, a] - st.near[k, a]
        else:
            hinge, ra = st.far[k, a], st.near[k, a] - st.far[k, a]
        rb = st.far[k, b] - st.near[k, b]
        return crease_relations(hinge, ra, rb, st.plane_normals[k, ci], relation=crease.relation)

    # -- deployment --------------------------------------------------------------------------
    def deploy(self, alpha: float | None = None, *, check: bool = True):
        """Deploy to the reference reflection angle ``alpha`` (degrees; default: the design).

        Returns
        -------
        compas_ccu.structure.Structure

        Raises
        ------
        DeploymentLimitError
            ``alpha`` is negative or beyond the deployment limit.
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
            Refuse states in which a crease overlaps itself (:class:`SelfIntersectionError`).

        Raises
        ------
        DeploymentLimitError, SelfIntersectionError
        """
        from compas_ccu.structure import Structure

        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        states = self.mechanism.deploy(np.radians(alphas))
        if check:
            bad = self._overlapping(states)
            if bad.any():
                k = int(np.flatnonzero(bad.any(axis=1))[0])
                ci = int(np.flatnonzero(bad[k])[0])
                what = "the leading crease" if ci == 0 else f"crease {ci - 1}"
                raise SelfIntersectionError(
                    f"self-intersection at alpha = {alphas[k]:.6g} deg: {what} overlaps itself "
                    f"in its plane (the plates would pass through each other); the largest "
                    f"alpha before any crease overlaps is {self.overlap_alpha:.6g} deg",
                    alpha=float(alphas[k]),
                    crease=None if ci == 0 else ci - 1,
                )
        metrics = self.invariants(states)
        kinds = self.crease_kinds()
        flat = self.flat()
        out = []
        for k, alpha in enumerate(alphas):
            out.append(Structure.from_model(self, states, k, float(alpha), metrics, kinds, flat))
        return out

    def vertices(self, alphas) -> np.ndarray:
        """(k, p, 2n + 2, 3) world vertices of every plate at reference angles ``alphas`` (deg).

        The plate vertices of :meth:`path` (same order as ``Structure.deployed``) without the
        metrics, checks and objects: for callers that need many states' geometry only.
        """
        states = self.mechanism.deploy(np.radians(np.atleast_1d(np.asarray(alphas, float))))
        return self.state_vertices(states)

    def state_vertices(self, states, k: int | None = None) -> np.ndarray:
        """World vertices of placed mechanism states in output plate order.

        (k, p, 2n + 2, 3) for all states, or (p, 2n + 2, 3) for state ``k`` only.
        """
        if k is not None:
            local = np.concatenate([states.near[k], states.far[k]], axis=1)[self.order]
        else:
            local = np.concatenate([states.near, states.far], axis=2)[:, self.order]
        return self._to_world(local)

    @property
    def planes(self):
        """The crease planes of a multi-crease layout at the design state, or None.

        :class:`compas_ccu.design.layouts.PlaneLayout` in the local frame of the leading plane.
        """
        return self.built.planes

    def plane_curves(self, states) -> np.ndarray:
        """(k, m + 1, n + 1, 3) world coordinates of the curves on crease planes ``0 .. m``.

        Curve ``i`` is the boundary of plate ``i`` (or of plate ``m - 1`` for ``i = m``) that
        lies on plane ``i``: the creases in plane order with the two free boundaries at the
        ends. Only for multi-crease layouts.

        Parameters
        ----------
        states : compas_ccu.kinematics.MechanismStates
        """
        planes = self.built.planes
        if planes is None:
            raise ValueError("plane curves exist only for multi-crease layouts")
        k0 = planes.leading
        ids = np.asarray(self.built.plate_ids)
        lower = np.where((ids >= k0)[None, :, None, None], states.near, states.far)
        upper = np.where((ids >= k0)[None, :, None, None], states.far, states.near)
        order = np.argsort(ids)
        curves = np.concatenate([lower[:, order], upper[:, order[-1:]]], axis=1)
        return self._to_world(curves)

    def relax(self, alpha: float | None = None, *, planarity_weight: float = 1.0, **options):
        """Deploy to ``alpha`` and relax the plates by least squares (the fallback of SPEC §2).

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
        from compas_ccu.kinematics.relaxation import links_from_mechanism, relax
        from compas_ccu.structure import Structure

        alpha = self.alpha_design if alpha is None else float(alpha)
        states = self.mechanism.deploy(np.radians([alpha]))
        result = relax(
            states.near[0],
            states.far[0],
            self._reference_lengths,
            links_from_mechanism(self.mechanism),
            planarity_weight=planarity_weight,
            **options,
        )
        relaxed = self.mechanism.refit(states, result.near[None], result.far[None])
        structure = Structure.from_model(
            self, relaxed, 0, alpha, self.invariants(relaxed), self.crease_kinds(), self.flat()
        )
        summary = result.summary()
        for key in ("max_strain_per_plate", "quad_planarity_per_plate", "displacement_per_plate"):
            summary[key] = [summary[key][i] for i in self.order]  # by plate id
        structure.metrics["relaxation"] = summary
        return structure, result

    def crease_planarity(self, alphas) -> np.ndarray:
        """(k, c) largest distance (m) of each crease's vertices from its fitted plane.

        Parameters
        ----------
        alphas : (k,) float
            Reference reflection angles, degrees.
        """
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        return self.mechanism.deploy(np.radians(alphas)).planarity

    def _overlapping(self, states) -> np.ndarray:
        """(k, 1 + c) bool: the leading crease, then every crease, overlapping itself."""
        k = states.near.shape[0]
        z = np.zeros((k, 3))
        z[:, 2] = 1.0
        cols = [self_intersecting(states.near[:, 0], np.zeros((k, 3)), z)]
        for ci, crease in enumerate(self.mechanism.creases):
            hinge = (states.near if crease.boundary_a == "near" else states.far)[:, crease.plate_a]
            cols.append(
                self_intersecting(hinge, states.plane_origins[:, ci], states.plane_normals[:, ci])
            )
        return np.stack(cols, axis=1)

    @property
    def overlap_alpha(self) -> float:
        """Largest reference alpha (degrees) before a crease overlaps itself (or the limit)."""
        if self._overlap_alpha is None:
            limit = self.mechanism.alpha_limit
            if not self._overlapping(self.mechanism.deploy(limit)).any():
                self._overlap_alpha = math.degrees(limit)
            else:
                lo, hi = 0.0, limit
                for _ in range(40):
                    mid = 0.5 * (lo + hi)
                    if self._overlapping(self.mechanism.deploy(mid)).any():
                        hi = mid
                    else:
                        lo = mid
                self._overlap_alpha = math.degrees(lo)
        return self._overlap_alpha

    def invariants(self, states) -> dict:
        """Invariant errors of ``k`` placed states (absolute, metres, and relative to size).

        Returns a dict of (k,) arrays: isometry (max quad side/diagonal length change),
        quad_planarity, hinge_gap, mirror_error, crease_planarity (k, c), leading_in_plane.
        """
        near, far = states.near, states.far
        lengths = self._quad_lengths(near, far)
        isometry = np.abs(lengths - self._reference_lengths[None]).max(axis=(1, 2, 3))
        a, b, c, d = near[..., :-1, :], near[..., 1:, :], far[..., 1:, :], far[..., :-1, :]
        normal = np.cross(b - a, d - a)
        normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
        planarity = np.abs(np.einsum("...i,...i", c - a, normal)).max(axis=(1, 2))
        gaps, mirror = [], []
        for ci, crease in enumerate(self.mechanism.creases):
            pa, pb = crease.plate_a, crease.plate_b
            if crease.boundary_a == "near":
                hinge_a, away_a = near[:, pa], far[:, pa] - near[:, pa]
            else:
                hinge_a, away_a = far[:, pa], near[:, pa] - far[:, pa]
            away_b = far[:, pb] - near[:, pb]
            gaps.append(np.linalg.norm(near[:, pb] - hinge_a, axis=-1).max(axis=1))
            # mirror symmetry: plate b's ruling points reflected in the crease plane land on
            # plate a's ruling lines (CCF: on their continuation)
            nrm = states.plane_normals[:, ci]
            ta = np.linalg.norm(away_a, axis=-1)
            tb = np.linalg.norm(away_b, axis=-1)
            t = np.minimum(ta, tb)
            pa_pts = hinge_a + away_a * (t / ta)[..., None]
            pb_pts = near[:, pb] + away_b * (t / tb)[..., None]
            if crease.relation == "ccf":
                pb_pts = 2.0 * near[:, pb] - pb_pts
            origin = states.plane_origins[:, ci]
            dist = np.einsum("kmi,ki->km", pb_pts - origin[:, None], nrm)
            reflected = pb_pts - 2.0 * dist[..., None] * nrm[:, None, :]
            mirror.append(np.linalg.norm(reflected - pa_pts, axis=-1).max(axis=1))
        k = near.shape[0]
        zeros = np.zeros(k)
        return {
            "isometry": isometry,
            "quad_planarity": planarity,
            "hinge_gap": np.max(gaps, axis=0) if gaps else zeros,
            "mirror_error": np.max(mirror, axis=0) if mirror else zeros,
            "crease_planarity": states.planarity,
            "leading_in_plane": np.abs(near[:, 0, :, 2]).max(axis=1),
        }
