"""Deployment time of the CCU kinematics against vertex count.

Run from the repository root (``make bench`` runs the full benchmark)::

    .venv/bin/python benchmarks/bench_deploy.py               # full: ~1e2 ... ~1e6 vertices
    .venv/bin/python benchmarks/bench_deploy.py --quick       # smoke run: up to ~1e4 vertices
    .venv/bin/python benchmarks/bench_deploy.py --out bench.json

The benchmark builds the corrugated arc vault of ``examples/vault.toml`` (10 plates, parallel
crease planes, orthogonal rulings) with an increasing number of crease segments; the vertex count
is ``plates * 2 * (segments + 1)``. For every size it reports the median wall time
(``time.perf_counter``, after a warm-up call, repeats adapted so that each measurement takes about
one second, fewer for the largest sizes) of

1. ``mechanism.deploy(alpha)``: redeploy the pure-NumPy kinematic core to a new reference angle,
   alternating between 24 and 26 degrees so that nothing can be cached;
2. ``mechanism.deploy(alphas)`` with 100 angles in one call (a whole deployment path), reported
   per state;
3. ``model.deploy(alpha)``: the core plus invariant metrics, the self-intersection check and the
   :class:`~compas_ccu.structure.Structure` object (only up to ~1e5 vertices).

It also splits the "10 plates x 200 segments" case (the speed bar of docs/geometry.md §3: redeploy
well under 10 ms on one core) into the alpha -> s0 inversion, the closed-form leading strip and the
per-plate reflection loop, and fits the scaling exponent (log-log least squares of time against
vertex count over the rows with at least 1e4 vertices).

BLAS/OpenMP are pinned to one thread (set below, before NumPy is imported).
"""

import os

os.environ["OMP_NUM_THREADS"] = "1"
os.environ["OPENBLAS_NUM_THREADS"] = "1"
os.environ["MKL_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import gc  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from compas_ccu import limits
from compas_ccu.design import Design  # noqa: E402
from compas_ccu.model import CCUModel

PLATES = 10
SEGMENTS_FULL = (4, 16, 64, 200, 500, 1000, 5000, 20000, 50000)
SPEC_SEGMENTS = 200
SPEC_LABEL = f"{PLATES} plates x {SPEC_SEGMENTS} segments"
SPEC_BAR_MS = 10.0
QUICK_MAX_VERTICES = 15_000  # --quick: up to ~1e4 vertices
MODEL_MAX_VERTICES = 150_000  # model.deploy (full, with metrics): up to ~1e5 vertices
FIT_MIN_VERTICES = 10_000
ALPHAS_DEG = (24.0, 26.0)  # redeploy alternates between these
PATH_STATES = 100
PATHS_DEG = ((1.0, 29.0), (2.0, 28.0))  # two 100-state paths, alternated
TARGET_S = 1.0  # wall time per measurement
MAX_REPEATS = 2000


def vertex_count(plates: int, segments: int) -> int:
    return plates * 2 * (segments + 1)


def build_model(segments: int, plates: int = PLATES):
    design = Design(
        {
            "design": {"name": "bench"},
            "crease": {
                "profile": "arc",
                "span": 2.5,
                "rise": 1.0,
                "segments": segments,
                "state": "deployed",
            },
            "rulings": {"type": "orthogonal", "side": "inside"},
            "deployment": {"alpha": 30.0},
            "layout": {"type": "parallel", "plates": plates, "spacing": 0.12},
        }
    )
    return CCUModel(design)


def measure(calls, *, target=TARGET_S, min_repeats=5, max_repeats=MAX_REPEATS):
    """Median and minimum wall time (s) of cycling through ``calls``, and the repeat count.

    Every call is made once as a warm-up; the warm-up (or, for fast calls, a short calibration
    batch of about 5 % of ``target``) sets the number of repeats so that the measurement takes
    about ``target`` seconds, clamped to ``[min_repeats, max_repeats]``.
    """
    gc.collect()
    start = time.perf_counter()
    for call in calls:
        call()
    per_call = (time.perf_counter() - start) / len(calls)
    if per_call < 0.05 * target:  # fast calls: calibrate on a short batch after the warm-up
        n, start = 0, time.perf_counter()
        while time.perf_counter() - start < 0.05 * target:
            calls[n % len(calls)]()
            n += 1
        per_call = (time.perf_counter() - start) / n
    repeats = int(min(max_repeats, max(min_repeats, target / max(per_call, 1e-9))))
    times = []
    for i in range(repeats):
        call = calls[i % len(calls)]
        t0 = time.perf_counter()
        call()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), repeats


