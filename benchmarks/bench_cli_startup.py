"""CPU time of the ``ccu`` command line starting up: ``ccu --help``, ``ccu --version``.

Run from the repository root (``make bench-cli``)::

    .venv/bin/python benchmarks/bench_cli_startup.py             # 15 runs of each command line
    .venv/bin/python benchmarks/bench_cli_startup.py --runs 5
    .venv/bin/python benchmarks/bench_cli_startup.py --out bench_cli.json

Each command line runs in a fresh process, ``runs`` times; the figure is the median CPU time
(user + system, ``resource.getrusage(RUSAGE_CHILDREN)`` around the child, the same figure as
``/usr/bin/time -f %U+%S``) and the median wall time. It runs

1. ``python -c pass``: the interpreter alone, the floor;
2. ``ccu --help`` and ``ccu --version``: what issue 31 item 6 asks to stay under 0.3 s of CPU;
3. ``python -m compas_ccu --help`` (``python -m compas_ccu.cli`` where the package has no
   ``__main__``);
4. ``ccu deploy --help``: one command's full help, which imports that command's module (COMPAS,
   NumPy, SciPy): what every command pays before it starts its work.

``ccu`` is the console script beside this Python (``.venv/bin/ccu``) if there is one, else
``python -m compas_ccu.cli``. For each line it also reports whether COMPAS, SciPy or Matplotlib
were imported (``-X importtime`` of one more run). BLAS/OpenMP are pinned to one thread.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

HEAVY = ("compas", "scipy", "matplotlib", "numpy", "shapely")
LIMIT = 0.3  # s of CPU, issue 31 item 6


def ccu() -> list:
    script = Path(sys.executable).with_name("ccu")
    return [str(script)] if script.exists() else [sys.executable, "-m", "compas_ccu.cli"]


def package_main() -> list:
    """``python -m compas_ccu``, or ``python -m compas_ccu.cli`` before the package had one."""
    probe = subprocess.run(
        [
            sys.executable,
            "-c",
            "import importlib.util as u; print(u.find_spec('compas_ccu.__main__'))",
        ],
        capture_output=True,
        text=True,
        env=_env(),
    )
    module = "compas_ccu" if probe.stdout.strip() != "None" else "compas_ccu.cli"
    return [sys.executable, "-m", module]


def _env() -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    env.pop("_ARGCOMPLETE", None)
    return env


def cpu_of(argv: list) -> tuple:
    """(CPU s, wall s) of one run of ``argv`` in a fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=_env())
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        raise SystemExit(f"{' '.join(argv)} exited {result.returncode}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall


def heavy_imports(argv: list) -> list:
    """The packages of :data:`HEAVY` that ``argv`` imports (``python -X importtime``; the
    console script is a Python file, run by this Python)."""
    rest = argv[1:] if argv[0] == sys.executable else argv
    err = subprocess.run(
        [sys.executable, "-X", "importtime", *rest], capture_output=True, text=True, env=_env()
    ).stderr
    names = {line.split("|")[-1].strip() for line in err.splitlines() if line.startswith("import")}
    return sorted(h for h in HEAVY if h in names)


def row(label: str, argv: list, runs: int) -> dict:
    cpu_of(argv)  # warm the file cache (.pyc files)
    samples = [cpu_of(argv) for _ in range(runs)]
    return {
        "command": label,
        "cpu_s": statistics.median(s[0] for s in samples),
        "cpu_min_s": min(s[0] for s in samples),
        "wall_s": statistics.median(s[1] for s in samples),
        "imports": heavy_imports(argv) if label != "python -c pass" else [],
    }


def machine() -> dict:
    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cpu_count": os.cpu_count(),
        "python": sys.version.split()[0],
        "load_average": [round(x, 2) for x in os.getloadavg()],
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=15, help="runs of each command line (15)")
    parser.add_argument("--out", metavar="FILE.json", help="also write the results as JSON")
    args = parser.parse_args(argv)

    info = machine()
    print(
        f"# bench_cli_startup: python {info['python']}, {info['cpu_count']} CPUs, "
        f"load {info['load_average'][0]:.2f}, median of {args.runs} runs",
        flush=True,
    )
    lines = [
        ("python -c pass", [sys.executable, "-c", "pass"]),
        ("ccu --help", [*ccu(), "--help"]),
        ("ccu --version", [*ccu(), "--version"]),
        (f"python -m {package_main()[-1]} --help", [*package_main(), "--help"]),
        ("ccu deploy --help", [*ccu(), "deploy", "--help"]),
    ]
    rows = [row(label, line, args.runs) for label, line in lines]
    print()
    print(
        "| command | CPU (median) | CPU (min) | wall (median) | imports of "
        + ", ".join(HEAVY)
        + " |"
    )
    print("|---|---|---|---|---|")
    for r in rows:
        print(
            f"| `{r['command']}` | {r['cpu_s'] * 1e3:.0f} ms | {r['cpu_min_s'] * 1e3:.0f} ms | "
            f"{r['wall_s'] * 1e3:.0f} ms | {', '.join(r['imports']) or 'none'} |"
        )
    slow = [r["command"] for r in rows if r["command"].endswith(("--help", "--version"))
            and "deploy" not in r["command"] and r["cpu_s"] > LIMIT]  # fmt: skip
    print()
    print(f"over {LIMIT} s of CPU: {', '.join(slow) or 'none'}")
    if args.out:
        Path(args.out).write_text(json.dumps({"machine": info, "rows": rows}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
