"""Deployment driven by the leading crease alone: does one crease drive all, statically?

The 1-DOF claim says that unfolding one crease unfolds the whole structure. The
``displacement`` strategy cannot show it (every plate's end rulings follow the kinematic path)
and neither can ``actuation`` (actuators at the feet of every crease). With ``drive="leading"``
(``ccu validate --drive leading``) the displacement mode runs in three stages:

1. **Pre-bending** (``prebend`` degrees, default an eighth of the target, in ``max(2, steps //
   4)`` steps): the end rulings of every plate follow the kinematic path from the flat stack, so
   that every crease leaves the flat, bifurcating state on the right side (at alpha = 0 each
   crease may fold either way). This stage is solved alone first, for the reactions that hold
   the pre-bent state.
2. **Release** (``RELEASE_STEPS``): the end rulings of every plate but the two of the leading
   crease are let go; their pre-bending reactions are put on as loads and ramped down to zero,
   the leading plates held at the pre-bent state. Nothing but the hinges holds the other
   plates from then on.
3. **Drive** (the remaining steps): only the end rulings of the two leading plates follow the
   kinematic path to the target. They also hold the structure in the model's frame (no other
   restraint is needed: the leading pair is fixed at both ends).

The followers' fold is then measured at every crease (:mod:`compas_ccu.fea.creases`): the FE
alpha next to the kinematic alpha of the step, their residual, and ``follow``, the share of the
drive's kinematic increment of alpha each crease took in the FE. The record is
``extra["drive"]`` of the :class:`~compas_ccu.fea.history.DeploymentHistory`, in
``validation.json`` under ``"drive"``.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fea.creases import crease_fold_table
from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.mesh import ShellMesh
from compas_ccu.fea.problem import FEError, FEProblem, LoadPattern
from compas_ccu.fea.settings import FESettings
from compas_ccu.fea.solving import solve_steps, strip_nodes, tie_set

__all__ = ["deploy_by_leading_crease", "driven_nodes", "RELEASE_STEPS"]

#: Steps over which the released supports' reactions are ramped down to zero.
RELEASE_STEPS = 2


def driven_nodes(mesh: ShellMesh) -> tuple:
    """The supports split into those driven throughout and those released after pre-bending.

    The driven ones are the end-ruling nodes of the two plates of the leading crease (crease
    0). Of two tied feet (at a crease end) only one is prescribed, the other follows it through
    the hinge tie; a foot tied to a driven foot is never prescribed.

    Returns
    -------
    driven : (D,) int
    released : (R,) int
    """
    lead = np.unique(mesh.ties[mesh.tie_crease == 0])
    lead_plates = np.unique(mesh.node_plate[lead])
    feet = mesh.supports
    on_lead = np.isin(mesh.node_plate[feet], lead_plates)
    driven, others = set(feet[on_lead].tolist()), feet[~on_lead]
    released = set()
    for a, b in mesh.ties[np.isin(mesh.ties, feet).all(axis=1)]:
        if a in driven and b in driven:
            driven.discard(int(b))
    for f in others.tolist():
        tied = mesh.ties[(mesh.ties == f).any(axis=1)].ravel()
        partners = set(tied.tolist()) - {f}
        if not partners & (driven | released):
            released.add(f)
    return np.array(sorted(driven), dtype=int), np.array(sorted(released), dtype=int)


def _schedule(settings: FESettings, alpha: float) -> tuple:
    """The pre-bending angle, the steps of the three stages and the angle of every step."""
    pre = settings.prebend if settings.prebend is not None else alpha / 8.0
    if not (0.0 < pre < alpha):
        raise FEError(f"prebend must lie between 0 and the target {alpha:g} deg, got {pre!r}")
    s1 = max(2, settings.steps // 4)
    s3 = max(2, settings.steps - s1)
    alphas = np.r_[
        np.linspace(0.0, pre, s1 + 1)[1:],
        np.full(RELEASE_STEPS, pre),
        np.linspace(pre, alpha, s3 + 1)[1:],
    ]
    return pre, s1, s3, alphas


def deploy_by_leading_crease(
    model, mesh: ShellMesh, settings: FESettings, *, alpha: float
) -> DeploymentHistory:
    """Deploy ``mesh`` of ``model`` to ``alpha`` driving the leading crease's plates alone.

    Raises
    ------
    FEError
        ``prebend`` does not lie between 0 and the target.
    ConvergenceError
        A step did not converge even after cutting it.
    """
    s = settings
    pre, s1, s3, alphas = _schedule(s, alpha)
    steps = len(alphas)
    structures = model.path(alphas, check=False)
    kin = mesh.kinematic(np.array([st.deployed for st in structures]))
    driven, released = driven_nodes(mesh)
    fixed = np.r_[driven, released]
    ties, lengths, _, _ = tie_set(mesh, fixed)
    common = dict(
        nodes=mesh.nodes,
        elements=mesh.elements,
        material=s.material,
        thickness=s.thickness,
        orthotropic=s.orthotropic,
        directions=mesh.directions,
        ties=ties,
        tie_lengths=lengths,
        hinge_stiffness=s.hinge_stiffness,
        hinge_translational_stiffness=s.hinge_translational_stiffness,
        fixed=fixed,
        name=model.design.name,
    )
    u = kin[:, fixed] - mesh.nodes[fixed]
    first = solve_steps(FEProblem(steps=s1, prescribed=u[:s1], **common), s, alphas[:s1])
    hold = np.zeros((len(mesh.nodes), 6))
    hold[released, :3] = first.reactions[-1][len(driven) :]
    # full at the last pre-bending step (the supports still hold), then down to zero
    factors = np.r_[np.zeros(s1 - 1), 1.0, np.linspace(1.0, 0.0, RELEASE_STEPS + 1)[1:]]
    factors = np.r_[factors, np.zeros(s3)]
    prescribed = u.copy()
    prescribed[s1:, len(driven) :] = np.nan
    problem = FEProblem(
        steps=steps,
        prescribed=prescribed,
        patterns=[LoadPattern("released pre-bending reactions", hold, factors)],
        **common,
    )
    result = solve_steps(problem, s, alphas)
    positions = result.positions(mesh.nodes)
    start = s1 + RELEASE_STEPS - 1
    record = {
        "drive": "leading",
        "prebend_deg": pre,
        "prebend_steps": s1,
        "release_steps": RELEASE_STEPS,
        "drive_steps": s3,
        "drive_start_step": start,
        "driven_nodes": len(driven),
        "released_nodes": len(released),
        "alpha": alphas.tolist(),
        "creases": crease_fold_table(mesh, positions, kin, start=start),
    }
    return DeploymentHistory(
        model,
        mesh,
        s,
        problem,
        strip_nodes(result, len(mesh.nodes)),
        alphas,
        kin,
        np.array([st.metrics["span"] for st in structures]),
        steps,
        extra={"drive": record},
    )
