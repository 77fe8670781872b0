"""Speed of the thickness model: thick placement, collision check and bending check.

Run: ``.venv/bin/python benchmarks/bench_thickness.py`` (``make bench-thickness``); results are
recorded in ``docs/benchmarks.md``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from compas_ccu.catalog import CATALOG_DIR
from compas_ccu.model import load_model
from compas_ccu.thickness import ThickModel

ROOT = Path(__file__).resolve().parents[1]


def best_of(fn, repeats: int = 5) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def bench_design(name: str) -> tuple:
    """One table row: timings of the thickness model of ``examples/<name>`` or catalog design
    ``catalog/<name>``."""
    catalog = name.startswith("catalog/")
    file = CATALOG_DIR / name[len("catalog/") :] if catalog else ROOT / "examples" / name
    model = load_model(file)
    thick = ThickModel(model)
    path = np.linspace(0.0, model.alpha_design, 41)
    verts = len(model.plate_ids) * (2 * model.segments + 2)
    return (
        name,
        len(model.plate_ids),
        verts,
        best_of(lambda: ThickModel(model), 3) * 1e3,
        best_of(lambda: model.mechanism.deploy(np.radians([20.0])), 20) * 1e3,
        best_of(lambda: thick.place([20.0]), 20) * 1e3,
        best_of(lambda: thick.place(path), 5) * 1e3,
        best_of(lambda: thick.bending(path), 5) * 1e3,
        best_of(lambda: thick.collisions(path), 2),
    )


def main() -> int:
    rows = [bench_design(name) for name in ("vault.toml", "catalog/fig12c-funnel.toml")]
    print(
        "| design | plates | vertices | ThickModel() ms | zero-t state ms | thick state ms "
        "| 41 thick states ms | bending, 41 states ms | collisions, 41 states s |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r[0]} | {r[1]} | {r[2]:,} | {r[3]:.1f} | {r[4]:.2f} | {r[5]:.2f} | {r[6]:.1f} "
            f"| {r[7]:.1f} | {r[8]:.2f} |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
