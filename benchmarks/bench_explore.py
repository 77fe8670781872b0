"""Throughput of a design-space sweep on 1 and 2 local Dask workers, and where the time goes.

Run from the repository root (``make bench-explore``); results are recorded in
``docs/benchmarks.md``::

    .venv/bin/python benchmarks/bench_explore.py              # the example sweep, 270 variants
    .venv/bin/python benchmarks/bench_explore.py --quick      # its first 60 variants
    .venv/bin/python benchmarks/bench_explore.py --out benchmarks/results/bench_explore.json

1. The example sweep (``examples/sweeps/vault.toml``: vault variants with the bending and the
   collision check over 11 path states) runs in-process (no Dask: the serial baseline), then on
   a fresh local cluster with 1 and with 2 worker processes. Throughput is variants per second
   from the first submission to the last result (the cluster start is reported apart); the
   scaling efficiency is ``throughput(2) / (2 * throughput(1))``.
2. The mean time of every evaluation stage (model, path, thickness, collisions) from the rows.
3. A profile (cProfile, by own time) of the slowest stage on 3 variants.

The kinematics' scaling with vertex count (1e2 ... 1e6) is ``benchmarks/bench_deploy.py``
(``make bench``).
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import platform
import pstats
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from compas_ccu.explore import evaluate_variant, load_sweep, run_sweep
from compas_ccu.explore.evaluate import STAGES
from compas_ccu.model import CCUModel

ROOT = Path(__file__).resolve().parents[1]
SWEEP = ROOT / "examples" / "sweeps" / "vault.toml"


def timed_run(sweep, **options) -> dict:
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        r = run_sweep(sweep, out, progress=False, summary=False, **options)
        wall = time.perf_counter() - t0
    stages = {
        s: statistics.fmean(x[f"t_{s}"] for x in r.rows if x.get(f"t_{s}") is not None)
        for s in STAGES
        if any(x.get(f"t_{s}") is not None for x in r.rows)
    }
    return {
        "scheduler": r.scheduler,
        "workers": r.workers,
        "variants": r.computed,
        "failed": r.failed,
        "seconds": r.seconds,
        "startup_s": r.startup,
        "wall_s": wall,
        "throughput_per_s": r.throughput,
        "mean_variant_s": statistics.fmean(x["seconds"] for x in r.rows),
        "stage_mean_s": stages,
    }


def stage_call(stage: str, document: dict, options: dict):
    """A zero-argument call that runs only ``stage`` of one variant (the rest prepared)."""
    from compas_ccu.design.document import Design
    from compas_ccu.explore import metrics as mx
    from compas_ccu.thickness import ThickModel

    alphas = np.linspace(0.0, document["deployment"]["alpha"], options["path_states"])
    if stage == "model":
        return lambda: mx.shape_metrics(*(lambda m: (m, m.deploy()))(CCUModel(Design(document))))
    model = CCUModel(Design(document))
    if stage == "path":
        return lambda: mx.path_metrics(model, alphas)
    if stage == "thickness":
        return lambda: mx.thickness_metrics(ThickModel(model), alphas)
    thick = ThickModel(model)
    if stage == "collisions":
        return lambda: mx.collision_metrics(thick, alphas)
    return lambda: mx.fe_metrics(model, thick, options["fe"])


def profile_stage(sweep, stage: str, count: int = 3, top: int = 14) -> tuple:
    calls = [
        stage_call(stage, sweep.document_for(v), sweep.options)
        for v in sweep.variants[:: max(1, len(sweep.variants) // count)][:count]
    ]
    profiler = cProfile.Profile()
    profiler.enable()
    for call in calls:
        call()
    profiler.disable()
    stream = io.StringIO()
    stats = pstats.Stats(profiler, stream=stream)
    total = stats.total_tt
    rows = []
    for (file, line, name), (_, ncalls, tottime, cumtime, _) in sorted(
        stats.stats.items(), key=lambda kv: -kv[1][2]
    )[:top]:
        where = f"{Path(file).name}:{line}" if line else file
        rows.append(
            {
                "function": f"{name} ({where})",
                "calls": ncalls,
                "own_s": tottime,
                "share": tottime / total,
                "cumulative_s": cumtime,
            }
        )
    return total / len(calls), rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="the first 60 variants only")
    parser.add_argument("--variants", type=int, default=None, help="the first N variants")
    parser.add_argument("--out", default=None, help="write the results as JSON")
    args = parser.parse_args()
    sweep = load_sweep(SWEEP)
    n = args.variants or (60 if args.quick else len(sweep.variants))
    sweep.variants = sweep.variants[:n]
    print(
        f"sweep {sweep.name}: {n} variants, {os.cpu_count()} cores, "
        f"{platform.processor() or platform.machine()}"
    )
    evaluate_variant(sweep.document_for(sweep.variants[0]), **sweep.options)  # warm the imports
    runs = [timed_run(sweep, in_process=True)]
    for workers in (1, 2):
        runs.append(timed_run(sweep, workers=workers))
    print(
        "\n| run | workers | variants | time s | cluster start s | variants/s "
        "| mean per variant s |"
    )
    print("|---|---|---|---|---|---|---|")
    for r in runs:
        print(
            f"| {r['scheduler']} | {r['workers']} | {r['variants']} | {r['seconds']:.1f} "
            f"| {r['startup_s']:.1f} | {r['throughput_per_s']:.2f} | {r['mean_variant_s']:.3f} |"
        )
    one, two = runs[1]["throughput_per_s"], runs[2]["throughput_per_s"]
    efficiency = two / (2.0 * one)
    print(f"\nspeed-up 2 workers / 1 worker: {two / one:.2f}x, scaling efficiency {efficiency:.0%}")
    print("\n| stage | in-process s | 1 worker s | 2 workers s |")
    print("|---|---|---|---|")
    for stage in runs[0]["stage_mean_s"]:
        cells = " | ".join(f"{r['stage_mean_s'][stage]:.4f}" for r in runs)
        print(f"| {stage} | {cells} |")
    slowest = max(runs[0]["stage_mean_s"], key=runs[0]["stage_mean_s"].get)
    per_call, rows = profile_stage(sweep, slowest)
    print(
        f"\nprofile of the slowest stage, {slowest} ({per_call:.3f} s per variant under cProfile):"
    )
    print("\n| function | calls | own time s | share |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| `{r['function']}` | {r['calls']} | {r['own_s']:.3f} | {r['share']:.0%} |")
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(
            json.dumps(
                {
                    "variants": n,
                    "cores": os.cpu_count(),
                    "runs": runs,
                    "speedup": two / one,
                    "efficiency": efficiency,
                    "slowest_stage": slowest,
                    "profile": rows,
                },
                indent=1,
            )
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
