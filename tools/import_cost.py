"""Measure what importing compas_ccu costs, alone and through COMPAS plugin discovery.

Usage: ``python tools/import_cost.py [--runs 5]`` (run with the Python and PYTHONPATH whose
compas_ccu you mean). Each measurement is a fresh interpreter; the table gives the median and
the range over the runs. Numbers are recorded in docs/rhino.md ("Import cost").
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys

PROBES = {
    "python -c pass": "pass",
    "import compas_ccu": "import compas_ccu",
    "import compas.scene": "import compas.scene",
    "Scene plugin discovery": (
        "import compas.scene, time; from compas.scene.context import register_scene_objects; "
        "t = time.perf_counter(); register_scene_objects(); print(time.perf_counter() - t)"
    ),
}

TIMER = (
    "import subprocess, sys, time; t = time.perf_counter(); "
    "out = subprocess.run([sys.executable, '-c', {code!r}], capture_output=True, text=True, "
    "check=True).stdout; print(time.perf_counter() - t, out.strip() or 'nan')"
)


def measure(code: str, runs: int) -> tuple:
    """``(wall seconds, inner seconds)`` per run: wall of a fresh interpreter, inner as printed."""
    walls, inner = [], []
    for _ in range(runs):
        out = subprocess.run(
            [sys.executable, "-c", TIMER.format(code=code)],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.split()
        walls.append(float(out[0]))
        inner.append(float(out[1]))
    return walls, inner


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args(argv)
    print(f"{'probe':28s} {'median s':>9s} {'min s':>7s} {'max s':>7s}   inner median s")
    for name, code in PROBES.items():
        walls, inner = measure(code, args.runs)
        inner_text = "" if all(x != x for x in inner) else f"{statistics.median(inner):.3f}"
        print(
            f"{name:28s} {statistics.median(walls):9.3f} {min(walls):7.3f} {max(walls):7.3f}"
            f"   {inner_text}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
