"""FE validation of the deployment: build the shell model, deploy it, compare with the kinematics.

Two ways to deploy (paper §3, §5.2):

* ``displacement`` (default, robust): the nodes on the end rulings of every plate (the
  supports), and with ``control="edges"`` also the two outer free boundaries, follow the exact
  kinematic path from the flat-folded stack (alpha = 0) to the target; everything else — the
  bending of the plates, the hinge rotations — is left to the FE equilibrium.
* ``actuation`` (the paper's procedure): pre-bending by the supports to ``prebend`` degrees,
  then the supports are released (a statically determinate restraint stays at the leading
  crease) and the structure is driven by forces at the crease ends: inward along the crease chord
  and outward perpendicular to the crease planes. Their magnitude per step is the force that
  does the work of bending along the kinematic path (dW/dalpha of the plates' bending energy,
  divided by the pattern's work per unit alpha), then corrected iteratively until the FE span
  reaches the target.

Optional structural checks on the deployed state (the formwork use case) add two load steps:
self-weight plus a distributed area load, with the supports held.

The deviation from the kinematic model is measured node by node at the same material point
(exact: every planar quad maps rigidly), in % of the span of the leading crease at that state.
"""

from __future__ import annotations

import json
import math
import os
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from compas_ccu.fea.engines import solve
from compas_ccu.fea.mesh import ShellMesh, mesh_model
from compas_ccu.fea.problem import ConvergenceError, FEError, FEProblem, FEResult, LoadPattern
from compas_ccu.fea.stresses import (
    principal,
    signed_bending_stress,
    stress_summary,
    surface_stresses,
)
from compas_ccu.materials import material as get_material

__all__ = ["FESettings", "Validation", "validate", "deployment_problem", "MODES", "CONTROLS"]

MODES = ("displacement", "actuation")
CONTROLS = ("supports", "edges")
GRAVITY = 9.81


@dataclass
class FESettings:
    """Options of an FE validation (SI units; angles in degrees).

    Attributes
    ----------
    engine : {"kratos", "opensees"}
    mode : {"displacement", "actuation"}
    element_size : float
        Target element edge length, m.
    steps : int
        Deployment increments from the flat stack to the target.
    alpha : float or None
        Target reference reflection angle, degrees (None: the design's).
    material : str or dict
        A name of :data:`compas_ccu.materials.MATERIALS` or a dict of values.
    thickness : float
        m (default 8 mm plywood).
    orthotropic : bool
        E1 along the crease, E2 across (else the isotropic equivalent).
    hinge_stiffness : float
        Rotational hinge spring, N m / rad per m of crease (0: free hinges).
    hinge_translational_stiffness : float or None
        In-plane / out-of-plane hinge springs, N/m per m, instead of rigid ties.
    control : {"supports", "edges"}
        Displacement mode: which nodes follow the kinematic path.
    self_weight : bool
        Self-weight during the deployment too.
    checks : bool
        Run the structural checks (self-weight + ``area_load``) on the deployed state.
    area_load : float
        Distributed load on the plates for the checks, Pa (1.5 kN/m² of wet concrete).
    deflection_limit : float
        Allowed deflection as a fraction of the span (1/500).
    prebend : float
        Actuation mode: pre-bending angle, degrees (default: a quarter of the target).
    actuator_stiffness : float
        Actuation mode: stiffness of the actuator at every crease end, N/m.
    tolerance, max_cuts, max_iterations
        Newton options of the engine.
    """

    engine: str = "kratos"
    mode: str = "displacement"
    element_size: float = 0.1
    steps: int = 8
    alpha: float | None = None
    material: object = "plywood"
    thickness: float = 0.008
    orthotropic: bool = False
    hinge_stiffness: float = 0.0
    hinge_translational_stiffness: float | None = None
    control: str = "supports"
    self_weight: bool = False
    checks: bool = True
    area_load: float = 1500.0
    deflection_limit: float = 1.0 / 500.0
    prebend: float | None = None
    actuator_stiffness: float = 2.0e5
    tolerance: float = 1e-6
    max_cuts: int = 6
    max_iterations: int = 30

    def __post_init__(self):
        if self.mode not in MODES:
            raise FEError(f"mode must be one of {MODES}, got {self.mode!r}")
        if self.control not in CONTROLS:
            raise FEError(f"control must be one of {CONTROLS}, got {self.control!r}")
        if not (isinstance(self.steps, int) and self.steps >= 1):
            raise FEError(f"steps must be an integer >= 1, got {self.steps!r}")
        for key in ("thickness", "element_size"):
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0.0):
                raise FEError(f"{key} must be > 0, got {v!r}")
        if self.area_load < 0.0 or not (0.0 < self.deflection_limit < 1.0):
            raise FEError(
                f"area_load must be >= 0 Pa and deflection_limit in (0, 1), got "
                f"{self.area_load!r} and {self.deflection_limit!r}"
            )
        self.material = get_material(self.material)


