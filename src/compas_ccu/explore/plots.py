"""Pictures of a design-space sweep or an optimisation study: metrics against parameters, the
Pareto front, and the convergence of a study."""

from __future__ import annotations

import numpy as np

from compas_ccu.explore.pareto import feasible, objective_matrix, pareto_mask
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["plot_design_space", "plot_pareto", "plot_convergence", "running_best"]

FEASIBLE = "#1f77b4"
INFEASIBLE = "#ff7f0e"
FAILED = "#d62728"
MAX_CATEGORIES = 12


def _axis_values(rows: list, name: str):
    """x positions of every row for parameter ``name``, tick labels (categorical) or None."""
    values = [r.get(name) for r in rows]
    numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)
    distinct = list(dict.fromkeys(values))
    if numeric and len(distinct) > MAX_CATEGORIES:
        return np.array(values, dtype=float), None
    if numeric:
        distinct = sorted(distinct)
    index = {v: i for i, v in enumerate(distinct)}
    labels = [f"{v:g}" if isinstance(v, float) else str(v) for v in distinct]
    return np.array([index[v] for v in values], dtype=float), labels


def _varies(values: np.ndarray) -> bool:
    v = values[np.isfinite(values)]
    return v.size > 0 and np.ptp(v) > EXACT_RELATIVE * max(1.0, np.abs(v).max())


def _metric(rows: list, name: str) -> np.ndarray:

    return objective_matrix(rows, [name])[:, 0]


def plot_design_space(rows: list, parameters: list, *, sweep=None, metrics=None, title=None):
    """Every metric against every parameter, and the share of failed variants.

    Parameters
    ----------
    rows : list of dict
        Rows of a results table.
    parameters : list of str
        Parameter columns (x axes, at most 8 are drawn).
    sweep : compas_ccu.explore.Sweep, optional
        Its objectives are drawn first and its constraints colour the points.
    metrics : list of str, optional
        Metric rows (default: the objectives, span and limit_margin; at most 6).

    Returns
    -------
    matplotlib.figure.Figure
        Feasible variants blue, successful but infeasible ones orange; metrics that are the
        same in every variant are left out; when variants failed, the last row is the fraction
        that failed (with their error) per parameter value.

    Examples
    --------
    >>> rows = [{"a": 1.0, "status": "ok", "rise": 1.0, "span": 2.0, "limit_margin": 3.0},
    ...         {"a": 2.0, "status": "failed"}]
    >>> fig = plot_design_space(rows, ["a"], metrics=["rise"])
    >>> len(fig.axes)
    2
    """
    from matplotlib.figure import Figure

    if metrics is None:
        metrics = list(sweep.objectives) if sweep is not None else ["rise"]
        metrics += [m for m in ("span", "plan_area", "limit_margin") if m not in metrics]
        metrics = [m for m in metrics if _varies(_metric(rows, m))]  # a constant says nothing
    metrics = metrics[:6]
    parameters = list(parameters)[:8]
    ok = np.array([r.get("status") == "ok" for r in rows], dtype=bool)
    good = feasible(rows, sweep.constraints) if sweep is not None else ok
    failures = bool((~ok).any())
    nrows, ncols = len(metrics) + failures, max(1, len(parameters))
    fig = Figure(figsize=(2.7 * ncols + 0.6, 2.0 * nrows + 0.6), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    rng = np.random.default_rng(0)
    for j, name in enumerate(parameters):
        x, labels = _axis_values(rows, name)
        jitter = rng.uniform(-0.18, 0.18, len(x)) if labels is not None else 0.0
        for i, metric in enumerate(metrics):
            ax = axes[i, j]
            y = _metric(rows, metric)
            for mask, color, label in (
                (ok & ~good, INFEASIBLE, "infeasible"),
                (good, FEASIBLE, "feasible"),
            ):
                ax.scatter(
                    (x + jitter)[mask], y[mask], s=7, color=color, alpha=0.6, lw=0, label=label
                )
            if j == 0:
                ax.set_ylabel(metric)
            ax.ticklabel_format(axis="y", useOffset=False, style="plain")
            last = i == nrows - 1
            if labels is not None:
                ax.set_xticks(range(len(labels)), labels=labels if last else [""] * len(labels))
                if last and (len(labels) > 5 or max(map(len, labels)) > 8):
                    ax.tick_params(axis="x", labelrotation=30, labelsize=7)
            elif not last:
                ax.tick_params(labelbottom=False)
            if last:
                ax.set_xlabel(name)
            ax.grid(alpha=0.3)
        if not failures:
            continue
        ax = axes[-1, j]
        if labels is not None:
            share = [(~ok[x == k]).mean() if (x == k).any() else 0.0 for k in range(len(labels))]
            ax.bar(range(len(labels)), share, color=FAILED, alpha=0.8)
            ax.set_xticks(
                range(len(labels)), labels=labels, rotation=45 if len(labels) > 5 else 0, fontsize=7
            )
        else:
            edges = np.linspace(np.nanmin(x), np.nanmax(x), 11)
            total, _ = np.histogram(x, edges)
            bad, _ = np.histogram(x[~ok], edges)
            ax.bar(
                0.5 * (edges[1:] + edges[:-1]),
                np.divide(bad, np.maximum(total, 1)),
                width=np.diff(edges) * 0.9,
                color=FAILED,
                alpha=0.8,
            )
        ax.set_ylim(0.0, 1.0)
        ax.set_xlabel(name)
        if j == 0:
            ax.set_ylabel("failed share")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7, loc="best", markerscale=2)
    fig.suptitle(
        (title or (sweep.name if sweep is not None else "design space"))
        + f": {len(rows)} variants, {int(good.sum())} feasible, {int((~ok).sum())} failed",
        fontsize=10,
    )
    return fig


