"""Thick plates of a built design: :class:`ThickModel` (axis shift, collisions, bending).

>>> from compas_ccu.model import load_model
>>> thick = ThickModel(load_model("examples/vault.toml"), thickness=0.008)
>>> round(thick.stack_height * 1000, 9)   # ten 8 mm plates, folded closed
80.0
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
from compas.data import Data

from compas_ccu.errors import GeometryError, SelfIntersectionError
from compas_ccu.geometry import unit
from compas_ccu.kinematics.mechanism import MechanismStates
from compas_ccu.kinematics.plates import stack_rows
from compas_ccu.materials import DesignFactors, Material, MaterialError
from compas_ccu.strips.curvature import plate_curvature
from compas_ccu.thickness.actuation import (
    Actuation,
    actuation_force,
    bending_energy,
    foot_ring,
)
from compas_ccu.thickness.axis_shift import ThickStates, crease_sides, place_thick, solid_faces
from compas_ccu.thickness.bending import BendingCheck, bending_angles, bending_check
from compas_ccu.thickness.collision import plate_contacts
from compas_ccu.thickness.splices import gap_summary, max_pile, slab_points, splice_gaps

__all__ = ["ThickModel", "ThickState", "CollisionReport", "collision_text"]


@dataclass
class ThickState:
    """One deployed state of the thick plates (world coordinates, plates in id order).

    Attributes
    ----------
    alpha : float
        Reference reflection angle, degrees.
    mid : (p, 2n + 2, 3) float
        Mid-surfaces (exact isometries of the cut patterns).
    solids : (p, 2, 2n + 2, 3) float
        Lower and upper face vertices of every thick plate (crease edges corrected for the
        design state).
    metrics : dict
    """

    alpha: float
    mid: np.ndarray
    solids: np.ndarray
    metrics: dict = field(default_factory=dict)


@dataclass
class CollisionReport:
    """Interpenetration check along a deployment path.

    Attributes
    ----------
    alphas : (k,) float
        Checked reference angles, degrees.
    penetration : (k,) float
        Largest penetration depth of a face vertex into another plate, m (<= tolerance: none).
    clearance : (k,) float
        Smallest gap between plates that share no crease, m; inf where no vertex of such a pair
        lies over the other plate (there is no such pair, or they are more than the contact
        reach apart).
    crossing : (k,) bool
        A plate passes through another one.
    first : dict or None
        The first state that interpenetrates: alpha, plates, vertex, point, depth.
    closest : dict or None
        Where the smallest clearance occurs: alpha, plates, vertex, point, clearance; None if
        the clearance is inf in every state.
    tolerance : float
    clearance_pairs : int
        Plate pairs that share no crease: the pairs the clearance is measured over (0 for a
        single crease between two plates).
    """

    alphas: np.ndarray
    penetration: np.ndarray
    clearance: np.ndarray
    crossing: np.ndarray
    first: dict | None
    closest: dict | None
    tolerance: float
    clearance_pairs: int = 0

    @property
    def ok(self) -> bool:
        return self.first is None

    def summary(self) -> dict:
        """Plain data (strict JSON: no inf / NaN); :func:`collision_text` words it.

        ``min_clearance`` (m) and ``closest`` are None when no clearance was measured: no plate
        pair shares no crease (``clearance_pairs`` = 0), or no vertex of such a pair lies over
        the other plate anywhere on the path.
        """
        clearance = float(self.clearance.min())
        return {
            "alphas": [float(self.alphas[0]), float(self.alphas[-1]), len(self.alphas)],
            "interpenetration": not self.ok,
            "max_penetration": float(self.penetration.max()),
            "min_clearance": clearance if math.isfinite(clearance) else None,
            "clearance_pairs": int(self.clearance_pairs),
            "first": self.first,
            "closest": self.closest,
            "tolerance": self.tolerance,
        }


def collision_text(summary: dict, *, degree: str = " deg") -> str:
    """One line on a :meth:`CollisionReport.summary`: the first interpenetration or "none"."""
    first = summary["first"]
    if first is not None:
        return (
            f"plates {first['plates'][0]} and {first['plates'][1]} interpenetrate at alpha "
            f"{first['alpha']:.4g}{degree} by {first['depth'] * 1e3:.3g} mm near "
            f"{[round(v, 3) for v in first['point']]} m"
        )
    if summary["min_clearance"] is None:
        if not summary.get("clearance_pairs"):
            return "none; no plate pair to check (every pair of plates shares a crease)"
        return "none; no plate lies over another one it shares no crease with"
    closest = summary["closest"]
    where = (
        f" (plates {closest['plates'][0]}/{closest['plates'][1]} at alpha "
        f"{closest['alpha']:.3g}{degree})"
        if closest and "plates" in closest
        else ""
    )
    return f"none; min clearance {summary['min_clearance'] * 1e3:.3g} mm{where}"


class ThickModel(Data):
    """The thick plates of a :class:`compas_ccu.model.CCUModel` (paper §5.3).

    A :class:`compas.data.Data`: ``compas.json_dumps`` writes the model, the thickness, the
    grain, the material's values and the design factors, and reads them back.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    thickness : float, optional
        Plate thickness, m; default: the design's ``plates.thickness``.
    material : str, dict or Material, optional
        Default: the design's ``plates.material``; a name may be one of the design file's
        ``[materials.NAME]`` or a library material.
    grain : float, optional
        Grain direction in the cut patterns, degrees from the plane x axis; default: the
        design's ``plates.grain``.
    design_code : dict or DesignFactors, optional
        The basis of the bending check: keys of the design's ``[design_code]`` section that
        override it, or the factors themselves; default: the section (EC5 design values when
        the file has none; docs/thickness.md, "Design values").

    Attributes
    ----------
    material : compas_ccu.materials.Material
    factors : compas_ccu.materials.DesignFactors
        k_mod, γ_M, k_def and the basis of the bending check.

    Raises
    ------
    GeometryError
        Thickness not positive and finite, or too large for the plates (more than half the
        narrowest plate width), or a design with CCF creases.
    MaterialError
        Unknown or impossible material, or a material without default design factors and
        none given.
    """

    def __init__(self, model, *, thickness=None, material=None, grain=None, design_code=None):
        super().__init__(name=model.name)
        plates = model.design.plates
        thickness = plates.thickness if thickness is None else thickness
        grain = plates.grain if grain is None else grain
        if isinstance(thickness, bool) or not isinstance(thickness, (int, float)):
            raise GeometryError(f"thickness must be a number in metres, got {thickness!r}")
        if not (math.isfinite(thickness) and thickness > 0.0):
            raise GeometryError(f"thickness must be a finite length > 0 m, got {thickness!r}")
        widths = [p.intrinsics.ruling_lengths.min() for p in model.mechanism.plates]
        narrowest = float(min(widths))
        if thickness > 0.5 * narrowest:
            raise GeometryError(
                f"thickness {thickness:.6g} m is more than half the narrowest plate width "
                f"({narrowest:.6g} m): the plates would be blocks, not bending-active plates"
            )
        if not (isinstance(grain, (int, float)) and math.isfinite(grain)):
            raise MaterialError(f"grain must be a finite angle in degrees, got {grain!r}")
        self.model = model
        self.thickness = float(thickness)
        self.material = model.design.resolve_material(material)
        if isinstance(design_code, DesignFactors):
            self.factors = design_code
        else:
            self.factors = model.design.design_factors(self.material, **(design_code or {}))
        self.grain = float(grain)
        mech = model.mechanism
        self.mechanism = mech
        alpha = model.alpha_design if model.alpha_design > 0.0 else 0.5 * model.alpha_limit
        probe = mech.deploy(math.radians(min(alpha, 0.5 * model.alpha_limit + 0.5 * alpha)))
        self.sides = crease_sides(mech, probe)
        design = self.place([model.alpha_design])
        self.design_corrections = design.corrections[0]  # (c, n + 1)
        index = model.plates
        # (p, 2n + 2) distance each vertex moves along its ruling into the plate: the crease
        # corrections of the design state on both plates of every crease, 0 at free boundaries
        self.shifts = np.zeros((index.count, index.vertex_count))
        for ci, (a, b) in enumerate(index.crease_plates):
            rows_a, rows_b = index.crease_rows(ci)
            self.shifts[a, rows_a] = self.design_corrections[ci]
            self.shifts[b, rows_b] = self.design_corrections[ci]
        p = index.count
        flat = self.place([0.0])
        heights = flat.near[0, :, :, 2].mean(axis=1)  # local z of the mid-surfaces
        order = np.argsort(heights)
        position = np.empty(p, dtype=int)
        position[order] = np.arange(p)
        self.stack_position = index.to_output(position).tolist()  # by plate id
        self._pairs_neighbours = {tuple(sorted((c.plate_a, c.plate_b))) for c in mech.creases}

    # -- COMPAS data ---------------------------------------------------------------------------
    @property
    def __data__(self) -> dict:
        return {
            "model": self.model,
            "thickness": self.thickness,
            "material": self.material.to_dict(),
            "grain": self.grain,
            "design_code": asdict(self.factors),
        }

    @classmethod
    def __from_data__(cls, data: dict) -> ThickModel:
        return cls(
            data["model"],
            thickness=data["thickness"],
            material=Material(**data["material"]),
            grain=data["grain"],
            design_code=DesignFactors(**data["design_code"]),
        )

    # -- placement ----------------------------------------------------------------------------
    def place(self, alphas) -> ThickStates:
        """Thick placement (local frame, mechanism order) at reference angles (degrees)."""
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        s0 = self.mechanism.leading.s0_for_alpha(np.radians(alphas))
        return place_thick(self.mechanism, s0, self.thickness, self.sides)

    def _shift_rows(self):
        """The shifts of the near and the far rows: (p, n + 1) each."""
        index = self.model.plates
        return self.shifts[:, index.near_rows], self.shifts[:, index.far_rows]

    def _faces_local(self, st: ThickStates) -> np.ndarray:
        shift_near, shift_far = self._shift_rows()
        return solid_faces(
            st.near, st.far, st.offsets, self.thickness, shift_near[None], shift_far[None]
        )

    def cut_patterns(self) -> np.ndarray:
        """(p, 2n + 2, 2) cut patterns of the thick plates, plates in id order, m.

        The zero-thickness patterns (:meth:`CCUModel.flat`) with the crease corrections of the
        design state (paper §5.3) applied along the rulings: the thick plates cut from them
        meet exactly along planar hinges at the design angle.
        """
        index = self.model.plates
        flat = self.model.flat()[:, :, :2].copy()
        near, far = flat[:, index.near_rows], flat[:, index.far_rows]
        ruling = unit(far - near)
        shift_near, shift_far = (index.to_output(s) for s in self._shift_rows())
        flat[:, index.near_rows] = near + shift_near[..., None] * ruling
        flat[:, index.far_rows] = far - shift_far[..., None] * ruling
        return flat

    def hinge_points(self, alphas) -> tuple:
        """Mid-surfaces and the hinge lines of the axis-shift hinges at reference angles
        ``alphas`` (degrees), world frame, plates in output order.

        Returns
        -------
        mid : (k, p, 2n + 2, 3) float
            The mid-surfaces (exact isometries of the cut patterns).
        hinge : (k, p, 2n + 2, 3) float
            For every vertex on a crease row, the hinge point on the plate's facing face:
            ``mid + σ t/2 ν`` moved along its ruling by the design state's correction (the
            fabricated crease edge); the mid-surface vertex itself on a free boundary. At the
            design state the two plates of a crease have the same hinge points (to the
            ``hinge_gap`` of :meth:`metrics`).

        Examples
        --------
        >>> from compas_ccu.model import load_model
        >>> thick = ThickModel(load_model("examples/cone.toml"))
        >>> mid, hinge = thick.hinge_points([40.0])
        >>> index = thick.model.plates
        >>> rows_a, rows_b = index.crease_rows(0)
        >>> where = np.argsort(index.to_output(np.arange(index.count)))  # output positions
        >>> a, b = where[list(index.crease_plates[0])]
        >>> gap = np.abs(hinge[0, a, rows_a] - hinge[0, b, rows_b]).max()
        >>> offset = np.linalg.norm(hinge[0, a, rows_a] - mid[0, a, rows_a], axis=1)
        >>> bool(gap < 1e-12), np.round([offset.min(), offset.max()], 6).tolist()
        (True, [0.0025, 0.0025])
        """
        st = self.place(alphas)
        index = self.model.plates
        half = 0.5 * self.thickness
        mid = stack_rows(st.near, st.far)
        nu = stack_rows(st.offsets, st.offsets)
        inward = stack_rows(unit(st.far - st.near), unit(st.near - st.far))
        hinge = mid.copy()
        for ci, (a, b) in enumerate(index.crease_plates):
            for plate, rows, side in zip((a, b), index.crease_rows(ci), self.sides[ci]):
                shift = self.shifts[plate, rows][None, :, None]
                hinge[:, plate, rows] += side * half * nu[:, plate, rows]
                hinge[:, plate, rows] += shift * inward[:, plate, rows]
        world = [self._world(index.to_output(x, axis=1)) for x in (mid, hinge)]
        return world[0], world[1]

    def _world(self, local: np.ndarray) -> np.ndarray:
        return self.model.to_world(local)

    def states(self, alphas) -> list:
        """:class:`ThickState` objects at reference angles ``alphas`` (degrees)."""
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        st = self.place(alphas)
        index = self.model.plates
        faces = index.to_output(self._faces_local(st), axis=1)
        mid = index.to_output(stack_rows(st.near, st.far), axis=1)
        metrics = self.metrics(st)
        out = []
        for k, alpha in enumerate(alphas):
            m = {key: np.asarray(v[k]).tolist() for key, v in metrics.items()}
            out.append(ThickState(float(alpha), self._world(mid[k]), self._world(faces[k]), m))
        return out

    def deploy(self, alpha: float | None = None) -> ThickState:
        """The thick plates at ``alpha`` (degrees; default: the design)."""
        alpha = self.model.alpha_design if alpha is None else float(alpha)
        return self.states([alpha])[0]

    def flat_stack(self) -> ThickState:
        """The flat-folded stack (alpha = 0)."""
        return self.states([0.0])[0]

    @property
    def stack_height(self) -> float:
        """Height of the flat-folded stack, m (Σt for plates folded completely closed)."""
        faces = self._faces_local(self.place([0.0]))[0]
        z = faces[..., 2]
        return float(z.max() - z.min())

    @property
    def stack_order(self) -> list:
        """Plate ids from the bottom of the flat-folded stack to its top."""
        ids = self.model.plate_ids
        return [ids[i] for i in np.argsort(self.stack_position)]

    # -- invariants ---------------------------------------------------------------------------
    def metrics(self, st: ThickStates) -> dict:
        """Invariants of ``k`` thick states: (k,) arrays, and (k, c) per crease.

        * ``isometry``, ``quad_planarity``, ``mirror_error``: of the mid-surfaces (exact);
        * ``hinge_gap``: largest distance between the two facing faces' crease edges;
        * ``offset_planarity`` (k, c): distance of the uncorrected offset crease from its plane;
        * ``correction`` (k, c): largest correction along the rulings (paper §5.3).
        """
        mstates = MechanismStates(
            st.near, st.far, st.hinge_origins, st.hinge_normals, st.offset_planarity, st.tilts
        )
        inv = self.model.invariants(mstates)
        faces = self._faces_local(st)
        index = self.model.plates
        gaps = []
        for ci, (a, b) in enumerate(index.crease_plates):
            sa, sb = self.sides[ci]
            rows_a, rows_b = index.crease_rows(ci)
            fa = faces[:, a, int(sa > 0), rows_a]
            fb = faces[:, b, int(sb > 0), rows_b]
            gaps.append(np.linalg.norm(fa - fb, axis=-1).max(axis=1))
        k = st.near.shape[0]
        return {
            "isometry": inv["isometry"],
            "quad_planarity": inv["quad_planarity"],
            "mirror_error": inv["mirror_error"],
            "hinge_gap": np.max(gaps, axis=0) if gaps else np.zeros(k),
            "offset_planarity": st.offset_planarity,
            "correction": np.abs(st.corrections).max(axis=2),
        }

    def pairing(self) -> list:
        """Per crease: which faces the hinge joins, "intrados" or "extrados" (paper Fig. 8c).

        The facing face of a plate is its intrados where the plate bends towards it (concave
        side, compressed) and its extrados where it bends away; by mirror symmetry both plates of
        a crease pair the same kind. Measured at the design state on the crease vertices
        (positive curvature: the quad normal points to the convex side).
        """
        st = self.place([self.model.alpha_design])
        kappa = plate_curvature(stack_rows(st.near, st.far)[0])
        index = self.model.plates
        out = []
        for ci, (a, _) in enumerate(index.crease_plates):
            k = np.median(self.sides[ci, 0] * kappa[a, index.crease_rows(ci)[0]])
            out.append("intrados" if k < 0 else ("extrados" if k > 0 else "flat"))
        return out

    # -- splice plates --------------------------------------------------------------------------
    def splice_stack(self, splices) -> dict:
        """The flat stack with splice plates (:mod:`compas_ccu.thickness.splices`).

        Parameters
        ----------
        splices : list of compas_ccu.thickness.splices.Splice
            Plate ids are the model's; footprints in :meth:`cut_patterns` coordinates.

        Returns
        -------
        dict
            ``stack_height`` (the plates' :attr:`stack_height` plus ``max_pile``, m),
            ``stack_height_plates``, ``max_pile`` (the highest pile of splice plates over one
            point of the plan, m), ``pile_point`` (where, cut-pattern coordinates, or None),
            ``count``, ``area`` (m²) and ``mass`` (kg, the plates' material).
        """
        quads = np.array([sp.footprint for sp in splices], dtype=float).reshape(-1, 4, 2)
        pile, point = max_pile(quads, [sp.thickness for sp in splices])
        plates = self.stack_height
        return {
            "stack_height": plates + pile,
            "stack_height_plates": plates,
            "max_pile": pile,
            "pile_point": None if point is None else [float(v) for v in point],
            "count": len(splices),
            "area": float(sum(sp.area for sp in splices)),
            "mass": float(sum(sp.area * sp.thickness for sp in splices) * self.material.density),
        }

    def splice_collisions(self, splices, alphas=None, *, tolerance: float = 1e-6) -> dict:
        """Splice plates against the neighbouring plates of the stack along the path.

        An upper-face splice plate faces the plate above its own in the flat stack, a lower-face
        one the plate below (none on the outside of the stack). Its :func:`slab_points` are
        tested against that plate's cells in every state (``alphas``, degrees; default: 41
        from the flat stack to the design): :func:`~compas_ccu.thickness.splices.gap_summary`.
        """
        if alphas is None:
            alphas = np.linspace(0.0, self.model.alpha_design, 41)
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        if not len(splices):
            return gap_summary([], [], alphas, np.full((len(alphas), 0), np.inf), tolerance)
        st = self.place(alphas)
        ruling = unit(st.far - st.near)
        shift_near, shift_far = self._shift_rows()
        mid_near = st.near + shift_near[None, :, :, None] * ruling
        mid_far = st.far - shift_far[None, :, :, None] * ruling
        index = self.model.plates
        mech = {pid: i for i, pid in enumerate(index.ids)}
        row = {pid: r for r, pid in enumerate(index.output_ids)}
        by_position = {int(k): pid for pid, k in zip(index.output_ids, self.stack_position)}
        cut = self.cut_patterns()
        n = index.segments
        up = np.sign(self.place([0.0]).offsets[0, :, :, 2].mean(axis=1))  # ν to the stack top
        plates = [mech[int(sp.plate)] for sp in splices]
        neighbours = [
            by_position.get(
                self.stack_position[row[int(sp.plate)]] + (1 if sp.face == "upper" else -1)
            )
            for sp in splices
        ]
        rows = [row[int(sp.plate)] for sp in splices]
        points = slab_points(
            splices,
            cut[rows, : n + 1],
            cut[rows, n + 1 :],
            mid_near[:, plates],
            mid_far[:, plates],
            st.offsets[:, plates],
            self.thickness,
            up[plates],
        )
        targets = [-1 if b is None else mech[b] for b in neighbours]
        gaps = splice_gaps(points, targets, mid_near, mid_far, st.offsets, self.thickness)
        return gap_summary(splices, neighbours, alphas, gaps, tolerance)

    # -- checks -------------------------------------------------------------------------------
    def contact_pairs(self) -> tuple:
        """The plate pairs of :meth:`collisions` (mechanism order), computed once.

        Returns
        -------
        pairs : (p (p - 1), 2) int
            Every ordered pair ``(a, b)``, ``a != b``, by ``a`` then ``b``.
        hinged : dict
            ``{(a, b): (4n + 4,) bool}``: the vertices of ``b`` (both faces) on the hinge it
            shares with ``a``, for the pairs joined by a crease.
        neighbours : (p (p - 1),) bool
            The pairs joined by a crease (left out of the clearance).
        """
        if getattr(self, "_contact_pairs", None) is None:
            index = self.model.plates
            p = index.count
            first, second = np.divmod(np.arange(p * p), p)
            pairs = np.c_[first, second][first != second]
            rows = {}
            for ci, (a, b) in enumerate(index.crease_plates):
                on_a = np.zeros(index.vertex_count, dtype=bool)
                on_b = np.zeros(index.vertex_count, dtype=bool)
                on_a[index.crease_rows(ci)[0]] = True
                on_b[index.crease_rows(ci)[1]] = True
                # vertices of b on the hinge with a, and of a on the hinge with b (both faces)
                rows[(a, b)] = np.concatenate([on_b, on_b])
                rows[(b, a)] = np.concatenate([on_a, on_a])
            joined = [a * p + b for a, b in self._pairs_neighbours]
            neighbours = np.isin(np.minimum(*pairs.T) * p + np.maximum(*pairs.T), joined)
            self._contact_pairs = pairs, rows, neighbours
        return self._contact_pairs

    def collisions(
        self, alphas=None, *, tolerance: float = 1e-6, method: str = "cells"
    ) -> CollisionReport:
        """Interpenetration of the thick plates along a path.

        Parameters
        ----------
        alphas : (k,) float, optional
            Reference angles, degrees; default: 41 states from the flat stack to the design.
        tolerance : float
            Penetration depth below which plates only touch, m.
        method : {"cells", "all"}
            :func:`compas_ccu.thickness.collision.plate_contacts`: the candidate search
            (default) or every vertex against every cell (the reference; same report).
        """
        if alphas is None:
            alphas = np.linspace(0.0, self.model.alpha_design, 41)
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        st = self.place(alphas)
        faces = self._faces_local(st)
        ruling = unit(st.far - st.near)
        shift_near, shift_far = self._shift_rows()
        mid_near = st.near + shift_near[None, :, :, None] * ruling
        mid_far = st.far - shift_far[None, :, :, None] * ruling
        pairs, rows, neighbours = self.contact_pairs()
        index = self.model.plates
        depth, clear, crossing, where = plate_contacts(
            mid_near,
            mid_far,
            st.offsets,
            faces,
            self.thickness,
            pairs=pairs,
            hinged=rows,
            method=method,
        )
        penetration = np.maximum(depth.max(axis=1), 0.0)
        others = clear[:, ~neighbours] if (~neighbours).any() else np.full((len(alphas), 1), np.inf)
        clearance = others.min(axis=1)

        def where_(k, q, what, value):
            a, b = (int(x) for x in pairs[q])
            v = int(where[k, q])
            point = self._world(faces[k, b].reshape(-1, 3)[v][None])[0]
            return {
                "alpha": float(alphas[k]),
                "plates": [index.output_id(a), index.output_id(b)],
                "vertex": v,
                "point": point.tolist(),
                what: float(value),
            }

        bad = (depth > tolerance) | crossing
        first = None
        if bad.any():
            k = int(np.flatnonzero(bad.any(axis=1))[0])
            q = int(np.flatnonzero(bad[k])[0])
            first = where_(k, q, "depth", depth[k, q])
            first["crossing"] = bool(crossing[k, q])
        closest = None
        if np.isfinite(clearance).any():
            masked = np.where(neighbours[None], np.inf, clear)
            k, q = np.unravel_index(np.argmin(masked), masked.shape)
            closest = where_(int(k), int(q), "clearance", masked[k, q])
        return CollisionReport(
            alphas,
            penetration,
            clearance,
            crossing.any(axis=1),
            first,
            closest,
            tolerance,
            clearance_pairs=int((~neighbours).sum()) // 2,
        )

    def check_collisions(self, alphas=None, **options) -> CollisionReport:
        """:meth:`collisions`, raising :class:`SelfIntersectionError` on interpenetration."""
        report = self.collisions(alphas, **options)
        if report.first is not None:
            f = report.first
            how = (
                "pass through each other"
                if f.get("crossing")
                else (f"interpenetrate by {f['depth'] * 1000:.3g} mm")
            )
            raise SelfIntersectionError(
                f"thick plates {f['plates'][0]} and {f['plates'][1]} {how} at alpha = "
                f"{f['alpha']:.6g} deg, near {np.round(f['point'], 4).tolist()} m "
                f"(thickness {self.thickness * 1000:.4g} mm)",
                alpha=f["alpha"],
                crease=None,
            )
        return report

    def first_collision(self, upto=None, *, states: int = 25, bisections: int = 6):
        """The first interpenetration of the thick plates from the flat stack to ``upto``.

        A scan of ``states`` states from the flat stack to ``upto`` degrees (default: the
        largest alpha the zero-thickness plates reach without crossing, or the deployment
        limit, :attr:`compas_ccu.model.CCUModel.collision_free_alpha`), then ``bisections``
        bisections between the last clear and the first colliding state, so the angle is known
        to ``upto / (states - 1) / 2 ** bisections``.

        Returns
        -------
        clear : float
            The largest scanned or bisected alpha (degrees) at which the thick plates are
            clear; ``upto`` if they are clear to it.
        first : dict or None
            The collision (``alpha``, ``plates``, ``depth``, ``crossing``, ``point``), or None.
        """
        if upto is None:
            upto = min(self.model.alpha_limit, self.model.collision_free_alpha)
        alphas = np.linspace(0.0, float(upto), states)
        first = self.collisions(alphas).first
        if first is None:
            return float(upto), None
        k = int(np.searchsorted(alphas, first["alpha"]))
        lo, hi = (alphas[k - 1] if k > 0 else 0.0), first["alpha"]
        for _ in range(bisections if k > 0 else 0):
            mid = 0.5 * (lo + hi)
            hit = self.collisions([mid]).first
            if hit is None:
                lo = mid
            else:
                hi, first = mid, hit
        return float(lo), first

    def bending(self, alphas=None) -> BendingCheck:
        """Bending utilisation (:func:`compas_ccu.thickness.bending.bending_check`).

        Default states: 21 from the flat stack to the design. Plates in id order.
        """
        if alphas is None:
            alphas = np.linspace(0.0, self.model.alpha_design, 21)
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        st = self.place(alphas)
        mid = self.model.plates.to_output(stack_rows(st.near, st.far), axis=1)
        return bending_check(
            mid,
            self.model.flat(),
            self.thickness,
            self.material,
            grain=math.radians(self.grain),
            factors=self.factors,
        )

    def actuation(self, alphas=None) -> Actuation:
        """Bending energy and the force between the feet along the path
        (:mod:`compas_ccu.thickness.actuation`); default: 21 states to the design.

        Examples
        --------
        >>> from compas_ccu.model import load_model
        >>> a = ThickModel(load_model("examples/cone.toml")).actuation()
        >>> round(float(a.energy[-1]), 2), round(a.force_max, 1)
        (25.44, 124.4)
        """
        if alphas is None:
            alphas = np.linspace(0.0, self.model.alpha_design, 21)
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        structures = self.model.path(alphas, check=False)
        vertices = np.array([st.deployed for st in structures])
        angles = bending_angles(self.model.flat(), math.radians(self.grain))
        rigidity = self.material.plate_rigidity(self.thickness, angles)
        energy = bending_energy(vertices, rigidity)
        span = np.array([st.metrics["span"] for st in structures])
        ring = radial_feet(self.model, vertices)
        feet = (None, None, None) if ring is None else foot_ring(vertices, *ring)
        return Actuation(alphas, energy, span, actuation_force(alphas, energy, span), *feet)

    def _final_modulus(self):
        """``E1 / (1 + k_def)``, ``E2 / (1 + k_def)`` (Pa): the final-state stiffness under the
        permanent active bending (EN 1995-1-1 2.3.2.2); None if k_def is unknown."""
        k_def = self.factors.k_def
        if k_def is None:
            return None
        return [self.material.E1 / (1.0 + k_def), self.material.E2 / (1.0 + k_def)]

    def summary(self, *, path_states: int = 41) -> dict:
        """Everything ``ccu info`` and the report show: stack, corrections, checks."""
        alphas = np.linspace(0.0, self.model.alpha_design, path_states)
        st = self.place(alphas)
        metrics = self.metrics(st)
        bend = self.bending(alphas)
        per_plate = bend.per_plate.max(axis=0)
        k, plate, vertex = bend.worst()
        collisions = self.collisions(alphas)
        clear, first = self.first_collision()
        push = self.actuation(alphas)
        design = -1
        return {
            "thickness": self.thickness,
            "material": self.material.name,
            "grain": self.grain,
            "stack_height": self.stack_height,
            "stack_order": self.stack_order,
            "pairing": self.pairing(),
            "offset_planarity_design": metrics["offset_planarity"][design].tolist(),
            "correction_design": metrics["correction"][design].tolist(),
            "correction_max_path": float(metrics["correction"].max()),
            "hinge_gap_max_path": float(metrics["hinge_gap"].max()),
            "isometry_max_path": float(metrics["isometry"].max()),
            "bending": {
                "basis": self.factors.to_dict(),
                "curvature_limit_min": float(bend.limit.min()),
                "curvature_limit_characteristic_min": float(bend.limit_characteristic.min()),
                "max_curvature": float(np.abs(bend.curvature).max()),
                "max_utilisation": bend.max,
                "max_utilisation_characteristic": bend.max_characteristic,
                "final_modulus": self._final_modulus(),
                "utilisation_per_plate": per_plate.tolist(),
                "worst": {
                    "alpha": float(alphas[k]),
                    "plate": self.model.plate_ids[plate],
                    "vertex": vertex,
                    # the ruling of the peak, and whether it runs from a kink of the crease
                    "ruling": vertex % (self.model.segments + 1),
                    "at_kink": vertex % (self.model.segments + 1) in self.model.geometry.kinks,
                },
                "exceeded": bool(bend.max > 1.0),
            },
            "collisions": collisions.summary(),
            "collision_free_alpha": clear,
            "first_collision": None
            if first is None
            else {
                "alpha": float(first["alpha"]),
                "plates": list(first["plates"]),
                "crossing": bool(first.get("crossing")),
            },
            "actuation": {
                "energy_J": float(push.energy[design]),
                "force_max_N": push.force_max,
                "force_design_N": float(push.force[design]),
                **_ring_summary(push, design),
            },
        }


def radial_feet(model, vertices) -> tuple | None:
    """The axis and the feet of a radial layout: ``(origin, axis, end)`` for
    :func:`compas_ccu.thickness.actuation.foot_ring`, or None for other layouts.

    The axis is the line every crease plane contains (world coordinates); the feet are the end
    rulings at the lower end of the creases (world z, at the last state of ``vertices``).
    """
    planes = model.planes
    if model.design.values["layout"]["type"] != "radial" or planes is None:
        return None
    # plane k holds the axis line x = axis, z = 0 of the leading frame: n . (axis, y, 0) = d
    k = int(np.argmax(np.abs(planes.normals[:, 0])))
    x = planes.offsets[k] / planes.normals[k, 0]
    origin, ahead = model.to_world(np.array([[x, 0.0, 0.0], [x, 1.0, 0.0]]))
    n = model.segments
    last = np.asarray(vertices, dtype=float)[-1]
    end = 0 if last[:, 0, 2].mean() <= last[:, n, 2].mean() else n
    return origin, ahead - origin, end


def _ring_summary(push, k: int) -> dict:
    """The ring of feet of a radial layout at state ``k`` (``ThickModel.summary``)."""
    if push.ring_length is None:
        return {}
    thrust, tension = push.ring_thrust, push.ring_tension
    return {
        "ring_radius_m": float(push.ring_radius[k]),
        "ring_angle_deg": float(np.degrees(push.ring_angle[k])),
        "ring_thrust_N_per_m": float(thrust[k]),
        "ring_tension_N": float(tension[k]),
    }
