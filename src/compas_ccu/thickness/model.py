"""Thick plates of a built design: :class:`ThickModel` (axis shift, collisions, bending).

The model is built here (the crease corrections of the design state, the shifts of the
vertices, the stack order) and placed at any angle (solids, cut patterns, hinge points; the
invariants: :mod:`compas_ccu.thickness.thick_invariants`). Its checks along the path are
modules of their own that take the model: the collision check
:mod:`compas_ccu.thickness.collision_check` (:class:`CollisionReport` and
:func:`collision_text`, importable from here too), the splice plates
:mod:`compas_ccu.thickness.splice_stack`, the bending check
:func:`compas_ccu.thickness.bending.path_bending`, the deployment effort
:func:`compas_ccu.thickness.actuation.path_actuation` (and :func:`radial_feet`, importable from
here too) and the summary :mod:`compas_ccu.thickness.summary`.

>>> from compas_ccu.model import load_model
>>> thick = ThickModel(load_model("examples/vault.toml"), thickness=0.008)
>>> round(thick.stack_height * 1000, 9)   # ten 8 mm plates, folded closed
80.0
"""

from __future__ import annotations

import copy
import math
from dataclasses import asdict, dataclass, field, fields

import numpy as np
from compas.data import Data

from compas_ccu.errors import GeometryError
from compas_ccu.geometry import unit, unit3
from compas_ccu.kinematics.plates import stack_rows
from compas_ccu.materials import DesignFactors, Material, MaterialError
from compas_ccu.thickness.actuation import Actuation, path_actuation, radial_feet
from compas_ccu.thickness.axis_shift import ThickStates, crease_sides, place_thick, solid_faces
from compas_ccu.thickness.bending import BendingCheck, path_bending
from compas_ccu.thickness.collision_check import (
    CollisionReport,
    checked_collisions,
    collision_text,
    ordered_pairs,
    path_collisions,
    scan_first_collision,
)
from compas_ccu.thickness.splice_stack import SpliceStack, splice_path_gaps, stack_with_splices
from compas_ccu.thickness.splices import SpliceGaps
from compas_ccu.thickness.summary import thick_summary
from compas_ccu.thickness.thick_invariants import ThickInvariants, hinge_pairing, thick_metrics