def min_repeats_for(vertices: int) -> int:
    """Fewer repeats for the largest sizes (each call there takes seconds)."""
    return 3 if vertices >= 300_000 else 5


def bench_row(segments: int, *, with_model: bool) -> dict:
    verts = vertex_count(PLATES, segments)
    t0 = time.perf_counter()
    model = build_model(segments)
    build_s = time.perf_counter() - t0
    mech = model.mechanism
    assert len(mech.plates) == PLATES, len(mech.plates)
    assert mech.segments == segments, mech.segments
    lo = min_repeats_for(verts)

    a, b = np.radians(ALPHAS_DEG)
    deploy_s, deploy_min, deploy_n = measure(
        [lambda: mech.deploy(a), lambda: mech.deploy(b)], min_repeats=lo
    )

    paths = [np.radians(np.linspace(p, q, PATH_STATES)) for p, q in PATHS_DEG]
    path_s, path_min, path_n = measure(
        [lambda: mech.deploy(paths[0]), lambda: mech.deploy(paths[1])], min_repeats=lo
    )

    row = {
        "label": SPEC_LABEL if segments == SPEC_SEGMENTS else f"{PLATES} x {segments}",
        "plates": PLATES,
        "segments": segments,
        "vertices": verts,
        "build_s": build_s,
        "deploy_ms": 1e3 * deploy_s,
        "deploy_min_ms": 1e3 * deploy_min,
        "deploy_repeats": deploy_n,
        "path_states": PATH_STATES,
        "path_call_ms": 1e3 * path_s,
        "path_per_state_ms": 1e3 * path_s / PATH_STATES,
        "path_per_state_min_ms": 1e3 * path_min / PATH_STATES,
        "path_repeats": path_n,
        "model_deploy_ms": None,
        "model_deploy_min_ms": None,
        "model_deploy_repeats": None,
    }
    if with_model:
        da, db = ALPHAS_DEG
        model_s, model_min, model_n = measure(
            [lambda: model.deploy(da), lambda: model.deploy(db)], min_repeats=lo
        )
        row["model_deploy_ms"] = 1e3 * model_s
        row["model_deploy_min_ms"] = 1e3 * model_min
        row["model_deploy_repeats"] = model_n
    return row


def breakdown(segments: int = SPEC_SEGMENTS) -> dict:
    """Split one redeploy of ``mech.deploy`` into its three stages (median ms each)."""
    mech = build_model(segments).mechanism
    lead = mech.leading
    alphas = np.radians(ALPHAS_DEG)
    s0s = [lead.s0_for_alpha(x) for x in alphas]
    invert, _, _ = measure(
        [lambda: lead.s0_for_alpha(alphas[0]), lambda: lead.s0_for_alpha(alphas[1])]
    )
    leading, _, _ = measure([lambda: lead.place(s0s[0]), lambda: lead.place(s0s[1])])
    place, _, _ = measure([lambda: mech.place(s0s[0]), lambda: mech.place(s0s[1])])
    total, _, _ = measure([lambda: mech.deploy(alphas[0]), lambda: mech.deploy(alphas[1])])
    return {
        "label": f"{PLATES} plates x {segments} segments",
        "deploy_ms": 1e3 * total,
        "invert_alpha_ms": 1e3 * invert,
        "leading_place_ms": 1e3 * leading,
        "reflection_loop_ms": 1e3 * (place - leading),
        "mechanism_place_ms": 1e3 * place,
    }


def fit_exponent(rows: list, key: str):
    """Slope of log(time) against log(vertices) over rows with >= FIT_MIN_VERTICES vertices."""
    pts = [(r["vertices"], r[key]) for r in rows if r["vertices"] >= FIT_MIN_VERTICES and r[key]]
    if len(pts) < 2:
        return None
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def _fmt(value, spec=".4g"):
    return "-" if value is None else format(value, spec)