def _tie_set(mesh: ShellMesh, fixed: np.ndarray) -> tuple:
    """Ties without pairs of prescribed nodes; a prescribed slave becomes the master."""
    ties = mesh.ties.copy()
    prescribed = np.zeros(len(mesh.nodes), dtype=bool)
    prescribed[fixed] = True
    keep = ~(prescribed[ties[:, 0]] & prescribed[ties[:, 1]])
    ties = ties[keep]
    swap = prescribed[ties[:, 1]]
    ties[swap] = ties[swap][:, ::-1]
    return ties, mesh.tie_lengths[keep], mesh.tie_crease[keep], keep


def _nodal_area_loads(mesh: ShellMesh, pressure: float, direction: np.ndarray) -> np.ndarray:
    """(N, 6) a uniform load per reference area lumped to the nodes (a quarter per corner)."""
    share = np.repeat(mesh.element_areas() / 4.0, 4)
    weight = np.bincount(mesh.elements.ravel(), weights=share, minlength=len(mesh.nodes))
    out = np.zeros((len(mesh.nodes), 6))
    out[:, :3] = pressure * weight[:, None] * direction[None]
    return out


def deployment_problem(model, mesh: ShellMesh, settings: FESettings, *, alpha: float) -> tuple:
    """The displacement-controlled deployment problem (plus the check steps if asked).

    Returns
    -------
    problem : FEProblem
    alphas : (S,) float
        Reference angle of every step (degrees; the check steps repeat the target).
    kinematic : (S, N, 3) float
        Exact kinematic node positions at every step.
    spans : (S,) float
        Span of the leading crease at every step.
    """
    s = settings
    alphas = np.linspace(0.0, alpha, s.steps + 1)[1:]
    structures = model.path(alphas, check=False)
    kinematic = mesh.kinematic(np.array([st.deployed for st in structures]))
    spans = np.array([st.metrics["span"] for st in structures])
    fixed = mesh.supports
    if s.control == "edges":
        fixed = np.union1d(fixed, mesh.free_edges)
    prescribed = kinematic[:, fixed] - mesh.nodes[fixed]
    up = model.axes[1]
    m = s.material
    weight = _nodal_area_loads(mesh, m.density * GRAVITY * s.thickness, -up)
    patterns = []
    steps = s.steps
    if s.checks:
        extra = 2
        prescribed = np.concatenate([prescribed, np.repeat(prescribed[-1:], extra, 0)])
        alphas = np.r_[alphas, [alpha] * extra]
        kinematic = np.concatenate([kinematic, np.repeat(kinematic[-1:], extra, 0)])
        spans = np.r_[spans, [spans[-1]] * extra]
        ramp = np.r_[np.zeros(steps), 0.5, 1.0]
        sw = np.r_[np.ones(steps), 1.0, 1.0] if s.self_weight else ramp
        patterns.append(LoadPattern("self-weight", weight, sw))
        if s.area_load > 0.0:
            q = _nodal_area_loads(mesh, s.area_load, -up)
            patterns.append(LoadPattern("area load", q, ramp))
        steps += extra
    elif s.self_weight:
        patterns.append(LoadPattern("self-weight", weight, np.ones(steps)))
    ties, lengths, _, _ = _tie_set(mesh, fixed)
    problem = FEProblem(
        nodes=mesh.nodes,
        elements=mesh.elements,
        material=m,
        thickness=s.thickness,
        steps=steps,
        orthotropic=s.orthotropic,
        directions=mesh.directions,
        ties=ties,
        tie_lengths=lengths,
        hinge_stiffness=s.hinge_stiffness,
        hinge_translational_stiffness=s.hinge_translational_stiffness,
        fixed=fixed,
        prescribed=prescribed,
        patterns=patterns,
        name=model.design.name,
    )
    return problem, alphas, kinematic, spans


