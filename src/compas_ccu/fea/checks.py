"""Structural checks of the deployed state under the load cases (formwork and service).

A displacement-controlled history with ``checks`` holds, after the deployment, the steps of
every load case of :mod:`compas_ccu.fea.loads` (:mod:`compas_ccu.fea.displacement`): its
characteristic loads (serviceability, SLS) and its design loads (ultimate, ULS). Per case:

* **deflection** — the largest node displacement from the deployed state at the SLS, against
  ``deflection_limit`` × span (span/500 by default): the instantaneous one, checked, and the
  final one with creep, ``u_G (1 + k_def) + u_Q (1 + ψ2 k_def)`` (EN 1995-1-1 2.2.3(5); u_G from
  the self-weight case), reported;
* **utilisation** — the largest surface principal stress at the ULS (the active-bending
  prestress of the deployed plates included: the permanent and the case's stresses combined)
  over the design strength ``k_mod f_k / γ_M`` with the k_mod of the case's load duration
  (:class:`~compas_ccu.materials.DesignFactors`; the characteristic utilisation beside it);
* **buckling factor** — the engine's linear buckling factor of the ULS state (Kratos): by how
  much all loads of the case may grow before the prestressed structure buckles; computed with
  E_mean, reported with the design stiffness ``E_mean / (γ_M (1 + ψ2 k_def))`` (EN 1995-1-1
  2.4.1(2)P, 2.3.2.2(2)): ``λ_d = λ_mean E_d / E_mean`` (:mod:`compas_ccu.fea.design_values`);
* **reactions** — the resultant the ground gives each side (the start and the end feet of the
  plates) at the SLS and the ULS, with a tie's force;
* **hinge line forces** — per crease at the ULS, the force the hinge passes to its plate b,
  resolved at every hinge node into the in-plane force across the crease (positive: tension,
  the hinge pulls the plate towards the crease), the out-of-plane shear (along the plate
  normal) and the shear along the crease, per metre of crease.

:func:`structural_checks` returns them per case and the governing values over the cases (the
keys of one case, so older readers of ``validation.json`` keep working):
:class:`~compas_ccu.fea.check_results.StructuralChecks`, whose ``to_dict()`` ``validation.json``
holds.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fea.check_results import (
    CreaseHingeForces,
    HingeExtremes,
    HingeLineForces,
    StructuralChecks,
)
from compas_ccu.fea.design_values import (
    StiffnessBasis,
    creep_psi2,
    design_buckling_factor,
    final_deflection,
)
from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.loads import GRAVITY
from compas_ccu.fea.solving import tie_set
from compas_ccu.fea.stresses import principal, surface_stresses
from compas_ccu.materials import design_factors
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = [
    "structural_checks",
    "case_factors",
    "hinge_line_forces",
    "resolve_hinge_forces",
    "StructuralChecks",
    "HingeLineForces",
]


def case_factors(history: DeploymentHistory, duration: str):
    """The design factors of the settings for a case of load duration ``duration``.

    The k_mod of the duration (EN 1995-1-1 Table 3.1), unless the design gives k_mod itself.
    """
    s = history.settings
    f = s.design_code
    if f.is_characteristic:
        return f
    return design_factors(
        s.material,
        code=f.code,
        service_class=f.service_class,
        load_duration=duration,
        gamma_M=f.gamma_M if "gamma_M given" in f.source else None,
        k_mod=f.k_mod if "k_mod given" in f.source else None,
        k_def=f.k_def,
    )


def resolve_hinge_forces(
    forces: np.ndarray,
    lengths: np.ndarray,
    tangents: np.ndarray,
    normals: np.ndarray,
    inward: np.ndarray,
) -> tuple:
    """Hinge forces per metre of crease in the crease's frame.

    Parameters
    ----------
    forces : (T, 3) float
        The force every hinge node passes to its plate b, N.
    lengths : (T,) float
        The crease length of every hinge node, m.
    tangents, normals : (T, 3) float
        The crease direction and plate b's normal at every hinge node (any length).
    inward : (T, 3) float
        Any vector from the hinge node into plate b.

    Returns
    -------
    across : (T,) float
        In-plane force across the crease, N/m: positive is tension (the hinge pulls plate b
        towards the crease), negative compression.
    normal : (T,) float
        Out-of-plane shear, N/m (absolute).
    along : (T,) float
        Shear along the crease, N/m (absolute).

    Examples
    --------
    >>> f = np.array([[-30.0, 0.0, 4.0]])  # plate b lies at +x of a crease along y
    >>> resolve_hinge_forces(f, np.array([0.5]), np.array([[0.0, 1.0, 0.0]]),
    ...                      np.array([[0.0, 0.0, 1.0]]), np.array([[1.0, 0.0, 0.0]]))
    (array([60.]), array([8.]), array([0.]))
    """
    t = tangents / np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), ZERO_LENGTH)
    n = normals - np.einsum("ij,ij->i", normals, t)[:, None] * t
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), ZERO_LENGTH)
    m = np.cross(n, t)
    m *= np.where(np.einsum("ij,ij->i", m, inward) >= 0.0, 1.0, -1.0)[:, None]
    per_m = 1.0 / np.maximum(lengths, ZERO_LENGTH)
    across = -np.einsum("ij,ij->i", forces, m) * per_m
    normal = np.abs(np.einsum("ij,ij->i", forces, n)) * per_m
    along = np.abs(np.einsum("ij,ij->i", forces, t)) * per_m
    return across, normal, along


def hinge_line_forces(history: DeploymentHistory, step: int) -> HingeLineForces:
    """The hinge line forces at ``step`` (0-based) resolved in the crease's frame, N/m
    (:func:`resolve_hinge_forces`).

    Returns
    -------
    HingeLineForces
        The largest tension and compression across a crease, out-of-plane shear and shear
        along a crease, the mean line force, and the same per crease (with the resultant, N).
        The largest values sit at the feet, where the hinge meets a held foot (a concentrated
        force the next hinge node takes, whose size depends on the element: the engines differ
        there); ``interior_max_N_per_m`` is the largest line force away from the feet (the
        middle 80 % of every crease), which they agree on.
    """
    h = history
    r = h.result
    mesh = h.mesh
    if r.tie_forces is None or not len(h.problem.ties):
        return HingeLineForces(None)
    fixed = h.problem.fixed[h.problem.fixed < len(mesh.nodes)]
    ties, lengths, crease, keep = tie_set(mesh, fixed)
    forces = r.tie_forces[step][: len(ties)]
    x = h.positions[step]
    slave = ties[:, 1]
    tangent = np.zeros((len(mesh.ties), 3))
    for c in np.unique(mesh.tie_crease):  # along the crease's row of nodes (mesh order)
        rows = np.flatnonzero(mesh.tie_crease == c)
        tangent[rows] = np.gradient(x[mesh.ties[rows, 1]], axis=0)
    q = x[mesh.elements]
    normal = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
    centre = q.mean(axis=1)
    node_normal = np.zeros_like(x)
    node_centre = np.zeros_like(x)
    for corner in range(4):
        np.add.at(node_normal, mesh.elements[:, corner], normal)
        np.add.at(node_centre, mesh.elements[:, corner], centre - q[:, corner])
    across, out_of_plane, along = resolve_hinge_forces(
        forces, lengths, tangent[keep], node_normal[slave], node_centre[slave]
    )
    line = np.linalg.norm(forces, axis=1) / np.maximum(lengths, ZERO_LENGTH)
    # where along its crease every hinge node sits (0 .. 1): the interior leaves out a tenth
    # of the crease at either foot, where the concentrated force depends on the element
    where = np.zeros(len(mesh.ties))
    for c in np.unique(mesh.tie_crease):
        rows = np.flatnonzero(mesh.tie_crease == c)
        s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(x[mesh.ties[rows, 1]], axis=0), axis=1))]
        where[rows] = s / max(s[-1], ZERO_LENGTH)
    interior = (where[keep] >= 0.1) & (where[keep] <= 0.9)

    def extremes(sel) -> HingeExtremes:
        inner = sel & interior
        return HingeExtremes(
            tension_max_N_per_m=float(max(across[sel].max(), 0.0)),
            compression_max_N_per_m=float(max(-across[sel].min(), 0.0)),
            out_of_plane_max_N_per_m=float(out_of_plane[sel].max()),
            along_crease_max_N_per_m=float(along[sel].max()),
            line_mean_N_per_m=float((line[sel] * lengths[sel]).sum() / lengths[sel].sum()),
            interior_max_N_per_m=float(line[inner].max()) if inner.any() else None,
        )

    rows = tuple(
        CreaseHingeForces(
            int(c), extremes(crease == c), np.round(forces[crease == c].sum(axis=0), 6).tolist()
        )
        for c in np.unique(crease)
    )
    return HingeLineForces(extremes(np.ones(len(ties), dtype=bool)), rows)


def _reactions(history: DeploymentHistory, step: int) -> dict:
    """The ground's resultant on the start and the end feet (N), and a tie's force."""
    h = history
    mesh, node, sup = h.mesh, h.problem.fixed, h.supports
    reac = h.result.reactions[step]
    n_mesh = len(mesh.nodes)
    side = np.full(len(node), -1)  # -1: not a foot (a controlled free edge)
    on_foot = np.isin(node, mesh.supports)
    side[on_foot] = sup.side[np.searchsorted(mesh.supports, node[on_foot])]
    ground = node >= n_mesh
    gi = node[ground] - n_mesh  # the ground node's spring
    side[ground] = sup.side[sup.ground[gi]]
    force = reac.copy()
    tie = np.zeros(3)
    if sup.tie:
        # the tie's ground force is the start feet's: the tie pulls them, not the ground
        k = sup.stiffness[gi]
        part = np.divide(sup.tie_stiffness[gi], k, out=np.zeros_like(k), where=k > 0.0)
        tie = (reac[ground] * part).sum(axis=0)
        force[ground] -= reac[ground] * part
    start = force[side == 0].sum(axis=0) + tie
    end = force[side == 1].sum(axis=0)
    up = h.model.axes[1]
    out = {"tie_N": round(float(np.abs(tie).max()), 3)}
    for name, r in (("start", start), ("end", end)):
        vertical = float(r @ up)
        out[f"{name}_N"] = np.round(r, 3).tolist()
        out[f"{name}_vertical_N"] = round(vertical, 3)
        out[f"{name}_horizontal_N"] = round(float(np.linalg.norm(r - vertical * up)), 3)
    return out


def _peak_stress(forces: np.ndarray, thickness: float) -> np.ndarray:
    """(E,) the largest absolute surface principal stress of every element, Pa."""
    stress = surface_stresses(forces, thickness=thickness)
    return np.maximum(
        np.abs(principal(stress.top)).max(axis=1),
        np.abs(principal(stress.bottom)).max(axis=1),
    )


def _stiffness(history: DeploymentHistory, case, factors, material, k0: int, uls: int):
    """The design stiffness of a case's buckling check (:class:`StiffnessBasis`).

    ψ2 of the creep (EN 1995-1-1 2.3.2.2(2)): 1 if the permanent action — the deployed
    state's active bending — causes the larger stress in relation to strength (its peak over
    the permanent design strength) than the case's loads (the peak of the stress they add at
    the ULS over the case's design strength), else the case's ψ2.
    """
    h = history
    t = h.settings.thickness
    f = h.result.forces
    permanent = case_factors(h, "permanent").strength_factor * material.strength
    prestress = float(_peak_stress(f[k0], t).max()) / permanent
    added = float(_peak_stress(f[uls] - f[k0], t).max()) / (
        factors.strength_factor * material.strength
    )
    if case.psi2 is None:  # permanent actions only
        return StiffnessBasis(material.kind, factors.gamma_M, factors.k_def, 1.0, "permanent")
    psi2 = creep_psi2(prestress, added, case.psi2)
    governing = "permanent" if prestress >= added else "variable"
    return StiffnessBasis(material.kind, factors.gamma_M, factors.k_def, psi2, governing)


def _final_deflection(history: DeploymentHistory, case, k_def, k0: int, sls: int) -> dict:
    """The final deflection of a case (EN 1995-1-1 2.2.3(5)): its permanent part u_G, the
    self-weight case's, with (1 + k_def), the rest with (1 + ψ2 k_def)."""
    h = history
    d = h.result.displacements
    u = d[sls] - d[k0]
    if k_def is None:
        return {"max_m": None, "vertical_max_m": None, "note": "no k_def: no creep"}
    weight = next((e for e in h.load_steps if e["case"].name == "self-weight"), None)
    note = ""
    if case.psi2 is None:  # permanent actions only
        u_G, u_Q, psi2 = u, np.zeros_like(u), 0.0
    elif weight is None:
        u_G, u_Q, psi2 = u, np.zeros_like(u), 0.0
        note = "no self-weight case: the whole deflection taken as permanent"
    else:
        u_G = d[weight["sls"]] - d[k0]
        u_Q, psi2 = u - u_G, case.psi2
    fin = final_deflection(u_G, u_Q, k_def, psi2)
    return {
        "max_m": float(np.linalg.norm(fin, axis=1).max()),
        "vertical_max_m": float(np.abs(fin @ h.model.axes[1]).max()),
        "psi2": psi2,
        "note": note,
    }


