"""One placed state as a :class:`~compas_ccu.structure.Structure`: the crease records and the
metrics of the ``ccu.structure`` contract (docs/structure-json.md)."""

from __future__ import annotations

import numpy as np

from compas_ccu.kinematics.invariants import INVARIANT_KEYS
from compas_ccu.strips.rulings import vertex_reflection_angles
from compas_ccu.structure import Structure
from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = ["state_structure"]


def state_structure(
    model, states, k: int, alpha: float, invariants: dict | None = None
) -> Structure:
    """The :class:`Structure` of state ``k`` of placed mechanism ``states``.

    Parameters
    ----------
    states : compas_ccu.kinematics.mechanism.MechanismStates
    k : int
    alpha : float
        The state's reference reflection angle, degrees.
    invariants : dict, optional
        :meth:`invariants` of ``states`` (computed if not given).
    """
    if invariants is None:
        invariants = model.invariants(states)
    n = model.segments
    kinds = model.crease_kinds()
    creases = []
    for ci in range(len(model.mechanism.creases)):
        rows_a, rows_b = model.plates.crease_rows(ci)
        rel = model.relations(states, k, ci)
        kind, vertex_kinds, _ = kinds[ci]
        origin = model.frame.to_world(states.plane_origins[k, ci])
        normal = model.frame.vector_to_world(states.plane_normals[k, ci])
        record = {
            "id": ci,
            "plates": list(model.plates.crease_ids(ci)),
            "vertices": [rows_a.tolist(), rows_b.tolist()],
            "kind": kind,
            "plane": {"origin": origin.tolist(), "normal": normal.tolist()},
            "planarity": float(invariants["crease_planarity"][k, ci]),
            "alpha": np.degrees(rel.alpha).tolist(),
            "sum_beta": np.degrees(rel.sum_beta[1:-1]).tolist(),
        }
        if kind == "mixed":
            record["vertex_kinds"] = vertex_kinds
        creases.append(record)
    deployed = model.state_vertices(states, k)
    lead_near, lead_far = states.near[k, 0], states.far[k, 0]
    chord = lead_near[-1, :2] - lead_near[0, :2]
    span = float(np.linalg.norm(chord))
    normal2d = np.array([-chord[1], chord[0]]) / max(span, DIVISION_FLOOR)
    rise = float(np.abs((lead_near[:, :2] - lead_near[0, :2]) @ normal2d).max())
    rulings = lead_far - lead_near
    metrics = {
        "alpha_limit": model.alpha_limit,
        "reference_vertex": model.reference,
        "segments": n,
        "span": span,
        "rise": rise,
        "bounding_box": np.ptp(deployed.reshape(-1, 3), axis=0).tolist(),
        "size": model.size,
        "alpha_leading": np.degrees(
            vertex_reflection_angles(
                lead_near[:, :2], rulings / np.linalg.norm(rulings, axis=1)[:, None]
            )
        ).tolist(),
    }
    for key in INVARIANT_KEYS:
        metrics[key] = float(invariants[key][k])
        metrics[key + "_relative"] = float(invariants[key][k]) / model.size
    cp = invariants["crease_planarity"][k]
    metrics["crease_planarity_max"] = float(cp.max()) if cp.size else 0.0
    metrics["crease_planarity_max_relative"] = metrics["crease_planarity_max"] / model.size
    return Structure(
        alpha,
        model.faces,
        model.flat(),
        deployed,
        creases,
        metrics,
        model.plate_ids,
        name=model.design.name,
    )