def markdown_table(rows: list) -> str:
    head = (
        "| case | vertices | `mech.deploy(alpha)` ms | reps | path of 100: ms / state | reps "
        "| `model.deploy(alpha)` ms | reps | build s |"
    )
    lines = [head, "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        label = f"**{r['label']}**" if r["segments"] == SPEC_SEGMENTS else r["label"]
        lines.append(
            f"| {label} | {r['vertices']:,} | {_fmt(r['deploy_ms'])} | {r['deploy_repeats']} "
            f"| {_fmt(r['path_per_state_ms'])} | {r['path_repeats']} "
            f"| {_fmt(r['model_deploy_ms'])} | {_fmt(r['model_deploy_repeats'], 'd')} "
            f"| {r['build_s']:.3g} |"
        )
    return "\n".join(lines)


def machine() -> dict:
    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cpu_count": os.cpu_count(),
        "python": sys.version.split()[0],
        "numpy": np.__version__,
        "threads": {
            k: os.environ[k] for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
        },
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smoke run, up to ~1e4 vertices")
    parser.add_argument("--out", metavar="FILE.json", help="also write the results as JSON")
    args = parser.parse_args(argv)

    segments = [
        s for s in SEGMENTS_FULL if not args.quick or vertex_count(PLATES, s) <= QUICK_MAX_VERTICES
    ]
    info = machine()
    print(
        f"# bench_deploy: python {info['python']}, numpy {info['numpy']}, "
        f"{info['cpu_count']} CPUs, BLAS/OpenMP pinned to 1 thread",
        flush=True,
    )
    rows = []
    for s in segments:
        verts = vertex_count(PLATES, s)
        print(f"  {PLATES} x {s} segments ({verts:,} vertices) ...", file=sys.stderr, flush=True)
        rows.append(bench_row(s, with_model=verts <= MODEL_MAX_VERTICES))

    print()
    print(markdown_table(rows))
    print()

    exponents = {
        "mech.deploy(alpha)": fit_exponent(rows, "deploy_ms"),
        "mech.deploy(path) per state": fit_exponent(rows, "path_per_state_ms"),
        "model.deploy(alpha)": fit_exponent(rows, "model_deploy_ms"),
    }
    print(f"Scaling exponent (time ~ vertices^p, rows with >= {FIT_MIN_VERTICES:,} vertices):")
    for name, p in exponents.items():
        note = "" if p is not None else " (needs >= 2 such rows; run without --quick)"
        print(f"  {name:30s} p = {_fmt(p, '.3f')}{note}")

    split = breakdown()
    spec = next((r for r in rows if r["segments"] == SPEC_SEGMENTS), None)
    spec_ms = spec["deploy_ms"] if spec else split["deploy_ms"]
    verdict = "PASS" if spec_ms < SPEC_BAR_MS else "FAIL"
    print()
    print(
        f"speed bar: {SPEC_LABEL} redeploys in {spec_ms:.3f} ms median "
        f"(bar {SPEC_BAR_MS:g} ms, {spec_ms / SPEC_BAR_MS:.1%} of it): {verdict}"
    )
    parts = ("invert_alpha_ms", "leading_place_ms", "reflection_loop_ms")
    total = sum(split[k] for k in parts)
    print(f"Split of one redeploy ({split['label']}, stages timed separately):")
    for k, name in zip(
        parts,
        (
            "alpha -> s0 inversion (Newton)",
            "leading strip closed form",
            "reflection loop (9 plates)",
        ),
    ):
        print(f"  {name:34s} {split[k]:.4f} ms ({split[k] / total:.0%})")

    if args.out:
        with open(args.out, "w", encoding="utf-8") as fh:
            json.dump(
                {
                    "machine": info,
                    "quick": args.quick,
                    "rows": rows,
                    "fit_min_vertices": FIT_MIN_VERTICES,
                    "exponents": exponents,
                    "spec_bar": {"label": SPEC_LABEL, "ms": spec_ms, "bar_ms": SPEC_BAR_MS},
                    "breakdown": split,
                },
                fh,
                indent=2,
            )
        print(f"\nwrote {args.out}")
    return 0


if __name__ == "__main__":
    # a benchmark of up to a million vertices on purpose: beyond the work limits of a design
    with limits.raised(segments=10**6, vertices=10**8, states=10**6, memory_gib=64.0):
        raise SystemExit(main())