def _case(history: DeploymentHistory, entry: dict, k0: int, span: float) -> dict:
    h = history
    s, r = h.settings, h.result
    case, sls, uls = entry["case"], entry["sls"], entry["uls"]
    deflection = np.linalg.norm(r.displacements[sls] - r.displacements[k0], axis=1)
    limit = s.deflection_limit * span
    m = s.material if s.orthotropic else s.material.isotropic_equivalent()
    peak = _peak_stress(r.forces[uls], s.thickness)
    factors = case_factors(h, case.duration)
    strength = m.strength * factors.strength_factor
    worst = int(np.argmax(peak))
    utilisation = float(peak[worst] / strength)
    buckling, note = r.buckling.get(uls + 1, (None, ""))
    stiffness = _stiffness(h, case, factors, m, k0, uls)
    final = _final_deflection(h, case, factors.k_def, k0, sls)
    creep = stiffness.k_def if stiffness.k_def is not None else 0.0
    buckling_design = design_buckling_factor(buckling, stiffness.gamma_M, creep, stiffness.psi2)
    up = h.model.axes[1]
    return {
        **case.to_dict(),
        "deflection_max_m": float(deflection.max()),
        "deflection_vertical_max_m": float(
            np.abs((r.displacements[sls] - r.displacements[k0]) @ up).max()
        ),
        "deflection_limit_m": limit,
        "deflection_ratio": float(deflection.max() / limit),
        "deflection_ok": bool(deflection.max() <= limit),
        "deflection_final_max_m": final["max_m"],
        "deflection_final_vertical_max_m": final["vertical_max_m"],
        "deflection_final_ratio": None if final["max_m"] is None else final["max_m"] / limit,
        "deflection_final_note": final["note"],
        "utilisation_max": utilisation,
        "utilisation_max_characteristic": float(peak[worst] / m.strength),
        "utilisation_plate": int(h.model.plate_ids[h.mesh.element_plate[worst]]),
        "stress_max_MPa": float(peak[worst] / 1e6),
        "strength_MPa": strength / 1e6,
        "strength_characteristic_MPa": m.strength / 1e6,
        "basis": factors.to_dict(),
        "stiffness": stiffness.to_dict(),
        "utilisation_ok": bool(utilisation <= 1.0),
        "buckling_factor": buckling_design,
        "buckling_ok": None if buckling_design is None else bool(buckling_design >= 1.0),
        "buckling_factor_instantaneous": design_buckling_factor(buckling, stiffness.gamma_M),
        "buckling_factor_mean": buckling,
        "buckling_note": note,
        "reactions_sls": _reactions(h, sls),
        "reactions_uls": _reactions(h, uls),
        "hinges_uls": hinge_line_forces(h, uls).to_dict(),
        "steps": {"sls": sls + 1, "uls": uls + 1},
    }


