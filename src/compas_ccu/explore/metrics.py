"""What a sweep measures on every variant: the catalogue of metrics and how each is computed.

:data:`METRICS` is the single source of truth for the results table's metric columns (name,
type, unit, meaning); ``docs/explore.md`` lists it. The functions take a built model and return
plain ``{name: value}`` dicts of Python scalars.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "Metric",
    "METRICS",
    "metric_names",
    "shape_metrics",
    "path_metrics",
    "thickness_metrics",
    "collision_metrics",
    "fe_metrics",
    "metrics_markdown",
]


@dataclass(frozen=True)
class Metric:
    """One column of the results table."""

    name: str
    dtype: str  # "float", "int", "bool", "str"
    unit: str
    doc: str
    group: str  # "shape", "path", "thickness", "collisions", "fe"


def _m(group, rows):
    return tuple(Metric(name, dtype, unit, doc, group) for name, dtype, unit, doc in rows)


METRICS = (
    *_m(
        "shape",
        [
            ("plates", "int", "", "Number of plates."),
            ("creases", "int", "", "Number of creases."),
            ("alpha_design", "float", "deg", "Design reflection angle at the reference vertex."),
            ("alpha_max", "float", "deg", "Largest reflection angle on any crease at the design."),
            (
                "alpha_limit",
                "float",
                "deg",
                "Deployment limit (a crease segment stands perpendicular to its plane).",
            ),
            ("overlap_alpha", "float", "deg", "Largest alpha before a crease overlaps itself."),
            (
                "limit_margin",
                "float",
                "deg",
                "min(alpha_limit, overlap_alpha) - alpha_design: "
                "how much further the structure could open.",
            ),
            ("span", "float", "m", "Chord of the leading crease at the design."),
            ("rise", "float", "m", "Height of the leading crease above its chord."),
            ("rise_to_span", "float", "", "rise / span."),
            ("plan_x", "float", "m", "Extent of the deployed structure along world x."),
            ("plan_y", "float", "m", "Extent along world y."),
            ("height", "float", "m", "Extent along world z."),
            ("plan_area", "float", "m2", "plan_x * plan_y."),
            ("plate_area", "float", "m2", "Area of all cut patterns (one face)."),
            ("stack_length", "float", "m", "Flat-folded stack: bounding box in the plane, long."),
            ("stack_width", "float", "m", "Flat-folded stack: bounding box in the plane, short."),
            (
                "global_curvature",
                "str",
                "",
                "Measured global shape: synclastic, anticlastic or "
                "monoclastic (4 or more plates in a plane layout; else empty).",
            ),
            (
                "invariant_error",
                "float",
                "",
                "Largest relative invariant error at the design "
                "(isometry, quad planarity, hinges, mirror symmetry), ~1e-15.",
            ),
        ],
    ),
    *_m(
        "path",
        [
            (
                "crease_planarity",
                "float",
                "m",
                "Largest distance of a crease from its plane "
                "over the path from the flat stack to the design (0 for exact designs).",
            ),
            ("crease_planarity_relative", "float", "", "crease_planarity / structure size."),
        ],
    ),
    *_m(
        "thickness",
        [
            ("thickness", "float", "m", "Plate thickness ([plates])."),
            ("material", "str", "", "Plate material ([plates])."),
            ("stack_height", "float", "m", "Height of the flat-folded stack (sum of thicknesses)."),
            ("mass", "float", "kg", "plate_area * thickness * density."),
            (
                "bending_utilisation",
                "float",
                "",
                "Largest |curvature| / (f / (E t / 2)) over "
                "all plates and path states (> 1: the plates break).",
            ),
            ("bending_curvature", "float", "1/m", "Largest plate curvature over the path."),
        ],
    ),
    *_m(
        "collisions",
        [
            (
                "collision_free",
                "bool",
                "",
                "No interpenetration of the thick plates along "
                "the path ([checks] collisions = true).",
            ),
            ("min_clearance", "float", "m", "Smallest gap between plates that share no crease."),
            ("max_penetration", "float", "m", "Largest penetration depth (0 when free)."),
            (
                "collision_alpha",
                "float",
                "deg",
                "First alpha that interpenetrates (empty when free).",
            ),
        ],
    ),
    *_m(
        "fe",
        [
            (
                "fe_deviation_percent",
                "float",
                "%",
                "FE deviation from the kinematic model at "
                "the design, largest node, % of the span ([fe]).",
            ),
            ("fe_deviation_path_percent", "float", "%", "Largest FE deviation along the path."),
            ("fe_bending_MPa", "float", "MPa", "Largest bending stress at the design."),
            ("fe_membrane_MPa", "float", "MPa", "Largest membrane stress at the design."),
            (
                "fe_utilisation",
                "float",
                "",
                "Structural check: largest stress / strength "
                "under self-weight + area load (fe.checks).",
            ),
            ("fe_deflection_ratio", "float", "", "Structural check: deflection / allowed."),
            ("fe_buckling_factor", "float", "", "Linear buckling factor (Kratos only)."),
            ("fe_elements", "int", "", "Shell elements of the FE mesh."),
        ],
    ),
)

_BY_NAME = {m.name: m for m in METRICS}


def metric_names(*, collisions: bool = False, fe: bool = False) -> list:
    """Names of the metrics a sweep computes with these options."""
    skip = {"collisions"} if not collisions else set()
    if not fe:
        skip.add("fe")
    return [m.name for m in METRICS if m.group not in skip]


def metric(name: str) -> Metric:
    return _BY_NAME[name]


def _plate_area(flat: np.ndarray, segments: int) -> float:
    """Total area (m2) of the (p, 2n + 2, 3) cut patterns (planar quads: half the cross
    product of the diagonals)."""
    near, far = flat[:, : segments + 1], flat[:, segments + 1 :]
    d1 = far[:, 1:] - near[:, :-1]
    d2 = far[:, :-1] - near[:, 1:]
    return float(0.5 * np.linalg.norm(np.cross(d1, d2), axis=-1).sum())


def shape_metrics(model, structure) -> dict:
    """Shape, kinematic limits and flat stack of a model deployed to its design.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    structure : compas_ccu.structure.Structure
        ``model.deploy()``.
    """
    from compas_ccu.io import flat_footprint

    m = structure.metrics
    alphas = [a for c in structure.creases for a in c["alpha"]] + list(m["alpha_leading"])
    bbox = m["bounding_box"]
    stack = sorted(flat_footprint(structure), reverse=True)
    overlap = model.overlap_alpha
    out = {
        "plates": len(structure.plate_ids),
        "creases": len(structure.creases),
        "alpha_design": float(model.alpha_design),
        "alpha_max": float(max(alphas)),
        "alpha_limit": float(model.alpha_limit),
        "overlap_alpha": float(overlap),
        "limit_margin": float(min(model.alpha_limit, overlap) - model.alpha_design),
        "span": m["span"],
        "rise": m["rise"],
        "rise_to_span": m["rise"] / m["span"],
        "plan_x": bbox[0],
        "plan_y": bbox[1],
        "height": bbox[2],
        "plan_area": bbox[0] * bbox[1],
        "plate_area": _plate_area(model.flat(), model.segments),
        "stack_length": stack[0],
        "stack_width": stack[1],
        "global_curvature": None,
        "invariant_error": structure.max_invariant_error,
    }
    planes = model.planes
    if planes is not None and planes.plates >= 4:
        from compas_ccu.analysis import global_curvature

        states = model.mechanism.deploy(np.radians([model.alpha_design]))
        out["global_curvature"] = global_curvature(model.plane_curves(states)[0]).kind
    return out


def path_metrics(model, alphas: np.ndarray) -> dict:
    """Crease planarity over the path states ``alphas`` (degrees)."""
    worst = float(model.crease_planarity(alphas).max()) if model.mechanism.creases else 0.0
    return {"crease_planarity": worst, "crease_planarity_relative": worst / model.size}


def thickness_metrics(thick, alphas: np.ndarray, plate_area: float) -> dict:
    """Stack, mass and bending check of a :class:`compas_ccu.thickness.ThickModel`."""
    bend = thick.bending(alphas)
    return {
        "thickness": thick.thickness,
        "material": thick.material.name,
        "stack_height": float(thick.stack_height),
        "mass": plate_area * thick.thickness * thick.material.density,
        "bending_utilisation": float(bend.max),
        "bending_curvature": float(np.abs(bend.curvature).max()),
    }


def collision_metrics(thick, alphas: np.ndarray) -> dict:
    """Collision check of the thick plates over the path states ``alphas`` (degrees)."""
    report = thick.collisions(alphas)
    return {
        "collision_free": bool(report.ok),
        "min_clearance": float(report.clearance.min()),
        "max_penetration": float(report.penetration.max()),
        "collision_alpha": None if report.ok else float(report.first["alpha"]),
    }


def fe_metrics(model, thick, options: dict) -> dict:
    """FE validation (:func:`compas_ccu.fea.validation.validate`) with the design's plates.

    Raises
    ------
    compas_ccu.fea.ConvergenceError
        The FE deployment did not converge (the sweep records it as the variant's error).
    """
    from compas_ccu.fea.validation import validate

    v = validate(model, thickness=thick.thickness, material=thick.material, **options)
    s = v.summary()
    checks = s["checks"] or {}
    buckling = checks.get("buckling_factor")

    def number(value):
        return None if value is None else float(value)

    return {
        "fe_deviation_percent": s["deviation"]["max_percent"],
        "fe_deviation_path_percent": s["deviation"]["max_percent_along_path"],
        "fe_bending_MPa": s["stresses"]["max_bending_MPa"],
        "fe_membrane_MPa": s["stresses"]["max_membrane_MPa"],
        "fe_utilisation": number(checks.get("utilisation_max")),
        "fe_deflection_ratio": number(checks.get("deflection_ratio")),
        "fe_buckling_factor": number(buckling),
        "fe_elements": int(s["mesh"]["elements"]),
    }


def metrics_markdown() -> str:
    """The metric table of ``docs/explore.md``."""
    lines = ["| metric | type | unit | group | meaning |", "|---|---|---|---|---|"]
    for m in METRICS:
        lines.append(f"| `{m.name}` | {m.dtype} | {m.unit} | {m.group} | {m.doc} |")
    return "\n".join(lines)
