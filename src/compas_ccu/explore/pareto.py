"""Feasibility, Pareto front and the best variants of a sweep."""

from __future__ import annotations

import numpy as np

from compas_ccu.tolerances import OBJECTIVE_RELATIVE

__all__ = ["pareto_mask", "feasible", "violations", "meets", "objective_matrix", "rank_best"]


def pareto_mask(values: np.ndarray, senses, *, chunk: int = 512) -> np.ndarray:
    """Which rows are Pareto-optimal (no other row is as good in every objective and better
    in one).

    Values are compared with a relative tolerance (:data:`compas_ccu.tolerances.
    OBJECTIVE_RELATIVE` of each objective's largest magnitude): a row better only by round-off
    in one objective is dominated by a row better by more in another, and rows equal within the
    tolerance do not dominate each other.

    Parameters
    ----------
    values : (n, m) float
        Objective values; rows with a NaN are never optimal.
    senses : sequence of {"min", "max"}, length m
    chunk : int
        Rows compared at once (memory ``chunk * n * m`` booleans).

    Returns
    -------
    (n,) bool

    Examples
    --------
    >>> v = np.array([[1.0, 5.0], [2.0, 2.0], [3.0, 3.0], [4.0, 1.0]])
    >>> pareto_mask(v, ["min", "min"]).tolist()
    [True, True, False, True]
    >>> pareto_mask(v, ["max", "max"]).tolist()
    [True, False, True, True]
    >>> pareto_mask([[1.0, 1.0], [1.0 - 3e-16, 5.0]], ["min", "min"]).tolist()
    [True, False]
    """
    v = np.asarray(values, dtype=float)
    if v.ndim != 2 or v.shape[1] != len(senses):
        raise ValueError(f"values must be (n, {len(senses)}), got shape {v.shape}")
    bad = [s for s in senses if s not in ("min", "max")]
    if bad:
        raise ValueError(f"senses must be 'min' or 'max', got {bad}")
    v = v * np.where(np.asarray(senses) == "max", -1.0, 1.0)  # all minimised
    valid = ~np.isnan(v).any(axis=1)
    mask = np.zeros(len(v), dtype=bool)
    w = v[valid]
    optimal = np.ones(len(w), dtype=bool)
    scale = np.abs(np.where(np.isfinite(w), w, 0.0)).max(axis=0) if len(w) else 0.0
    tol = OBJECTIVE_RELATIVE * scale  # (m,): the objectives' round-off
    for start in range(0, len(w), chunk):
        block = w[start : start + chunk, None, :]  # (c, 1, m) against (1, n, m)
        dominated = (w[None] <= block + tol).all(axis=2) & (w[None] < block - tol).any(axis=2)
        optimal[start : start + chunk] = ~dominated.any(axis=1)
    mask[np.flatnonzero(valid)] = optimal
    return mask


def violations(row: dict, constraints: dict) -> dict[str, float | None]:
    """How far ``row`` is from meeting each constraint.

    Parameters
    ----------
    row : dict
        A results row (metric -> value).
    constraints : dict
        Metric -> ``{"min": a, "max": b}`` (either bound) or a required bool value.

    Returns
    -------
    dict of str to float or None
        Metric -> violation, every metric of ``constraints`` in its order: <= 0 met (a
        range's negative value is the slack), > 0 missed by that much relative to the bound
        (``(value - max) / |max|``, ``(min - value) / |min|``; a bound of 0 counts
        absolutely), 1.0 for a wrong bool; None where the metric was not measured (None or
        NaN).

    Examples
    --------
    >>> rules = {"bending_utilisation": {"max": 1.0}, "fe_buckling_factor": {"min": 4.0},
    ...          "collision_free": True, "fe_deflection_ratio": {"max": 1.0}}
    >>> row = {"bending_utilisation": 1.25, "fe_buckling_factor": 3.0, "collision_free": True}
    >>> violations(row, rules)
    {'bending_utilisation': 0.25, 'fe_buckling_factor': 0.25, 'collision_free': 0.0, \
'fe_deflection_ratio': None}
    """
    out = {}
    for name, rule in constraints.items():
        value = row.get(name)
        if value is None or (isinstance(value, float) and np.isnan(value)):
            out[name] = None
        elif isinstance(rule, bool):
            out[name] = 0.0 if (value is rule or value == rule) else 1.0
        else:
            missed = []
            if "max" in rule:
                missed.append((value - rule["max"]) / (abs(rule["max"]) or 1.0))
            if "min" in rule:
                missed.append((rule["min"] - value) / (abs(rule["min"]) or 1.0))
            out[name] = float(max(missed))
    return out


def meets(row: dict, constraints: dict) -> bool:
    """Every constraint measured and met (:func:`violations` all <= 0); the row's status is
    not looked at."""
    return all(v is not None and v <= 0.0 for v in violations(row, constraints).values())


def feasible(rows: list, constraints: dict) -> np.ndarray:
    """(n,) bool: the row succeeded and meets every constraint.

    Parameters
    ----------
    rows : list of dict
    constraints : dict
        Metric -> ``{"min": a, "max": b}`` (either bound) or a required bool value.
    """
    return np.array(
        [row.get("status") == "ok" and meets(row, constraints) for row in rows], dtype=bool
    )


def objective_matrix(rows: list, objectives) -> np.ndarray:
    """(n, m) float values of the metrics ``objectives`` (names, or a dict keyed by them) in
    ``rows`` (NaN where missing)."""
    return np.array(
        [[np.nan if r.get(k) is None else float(r[k]) for k in objectives] for r in rows],
        dtype=float,
    ).reshape(len(rows), len(objectives))


def rank_best(rows: list, objectives: dict, constraints: dict, count: int) -> tuple:
    """Pareto front of the feasible rows and the ``count`` best on it.

    "Best" are the Pareto-optimal feasible variants closest to the ideal point: each objective
    is scaled to [0, 1] over the feasible variants (0 = best value found) and the variants are
    ranked by their Euclidean distance from the origin, so the picks balance the objectives.

    Returns
    -------
    front : (n,) bool
        Pareto-optimal among the feasible rows.
    best : list of (int, float)
        Row index and distance, best first.
    """
    ok = feasible(rows, constraints)
    values = objective_matrix(rows, objectives)
    senses = list(objectives.values())
    front = np.zeros(len(rows), dtype=bool)
    if not ok.any():
        return front, []
    idx = np.flatnonzero(ok)
    front[idx] = pareto_mask(values[idx], senses)
    v = values[idx] * np.where(np.asarray(senses) == "max", -1.0, 1.0)
    low, high = np.nanmin(v, axis=0), np.nanmax(v, axis=0)
    scaled = (v - low) / np.where(high > low, high - low, 1.0)
    distance = np.full(len(rows), np.inf)
    distance[idx] = np.linalg.norm(scaled, axis=1)
    on_front = np.flatnonzero(front)
    order = on_front[np.argsort(distance[on_front], kind="stable")]
    return front, [(int(i), float(distance[i])) for i in order[:count]]
