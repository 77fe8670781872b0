"""Displacement-controlled deployment (the default strategy, robust; paper §5.2).

The nodes on the end rulings of every plate (the feet), and with ``control="edges"`` also
the two outer free boundaries, follow the exact kinematic path in ``steps`` increments from the
flat-folded stack (alpha = 0, stress-free) to the target; everything else — the bending of the
plates, the hinge rotations — is left to the FE equilibrium. The hinges are rigid ties of the
three translations (or translational springs), with an optional rotational spring.

With ``checks`` (the formwork and service use) every load case of the settings
(:mod:`compas_ccu.fea.loads`) follows on the deployed state, with the feet held as the
``supports`` say (:mod:`compas_ccu.fea.supports`), in two or three steps: its characteristic
loads (serviceability), its design loads (ultimate, where the engine also computes the linear
buckling factor: Kratos) and, unless it is the last case, unloading back to the deployed state.
With ``self_weight`` the self-weight acts during the deployment too. With
``hinge_eccentricity = "axis-shift"`` the plates hinge on their faces
(:mod:`compas_ccu.fea.eccentric`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from compas_ccu.fea.eccentric import FaceHinges
from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.loads import GRAVITY, nodal_loads
from compas_ccu.fea.mesh import ShellMesh
from compas_ccu.fea.problem import FEProblem, LoadPattern
from compas_ccu.fea.settings import FESettings
from compas_ccu.fea.solving import solve_steps, strip_nodes, tie_set
from compas_ccu.fea.supports import support_model
from compas_ccu.thickness import ThickModel

__all__ = ["deploy_by_displacement", "deployment_problem", "nodal_area_loads"]


def nodal_area_loads(mesh: ShellMesh, pressure: float, direction: np.ndarray) -> np.ndarray:
    """(N, 6) a uniform load per reference area lumped to the nodes (a quarter per corner)."""
    share = np.repeat(mesh.element_areas() / 4.0, 4)
    weight = np.bincount(mesh.elements.ravel(), weights=share, minlength=len(mesh.nodes))
    out = np.zeros((len(mesh.nodes), 6))
    out[:, :3] = pressure * weight[:, None] * direction[None]
    return out


def deployment_problem(model, mesh: ShellMesh, settings: FESettings, *, alpha: float) -> tuple:
    """The displacement-controlled deployment problem (plus the load-case steps if asked).

    Returns
    -------
    problem : FEProblem
        Its nodes are the mesh's, then one ground node per support spring.
    alphas : (S,) float
        Reference angle of every step (degrees; the load-case steps repeat the target).
    kinematic : (S, N, 3) float
        Exact kinematic node positions at every step (the mesh's nodes).
    spans : (S,) float
        Span of the leading crease at every step.
    load_steps : list of dict
        Per load case: ``case`` (:class:`~compas_ccu.fea.loads.LoadCase`) and the 0-based
        steps ``sls`` and ``uls`` of its characteristic and design loads.
    supports : SupportModel or None
    mesh : ShellMesh
        The mesh as solved: with axis-shift hinges its nodes lie on the surface through the
        hinge lines (:mod:`compas_ccu.fea.eccentric`).
    """
    s = settings
    alphas = np.linspace(0.0, alpha, s.steps + 1)[1:]
    structures = model.path(alphas, check=False)
    spans = np.array([st.metrics["span"] for st in structures])
    offsets = None
    if s.hinge_eccentricity == "axis-shift":
        faces = FaceHinges.build(mesh, ThickModel(model, thickness=s.thickness))
        offsets = faces.offsets
        mesh = replace(mesh, nodes=faces.positions(mesh, [0.0])[0])  # the thick flat stack
        kinematic = faces.positions(mesh, alphas)
    else:
        kinematic = mesh.kinematic(np.array([st.deployed for st in structures]))
    feet = mesh.supports
    cases = s.cases() if s.checks else []
    up, span_axis = model.axes[1], model.axes[0]
    sup = None
    if cases:
        sup = support_model(
            mesh,
            kinematic[-1],
            kind=s.supports["type"],
            stiffness=s.supports["stiffness"],
            tie=s.supports["tie"],
            tie_stiffness=s.supports["tie_stiffness"],
            span_axis=span_axis,
        )
    released = sup is not None and bool(sup.released.any())
    fixed = feet
    if released:
        # a foot tied to another foot follows it through the hinge tie (once released, the
        # feet of a crease must stay together)
        both = np.isin(mesh.ties, feet).all(axis=1)
        fixed = np.setdiff1d(feet, mesh.ties[both, 1])
    if s.control == "edges":
        fixed = np.union1d(fixed, mesh.free_edges)
    ground = np.zeros(0, dtype=int) if sup is None else feet[sup.ground]
    ground_nodes = len(mesh.nodes) + np.arange(len(ground))
    nodes = np.vstack([mesh.nodes, mesh.nodes[ground]])
    path_nodes = np.r_[fixed, ground_nodes]  # a ground node follows its foot
    prescribed = kinematic[:, np.r_[fixed, ground]] - nodes[path_nodes]
    patterns, load_steps = [], []
    steps = s.steps
    m = s.material
    weight = nodal_area_loads(mesh, m.density * GRAVITY * s.thickness, -up)
    if cases:
        deployed = kinematic[-1]
        ends = deployed[feet] @ span_axis
        middle = 0.5 * (ends.min() + ends.max())
        extra = 3 * len(cases) - 1
        held = np.repeat(prescribed[-1:], extra, 0)
        is_foot = np.isin(path_nodes, feet)
        released_rows = np.zeros((len(path_nodes), 3), dtype=bool)
        if sup is not None:
            where = np.searchsorted(feet, path_nodes[: len(fixed)])
            on_feet = is_foot[: len(fixed)]
            released_rows[: len(fixed)][on_feet] = sup.released[where[on_feet]]
        released_rows[: len(fixed)][~is_foot[: len(fixed)]] = True  # free edges are no supports
        held[:, released_rows] = np.nan
        prescribed = np.concatenate([prescribed, held])
        alphas = np.r_[alphas, [alpha] * extra]
        kinematic = np.concatenate([kinematic, np.repeat(kinematic[-1:], extra, 0)])
        spans = np.r_[spans, [spans[-1]] * extra]
        total = steps + extra
        base = 1.0 if s.self_weight else 0.0
        for i, case in enumerate(cases):
            sls, uls = steps + 3 * i, steps + 3 * i + 1
            load_steps.append({"case": case, "sls": sls, "uls": uls})
            for action in case.actions:
                if action.name == "self-weight":
                    continue  # one pattern for all cases, below
                factors = np.zeros(total)
                factors[sls], factors[uls] = 1.0, case.factor(action)
                loads = nodal_loads(
                    mesh.elements, deployed, action, up=up, span_axis=span_axis, middle=middle
                )
                patterns.append(LoadPattern(f"{case.name}: {action.name}", loads, factors))
        sw = np.full(total, base)
        for step in load_steps:
            sw[step["sls"]], sw[step["uls"]] = 1.0, step["case"].gamma_G
        patterns.insert(0, LoadPattern("self-weight", weight, sw))
        steps = total
    elif s.self_weight:
        patterns.append(LoadPattern("self-weight", weight, np.ones(steps)))
    for p in patterns:  # the ground nodes carry no load
        p.loads = np.vstack([p.loads, np.zeros((len(ground), 6))])
    ties, lengths, _, _ = tie_set(mesh, fixed)
    problem = FEProblem(
        nodes=nodes,
        elements=mesh.elements,
        material=m,
        thickness=s.thickness,
        steps=steps,
        orthotropic=s.orthotropic,
        directions=mesh.directions,
        offsets=offsets,
        ties=ties,
        tie_lengths=lengths,
        hinge_stiffness=s.hinge_stiffness,
        hinge_translational_stiffness=s.hinge_translational_stiffness,
        fixed=path_nodes,
        prescribed=prescribed,
        fixed_rotations=ground_nodes,
        springs=np.c_[ground_nodes, ground],
        spring_stiffness=np.zeros((0, 3)) if sup is None else sup.stiffness,
        patterns=patterns,
        name=model.design.name,
    )
    return problem, alphas, kinematic, spans, load_steps, sup, mesh


def deploy_by_displacement(
    model, mesh: ShellMesh, settings: FESettings, *, alpha: float
) -> DeploymentHistory:
    """Deploy ``mesh`` of ``model`` to ``alpha`` by prescribing the supports' kinematic path.

    Raises
    ------
    ConvergenceError
        A step did not converge even after cutting it.
    """
    problem, alphas, kinematic, spans, load_steps, sup, mesh = deployment_problem(
        model, mesh, settings, alpha=alpha
    )
    buckling = [step["uls"] + 1 for step in load_steps]
    result = solve_steps(problem, settings, alphas, buckling=buckling)
    return DeploymentHistory(
        model,
        mesh,
        settings,
        problem,
        strip_nodes(result, len(mesh.nodes)),
        alphas,
        kinematic,
        spans,
        settings.steps,
        load_steps=load_steps,
        supports=sup,
    )
