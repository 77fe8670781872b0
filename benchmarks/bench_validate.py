"""CPU time of ``ccu validate`` split per stage: deployment, every load case's SLS / ULS /
buckling / unloading, the checks and the output.

Run from the repository root::

    .venv/bin/python benchmarks/bench_validate.py        # the vault (make bench-validate)
    .venv/bin/python benchmarks/bench_validate.py --design examples/cone.toml --element-size 0.2 \\
        --steps 4 --out bench-validate.json

It runs what ``ccu validate DESIGN --out DIR`` runs (Kratos, displacement mode, the design's
``[loads]``), timing the Kratos engine's steps, records and buckling analyses by wrapping its
methods (so the same script measures any version of the engine), and reports per stage the CPU
time of the process (``time.process_time``: all threads) and the wall time, with the numbers a
run must reproduce: per case the deflection, the utilisation, the buckling factors and the
deviation. Results are recorded in ``docs/benchmarks.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from collections import defaultdict

from compas_ccu.fea.engines import kratos
from compas_ccu.fea.validation import validate
from compas_ccu.model import load_model


class Clock:
    """CPU and wall time per stage label."""

    def __init__(self):
        self.cpu = defaultdict(float)
        self.wall = defaultdict(float)
        self.labels = {}  # 1-based step -> stage prefix

    def add(self, label, cpu, wall):
        self.cpu[label] += cpu
        self.wall[label] += wall

    def label(self, t: float) -> str:
        step = int(round(t)) if abs(t - round(t)) < 1e-9 else int(t) + 1
        return self.labels.get(step, "deployment")


def _timed(clock: Clock, name, stage):
    original = getattr(kratos._Model, name)

    def wrapper(self, *args, **kwargs):
        c, w = time.process_time(), time.perf_counter()
        try:
            return original(self, *args, **kwargs)
        finally:
            label = stage(self, *args)
            if label is not None:  # None: inside a buckling analysis, counted there
                clock.add(label, time.process_time() - c, time.perf_counter() - w)

    wrapper.__wrapped__ = original
    return wrapper


def instrument(clock: Clock) -> list:
    """Wrap the engine's methods; returns the originals to restore."""
    state = {"buckling": 0}

    def advance_stage(model, t, *args):
        return None if state["buckling"] else clock.label(t)

    def record_stage(model, *args):
        return "records"

    originals = [(n, getattr(kratos._Model, n)) for n in ("advance", "record", "buckling")]
    kratos._Model.advance = _timed(clock, "advance", advance_stage)
    kratos._Model.record = _timed(clock, "record", record_stage)
    buckling_original = originals[2][1]

    def buckling(self, *args, **kwargs):
        # everything inside the buckling analysis (its two re-solves included) is "buckling"
        label = clock.label(self.time).split(":")[0] + ": buckling"
        state["buckling"] += 1
        c, w = time.process_time(), time.perf_counter()
        try:
            return buckling_original(self, *args, **kwargs)
        finally:
            state["buckling"] -= 1
            clock.add(label, time.process_time() - c, time.perf_counter() - w)

    kratos._Model.buckling = buckling
    return originals


def restore(originals):
    for name, f in originals:
        setattr(kratos._Model, name, f)


def run(design: str, element_size: float, steps: int, out: str | None) -> dict:
    model = load_model(design)
    clock = Clock()
    originals = instrument(clock)
    try:
        c0, w0 = time.process_time(), time.perf_counter()
        # the labels need the load steps: set them as soon as the problem exists
        from compas_ccu.fea import displacement

        problem_original = displacement.deployment_problem

        def deployment_problem(*args, **kwargs):
            got = problem_original(*args, **kwargs)
            load_steps = got[4]
            for e in load_steps:
                name = e["case"].name
                clock.labels[e["sls"] + 1] = f"{name}: sls"
                clock.labels[e["uls"] + 1] = f"{name}: uls"
                clock.labels[e["uls"] + 2] = f"{name}: unloading"
            return got

        displacement.deployment_problem = deployment_problem
        try:
            v = validate(model, engine="kratos", element_size=element_size, steps=steps)
        finally:
            displacement.deployment_problem = problem_original
        c1, w1 = time.process_time(), time.perf_counter()
        summary = v.summary()
        c2, w2 = time.process_time(), time.perf_counter()
        with tempfile.TemporaryDirectory() as tmp:
            v.write(out or tmp)
        c3, w3 = time.process_time(), time.perf_counter()
    finally:
        restore(originals)
    engine_cpu = sum(clock.cpu.values())
    engine_wall = sum(clock.wall.values())
    clock.add(
        "validate (rest: mesh, model build, comparison)",
        c1 - c0 - engine_cpu,
        w1 - w0 - engine_wall,
    )
    clock.add("summary and checks", c2 - c1, w2 - w1)
    clock.add("output writing", c3 - c2, w3 - w2)
    checks = summary["checks"] or {"cases": []}
    cases = [
        {
            "case": c["name"],
            "deflection_max_mm": round(1e3 * c["deflection_max_m"], 5),
            "deflection_final_max_mm": None
            if c["deflection_final_max_m"] is None
            else round(1e3 * c["deflection_final_max_m"], 5),
            "utilisation_max": round(c["utilisation_max"], 5),
            "buckling_factor": None
            if c["buckling_factor"] is None
            else round(c["buckling_factor"], 5),
            "buckling_factor_mean": None
            if c["buckling_factor_mean"] is None
            else round(c["buckling_factor_mean"], 5),
            "buckling_note": c["buckling_note"],
        }
        for c in checks["cases"]
    ]
    return {
        "design": design,
        "element_size": element_size,
        "steps": steps,
        "elements": summary["mesh"]["elements"],
        "machine": f"{platform.node()} {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores",
        "load_average": [round(x, 2) for x in os.getloadavg()],
        "cpu_s": {k: round(x, 2) for k, x in clock.cpu.items()},
        "wall_s": {k: round(x, 2) for k, x in clock.wall.items()},
        "cpu_total_s": round(c3 - c0, 2),
        "wall_total_s": round(w3 - w0, 2),
        "deviation_max_percent": round(summary["deviation"]["max_percent"], 5),
        "utilisation_max": None if not checks["cases"] else round(checks["utilisation_max"], 5),
        "buckling_factor": checks.get("buckling_factor"),
        "cases": cases,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--design", default="examples/vault.toml")
    parser.add_argument("--element-size", type=float, default=0.1)
    parser.add_argument("--steps", type=int, default=8)
    parser.add_argument("--out", default=None, help="write the validation into this folder")
    parser.add_argument("--json", default=None, help="write the measurement as JSON")
    args = parser.parse_args(argv)
    row = run(args.design, args.element_size, args.steps, args.out)
    print("| stage | CPU s | wall s |")
    print("|---|---:|---:|")
    for k in row["cpu_s"]:
        print(f"| {k} | {row['cpu_s'][k]:.1f} | {row['wall_s'][k]:.1f} |")
    print(f"| total | {row['cpu_total_s']:.1f} | {row['wall_total_s']:.1f} |")
    print(json.dumps({k: row[k] for k in row if k not in ("cpu_s", "wall_s")}, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(row, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
