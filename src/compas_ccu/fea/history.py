"""The record of an FE deployment, increment by increment: what both strategies return.

A :class:`DeploymentHistory` holds, for every step of the analysis, the FE state (node
positions, element forces and surface stresses, support reactions, hinge tie forces) next to
the exact kinematic state it is compared with (node positions, reference angle, span). The
quantities derived from the FE history alone — hinge line forces, the work of the supports and
the load–deployment curve — are methods here; the comparison with the kinematic model is
:mod:`compas_ccu.fea.comparison`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compas_ccu.fea.mesh import ShellMesh
from compas_ccu.fea.problem import FEProblem, FEResult
from compas_ccu.fea.settings import FESettings
from compas_ccu.fea.solving import tie_set
from compas_ccu.fea.stresses import SurfaceStresses, surface_stresses
from compas_ccu.thickness.actuation import actuation_force
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = ["DeploymentHistory"]


@dataclass
class DeploymentHistory:
    """An FE deployment, step by step, next to its kinematic counterpart.

    Attributes
    ----------
    model : compas_ccu.model.CCUModel
    mesh : ShellMesh
    settings : FESettings
    problem : FEProblem
        The problem solved (for the actuation: the last of its runs).
    result : FEResult
        The engine's history, of the mesh's nodes only (k steps).
    alphas : (k,) float
        Reference angle of the kinematic state of every step, degrees (the check steps repeat
        the target).
    kinematic : (k, N, 3) float
        Exact kinematic positions of the FE nodes at every step.
    spans : (k,) float
        Span of the leading crease of the kinematic state at every step, m.
    deployment_steps : int
        The steps of the deployment proper; any after them are the structural check steps.
    extra : dict
        JSON-ready record particular to the strategy (e.g. ``{"actuation": {...}}``).
    load_steps : list of dict
        Per load case (displacement mode with checks): ``case``
        (:class:`~compas_ccu.fea.loads.LoadCase`) and the 0-based steps ``sls`` and ``uls``
        of its characteristic and design loads.
    supports : SupportModel or None
        How the feet were held under the load cases.
    """

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
    load_steps: list = field(default_factory=list)
    supports: object = None

    # -- the FE state at every step ---------------------------------------------------------------
    @property
    def steps(self) -> int:
        """Number of converged steps k."""
        return self.result.steps

    @property
    def positions(self) -> np.ndarray:
        """(k, N, 3) FE node positions at every step."""
        return self.result.positions(self.mesh.nodes)

    @property
    def forces(self) -> np.ndarray:
        """(k, E, 6) element forces per unit length (see :mod:`compas_ccu.fea.problem`)."""
        return self.result.forces

    @property
    def reactions(self) -> np.ndarray:
        """(k, F, 3) reactions of the prescribed nodes at every step, N."""
        return self.result.reactions

    def stresses(self) -> SurfaceStresses:
        """Plane stresses ``top`` / ``bottom`` / ``membrane`` (k, E, 3) in the element frame,
        Pa (:func:`~compas_ccu.fea.stresses.surface_stresses`)."""
        return surface_stresses(self.result.forces, thickness=self.settings.thickness)

    def hinge_forces(self, step: int = -1) -> list:
        """Per crease: peak and mean hinge line force (N/m) and the resultant (N) at one step."""
        r = self.result
        if r.tie_forces is None or not len(self.problem.ties):
            return []
        fixed = self.problem.fixed[self.problem.fixed < len(self.mesh.nodes)]
        _, lengths, crease, _ = tie_set(self.mesh, fixed)
        forces = r.tie_forces[step][: len(lengths)]  # hinge ties first (then any actuators)
        line = np.linalg.norm(forces, axis=1) / np.maximum(lengths, ZERO_LENGTH)
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

    def kinematic_span_at_zero(self) -> float:
        """Span of the leading crease in the flat-folded stack (alpha = 0), m."""
        return float(self.model.path([0.0], check=False)[0].metrics["span"])

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
        """The load–deployment curve over the deployment steps (JSON-ready)."""
        k = min(self.deployment_steps, self.result.steps)
        a = np.r_[0.0, self.alphas[:k]]
        w = np.r_[0.0, self.work()[:k]]
        force = np.zeros_like(a)
        if len(a) > 2:
            # steps at one angle (the release of the leading drive, fea.leading): no dW/dalpha
            with np.errstate(divide="ignore", invalid="ignore"):
                force = np.gradient(w, np.radians(a))
        span = np.r_[self.kinematic_span_at_zero(), self.spans[:k]]
        foot = actuation_force(a, w, span)
        reac = np.r_[0.0, np.linalg.norm(self.result.reactions[:k].sum(axis=1), axis=1)]
        peak = np.r_[0.0, np.linalg.norm(self.result.reactions[:k], axis=2).max(axis=1)]
        return {
            "alpha": a.tolist(),
            "work_J": w.tolist(),
            "generalised_force_J_per_rad": [
                None if not np.isfinite(f) else float(f) for f in force
            ],
            "foot_force_N": [None if not np.isfinite(f) else float(f) for f in foot],
            "reaction_resultant_N": reac.tolist(),
            "reaction_peak_N": peak.tolist(),
        }
