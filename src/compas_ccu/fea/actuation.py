"""Deployment by actuation, the paper's procedure (§3): pre-bending, then actuators at the
crease ends, corrected iteratively.

1. **Pre-bending** (``prebend`` degrees, default a quarter of the target, in ``max(2, steps //
   4)`` steps): the end rulings of every plate (the supports) follow the kinematic path from the
   flat stack, so the plates leave the flat, bifurcating state bent the right way (the paper's
   SOFiSTiK model needed it "to avoid buckling"). This stage is solved alone first, for the
   reactions that hold the pre-bent state.
2. **Actuation** (the remaining steps): the supports are released; their pre-bending reactions
   stay on as dead loads, and the structure is driven by *actuators* at the crease ends (the feet
   of every crease, both plates' nodes): a spring of stiffness ``actuator_stiffness`` from each
   foot to an anchor node that moves towards the foot's kinematic target. The actuator forces
   are results, split into the component along the leading crease chord (the crease-aligned
   push) and the rest (the pull perpendicular to it).
3. **Iteratively**: the springs stretch, so the anchors' end positions are corrected by the
   feet's miss (up to four runs) until the feet reach their targets to 0.1 % of the diagonal of
   the deployed kinematic bounding box.

An actuator with a finite stiffness (a jack, a winch, a person) rather than dead loads at the
feet: the released structure has no stable equilibrium under dead loads there (``docs/fea.md``).

The history (:class:`~compas_ccu.fea.history.DeploymentHistory`, anchors removed) holds at every
step the kinematic state at the angle the FE structure actually reached — found from the span of
the leading crease — not the scheduled one; its ``extra["actuation"]`` records the schedule, the
angles reached, the actuator forces, the feet's miss per run and the plates' kinematic bending
energy. The plate ends are free, so :func:`compas_ccu.fea.validation.validate` compares the shape
after a best-fit rigid alignment (:mod:`compas_ccu.fea.comparison`).
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.mesh import ShellMesh
from compas_ccu.fea.problem import FEError, FEProblem, LoadPattern
from compas_ccu.fea.settings import FESettings
from compas_ccu.fea.solving import solve_steps, strip_nodes, tie_set
from compas_ccu.thickness.actuation import bending_energy

__all__ = ["actuate", "bending_energy"]  # bending_energy: compas_ccu.thickness.actuation


def actuate(model, mesh: ShellMesh, settings: FESettings, *, alpha: float) -> DeploymentHistory:
    """Deploy ``mesh`` of ``model`` to ``alpha`` by pre-bending, then actuators (see above).

    Raises
    ------
    FEError
        ``prebend`` does not lie between 0 and the target.
    ConvergenceError
        A step of a run did not converge even after cutting it.
    """
    s = settings
    pre = s.prebend if s.prebend is not None else alpha / 4.0
    if not (0.0 < pre < alpha):
        raise FEError(f"prebend must lie between 0 and the target {alpha:g} deg, got {pre!r}")
    s1 = max(2, s.steps // 4)
    s2 = max(2, s.steps - s1)
    alphas1 = np.linspace(0.0, pre, s1 + 1)[1:]
    alphas2 = np.linspace(pre, alpha, s2 + 1)[1:]
    steps = s1 + s2
    kin = mesh.kinematic(np.array([st.deployed for st in model.path(np.r_[alphas1, alphas2])]))
    supports = mesh.supports
    feet = np.intersect1d(supports, mesh.ties.ravel())  # both plates' nodes at every crease end
    n_nodes = len(mesh.nodes)
    anchors = n_nodes + np.arange(len(feet))
    nodes = np.vstack([mesh.nodes, mesh.nodes[feet]])
    hinge_k = 1e11  # N/m per m of crease: rigid for plates of this size (checked in the tests)
    ties, lengths, _, _ = tie_set(mesh, supports)
    ties_all = np.vstack([ties, np.c_[anchors, feet]])
    lengths_all = np.r_[lengths, np.full(len(feet), s.actuator_stiffness / hinge_k)]
    common = dict(
        nodes=nodes,
        elements=mesh.elements,
        material=s.material,
        thickness=s.thickness,
        orthotropic=s.orthotropic,
        directions=mesh.directions,
        hinge_stiffness=s.hinge_stiffness,
        hinge_translational_stiffness=hinge_k,
        ties=ties_all,
        tie_lengths=lengths_all,
        fixed_rotations=anchors,
        name=model.design.name,
    )
    fixed = np.r_[supports, anchors]
    u_sup = kin[:, supports] - mesh.nodes[supports]
    u_feet = kin[:, feet] - mesh.nodes[feet]

    # stage 1 alone: the reactions that hold the pre-bent state
    stage1 = FEProblem(
        steps=s1, fixed=fixed, prescribed=np.concatenate([u_sup, u_feet], 1)[:s1], **common
    )
    first = solve_steps(stage1, s, alphas1)
    hold = np.zeros((len(nodes), 6))
    hold[supports, :3] = first.reactions[-1][: len(supports)]
    held = np.r_[np.zeros(s1 - 1), np.ones(s2 + 1)]  # full while the supports still hold

    correction = np.zeros((len(feet), 3))
    history = []
    span_ref = float(np.linalg.norm(np.ptp(kin[-1], axis=0)))
    for _ in range(4):
        prescribed = np.full((steps, len(fixed), 3), np.nan)
        prescribed[:s1, : len(supports)] = u_sup[:s1]
        ramp = np.r_[np.zeros(s1), np.linspace(1.0 / s2, 1.0, s2)]
        prescribed[:, len(supports) :] = u_feet + ramp[:, None, None] * correction[None]
        problem = FEProblem(
            steps=steps,
            fixed=fixed,
            prescribed=prescribed,
            patterns=[LoadPattern("pre-bending reactions", hold, held)],
            **common,
        )
        result = solve_steps(problem, s, np.r_[alphas1, alphas2])
        x = result.positions(nodes)
        miss = kin[-1, feet] - x[-1, feet]
        history.append(float(np.linalg.norm(miss, axis=1).max()))
        if history[-1] <= 1e-3 * span_ref:
            break
        correction += miss
    # positions of the plates only (the anchors are not part of the structure)
    x = x[:, :n_nodes]
    forces = s.actuator_stiffness * (
        (nodes[anchors] + result.displacements[:, anchors]) - x[:, feet]
    )
    lead = mesh.ties[mesh.tie_crease == 0, 0]
    ends = lead[[0, -1]]
    dense = np.linspace(0.0, alpha, 721)
    k_dense = mesh.kinematic(model.vertices(dense))
    kin_span = np.linalg.norm(k_dense[:, ends[0]] - k_dense[:, ends[1]], axis=1)
    order = np.argsort(kin_span)
    fe_span = np.linalg.norm(x[:, ends[0]] - x[:, ends[1]], axis=1)
    reached = np.interp(fe_span, kin_span[order], dense[order])
    matched_states = model.path(reached, check=False)
    matched = mesh.kinematic(np.array([st.deployed for st in matched_states]))
    chord = x[:, ends[1]] - x[:, ends[0]]
    chord /= np.linalg.norm(chord, axis=1, keepdims=True)
    along = np.einsum("kfi,ki->kf", forces, chord)
    across = np.linalg.norm(forces - along[..., None] * chord[:, None], axis=2)
    rigidity = s.material.isotropic_equivalent().plate_rigidity(s.thickness)
    record = {
        "prebend_deg": pre,
        "prebend_steps": s1,
        "force_steps": s2,
        "actuator_stiffness_N_per_m": s.actuator_stiffness,
        "scheduled_alpha": np.r_[alphas1, alphas2].tolist(),
        "reached_alpha": reached.tolist(),
        "feet": len(feet),
        "force_max_N": np.linalg.norm(forces, axis=2).max(axis=1).tolist(),
        "force_crease_aligned_max_N": np.abs(along).max(axis=1).tolist(),
        "force_perpendicular_max_N": across.max(axis=1).tolist(),
        "foot_miss_m": history,
        "kinematic_bending_energy_J": float(
            bending_energy(matched_states[-1].deployed[None], rigidity)[0]
        ),
    }
    return DeploymentHistory(
        model,
        mesh,
        s,
        problem,
        strip_nodes(result, n_nodes),
        reached,
        matched,
        np.array([st.metrics["span"] for st in matched_states]),
        steps,
        extra={"actuation": record},
    )