def plot_pareto(rows: list, objectives: dict, front, best, feasible_mask, *, title=None):
    """The first objective against each other one, with the Pareto front and the best picks.

    Parameters
    ----------
    rows : list of dict
    objectives : dict
        Metric -> "min" / "max" (the first is the y axis of every panel).
    front : (n,) bool
        Pareto-optimal over all objectives (:func:`compas_ccu.explore.pareto.rank_best`).
    best : list of (int, float)
        Row index and distance of the best variants, best first.
    feasible_mask : (n,) bool

    Returns
    -------
    matplotlib.figure.Figure
        One panel per further objective (at most 3): infeasible variants grey, feasible ones
        coloured by the next objective, the Pareto-optimal ones ringed in black, the
        two-objective front of the panel as a step line, the best variants numbered.
    """
    from matplotlib.figure import Figure

    names = list(objectives)
    front = np.asarray(front, dtype=bool)
    feasible_mask = np.asarray(feasible_mask, dtype=bool)
    y_name = names[0]
    others = names[1:4] or [y_name]
    fig = Figure(figsize=(5.2 * len(others), 4.4), layout="constrained")
    axes = fig.subplots(1, len(others), squeeze=False)[0]
    y = _metric(rows, y_name)
    ok = np.array([r.get("status") == "ok" for r in rows], dtype=bool)
    for ax, x_name in zip(axes, others):
        x = _metric(rows, x_name) if x_name != y_name else np.arange(len(rows), dtype=float)
        rest = [n for n in names if n not in (y_name, x_name)]
        c_name = rest[0] if rest else None
        grey = ok & ~feasible_mask
        ax.scatter(x[grey], y[grey], s=8, color="0.75", lw=0, label="infeasible")
        f = feasible_mask
        if c_name is not None and f.any():
            c = _metric(rows, c_name)
            sc = ax.scatter(x[f], y[f], s=14, c=c[f], cmap="viridis", lw=0, label="feasible")
            fig.colorbar(sc, ax=ax, label=f"{c_name} ({objectives[c_name]})")
        else:
            ax.scatter(x[f], y[f], s=14, color=FEASIBLE, lw=0, label="feasible")
        ax.scatter(
            x[front],
            y[front],
            s=30,
            facecolors="none",
            edgecolors="k",
            lw=0.8,
            label="Pareto-optimal (all objectives)",
        )
        if x_name != y_name and f.sum() > 1:
            idx = np.flatnonzero(f)
            pair = pareto_mask(np.c_[x[idx], y[idx]], [objectives[x_name], objectives[y_name]])
            pts = idx[pair]
            pts = pts[np.argsort(x[pts])]
            where = "post" if objectives[x_name] != objectives[y_name] else "pre"
            ax.step(
                x[pts],
                y[pts],
                where=where,
                color="k",
                lw=0.8,
                alpha=0.7,
                label=f"front of {y_name} / {x_name}",
            )
        for rank, (i, _) in enumerate(best):
            ax.annotate(
                str(rank + 1),
                (x[i], y[i]),
                xytext=(4, 4),
                textcoords="offset points",
                fontsize=8,
                weight="bold",
                color="crimson",
            )
        ax.set_xlabel(f"{x_name} ({objectives[x_name]})" if x_name != y_name else "variant")
        ax.set_ylabel(f"{y_name} ({objectives[y_name]})")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="best")
    fig.suptitle(
        f"{title or 'sweep'}: Pareto front of {', '.join(names)} ({int(front.sum())} "
        f"optimal of {int(feasible_mask.sum())} feasible); best numbered",
        fontsize=10,
    )
    return fig


