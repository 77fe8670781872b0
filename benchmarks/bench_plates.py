"""Deployment and collision check against the plate count (issue 31, "linear in plates").

Run from the repository root (results are recorded in ``docs/benchmarks.md``)::

    .venv/bin/python benchmarks/bench_plates.py              # 10 ... 200 plates (~2 min)
    .venv/bin/python benchmarks/bench_plates.py --quick      # 10 ... 50 plates
    .venv/bin/python benchmarks/bench_plates.py --out plates.json
    PYTHONPATH=<old checkout>/src .venv/bin/python benchmarks/bench_plates.py   # an older commit

Two layouts, 64 crease segments, 10, 20, 50, 100 and 200 plates:

* **parallel**: ``examples/vault.toml`` (arc creases in parallel planes 0.12 m apart, 6 mm
  plates) with ``layout.plates`` changed;
* **radial**: the dome of catalog Fig. 12b (planes through one axis) with ``layout.plates``
  changed and ``layout.angle`` = 300° / plates (a radial ring must turn by less than 360°), in
  4 mm plates (the 1.5° plates of a 200-plate ring are 13 mm wide at their narrow end).

What is timed, as CPU time of the process (``time.process_time``; the machine is shared, so
CPU time is steadier than wall time), median of the repeats after a warm-up call:

* **deploy**: ``model.mechanism.deploy(alpha)``, one state (alternating 24° and 26°);
* **collisions / state**: ``ThickModel(model).collisions([alpha_design])``, one state;
* **path (41 states)**: ``ThickModel.collisions()`` with its default 41 states from the flat
  stack to the design angle (one call; in the flat-folded stack and the states near it every
  plate lies within the contact reach of its ~17 neighbours in the stack, and the report's
  check looks only as far as the state's smallest clearance, ``thickness/report_pairs.py``).

The fitted exponent is the least-squares slope of log time against log plates. The load
average (``os.getloadavg``) is printed with every row. BLAS/OpenMP are pinned to one thread
(set below, before NumPy is imported). Only public API is used, so an older checkout runs too.
"""

import os

os.environ["OMP_NUM_THREADS"] = "1"
os.environ["OPENBLAS_NUM_THREADS"] = "1"
os.environ["MKL_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import copy  # noqa: E402
import gc  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from compas_ccu.catalog import catalog_path  # noqa: E402
from compas_ccu.design import Design  # noqa: E402
from compas_ccu.design.document import read_toml  # noqa: E402
from compas_ccu.model import CCUModel  # noqa: E402
from compas_ccu.thickness import ThickModel  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PLATES = (10, 20, 50, 100, 200)
SEGMENTS = 64
PATH_STATES = 41


def parallel(plates: int) -> ThickModel:
    """The vault of ``examples/vault.toml`` with ``plates`` plates."""
    document = copy.deepcopy(read_toml(ROOT / "examples" / "vault.toml"))
    document["layout"]["plates"] = plates
    document["crease"]["segments"] = SEGMENTS
    return ThickModel(CCUModel(Design(document, name="vault")))


def radial(plates: int) -> ThickModel:
    """The dome of catalog Fig. 12b with ``plates`` plates turning 300° in all, 4 mm thick."""
    document = copy.deepcopy(read_toml(catalog_path("fig12b-dome")))
    document["layout"]["plates"] = plates
    document["layout"]["angle"] = 300.0 / plates
    document["crease"]["segments"] = SEGMENTS
    return ThickModel(CCUModel(Design(document, name="dome")), thickness=0.004)


LAYOUTS = {"parallel": parallel, "radial": radial}


def cpu_ms(calls, *, target: float, min_repeats: int = 3, max_repeats: int = 500) -> float:
    """Median CPU time (ms) of cycling through ``calls`` for about ``target`` CPU seconds."""
    gc.collect()
    for call in calls:  # warm-up
        call()
    times = []
    start = time.process_time()
    while len(times) < max_repeats and (
        len(times) < min_repeats or time.process_time() - start < target
    ):
        t0 = time.process_time()
        calls[len(times) % len(calls)]()
        times.append(time.process_time() - t0)
    return 1e3 * statistics.median(times)


def load() -> float:
    """The 1-minute load average."""
    return round(os.getloadavg()[0], 2)


def measure(thick: ThickModel, target: float) -> dict:
    """The timings of one model (module docstring)."""
    mech = thick.model.mechanism
    a, b = np.radians(24.0), np.radians(26.0)
    design = thick.model.alpha_design
    row = {"plates": len(mech.plates), "load_before": load()}
    row["deploy_ms"] = cpu_ms([lambda: mech.deploy(a), lambda: mech.deploy(b)], target=target)
    row["collisions_ms"] = cpu_ms([lambda: thick.collisions([design])], target=target)
    path = np.linspace(0.0, design, PATH_STATES)
    gc.collect()
    t0 = time.process_time()
    report = thick.collisions(path)
    row["path_s"] = time.process_time() - t0
    row["path_ok"] = bool(report.ok)
    row["load_after"] = load()
    return row


def bench_layout(make, plates_list, target: float) -> list:
    rows = []
    for plates in plates_list:
        row = measure(make(plates), target)
        rows.append(row)
        print(
            f"| {plates} | {row['deploy_ms']:.3f} | {row['collisions_ms']:.2f} | "
            f"{row['path_s']:.2f} | {1e3 * row['path_s'] / PATH_STATES:.1f} | "
            f"{row['load_before']} / {row['load_after']} |",
            flush=True,
        )
    return rows


def exponent(rows, key: str) -> float:
    """Least-squares slope of log(time) against log(plates)."""
    plates = np.log([r["plates"] for r in rows])
    return float(np.polyfit(plates, np.log([r[key] for r in rows]), 1)[0])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10, 20 and 50 plates only")
    parser.add_argument("--layout", choices=sorted(LAYOUTS), action="append")
    parser.add_argument("--out", help="also write the results as JSON")
    args = parser.parse_args(argv)
    plates_list = PLATES[:3] if args.quick else PLATES
    target = 0.3 if args.quick else 1.0
    results = {"load_start": load()}
    for name in args.layout or list(LAYOUTS):
        print(f"\n{name}, {SEGMENTS} segments (CPU ms, median; load = 1-min load average)\n")
        print(
            "| plates | deploy ms | collisions ms / state | path (41 states) s | "
            "path ms / state | load before / after |"
        )
        print("|---:|---:|---:|---:|---:|---|")
        rows = bench_layout(LAYOUTS[name], plates_list, target)
        slopes = {key: exponent(rows, key) for key in ("deploy_ms", "collisions_ms", "path_s")}
        print(
            f"\nexponents (time ~ plates^p): deploy {slopes['deploy_ms']:.2f}, collisions / "
            f"state {slopes['collisions_ms']:.2f}, path {slopes['path_s']:.2f}"
        )
        results[name] = {"rows": rows, "exponents": slopes}
    if args.out:
        Path(args.out).write_text(json.dumps(results, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
