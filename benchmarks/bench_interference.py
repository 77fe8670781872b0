"""Cost of the interpenetration certificate (docs/geometry.md §4) per model.

Run from the repository root (``make bench-interference``)::

    .venv/bin/python benchmarks/bench_interference.py

For the vault (10 plates x 64 segments), the dome preset (12 x 48), a 16-plate ring turning
358 deg (24 segments) and the 12 x 29 deg ring that meets itself at 32.7 deg, on a fresh model
each time, it reports the CPU time (``time.process_time``, median of 3) of

1. the first ``model.deploy()`` at the design angle (the scan up to the design, as every
   command pays it once), and
2. ``model.collision_free_alpha`` (the scan of the whole range, as ``ccu info`` and the studio
   pay it once per model),

with the states placed and tested. BLAS/OpenMP are pinned to one thread.
"""

import os

os.environ["OMP_NUM_THREADS"] = "1"
os.environ["OPENBLAS_NUM_THREADS"] = "1"

import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from compas_ccu.design import Design  # noqa: E402
from compas_ccu.model import CCUModel, load_model  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DOME = ROOT / "src" / "compas_ccu" / "data" / "presets" / "dome.toml"


def ring(plates, angle, segments=24):
    return CCUModel(
        Design(
            {
                "design": {"name": f"ring-{plates}"},
                "crease": {
                    "profile": "spline",
                    "points": [[0.25, 1.2], [1.0, 1.0], [1.6, 0.5], [1.9, 0.0]],
                    "segments": segments,
                },
                "rulings": {"type": "orthogonal", "side": "inside"},
                "deployment": {"alpha": 30.0},
                "layout": {"type": "radial", "plates": plates, "angle": angle, "axis": 0.0},
            }
        )
    )


CASES = {
    "vault (10 x 64)": lambda: load_model(ROOT / "examples" / "vault.toml"),
    "dome preset (12 x 48)": lambda: load_model(DOME),
    "ring 16 x 22.375 deg (24)": lambda: ring(16, 358.0 / 16),
    "ring 12 x 29 deg (48)": lambda: ring(12, 29.0, segments=48),
}


def main():
    print(
        f"{platform.processor() or platform.machine()}, Python {sys.version.split()[0]}, "
        f"load {os.getloadavg()[0]:.2f}"
    )
    print("| design | first deploy (design) | states | collision_free_alpha | states | deg |")
    print("|---|---|---|---|---|---|")
    for name, make in CASES.items():

        def first(make=make):
            model = make()
            t = time.process_time()
            model.deploy()
            return time.process_time() - t, model.certificate.states

        def whole(make=make):
            model = make()
            t = time.process_time()
            value = model.collision_free_alpha
            return time.process_time() - t, model.certificate.states, value

        deploy = [first() for _ in range(3)]
        scan = [whole() for _ in range(3)]
        d = statistics.median(x[0] for x in deploy)
        s = statistics.median(x[0] for x in scan)
        print(
            f"| {name} | {d * 1e3:.0f} ms | {deploy[0][1]} | {s * 1e3:.0f} ms | "
            f"{scan[0][1]} | {scan[0][2]:.4f} |"
        )


if __name__ == "__main__":
    main()
