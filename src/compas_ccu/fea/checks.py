"""Structural checks of the deployed state (the formwork use case).

A displacement-controlled history with ``checks`` has two steps after the deployment, with the
supports held, that add self-weight and the distributed ``area_load``
(:mod:`compas_ccu.fea.displacement`). Checked at the last of them: the largest deflection from
the deployed state against ``deflection_limit`` × span, the bending utilisation (largest surface
principal stress, prestress from the active bending included, over the material's design strength
``k_mod f_k / γ_M`` of ``settings.design_code``, the same as the bending check's),
the total reaction and the engine's linear buckling factor of the loaded state.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.settings import GRAVITY
from compas_ccu.fea.stresses import principal, surface_stresses

__all__ = ["structural_checks"]


def structural_checks(history: DeploymentHistory) -> dict | None:
    """Deflection under self-weight + area load and bending utilisation, JSON-ready.

    None if the history has no check steps (``checks=False``, or the actuation strategy).
    """
    h = history
    s, r = h.settings, h.result
    if not s.checks or r.steps <= h.deployment_steps:
        return None
    k0 = h.deployment_steps - 1
    deflection = np.linalg.norm(r.displacements[-1] - r.displacements[k0], axis=1)
    span = float(h.spans[k0])
    m = s.material if s.orthotropic else s.material.isotropic_equivalent()
    stress = surface_stresses(r.forces[-1], thickness=s.thickness)
    peak = np.maximum(
        np.abs(principal(stress["top"])).max(axis=1),
        np.abs(principal(stress["bottom"])).max(axis=1),
    )
    factors = s.design_code
    strength = m.strength * factors.strength_factor
    utilisation = peak / strength
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
        "utilisation_max_characteristic": float((peak / m.strength).max()),
        "utilisation_plate": int(h.model.plate_ids[h.mesh.element_plate[worst]]),
        "strength_MPa": strength / 1e6,
        "strength_characteristic_MPa": m.strength / 1e6,
        "basis": factors.to_dict(),
        "utilisation_ok": bool(utilisation[worst] <= 1.0),
        "reaction_total_N": np.round(r.reactions[-1].sum(axis=0), 3).tolist(),
        "buckling_factor": r.buckling_factor,
        "buckling_note": r.buckling_note,
    }
