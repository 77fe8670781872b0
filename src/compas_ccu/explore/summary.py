"""Summary of a finished sweep: counts, errors, stage times, Pareto front, best variants, plots."""

from __future__ import annotations

import statistics
from collections import Counter
from pathlib import Path

import numpy as np

from compas_ccu.design.document import Design
from compas_ccu.design.writer import design_toml
from compas_ccu.explore.evaluate import STAGES
from compas_ccu.explore.pareto import feasible, rank_best
from compas_ccu.explore.plots import plot_design_space, plot_pareto
from compas_ccu.io import write_obj, write_structure_json
from compas_ccu.model import CCUModel
from compas_ccu.outputs import write_json
from compas_ccu.viz.export import save_figure

__all__ = ["summarise", "write_best", "stage_seconds", "counts"]


def write_best(sweep, picks: list, out, *, origin=None) -> list:
    """The best variants' files: ``best/<rank>-<variant>/`` with the design (TOML), the
    deployed structure (``structure.json``, docs/structure-json.md) and ``structure.obj``.

    Parameters
    ----------
    sweep : compas_ccu.explore.Sweep
    picks : list of (rank, Variant)
    out : path-like
        The sweep's output folder.
    origin : callable, optional
        ``origin(rank, variant)``: the first line of the file's header (default: ``variant ...
        of sweep ... (rank ...)``).
    """
    files = []
    for rank, variant in picks:
        folder = Path(out) / "best" / f"{rank}-{variant.id}"
        folder.mkdir(parents=True, exist_ok=True)
        document = sweep.document_for(variant)
        text = design_toml(document)
        first = (
            origin(rank, variant)
            if origin is not None
            else f"variant {variant.id} of sweep {sweep.name!r} (rank {rank})"
        )
        header = f"# {first}; parameters:\n" + "".join(
            f"#   {k} = {v!r}\n" for k, v in variant.params.items()
        )
        (folder / "design.toml").write_text(header + text, encoding="utf-8")
        structure = CCUModel(Design(document)).deploy()
        files += [
            folder / "design.toml",
            write_structure_json(structure, folder / "structure.json"),
            write_obj(structure, folder / "structure.obj"),
        ]
    return files


def counts(values) -> dict:
    """Occurrences, most frequent first, ties by name."""
    return dict(sorted(Counter(values).items(), key=lambda kv: (-kv[1], str(kv[0]))))


def stage_seconds(rows: list) -> dict:
    """Mean, largest and total time and count of every evaluation stage over ``rows``."""

    out = {}
    for stage in STAGES:
        times = [r[f"t_{stage}"] for r in rows if r.get(f"t_{stage}") is not None]
        if times:
            out[stage] = {
                "mean": statistics.fmean(times),
                "max": max(times),
                "total": sum(times),
                "count": len(times),
            }
    return out


def summarise(sweep, rows: list, out, *, run=None, plots: bool = True) -> dict:
    """Write ``summary.json``, the plots and the best variants' files of a complete sweep.

    Parameters
    ----------
    sweep : compas_ccu.explore.Sweep
    rows : list of dict
        The results table's rows, in sweep order.
    out : path-like
    run : compas_ccu.explore.SweepResult, optional
        Adds the run's timing (computed, reused, seconds, throughput, workers).
    plots : bool
        Write ``plots/design_space.png`` and ``plots/pareto.png`` (needs matplotlib).

    Returns
    -------
    dict
        What ``summary.json`` holds, plus ``files``.
    """

    out = Path(out)
    ok = [r for r in rows if r.get("status") == "ok"]
    failed = [r for r in rows if r.get("status") != "ok"]
    feasible_mask = feasible(rows, sweep.constraints)
    front, best = rank_best(rows, sweep.objectives, sweep.constraints, sweep.best)
    by_id = {v.id: v for v in sweep.variants}
    picks = [(rank + 1, by_id[rows[i]["variant"]]) for rank, (i, _) in enumerate(best)]
    files = write_best(sweep, picks, out)
    summary = {
        "format": "ccu.sweep-summary",
        "version": 1,
        "name": sweep.name,
        "variants": len(rows),
        "ok": len(ok),
        "failed": len(failed),
        "errors": counts(r.get("error_type") for r in failed),
        "failed_stage": counts(r.get("stage") for r in failed),
        "feasible": int(feasible_mask.sum()),
        "objectives": sweep.objectives,
        "constraints": sweep.constraints,
        "pareto": [rows[i]["variant"] for i in np.flatnonzero(front)],
        "best": [
            {
                "rank": rank + 1,
                "variant": rows[i]["variant"],
                "distance": dist,
                "parameters": {k: rows[i].get(k) for k in sweep.parameter_names},
                "objectives": {k: rows[i].get(k) for k in sweep.objectives},
                "folder": str(out / "best" / f"{rank + 1}-{rows[i]['variant']}"),
            }
            for rank, (i, dist) in enumerate(best)
        ],
        "ranges": {
            name: [min(vals), max(vals)]
            for name in sweep.objectives
            if (vals := [r[name] for r in ok if r.get(name) is not None])
        },
        "stage_seconds": stage_seconds(ok),
    }
    if run is not None:
        summary["run"] = {
            "computed": run.computed,
            "reused": run.reused,
            "seconds": run.seconds,
            "startup_seconds": run.startup,
            "throughput_per_s": run.throughput,
            "workers": run.workers,
            "scheduler": run.scheduler,
        }
    if plots:
        folder = out / "plots"
        folder.mkdir(exist_ok=True)
        fig = plot_design_space(rows, sweep.parameter_names, sweep=sweep)
        files += save_figure(fig, folder / "design_space", formats=("png",))
        fig = plot_pareto(rows, sweep.objectives, front, best, feasible_mask, title=sweep.name)
        files += save_figure(fig, folder / "pareto", formats=("png",))
    path = out / "summary.json"
    summary["files"] = [str(f) for f in files] + [str(path)]
    write_json(path, summary, default=float)
    return summary
