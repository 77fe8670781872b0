"""Feasibility of a study's designs: violations, and the values told to the sampler.

:func:`assess` judges one evaluated row against a study's constraints and objectives: the
relative violation of every constraint (:func:`compas_ccu.explore.pareto.violations`, told to
Optuna as constraint values, <= 0 feasible), the text of what a design misses, and the objective
values. A design that cannot be built or measured is infeasible by :data:`FAILED_VIOLATION`; a
constraint or an objective that was not measured (not because a cheap check stopped the FE) by
:data:`UNMEASURED_VIOLATION`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.explore.metrics import metric_group
from compas_ccu.explore.pareto import violations

__all__ = ["Assessment", "assess", "feasible_rows", "FAILED_VIOLATION", "UNMEASURED_VIOLATION"]
__all__ += ["STUDY_COLUMNS"]

#: Violation of a design that could not be built or measured (its row's error says why).
FAILED_VIOLATION = 1000.0
#: Violation of a constraint or objective that the evaluation did not measure.
UNMEASURED_VIOLATION = 1.0
#: The columns a study adds to those of a sweep, with their types.
STUDY_COLUMNS = {
    "feasible": "bool",
    "violation": "float",
    "violations": "str",
    "fe_gated": "bool",
    "reused": "bool",
}


@dataclass(frozen=True)
class Assessment:
    """How a trial's row stands against the study's constraints and objectives.

    Attributes
    ----------
    feasible : bool
        Evaluated, every constraint measured and met, every objective measured.
    violation : float
        Sum of the positive violations (0 for a feasible design): the order of the
        least-violating designs.
    details : tuple of str
        One text per missed constraint (``"bending_utilisation 1.12 > max 1"``), missing
        measurement or error.
    constraints : dict
        Name -> value told to the sampler (<= 0 met); the same keys for every trial.
    gated : bool
        A cheap constraint failed, so the FE stage did not run.
    values : tuple of float
        The objective values told to the sampler (+-inf where not measured).
    """

    feasible: bool
    violation: float
    details: tuple
    constraints: dict
    gated: bool
    values: tuple


def _missed(name: str, value, rule) -> str:
    """``"bending_utilisation 1.12 > max 1"``: 4 significant digits, more when they would
    show the value equal to its bound (1.00004 > max 1)."""
    if isinstance(rule, bool):
        return f"{name} is {value} (required {rule})"
    side, bound = (">", rule["max"]) if "max" in rule and value > rule["max"] else ("<", None)
    if bound is None:
        bound = rule["min"]
    digits = next((d for d in (4, 6, 9) if f"{value:.{d}g}" != f"{bound:.{d}g}"), 12)
    kind = "max" if side == ">" else "min"
    return f"{name} {value:.{digits}g} {side} {kind} {bound:.4g}"


def _measured(value) -> bool:
    return value is not None and not (isinstance(value, float) and not math.isfinite(value))


def assess(row: dict, study) -> Assessment:
    """Feasibility, violations and the sampler's values of one evaluated trial.

    Examples
    --------
    >>> from compas_ccu.explore.study import Study
    >>> study = Study({"study": {"base": "vault.toml"},
    ...                "parameters": {"crease.rise": {"min": 0.6, "max": 1.4}},
    ...                "objectives": {"mass": "min"}}, base_dir="examples")
    >>> a = assess({"status": "ok", "mass": 30.0, "bending_utilisation": 1.25}, study)
    >>> a.feasible, a.violation, a.details, a.values
    (False, 0.25, ('bending_utilisation 1.25 > max 1',), (30.0,))
    >>> assess({"status": "ok", "mass": 30.0, "bending_utilisation": 1.00004}, study).details
    ('bending_utilisation 1.00004 > max 1',)
    """
    senses = list(study.objectives.values())
    names = list(study.constraints)
    if row.get("status") != "ok":
        stage = row.get("stage")
        text = f"failed at stage {stage}: {row.get('error_type')}: {row.get('error')}"
        constraints = dict.fromkeys(names, 0.0)
        constraints.update(dict.fromkeys((f"objective {k}" for k in study.objectives), 0.0))
        constraints["evaluation"] = FAILED_VIOLATION
        worst = tuple(math.inf if s == "min" else -math.inf for s in senses)
        return Assessment(False, FAILED_VIOLATION, (text,), constraints, False, worst)

    gated = study.fe is not None and row.get("t_fe") is None
    details, constraints = [], {}
    for name, v in violations(row, study.constraints).items():
        if v is None and gated and metric_group(name) == "fe":
            constraints[name] = 0.0  # not measured because a cheap check failed: counted there
        elif v is None:
            constraints[name] = UNMEASURED_VIOLATION
            details.append(f"{name} not measured")
        else:
            constraints[name] = v
            if v > 0:
                details.append(_missed(name, row[name], study.constraints[name]))
    values = []
    for name, sense in study.objectives.items():
        value = row.get(name)
        if _measured(value):
            values.append(float(value))
            continue
        values.append(math.inf if sense == "min" else -math.inf)
        if not gated:
            constraints[f"objective {name}"] = UNMEASURED_VIOLATION
            details.append(f"objective {name} not measured")
    if gated:
        details.append("no FE: a cheap check failed")
    constraints["evaluation"] = 0.0
    for name in study.objectives:  # the same keys for every trial
        constraints.setdefault(f"objective {name}", 0.0)
    total = float(sum(v for v in constraints.values() if v > 0))
    ok = total == 0.0 and not gated
    return Assessment(ok, total, tuple(details), constraints, gated, tuple(values))


def feasible_rows(rows: list, study) -> np.ndarray:
    """(n,) bool: the study's feasibility (:func:`assess`) of results rows, e.g. of a sweep's
    table on the same problem."""
    return np.array([assess(r, study).feasible for r in rows], dtype=bool)
