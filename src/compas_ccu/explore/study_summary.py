"""The outputs of a study (``ccu optimize``): ``summary.json``, the best designs and the plots.

With one objective the best designs are the feasible ones in order of the objective; with
several, the Pareto front of the feasible designs ranked by the distance from the ideal point
(:func:`compas_ccu.explore.pareto.rank_best`, as in a sweep). A design proposed again is ranked
once. With no feasible design the summary lists the least-violating ones.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np

from compas_ccu.explore.pareto import rank_best
from compas_ccu.explore.plots import plot_convergence, plot_design_space, plot_pareto
from compas_ccu.explore.summary import counts, stage_seconds, write_best
from compas_ccu.outputs import write_json
from compas_ccu.viz.export import save_figure

__all__ = ["summarise_study", "convergence", "best_value"]


def best_value(rows, study):
    """The best feasible value of the first objective so far (None: none feasible)."""
    name, sense = next(iter(study.objectives.items()))
    values = [r[name] for r in rows if r.get("feasible")]
    if not values:
        return None
    return min(values) if sense == "min" else max(values)


def _distinct(rows: list) -> list:
    """Indices of the first row of every design (a design proposed again is not ranked twice)."""
    seen, out = set(), []
    for i, r in enumerate(rows):
        if r["variant"] not in seen:
            seen.add(r["variant"])
            out.append(i)
    return out


def _best(study, rows: list) -> tuple:
    """(front mask, [(row index, score)]): one objective: the feasible designs by value;
    several: the Pareto front of the feasible designs, closest to the ideal point first."""
    idx = _distinct(rows)
    sub = [rows[i] for i in idx]
    good = np.array([bool(r.get("feasible")) for r in sub], dtype=bool)
    front = np.zeros(len(rows), dtype=bool)
    if len(study.objectives) == 1:
        name, sense = next(iter(study.objectives.items()))
        ranked = sorted(
            (j for j in range(len(sub)) if good[j]),
            key=lambda j: sub[j][name] if sense == "min" else -sub[j][name],
        )
        if ranked:
            front[[idx[j] for j in ranked if sub[j][name] == sub[ranked[0]][name]]] = True
        return front, [(idx[j], float(sub[j][name])) for j in ranked[: study.best]]
    # feasibility as the assessment decided it (constraints, objectives measured)
    sub_front, best = rank_best(sub, study.objectives, {"feasible": True}, study.best)
    front[[idx[j] for j in np.flatnonzero(sub_front)]] = True
    return front, [(idx[j], d) for j, d in best]


def convergence(rows: list, study) -> list:
    """The best feasible value of the first objective after every trial (None before the
    first feasible one), in trial order."""
    out, best = [], None
    name, sense = next(iter(study.objectives.items()))
    for r in rows:
        if r.get("feasible"):
            v = r[name]
            if best is None or (v < best if sense == "min" else v > best):
                best = v
        out.append(best)
    return out


def _trial_entry(study, row: dict) -> dict:
    return {
        "trial": row["trial"],
        "variant": row["variant"],
        "parameters": {k: row.get(k) for k in study.parameter_names},
        "objectives": {k: row.get(k) for k in study.objectives},
        "constraints": {k: row.get(k) for k in study.constraints},
    }


def _least_violating(study, rows: list, count: int = 5) -> list:
    """The ``count`` designs of smallest total violation (none feasible), with what they miss."""
    order = sorted(_distinct(rows), key=lambda i: (rows[i]["violation"], rows[i]["trial"]))
    return [
        {**_trial_entry(study, rows[i]), "violation": rows[i]["violation"],
         "violations": rows[i]["violations"]}
        for i in order[:count]
    ]  # fmt: skip


def _run_entry(run) -> dict:
    """The counts and timing of a run (a :class:`~compas_ccu.explore.optimize.StudyResult`)."""
    return {
        "computed": run.computed,
        "evaluations": run.evaluations,
        "fe_gated": run.gated,
        "earlier": run.earlier,
        "seconds": run.seconds,
        "startup_seconds": run.startup,
        "throughput_per_s": run.throughput,
        "workers": run.workers,
        "scheduler": run.scheduler,
        "interrupted": run.interrupted,
    }


def _write_plots(study, rows: list, folder: Path, front, best: list, good) -> list:
    """``convergence.png``, ``design_space.png`` and, for several objectives, ``pareto.png``."""
    folder.mkdir(exist_ok=True)
    fig = plot_convergence(rows, study.objectives, good, title=study.name)
    files = save_figure(fig, folder / "convergence", formats=("png",))
    fig = plot_design_space(rows, study.parameter_names, sweep=study)
    files += save_figure(fig, folder / "design_space", formats=("png",))
    if len(study.objectives) > 1:
        fig = plot_pareto(rows, study.objectives, front, best, good, title=study.name)
        files += save_figure(fig, folder / "pareto", formats=("png",))
    return files


def summarise_study(study, rows: list, out, *, run=None, plots: bool = True) -> dict:
    """Write ``summary.json``, the best designs' files and the plots of a study.

    Parameters
    ----------
    study : compas_ccu.explore.study.Study
    rows : list of dict
        The results table's rows, by trial.
    out : path-like
    run : StudyResult, optional
        Adds the run's counts and timing.
    plots : bool
        Write ``plots/convergence.png``, ``plots/design_space.png`` and, for several
        objectives, ``plots/pareto.png`` (needs matplotlib).

    Returns
    -------
    dict
        What ``summary.json`` holds, plus ``files``. With no feasible design, ``best`` is
        empty and ``least_violating`` lists the designs closest to feasible (smallest total
        violation) with what they miss.
    """
    out = Path(out)
    ok = [r for r in rows if r.get("status") == "ok"]
    failed = [r for r in rows if r.get("status") != "ok"]
    good = np.array([bool(r.get("feasible")) for r in rows], dtype=bool)
    front, best = _best(study, rows)
    if (out / "best").is_dir():  # the picks of an earlier summary
        shutil.rmtree(out / "best")
    picks = [(rank + 1, study.variant_of_row(rows[i])) for rank, (i, _) in enumerate(best)]
    files = write_best(
        study,
        picks,
        out,
        origin=lambda rank, v: f"trial {v.index} of study {study.name!r} (rank {rank})",
    )
    history = convergence(rows, study)
    reached = None
    if history and history[-1] is not None:
        reached = next(k + 1 for k, v in enumerate(history) if v == history[-1])
    least = [] if good.any() else _least_violating(study, rows)
    summary = {
        "format": "ccu.study-summary",
        "version": 1,
        "name": study.name,
        "sampler": study.sampler_name,
        "seed": study.seed,
        "trials": len(rows),
        "evaluations": sum(not r.get("reused") for r in rows),
        "ok": len(ok),
        "failed": len(failed),
        "errors": counts(r.get("error_type") for r in failed),
        "fe_gated": sum(bool(r.get("fe_gated")) for r in rows),
        "feasible": int(good.sum()),
        "objectives": study.objectives,
        "constraints": study.constraints,
        "best": [
            {
                "rank": rank + 1,
                **_trial_entry(study, rows[i]),
                "score": score,
                "folder": str(out / "best" / f"{rank + 1}-{rows[i]['variant']}"),
            }
            for rank, (i, score) in enumerate(best)
        ],
        "pareto": [rows[i]["trial"] for i in np.flatnonzero(front)],
        "best_reached_at_trial": reached,
        "convergence": history,
        "least_violating": least,
        "stage_seconds": stage_seconds(ok),
    }
    if run is not None:
        summary["run"] = _run_entry(run)
    if plots and rows:
        files += _write_plots(study, rows, out / "plots", front, best, good)
    path = out / "summary.json"
    summary["files"] = [str(f) for f in files] + [str(path)]
    write_json(path, summary, default=float)
    return summary