__all__ = ["ThickModel", "ThickState", "CollisionReport", "collision_text", "radial_feet"]


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
        # the geometry's part (not the material's), kept for the models of one geometry
        limits = getattr(model, "limits", None)
        key = ("thick_frame", self.thickness, float(model.alpha_design))
        frame = self._frame() if limits is None else limits.measure(key, self._frame)
        sides, corrections, shifts, position, self._flat_states = frame
        self.sides, self.design_corrections = sides.copy(), corrections.copy()  # (c, n + 1)
        # (p, 2n + 2) distance each vertex moves along its ruling into the plate: the crease
        # corrections of the design state on both plates of every crease, 0 at free boundaries
        self.shifts = shifts.copy()
        self.stack_position = list(position)  # by plate id
        self._pairs_neighbours = {tuple(sorted((c.plate_a, c.plate_b))) for c in mech.creases}

    def _frame(self) -> tuple:
        """The hinge sides, the design state's crease corrections, the shifts, the stack
        position and the flat stack's placement (the thickness and the geometry's only)."""
        model, mech = self.model, self.mechanism
        alpha = model.alpha_design if model.alpha_design > 0.0 else 0.5 * model.alpha_limit
        probe = mech.deploy(math.radians(min(alpha, 0.5 * model.alpha_limit + 0.5 * alpha)))
        self.sides = crease_sides(mech, probe)
        design = self.place([model.alpha_design])
        corrections = design.corrections[0]
        index = model.plates
        shifts = np.zeros((index.count, index.vertex_count))
        for ci, (a, b) in enumerate(index.crease_plates):
            rows_a, rows_b = index.crease_rows(ci)
            shifts[a, rows_a] = corrections[ci]
            shifts[b, rows_b] = corrections[ci]
        p = index.count
        flat = self.place([0.0])
        heights = flat.near[0, :, :, 2].mean(axis=1)  # local z of the mid-surfaces
        order = np.argsort(heights)
        position = np.empty(p, dtype=int)
        position[order] = np.arange(p)
        return self.sides, corrections, shifts, index.to_output(position).tolist(), flat

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

    def shift_rows(self):
        """The shifts of the near and the far rows: (p, n + 1) each, m."""
        index = self.model.plates
        return self.shifts[:, index.near_rows], self.shifts[:, index.far_rows]

    def faces_local(self, st: ThickStates) -> np.ndarray:
        """(k, p, 2, 2n + 2, 3) lower and upper face vertices of placed states ``st`` (local
        frame, mechanism order), crease edges corrected for the design state."""
        shift_near, shift_far = self.shift_rows()
        return solid_faces(
            st.near, st.far, st.offsets, self.thickness, shift_near[None], shift_far[None]
        )

    def corrected_boundaries(self, st: ThickStates) -> tuple:
        """The near and far boundaries of the mid-surfaces of placed states ``st``, each
        vertex moved along its ruling into the plate by its shift: (k, p, n + 1, 3) each
        (local frame, mechanism order; the plates' cells in the collision checks)."""
        ruling = unit3(st.far - st.near)
        shift_near, shift_far = self.shift_rows()
        mid_near = st.near + shift_near[None, :, :, None] * ruling
        mid_far = st.far - shift_far[None, :, :, None] * ruling
        return mid_near, mid_far

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
        shift_near, shift_far = (index.to_output(s) for s in self.shift_rows())
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
        faces = index.to_output(self.faces_local(st), axis=1)
        mid = index.to_output(stack_rows(st.near, st.far), axis=1)
        metrics = self.metrics(st)
        out = []
        for k, alpha in enumerate(alphas):
            m = {f.name: np.asarray(getattr(metrics, f.name)[k]).tolist() for f in fields(metrics)}
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
        faces = self.faces_local(self._flat_states)[0]  # the placement of [0.0]
        z = faces[..., 2]
        return float(z.max() - z.min())

    @property
    def stack_order(self) -> list:
        """Plate ids from the bottom of the flat-folded stack to its top."""
        ids = self.model.plate_ids
        return [ids[i] for i in np.argsort(self.stack_position)]

    # -- invariants ---------------------------------------------------------------------------
    def metrics(self, st: ThickStates) -> ThickInvariants:
        """Invariants of ``k`` thick states (:class:`ThickInvariants`): (k,) arrays, and
        (k, c) per crease.

        * ``isometry``, ``quad_planarity``, ``mirror_error``: of the mid-surfaces (exact);
        * ``hinge_gap``: largest distance between the two facing faces' crease edges;
        * ``offset_planarity`` (k, c): distance of the uncorrected offset crease from its plane;
        * ``correction`` (k, c): largest correction along the rulings (paper §5.3).
        """
        return thick_metrics(self, st)

    def pairing(self) -> list:
        """Per crease: which faces the hinge joins, "intrados" or "extrados" (paper Fig. 8c).

        The facing face of a plate is its intrados where the plate bends towards it (concave
        side, compressed) and its extrados where it bends away; by mirror symmetry both plates of
        a crease pair the same kind. Measured at the design state on the crease vertices
        (positive curvature: the quad normal points to the convex side).
        """
        return hinge_pairing(self)

    # -- splice plates --------------------------------------------------------------------------
    def splice_stack(self, splices) -> SpliceStack:
        """The flat stack with splice plates (:mod:`compas_ccu.thickness.splices`).

        Parameters
        ----------
        splices : list of compas_ccu.thickness.splices.Splice
            Plate ids are the model's; footprints in :meth:`cut_patterns` coordinates.

        Returns
        -------
        compas_ccu.thickness.splice_stack.SpliceStack
            ``stack_height`` (the plates' :attr:`stack_height` plus ``max_pile``, m),
            ``stack_height_plates``, ``max_pile`` (the highest pile of splice plates over one
            point of the plan, m), ``pile_point`` (where, cut-pattern coordinates, or None),
            ``count``, ``area`` (m²) and ``mass`` (kg, the plates' material).
        """
        return stack_with_splices(self, splices)

    def splice_collisions(self, splices, alphas=None, *, tolerance: float = 1e-6) -> SpliceGaps:
        """Splice plates against the neighbouring plates of the stack along the path.

        An upper-face splice plate faces the plate above its own in the flat stack, a lower-face
        one the plate below (none on the outside of the stack). Its :func:`slab_points` are
        tested against that plate's cells in every state (``alphas``, degrees; default: 41
        from the flat stack to the design): :func:`~compas_ccu.thickness.splices.gap_summary`
        (:class:`~compas_ccu.thickness.splices.SpliceGaps`).
        """
        if alphas is None:
            alphas = np.linspace(0.0, self.model.alpha_design, 41)
        alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
        return splice_path_gaps(self, splices, alphas, tolerance)

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
            self._contact_pairs = ordered_pairs(self.model.plates, self._pairs_neighbours)
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
        return path_collisions(self, alphas, tolerance, method)

    def check_collisions(self, alphas=None, **options) -> CollisionReport:
        """:meth:`collisions`, raising :class:`SelfIntersectionError` on interpenetration."""
        return checked_collisions(self, alphas, **options)

    def first_collision(self, upto=None, *, states: int = 25, bisections: int = 6):
        """The first interpenetration of the thick plates from the flat stack to ``upto``.

        A scan of ``states`` states from the flat stack to ``upto`` degrees (default: the
        largest alpha the zero-thickness plates reach without crossing, or the deployment
        limit, :attr:`compas_ccu.model.CCUModel.collision_free_alpha`), then ``bisections``
        bisections between the last clear and the first colliding state, so the angle is known
        to ``upto / (states - 1) / 2 ** bisections``. Measured once per model, thickness and
        arguments.

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
        # once per model and thickness (the model's limits, kept between models of the same
        # geometry: compas_ccu.model.self_intersection.adopt_limits)
        key = ("thick_first_collision", self.thickness, float(upto), states, bisections)
        found = self.model.limits.measure(
            key, lambda: scan_first_collision(self, upto, states, bisections)
        )
        return copy.deepcopy(found)

    def bending(self, alphas=None) -> BendingCheck:
        """Bending utilisation (:func:`compas_ccu.thickness.bending.bending_check`).

        Default states: 21 from the flat stack to the design. Plates in id order.
        """
        return path_bending(self, alphas)

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
        return path_actuation(self, alphas)

    def summary(self, *, path_states: int = 41) -> dict:
        """Everything ``ccu info`` and the report show: stack, corrections, checks."""
        return thick_summary(self, path_states)
