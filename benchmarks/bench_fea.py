"""FE validation cost and mesh convergence: wall time, size and accuracy against element size.

Run from the repository root::

    .venv/bin/python benchmarks/bench_fea.py                                  # cone, both engines
    .venv/bin/python benchmarks/bench_fea.py --design examples/vault.toml --engines kratos \\
        --sizes 0.2 0.1 0.05 --steps 8 --out bench-fea.json

For every engine and element size it runs a displacement-controlled validation (no structural
checks) and reports nodes, elements, Newton iterations, wall time of the engine, the largest and
mean deviation from the kinematic model (% of span) and the peak bending stress. Results of a run
are recorded in ``docs/fea.md``.
"""

from __future__ import annotations

import argparse
import json
import time

from compas_ccu.fea.validation import validate
from compas_ccu.model import load_model


def run(design: str, engines, sizes, steps: int) -> list:
    model = load_model(design)
    rows = []
    for engine in engines:
        for size in sizes:
            start = time.perf_counter()
            v = validate(model, engine=engine, element_size=size, steps=steps, checks=False)
            total = time.perf_counter() - start
            s = v.summary()
            rows.append(
                {
                    "design": model.design.name,
                    "engine": engine,
                    "element_size": size,
                    "nodes": s["mesh"]["nodes"],
                    "elements": s["mesh"]["elements"],
                    "iterations": sum(s["solver"]["iterations"]),
                    "engine_s": round(s["solver"]["wall_time_s"], 2),
                    "total_s": round(total, 2),
                    "deviation_max_percent": round(s["deviation"]["max_percent"], 4),
                    "deviation_mean_percent": round(s["deviation"]["mean_percent"], 4),
                    "bending_max_MPa": round(s["stresses"]["max_bending_MPa"], 2),
                }
            )
            print(json.dumps(rows[-1]), flush=True)
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--design", default="examples/cone.toml")
    parser.add_argument("--engines", nargs="+", default=["kratos", "opensees"])
    parser.add_argument("--sizes", nargs="+", type=float, default=[0.2, 0.1, 0.05])
    parser.add_argument("--steps", type=int, default=4)
    parser.add_argument("--out", default=None, help="write the rows as JSON")
    args = parser.parse_args(argv)
    rows = run(args.design, args.engines, args.sizes, args.steps)
    keys = list(rows[0])
    print("| " + " | ".join(keys) + " |")
    print("|" + "---|" * len(keys))
    for r in rows:
        print("| " + " | ".join(str(r[k]) for k in keys) + " |")
    if args.out:
        with open(args.out, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
