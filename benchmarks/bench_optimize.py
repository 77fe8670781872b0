"""The optimiser (``ccu optimize``) against a grid sweep (``ccu explore``) on the same problem.

Run from the repository root (``make bench-optimize``); results are recorded in
``docs/benchmarks.md`` and ``docs/optimize.md``::

    .venv/bin/python benchmarks/bench_optimize.py                   # both parts, ~30 min on 2 cores
    .venv/bin/python benchmarks/bench_optimize.py --part kinematic  # ~17 min
    .venv/bin/python benchmarks/bench_optimize.py --part fe         # ~15 min (FE, Kratos)
    .venv/bin/python benchmarks/bench_optimize.py --quick           # the coarse grid, 2 seeds

The problem is a study file; the grid is built from it (:func:`grid_sweep`: the same base
design, checks, FE options, objectives and constraints, every range at a number of levels), so
both solve exactly the same problem, and feasibility is decided for both by the study's rules
(:func:`compas_ccu.explore.optimize.assess`).

1. **Kinematic** (``examples/optimize/vault-sheets.toml``: the largest plan area from 40 kg of
   plywood cut from 3050 x 1525 mm sheets; 5 parameters, ~0.2 s per design). Two grids a user
   would choose: 3 levels of every parameter (243 designs) and 5 levels (4, 6, ... 12 plates;
   3 thicknesses 4, 8, 12 mm: 1875 designs). The optimiser (TPE) runs with 5 seeds and a budget
   of 1/5 of the fine grid (375 trials); random search with the same seeds and budget is the
   baseline. Reported per seed: the best feasible objective after as many trials as each grid
   has designs and after 1/5 of them, and the trials it needed to reach each grid's best. A
   trial counts as an evaluation even when it proposed a design already evaluated (its row is
   reused): the counts are conservative for the optimiser.
2. **FE** (``examples/optimize/vault-concrete.toml`` with the plate count and spacing of the
   base design: the lightest vault formwork for 8 cm of wet concrete). The grid (thickness 4 ..
   20 mm at 5 levels x rise at 2 x 3 materials = 30 designs) runs the FE on every design, as a
   sweep does; the optimiser (TPE, 5 random trials first) runs 30 trials with 3 seeds, the FE
   only after the cheap checks.

Everything on a local Dask cluster of ``--workers`` (2) workers; wall times include the
cluster start. ``--out`` writes the numbers as JSON and the convergence plots as PNG.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from compas_ccu.design.document import read_toml
from compas_ccu.explore import run_sweep
from compas_ccu.explore.optimize import convergence, feasible_rows, run_study
from compas_ccu.explore.plots import running_best
from compas_ccu.explore.study import Study, load_study
from compas_ccu.explore.sweep import Sweep

ROOT = Path(__file__).resolve().parents[1]
SHEETS = ROOT / "examples" / "optimize" / "vault-sheets.toml"
CONCRETE = ROOT / "examples" / "optimize" / "vault-concrete.toml"


def grid_sweep(study_path: Path, levels: dict, *, drop=()) -> Sweep:
    """The grid sweep of a study file: its base, checks, FE, objectives and constraints, every
    range at ``levels[name]`` values (choices as they are); ``drop``: parameters left at the
    base design's value."""
    doc = copy.deepcopy(read_toml(study_path))
    head = doc.pop("study")
    parameters = {}
    for name, spec in doc.pop("parameters").items():
        if name in drop:
            continue
        if isinstance(spec, dict):
            spec = {"min": spec["min"], "max": spec["max"], "num": levels[name]}
        parameters[name] = spec
    sweep = {"name": f"{head['name']}-grid", "base": head["base"], "sampling": "grid"}
    return Sweep({"sweep": sweep, "parameters": parameters, **doc}, base_dir=study_path.parent)


def study_without(study_path: Path, drop=(), **head) -> Study:
    """The study file with the parameters ``drop`` fixed at the base design's value."""
    doc = copy.deepcopy(read_toml(study_path))
    for name in drop:
        del doc["parameters"][name]
    doc["study"].update(head)
    return Study(doc, base_dir=study_path.parent, name=study_path.stem)


def best_of(rows: list, study) -> float | None:
    name, sense = next(iter(study.objectives.items()))
    good = feasible_rows(rows, study)
    values = [r[name] for r, ok in zip(rows, good) if ok]
    if not values:
        return None
    return min(values) if sense == "min" else max(values)


