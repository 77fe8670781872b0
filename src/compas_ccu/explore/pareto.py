"""Feasibility, Pareto front and the best variants of a sweep."""

from __future__ import annotations

import numpy as np

__all__ = ["pareto_mask", "feasible", "objective_matrix", "rank_best"]


def pareto_mask(values: np.ndarray, senses, *, chunk: int = 512) -> np.ndarray:
    """Which rows are Pareto-optimal (no other row is as good in every objective and better
    in one).

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
    for start in range(0, len(w), chunk):
        block = w[start : start + chunk, None, :]  # (c, 1, m) against (1, n, m)
        dominated = (w[None] <= block).all(axis=2) & (w[None] < block).any(axis=2)
        optimal[start : start + chunk] = ~dominated.any(axis=1)
    mask[np.flatnonzero(valid)] = optimal
    return mask


def feasible(rows: list, constraints: dict) -> np.ndarray:
    """(n,) bool: the row succeeded and meets every constraint.

    Parameters
    ----------
    rows : list of dict
    constraints : dict
        Metric -> ``{"min": a, "max": b}`` (either bound) or a required bool value.
    """
    out = np.zeros(len(rows), dtype=bool)
    for i, row in enumerate(rows):
        ok = row.get("status") == "ok"
        for name, rule in constraints.items():
            if not ok:
                break
            value = row.get(name)
            if isinstance(rule, bool):
                ok = value is rule or value == rule
            elif value is None:
                ok = False
            else:
                ok = rule.get("min", -np.inf) <= value <= rule.get("max", np.inf)
        out[i] = ok
    return out


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
