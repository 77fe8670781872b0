"""The summary of thick plates: every number ``ccu info`` and the report show, as plain data.

:meth:`compas_ccu.thickness.ThickModel.summary`: the stack, the axis-shift corrections, the
bending check (:mod:`compas_ccu.thickness.bending`), the collision check
(:mod:`compas_ccu.thickness.collision_check`) and the deployment effort
(:mod:`compas_ccu.thickness.actuation`) along the path, strict JSON.
:mod:`compas_ccu.key_figures.thickness_text` words it.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.errors import OptionError

__all__ = ["thick_summary"]


def thick_summary(thick, path_states: int = 41) -> dict:
    """:meth:`ThickModel.summary` of ``thick`` over ``path_states`` states to the design."""
    if isinstance(path_states, bool) or int(path_states) != path_states or path_states < 2:
        raise OptionError(
            "path_states must be an integer >= 2 (the flat stack and the design state at "
            f"least), got {path_states!r}"
        )
    alphas = np.linspace(0.0, thick.model.alpha_design, path_states)
    st = thick.place(alphas)
    metrics = thick.metrics(st)
    bend = thick.bending(alphas)
    per_plate = bend.per_plate.max(axis=0)
    k, plate, vertex = bend.worst()
    collisions = thick.collisions(alphas)
    clear, first = thick.first_collision()
    push = thick.actuation(alphas)
    design = -1
    return {
        "thickness": thick.thickness,
        "material": thick.material.name,
        "grain": thick.grain,
        "stack_height": thick.stack_height,
        "stack_order": thick.stack_order,
        "pairing": thick.pairing(),
        "offset_planarity_design": metrics.offset_planarity[design].tolist(),
        "correction_design": metrics.correction[design].tolist(),
        "correction_max_path": float(metrics.correction.max()),
        "hinge_gap_max_path": float(metrics.hinge_gap.max()),
        "isometry_max_path": float(metrics.isometry.max()),
        "bending": {
            "basis": thick.factors.to_dict(),
            "curvature_limit_min": float(bend.limit.min()),
            "curvature_limit_characteristic_min": float(bend.limit_characteristic.min()),
            "max_curvature": float(np.abs(bend.curvature).max()),
            "max_utilisation": bend.max,
            "max_utilisation_characteristic": bend.max_characteristic,
            "final_modulus": _final_modulus(thick),
            "utilisation_per_plate": per_plate.tolist(),
            "worst": {
                "alpha": float(alphas[k]),
                "plate": thick.model.plate_ids[plate],
                "vertex": vertex,
                # the ruling of the peak, and whether it runs from a kink of the crease
                "ruling": vertex % (thick.model.segments + 1),
                "at_kink": vertex % (thick.model.segments + 1) in thick.model.geometry.kinks,
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


def _final_modulus(thick):
    """``E1 / (1 + k_def)``, ``E2 / (1 + k_def)`` (Pa): the final-state stiffness under the
    permanent active bending (EN 1995-1-1 2.3.2.2); None if k_def is unknown."""
    k_def = thick.factors.k_def
    if k_def is None:
        return None
    return [thick.material.E1 / (1.0 + k_def), thick.material.E2 / (1.0 + k_def)]


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