def run_grid(sweep: Sweep, study, workers: int) -> dict:
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        r = run_sweep(sweep, out, workers=workers, progress=False, summary=False)
        wall = time.perf_counter() - t0
    good = feasible_rows(r.rows, study)
    return {
        "designs": len(r.rows),
        "feasible": int(good.sum()),
        "failed": r.failed,
        "best": best_of(r.rows, study),
        "wall_s": wall,
        "compute_s": r.seconds,
        "levels": {p.name: len(p.grid_values()) for p in sweep.parameters},
    }


def run_optimiser(study, budget: int, workers: int) -> dict:
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        r = run_study(study, out, trials=budget, workers=workers, progress=False, summary=False)
        wall = time.perf_counter() - t0
    history = convergence(r.rows, study)
    return {
        "seed": study.seed,
        "sampler": study.sampler_name,
        "trials": len(r.rows),
        "evaluations": r.evaluations,
        "fe_gated": r.gated,
        "feasible": int(sum(bool(x["feasible"]) for x in r.rows)),
        "best": history[-1] if history else None,
        "history": history,
        "wall_s": wall,
        "compute_s": r.seconds,
        "fe_seconds": sum(x["t_fe"] or 0.0 for x in r.rows if not x["reused"]),
    }


def at(history: list, k: int):
    """Best after ``k`` trials (None before the first feasible one)."""
    return history[min(k, len(history)) - 1] if history and k > 0 else None


def reached(history: list, target: float, sense: str):
    """Trials needed to reach ``target`` (None: not reached)."""
    for k, v in enumerate(history):
        if v is not None and (v <= target if sense == "min" else v >= target):
            return k + 1
    return None


def better(a, b, sense: str) -> bool:
    return a is not None and (b is None or (a < b if sense == "min" else a > b))


