"""Displacement-controlled deployment (the default strategy, robust; paper §5.2).

The nodes on the end rulings of every plate (the supports), and with ``control="edges"`` also
the two outer free boundaries, follow the exact kinematic path in ``steps`` increments from the
flat-folded stack (alpha = 0, stress-free) to the target; everything else — the bending of the
plates, the hinge rotations — is left to the FE equilibrium. The hinges are rigid ties of the
three translations (or translational springs), with an optional rotational spring.

With ``checks`` (the formwork use case) two more steps with the supports held add self-weight
and the distributed ``area_load``, and the engine computes the linear buckling factor of the
loaded state (Kratos). With ``self_weight`` the self-weight acts during the deployment too.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.mesh import ShellMesh
from compas_ccu.fea.problem import FEProblem, LoadPattern
from compas_ccu.fea.settings import GRAVITY, FESettings
from compas_ccu.fea.solving import solve_steps, tie_set

__all__ = ["deploy_by_displacement", "deployment_problem", "nodal_area_loads"]


def nodal_area_loads(mesh: ShellMesh, pressure: float, direction: np.ndarray) -> np.ndarray:
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
    weight = nodal_area_loads(mesh, m.density * GRAVITY * s.thickness, -up)
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
            q = nodal_area_loads(mesh, s.area_load, -up)
            patterns.append(LoadPattern("area load", q, ramp))
        steps += extra
    elif s.self_weight:
        patterns.append(LoadPattern("self-weight", weight, np.ones(steps)))
    ties, lengths, _, _ = tie_set(mesh, fixed)
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


def deploy_by_displacement(
    model, mesh: ShellMesh, settings: FESettings, *, alpha: float
) -> DeploymentHistory:
    """Deploy ``mesh`` of ``model`` to ``alpha`` by prescribing the supports' kinematic path.

    Raises
    ------
    ConvergenceError
        A step did not converge even after cutting it.
    """
    problem, alphas, kinematic, spans = deployment_problem(model, mesh, settings, alpha=alpha)
    result = solve_steps(problem, settings, alphas, buckling=settings.checks)
    return DeploymentHistory(
        model, mesh, settings, problem, result, alphas, kinematic, spans, settings.steps
    )