@dataclass
class Validation:
    """The outcome of :func:`validate`: FE history, comparison, stresses, checks."""

    model: object
    mesh: ShellMesh
    settings: FESettings
    problem: FEProblem
    result: FEResult
    alphas: np.ndarray
    kinematic: np.ndarray
    spans: np.ndarray
    deployment_steps: int
    extra: dict = field(default_factory=dict)

    # -- comparison -----------------------------------------------------------------------------
    @property
    def positions(self) -> np.ndarray:
        """(k, N, 3) FE node positions at every step."""
        return self.result.positions(self.mesh.nodes)

    @property
    def deviation(self) -> np.ndarray:
        """(k, N) distance of every FE node from its kinematic position, m."""
        if "aligned" in self.extra:
            return self.extra["aligned"]
        return np.linalg.norm(self.positions - self.kinematic, axis=2)

    def deviation_percent(self) -> np.ndarray:
        """(k, N) deviation in % of the span at that state."""
        return 100.0 * self.deviation / self.spans[:, None]

    def plate_table(self, step: int = -1) -> list:
        """Per plate at one step: max and mean deviation (% span), peak bending stress (MPa)."""
        d = self.deviation_percent()[step]
        bend = signed_bending_stress(self.result.forces[step], thickness=self.settings.thickness)
        rows = []
        for p in range(len(self.mesh.across)):
            nodes = self.mesh.node_plate == p
            el = self.mesh.element_plate == p
            rows.append(
                {
                    "plate": int(self.model.plate_ids[p]),
                    "deviation_max_percent": float(d[nodes].max()),
                    "deviation_mean_percent": float(d[nodes].mean()),
                    "bending_max_MPa": float(np.abs(bend[el]).max() / 1e6),
                }
            )
        return rows

    # -- load path --------------------------------------------------------------------------------
    def work(self) -> np.ndarray:
        """(k,) work done by the supports' prescribed motion up to every step, J.

        The strain energy stored by the deployment (a conservative elastic system):
        trapezoidal sum of reaction · displacement increment over the steps.
        """
        r = self.result
        u = np.nan_to_num(self.problem.prescribed[: r.steps])
        du = np.diff(np.concatenate([np.zeros_like(u[:1]), u]), axis=0)
        reac = np.concatenate([np.zeros_like(r.reactions[:1]), r.reactions])
        mean = 0.5 * (reac[1:] + reac[:-1])
        return np.cumsum(np.einsum("kfi,kfi->k", mean, du))

    def load_path(self) -> dict:
        """The load–deployment curve over the deployment steps."""
        k = min(self.deployment_steps, self.result.steps)
        a = np.r_[0.0, self.alphas[:k]]
        w = np.r_[0.0, self.work()[:k]]
        force = np.gradient(w, np.radians(a)) if len(a) > 2 else np.zeros_like(a)
        reac = np.r_[0.0, np.linalg.norm(self.result.reactions[:k].sum(axis=1), axis=1)]
        peak = np.r_[0.0, np.linalg.norm(self.result.reactions[:k], axis=2).max(axis=1)]
        return {
            "alpha": a.tolist(),
            "work_J": w.tolist(),
            "generalised_force_J_per_rad": force.tolist(),
            "reaction_resultant_N": reac.tolist(),
            "reaction_peak_N": peak.tolist(),
        }

    # -- hinges -----------------------------------------------------------------------------------
    def hinge_forces(self, step: int = -1) -> list:
        """Per crease: peak and mean hinge line force (N/m) at one step."""
        r = self.result
        if r.tie_forces is None or not len(self.problem.ties):
            return []
        fixed = self.problem.fixed[self.problem.fixed < len(self.mesh.nodes)]
        _, lengths, crease, _ = _tie_set(self.mesh, fixed)
        forces = r.tie_forces[step][: len(lengths)]  # hinge ties first (then any actuators)
        line = np.linalg.norm(forces, axis=1) / np.maximum(lengths, 1e-12)
        out = []
        for c in np.unique(crease):
            sel = crease == c
            out.append(
                {
                    "crease": int(c),
                    "max_N_per_m": float(line[sel].max()),
                    "mean_N_per_m": float(line[sel].mean()),
                    "resultant_N": np.round(forces[sel].sum(axis=0), 6).tolist(),
                }
            )
        return out

    # -- checks -----------------------------------------------------------------------------------
    def structural_checks(self) -> dict | None:
        """Deflection under self-weight + area load and bending utilisation (formwork use)."""
        s, r = self.settings, self.result
        if not s.checks or r.steps <= self.deployment_steps:
            return None
        k0 = self.deployment_steps - 1
        deflection = np.linalg.norm(r.displacements[-1] - r.displacements[k0], axis=1)
        span = float(self.spans[k0])
        m = s.material if s.orthotropic else s.material.isotropic_equivalent()
        stress = surface_stresses(r.forces[-1], thickness=s.thickness)
        peak = np.maximum(
            np.abs(principal(stress["top"])).max(axis=1),
            np.abs(principal(stress["bottom"])).max(axis=1),
        )
        utilisation = peak / m.strength
        worst = int(np.argmax(utilisation))
        limit = s.deflection_limit * span
        return {
            "load": {
                "self_weight_N_per_m2": m.density * GRAVITY * s.thickness,
                "area_load_N_per_m2": s.area_load,
            },
            "deflection_max_m": float(deflection.max()),
            "deflection_limit_m": limit,
            "deflection_ratio": float(deflection.max() / limit),
            "deflection_ok": bool(deflection.max() <= limit),
            "utilisation_max": float(utilisation[worst]),
            "utilisation_plate": int(self.model.plate_ids[self.mesh.element_plate[worst]]),
            "strength_MPa": m.strength / 1e6,
            "utilisation_ok": bool(utilisation[worst] <= 1.0),
            "reaction_total_N": np.round(r.reactions[-1].sum(axis=0), 3).tolist(),
            "buckling_factor": r.buckling_factor,
            "buckling_note": r.buckling_note,
        }

    # -- summary ----------------------------------------------------------------------------------
    def summary(self) -> dict:
        """Everything a report needs, JSON-ready."""
        s, r, k = self.settings, self.result, self.deployment_steps - 1
        d = self.deviation_percent()[: k + 1]
        settings = asdict(s)
        settings["material"] = s.material.to_dict()
        return {
            "format": "ccu.validation",
            "version": 1,
            "design": self.model.design.name,
            "engine": r.engine,
            "mode": s.mode,
            "converged": r.converged,
            "alpha": float(self.alphas[k]),
            "span": float(self.spans[k]),
            "mesh": {
                "nodes": len(self.mesh.nodes),
                "elements": len(self.mesh.elements),
                "ties": len(self.problem.ties),
                "element_size": self.mesh.element_size,
                "along": self.mesh.along,
                "across": self.mesh.across.tolist(),
            },
            "deviation": {
                "max_percent": float(d[-1].max()),
                "mean_percent": float(d[-1].mean()),
                "max_percent_along_path": float(d.max()),
                "max_m": float(self.deviation[k].max()),
                "per_step_max_percent": d.max(axis=1).tolist(),
                "per_step_mean_percent": d.mean(axis=1).tolist(),
            },
            "plates": self.plate_table(k),
            "stresses": stress_summary(r.forces[k], thickness=s.thickness),
            "hinges": self.hinge_forces(k),
            "load_path": self.load_path(),
            "checks": self.structural_checks(),
            "solver": {
                "steps": int(self.problem.steps),
                "iterations": r.iterations.tolist() if r.iterations is not None else [],
                "cuts": int(r.cuts),
                "wall_time_s": float(r.wall_time),
                "message": r.message,
            },
            "settings": settings,
            **{key: v for key, v in self.extra.items() if key != "aligned"},
        }

    def write(self, out, *, figures: bool = True) -> list:
        """Write ``validation.json``, ``fe_results.npz`` and the pictures into ``out``.

        ``fe_results.npz`` holds, for every step: node ``positions`` and their ``kinematic``
        positions (k, N, 3), element ``forces`` (k, E, 6) and the plane stresses
        ``stress_top`` / ``stress_bottom`` / ``stress_membrane`` (k, E, 3) in the element frame,
        support ``reactions``, hinge ``tie_forces`` (k, T, 3) of the node pairs ``ties``, and the
        ``deviation`` (k, N) in m; plus the mesh (``nodes``, ``elements``, ``element_plate``).
        """
        os.makedirs(out, exist_ok=True)
        paths = []
        summary = self.summary()
        path = os.path.join(out, "validation.json")
        with open(path, "w") as f:
            json.dump(summary, f, indent=1)
        paths.append(path)
        path = os.path.join(out, "fe_results.npz")
        stresses = surface_stresses(self.result.forces, thickness=self.settings.thickness)
        np.savez_compressed(
            path,
            nodes=self.mesh.nodes,
            elements=self.mesh.elements,
            element_plate=self.mesh.element_plate,
            alphas=self.alphas,
            positions=self.positions,
            kinematic=self.kinematic,
            forces=self.result.forces,
            stress_top=stresses["top"],
            stress_bottom=stresses["bottom"],
            stress_membrane=stresses["membrane"],
            reactions=self.result.reactions,
            tie_forces=self.result.tie_forces,
            ties=self.problem.ties,
            deviation=self.deviation,
        )
        paths.append(path)
        if figures:
            paths += self.figures(out)
        return paths

    def figures(self, out) -> list:
        """``fe_stress.png`` (Fig. 7 colouring), ``fe_deviation.png``, ``fe_curves.png``."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from compas_ccu.viz.fea import plot_fe_curves, plot_fe_shape

        os.makedirs(out, exist_ok=True)
        k = self.deployment_steps - 1
        s = self.settings
        x = self.positions[k]
        name = self.model.design.name
        # the surface facing up (the extrados) on every plate: alternate plates are mirrored in
        # the stack, so their element normals point down; bending flips sign between the faces
        bend = signed_bending_stress(self.result.forces[k], thickness=s.thickness)
        up = self.mesh.element_normals(x) @ self.model.axes[1]
        bend = np.where(up < 0.0, -bend, bend)
        paths = []
        fig = plot_fe_shape(
            x,
            self.mesh.elements,
            bend,
            mode="stress",
            label="bending stress, upper surface [MPa]",
            title=f"{name}, alpha = {self.alphas[k]:.1f} deg ({self.result.engine}): "
            "active bending, tension blue, compression red",
        )
        paths.append(os.path.join(out, "fe_stress.png"))
        fig.savefig(paths[-1], dpi=130)
        plt.close(fig)
        dev = self.deviation_percent()[k]
        fig = plot_fe_shape(
            x,
            self.mesh.elements,
            dev,
            mode="deviation",
            title=f"{name}: FE against the kinematic model, max {dev.max():.3f} % of span",
        )
        paths.append(os.path.join(out, "fe_deviation.png"))
        fig.savefig(paths[-1], dpi=130)
        plt.close(fig)
        lp = self.load_path()
        d = self.deviation_percent()[: k + 1]
        fig = plot_fe_curves(
            np.r_[0.0, self.alphas[: k + 1]],
            deviation_max=np.r_[0.0, d.max(axis=1)],
            deviation_mean=np.r_[0.0, d.mean(axis=1)],
            force=np.asarray(lp["generalised_force_J_per_rad"]),
            energy=np.asarray(lp["work_J"]),
            title=f"{name}: deployment ({s.mode})",
        )
        paths.append(os.path.join(out, "fe_curves.png"))
        fig.savefig(paths[-1], dpi=130)
        plt.close(fig)
        return paths


def validate(model, **options) -> Validation:
    """Deploy ``model`` with a nonlinear FE engine and compare with the kinematic model.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    **options
        Fields of :class:`FESettings` (engine, mode, element_size, steps, alpha, material,
        thickness, orthotropic, hinge_stiffness, control, checks, area_load, ...).

    Returns
    -------
    Validation

    Raises
    ------
    ConvergenceError
        A step did not converge even after cutting it; names the step, the angle and the
        residual (the partial history is attached, never returned as a result).
    DeploymentLimitError
        The target angle lies beyond the deployment limit.
    """
    unknown = sorted(set(options) - set(FESettings.__dataclass_fields__))
    if unknown:
        raise FEError(
            f"unknown FE option(s) {unknown}; known: {sorted(FESettings.__dataclass_fields__)}"
        )
    settings = FESettings(**options)
    alpha = model.alpha_design if settings.alpha is None else float(settings.alpha)
    model.deploy(alpha)  # the limit and self-intersection checks, with their errors
    mesh = mesh_model(model, element_size=settings.element_size)
    start = time.perf_counter()
    if settings.mode == "actuation":
        from compas_ccu.fea.actuation import actuate

        validation = actuate(model, mesh, settings, alpha=alpha)
    else:
        problem, alphas, kinematic, spans = deployment_problem(model, mesh, settings, alpha=alpha)
        result = _solve(problem, settings, alphas, buckling=settings.checks)
        validation = Validation(
            model, mesh, settings, problem, result, alphas, kinematic, spans, settings.steps
        )
    validation.extra["wall_time_total_s"] = time.perf_counter() - start
    return validation


def _solve(
    problem: FEProblem, settings: FESettings, alphas: np.ndarray, *, buckling: bool = False
) -> FEResult:
    result = solve(
        problem,
        settings.engine,
        tolerance=settings.tolerance,
        max_iterations=settings.max_iterations,
        max_cuts=settings.max_cuts,
        buckling=buckling,
    )
    if not result.converged:
        step = result.failed_step
        raise ConvergenceError(
            f"the {settings.engine} analysis did not converge at step {step} of "
            f"{problem.steps} (alpha = {alphas[step - 1]:.4g} deg): {result.message}",
            step=step,
            residual=result.residual if result.residual is not None else float("nan"),
            result=result,
        )
    return result