def compare(grids: dict, runs: list, sense: str) -> dict:
    """Per grid and optimiser run: the best at equal and at 1/5 of the grid's evaluations, the
    trials needed to reach the grid's best, and whether the two requirements hold."""
    out = {}
    for label, g in grids.items():
        n = g["designs"]
        rows = []
        for r in runs:
            equal, fifth = at(r["history"], n), at(r["history"], n // 5)
            need = reached(r["history"], g["best"], sense) if g["best"] is not None else 1
            rows.append(
                {
                    "seed": r["seed"],
                    "sampler": r["sampler"],
                    "best_at_equal": equal if len(r["history"]) >= n else None,
                    "best_at_fifth": fifth,
                    "trials_to_grid_best": need,
                    "better_at_equal": better(at(r["history"], n), g["best"], sense),
                    "grid_best_within_fifth": need is not None and need <= n // 5,
                }
            )
        out[label] = rows
    return out


def plot(path: Path, title: str, study, grids: dict, runs: list) -> None:
    from matplotlib.figure import Figure

    name, sense = next(iter(study.objectives.items()))
    fig = Figure(figsize=(7.5, 4.6), layout="constrained")
    ax = fig.subplots()
    labelled = set()
    for r in runs:
        y = np.array([np.nan if v is None else v for v in r["history"]], dtype=float)
        x = np.arange(1, len(y) + 1)
        tpe = r["sampler"] == "tpe"
        seeds = [str(q["seed"]) for q in runs if q["sampler"] == r["sampler"]]
        label = None if r["sampler"] in labelled else f"{r['sampler']}, seeds {', '.join(seeds)}"
        labelled.add(r["sampler"])
        best = running_best(y, np.isfinite(y), sense)
        ax.step(x, best, where="post", ls="-" if tpe else ":", lw=1.1,
                color="C0" if tpe else "0.45", label=label)  # fmt: skip
    for k, (label, g) in enumerate(grids.items()):
        if g["best"] is None:
            continue
        ax.axhline(g["best"], color=f"C{k + 1}", ls="--", lw=1,
                   label=f"grid {label}: best of {g['designs']} designs")  # fmt: skip
        ax.axvline(g["designs"] // 5, color=f"C{k + 1}", ls=":", lw=0.8)
    ax.set_xlabel("trials (evaluations); dotted verticals: 1/5 of each grid")
    ax.set_ylabel(f"best feasible {name} ({sense})")
    if max(len(r["history"]) for r in runs) > 100:
        ax.set_xscale("log")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    fig.suptitle(title, fontsize=10)
    fig.savefig(path, dpi=110)


def kinematic(args) -> dict:
    study = load_study(SHEETS)
    sense = study.objectives["plan_area"]
    levels5 = {n: 5 for n in study.parameter_names} | {"plates.thickness": 3}
    levels3 = {n: 3 for n in study.parameter_names}
    grids = {}
    grids["3 levels"] = run_grid(grid_sweep(SHEETS, levels3), study, args.workers)
    print(f"grid 3 levels: {grids['3 levels']}", flush=True)
    if not args.quick:
        grids["5 levels"] = run_grid(grid_sweep(SHEETS, levels5), study, args.workers)
        print(f"grid 5 levels: {grids['5 levels']}", flush=True)
    budget = max(g["designs"] for g in grids.values()) // 5
    budget = max(budget, grids["3 levels"]["designs"])  # also equal to the coarse grid
    seeds = range(2) if args.quick else range(5)
    runs = []
    for sampler in ("tpe", "random"):
        for seed in seeds:
            s = study_without(SHEETS, seed=seed, sampler=sampler)
            r = run_optimiser(s, budget, args.workers)
            print(
                f"{sampler} seed {seed}: best {r['best']} after {r['trials']} trials "
                f"({r['evaluations']} evaluations), {r['wall_s']:.0f} s",
                flush=True,
            )
            runs.append(r)
    return {
        "problem": str(SHEETS.relative_to(ROOT)),
        "objective": "plan_area (max)",
        "grids": grids,
        "runs": runs,
        "budget": budget,
        "comparison": compare(grids, runs, sense),
    }


def fe(args) -> dict:
    drop = ("layout.plates", "layout.spacing")
    study = study_without(CONCRETE, drop=drop, startup=5)
    levels = {"plates.thickness": 5, "crease.rise": 2}
    grid = run_grid(grid_sweep(CONCRETE, levels, drop=drop), study, args.workers)
    print(f"FE grid: {grid}", flush=True)
    runs = []
    seeds = range(1) if args.quick else range(3)
    for seed in seeds:
        s = study_without(CONCRETE, drop=drop, startup=5, seed=seed)
        r = run_optimiser(s, grid["designs"], args.workers)
        print(
            f"FE tpe seed {seed}: best {r['best']} after {r['trials']} trials "
            f"({r['fe_gated']} without FE), {r['wall_s']:.0f} s",
            flush=True,
        )
        runs.append(r)
    return {
        "problem": f"{CONCRETE.relative_to(ROOT)} without {', '.join(drop)}",
        "objective": "mass (min)",
        "grids": {"5 x 2 x 3": grid},
        "runs": runs,
        "comparison": compare({"5 x 2 x 3": grid}, runs, "min"),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("kinematic", "fe", "all"), default="all")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--quick", action="store_true", help="the coarse grid, fewer seeds")
    parser.add_argument("--out", default=None, help="JSON file for the numbers (+ PNG plots)")
    args = parser.parse_args()
    result = {
        "machine": {
            "python": platform.python_version(),
            "cpus": os.cpu_count(),
            "load_average_at_start": os.getloadavg(),
        },
        "workers": args.workers,
    }
    t0 = time.perf_counter()
    if args.part in ("kinematic", "all"):
        result["kinematic"] = kinematic(args)
    if args.part in ("fe", "all"):
        result["fe"] = fe(args)
    result["total_s"] = time.perf_counter() - t0
    for part in ("kinematic", "fe"):
        if part not in result:
            continue
        print(f"\n== {part}: {result[part]['problem']}")
        for label, g in result[part]["grids"].items():
            print(
                f"grid {label}: {g['designs']} designs, {g['feasible']} feasible, best "
                f"{g['best']}, {g['wall_s']:.0f} s"
            )
            for c in result[part]["comparison"][label]:
                print(f"  {c}")
        walls = [r["wall_s"] for r in result[part]["runs"]]
        print(f"optimiser wall time: mean {statistics.fmean(walls):.0f} s")
    if args.out:
        out = Path(args.out)
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(json.dumps(result, indent=1, default=float))
        for part in ("kinematic", "fe"):
            if part in result:
                study = load_study(SHEETS if part == "kinematic" else CONCRETE)
                plot(
                    out.with_name(f"{out.stem}_{part}.png"),
                    f"{result[part]['problem']}: optimiser vs grid ({args.workers} workers)",
                    study,
                    result[part]["grids"],
                    result[part]["runs"],
                )
    print(f"total {result['total_s']:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