def structural_checks(history: DeploymentHistory) -> StructuralChecks | None:
    """Every load case's checks and the governing values (:class:`StructuralChecks`; its
    ``to_dict()`` is JSON-ready).

    None if the history has no load-case steps (``checks=False``, or the actuation strategy).
    """
    h = history
    s = h.settings
    if not h.load_steps or h.result.steps < h.load_steps[-1]["uls"] + 1:
        return None
    k0 = h.deployment_steps - 1
    span = float(h.spans[k0])
    cases = [_case(h, entry, k0, span) for entry in h.load_steps]

    def worst(key, pick=max):
        values = [c[key] for c in cases if c[key] is not None]
        if not values:
            return None, None
        v = pick(values)
        return v, next(c["name"] for c in cases if c[key] == v)

    defl, defl_case = worst("deflection_ratio")
    util, util_case = worst("utilisation_max")
    buck, buck_case = worst("buckling_factor", min)
    governing = next(c for c in cases if c["name"] == util_case)
    # the largest total reaction of the characteristic loads (the heaviest case), N
    totals = [np.add(c["reactions_sls"]["start_N"], c["reactions_sls"]["end_N"]) for c in cases]
    heaviest = np.round(max(totals, key=lambda r: abs(r @ h.model.axes[1])), 3).tolist()
    m = s.material
    area = next((c for c in cases if c["name"] == "area-load"), None)
    return StructuralChecks(
        load={
            "self_weight_N_per_m2": m.density * GRAVITY * s.thickness,
            "area_load_N_per_m2": s.area_load if area is not None else 0.0,
        },
        supports=h.supports.to_dict() if h.supports is not None else {"type": "pinned"},
        cases=cases,
        governing={"deflection": defl_case, "utilisation": util_case, "buckling": buck_case},
        deflection_max_m=max(c["deflection_max_m"] for c in cases),
        deflection_limit_m=cases[0]["deflection_limit_m"],
        deflection_ratio=defl,
        deflection_ok=all(c["deflection_ok"] for c in cases),
        utilisation_max=util,
        utilisation_max_characteristic=max(c["utilisation_max_characteristic"] for c in cases),
        utilisation_plate=governing["utilisation_plate"],
        strength_MPa=governing["strength_MPa"],
        strength_characteristic_MPa=governing["strength_characteristic_MPa"],
        basis=governing["basis"],
        utilisation_ok=all(c["utilisation_ok"] for c in cases),
        reaction_total_N=heaviest,
        buckling_factor=buck,
        buckling_ok=None if buck is None else bool(buck >= 1.0),
        buckling_factor_mean=next(
            (c["buckling_factor_mean"] for c in cases if c["name"] == buck_case), None
        ),
        stiffness=next((c["stiffness"] for c in cases if c["name"] == buck_case), None)
        or governing["stiffness"],
        deflection_final_max_m=max(
            (c["deflection_final_max_m"] for c in cases if c["deflection_final_max_m"] is not None),
            default=None,
        ),
        buckling_note=next((c["buckling_note"] for c in cases if c["buckling_note"]), ""),
        hinge_tension_max_N_per_m=max(
            c["hinges_uls"].get("tension_max_N_per_m", 0.0) for c in cases
        ),
        hinge_mean_N_per_m=governing["hinges_uls"].get("line_mean_N_per_m"),
        hinge_shear_max_N_per_m=max(
            c["hinges_uls"].get("out_of_plane_max_N_per_m", 0.0) for c in cases
        ),
    )
