"""What a sweep measures on every variant: the catalogue of metrics and how each is computed.

:data:`METRICS` is the single source of truth for the results table's metric columns (name,
type, unit, meaning); ``docs/explore.md`` lists it. The shape, path and thickness columns are key
figures of the design (:mod:`compas_ccu.key_figures`): :data:`KEY_FIGURE_COLUMNS` names the
figure behind each column (the columns keep the names sweep files and results tables have
always used: ``span`` is the key figure ``crease_span``) and their type, unit and meaning come
from the key-figure table. The collision and FE columns are the sweep's own. The functions take
a built model and return plain ``{column: value}`` dicts of Python scalars.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu import key_figures as kf
from compas_ccu.fea.validation import validate

__all__ = [
    "Metric",
    "METRICS",
    "KEY_FIGURE_COLUMNS",
    "metric_names",
    "metric",
    "metric_group",
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
    figure: str | None = None  # the key figure behind the column, if it is one


#: Results columns that are key figures, by group: column -> key figure.
KEY_FIGURE_COLUMNS = {
    "shape": {
        "plates": "plates",
        "creases": "creases",
        "alpha_design": "alpha_design",
        "alpha_max": "alpha_max",
        "alpha_limit": "alpha_limit",
        "overlap_alpha": "overlap_alpha",
        "collision_free_alpha": "collision_free_alpha",
        "limit_margin": "limit_margin",
        "span": "crease_span",
        "rise": "crease_rise",
        "rise_to_span": "crease_rise_to_span",
        "plan_x": "plan_x",
        "plan_y": "plan_y",
        "height": "height",
        "plan_area": "plan_area",
        "plate_area": "plate_area",
        "stack_length": "stack_length",
        "stack_width": "stack_width",
        "plate_length": "plate_length",
        "plate_width": "plate_width",
        "global_curvature": "global_curvature",
        "invariant_error": "invariant_max_relative",
    },
    "path": {
        "crease_planarity": "crease_planarity_path",
        "crease_planarity_relative": "crease_planarity_path_relative",
    },
    "thickness": {
        name: name
        for name in (
            "thickness",
            "material",
            "stack_height",
            "mass",
            "deployment_energy",
            "actuation_force",
            "bending_utilisation",
            "bending_utilisation_characteristic",
            "bending_basis",
            "k_mod",
            "gamma_M",
            "bending_curvature",
        )
    },
}


def _key_figure_metrics(group: str) -> tuple:
    out = []
    for column, name in KEY_FIGURE_COLUMNS[group].items():
        f = kf.figure(name)
        doc = f.doc if column == name else f"{f.doc} (key figure `{name}`)"
        out.append(Metric(column, f.dtype, f.unit, doc, group, name))
    return tuple(out)


def _m(group, rows):
    return tuple(Metric(name, dtype, unit, doc, group) for name, dtype, unit, doc in rows)


METRICS = (
    *_key_figure_metrics("shape"),
    *_key_figure_metrics("path"),
    *_key_figure_metrics("thickness"),
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
                "Structural check: largest ULS stress / design strength over the load cases "
                "(the design's [loads], or self-weight + area load; fe.checks).",
            ),
            (
                "fe_deflection_ratio",
                "float",
                "",
                "Structural check: largest deflection / allowed over the load cases.",
            ),
            (
                "fe_buckling_factor",
                "float",
                "",
                "Smallest design linear buckling factor over the load cases, with "
                "E_mean / (gamma_M (1 + psi2 k_def)) (docs/structural.md; Kratos only).",
            ),
            (
                "fe_hinge_tension",
                "float",
                "N/m",
                "Largest hinge line force across a crease (tension) under the load cases.",
            ),
            (
                "fe_hinge_shear",
                "float",
                "N/m",
                "Largest out-of-plane hinge shear under the load cases.",
            ),
            (
                "fe_hinge_mean",
                "float",
                "N/m",
                "Mean hinge line force of the governing case (away from the feet).",
            ),
            (
                "fe_actuation_force",
                "float",
                "N",
                "Largest force between the feet during the FE deployment, dW/d span.",
            ),
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


def metric_group(name: str) -> str | None:
    """The group of a metric (``"shape"``, ..., ``"collisions"``, ``"fe"``); None: unknown.

    >>> metric_group("fe_buckling_factor"), metric_group("mass"), metric_group("beauty")
    ('fe', 'thickness', None)
    """
    m = _BY_NAME.get(name)
    return None if m is None else m.group


def _columns(group: str, figures: dict) -> dict:
    return {column: figures[name] for column, name in KEY_FIGURE_COLUMNS[group].items()}


def shape_metrics(model, structure) -> dict:
    """Shape, kinematic limits and flat stack of a model deployed to its design.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    structure : compas_ccu.structure.Structure
        ``model.deploy()``.
    """
    return _columns("shape", kf.design_state_figures(model, structure))


def path_metrics(model, alphas: np.ndarray) -> dict:
    """Crease planarity over the path states ``alphas`` (degrees)."""
    return _columns("path", kf.path_figures(model, np.asarray(alphas, dtype=float)))


def thickness_metrics(thick, alphas: np.ndarray) -> dict:
    """Stack, mass and bending check of a :class:`compas_ccu.thickness.ThickModel`."""
    return _columns("thickness", kf.thickness_figures(thick, alphas))


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
        "fe_hinge_tension": number(checks.get("hinge_tension_max_N_per_m")),
        "fe_hinge_shear": number(checks.get("hinge_shear_max_N_per_m")),
        "fe_hinge_mean": number(checks.get("hinge_mean_N_per_m")),
        "fe_actuation_force": max(
            (abs(f) for f in s["load_path"]["foot_force_N"] if f is not None), default=None
        ),
        "fe_elements": int(s["mesh"]["elements"]),
    }


def metrics_markdown() -> str:
    """The metric table of ``docs/explore.md``."""
    lines = ["| metric | type | unit | group | meaning |", "|---|---|---|---|---|"]
    for m in METRICS:
        lines.append(f"| `{m.name}` | {m.dtype} | {m.unit} | {m.group} | {m.doc} |")
    return "\n".join(lines)