def running_best(values, mask, sense: str) -> np.ndarray:
    """The best of ``values[mask]`` up to every position (NaN before the first).

    >>> running_best([3.0, 5.0, 2.0, 1.0], [False, True, True, False], "min").tolist()
    [nan, 5.0, 2.0, 2.0]
    """
    v = np.where(np.asarray(mask, dtype=bool), np.asarray(values, dtype=float), np.nan)
    sign = 1.0 if sense == "min" else -1.0
    best = np.fmin.accumulate(np.where(np.isnan(v), np.inf, sign * v))
    return np.where(np.isinf(best), np.nan, sign * best)


def plot_convergence(rows: list, objectives: dict, feasible_mask, *, title=None, references=None):
    """Every trial's objective values in trial order, and the best feasible value so far.

    Parameters
    ----------
    rows : list of dict
        A study's results rows, by trial.
    objectives : dict
        Metric -> "min" / "max" (one panel each, at most 3).
    feasible_mask : (n,) bool
    references : dict, optional
        Label -> {metric: value}: horizontal lines (e.g. the best of a grid sweep).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> rows = [{"status": "ok", "mass": m} for m in (5.0, 4.0, 6.0)]
    >>> fig = plot_convergence(rows, {"mass": "min"}, [True, False, True])
    >>> len(fig.axes)
    1
    """
    from matplotlib.figure import Figure

    names = list(objectives)[:3]
    good = np.asarray(feasible_mask, dtype=bool)
    ok = np.array([r.get("status") == "ok" for r in rows], dtype=bool)
    x = np.arange(1, len(rows) + 1)
    fig = Figure(figsize=(5.4 * len(names), 4.0), layout="constrained")
    axes = fig.subplots(1, len(names), squeeze=False)[0]
    for ax, name in zip(axes, names):
        y = _metric(rows, name)
        ax.scatter(x[ok & ~good], y[ok & ~good], s=10, color=INFEASIBLE, lw=0, label="infeasible")
        ax.scatter(x[good], y[good], s=14, color=FEASIBLE, lw=0, label="feasible")
        best = running_best(y, good, objectives[name])
        ax.step(x, best, where="post", color="k", lw=1.2, label="best feasible so far")
        for k, (label, values) in enumerate((references or {}).items()):
            if name in values:
                ax.axhline(values[name], color=f"C{k + 2}", ls="--", lw=1, label=label)
        ax.set_xlabel("trial (designs evaluated, in order)")
        ax.set_ylabel(f"{name} ({objectives[name]})")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="best")
    fig.suptitle(
        f"{title or 'study'}: {len(rows)} trials, {int(good.sum())} feasible, "
        f"{int((~ok).sum())} failed",
        fontsize=10,
    )
    return fig
