"""The two hot paths of an interactive design studio: redeploy and collision check.

Run from the repository root (results are recorded in ``docs/benchmarks.md``)::

    .venv/bin/python benchmarks/bench_hotpath.py            # both parts
    .venv/bin/python benchmarks/bench_hotpath.py --quick    # fewer repeats, up to 128 segments
    .venv/bin/python benchmarks/bench_hotpath.py --out hotpath.json

1. **Redeploy** (``examples/vault.toml``, 10 plates x 64 segments): the geometry only
   (``model.vertices([alpha])``), ``model.deploy(alpha)`` with its checks (the overlap check), the
   same without the check, the same with the crease records and metrics read, with the whole
   contract (``structure.to_contract()``: also the plates' vertex lists), and a path of 21
   states (``model.path``) with and without the contracts; every call alternates between two
   angles so nothing is cached. The geometry and the checked redeploy are also measured in
   turn, call by call, for their ratio (other load on the machine hits both alike).
2. **Collision check** of the thick plates (``ThickModel.collisions``) per state on the vault at
   32, 64, 128 and 256 segments (five states from the flat stack to the design, time divided by
   five) and on the funnel of catalog Fig. 12c near its limit (where it collides); where the
   check has the ``method`` option, also the brute force (``method="all"``) in the same run.

Each figure is the median wall time (``time.perf_counter``) after a warm-up call. BLAS/OpenMP are
pinned to one thread (set below, before NumPy is imported). The script uses only public API, so
it times an older checkout too (``PYTHONPATH=<old>/src``).
"""

import os

os.environ["OMP_NUM_THREADS"] = "1"
os.environ["OPENBLAS_NUM_THREADS"] = "1"
os.environ["MKL_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import copy  # noqa: E402
import gc  # noqa: E402
import inspect  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from bench_deploy import measure  # noqa: E402

from compas_ccu.catalog import catalog_path  # noqa: E402
from compas_ccu.design import Design  # noqa: E402
from compas_ccu.design.document import read_toml  # noqa: E402
from compas_ccu.model import CCUModel, load_model  # noqa: E402
from compas_ccu.thickness import ThickModel  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
VAULT = ROOT / "examples" / "vault.toml"
ALPHAS = (24.0, 26.0)
SEGMENTS = (32, 64, 128, 256)
STATES = 5  # collision check: states per call


def median_ms(calls, *, target=1.0, min_repeats=5, max_repeats=2000) -> float:
    """Median wall time (ms) of cycling through ``calls`` for about ``target`` seconds
    (:func:`bench_deploy.measure`)."""
    return 1e3 * measure(calls, target=target, min_repeats=min_repeats, max_repeats=max_repeats)[0]


def bench_deploy(target: float) -> dict:
    model = load_model(VAULT)
    a, b = ALPHAS
    path_a, path_b = np.linspace(0.0, 30.0, 21), np.linspace(0.5, 29.5, 21)

    def full(alpha):
        return model.deploy(alpha).to_contract()

    def records(alpha):
        structure = model.deploy(alpha)
        return structure.creases, structure.metrics

    def path_full(alphas):
        return [s.to_contract() for s in model.path(alphas)]

    rows = {
        "geometry: model.vertices([alpha])": [
            lambda: model.vertices([a]),
            lambda: model.vertices([b]),
        ],
        "model.deploy(alpha) (checks)": [lambda: model.deploy(a), lambda: model.deploy(b)],
        "model.deploy(alpha, check=False)": [
            lambda: model.deploy(a, check=False),
            lambda: model.deploy(b, check=False),
        ],
        "model.deploy(alpha), creases and metrics read": [lambda: records(a), lambda: records(b)],
        "model.deploy(alpha) + to_contract()": [lambda: full(a), lambda: full(b)],
        "model.path(21 alphas), per state": [
            lambda: model.path(path_a),
            lambda: model.path(path_b),
        ],
        "model.path(21 alphas) + to_contract(), per state": [
            lambda: path_full(path_a),
            lambda: path_full(path_b),
        ],
    }
    out = {}
    for label, calls in rows.items():
        ms = median_ms(calls, target=target)
        out[label] = ms / 21 if "per state" in label else ms
    # the two of the speed bar measured turn about, so that other load hits both alike
    geometry, checked = paired_ms(
        rows["geometry: model.vertices([alpha])"],
        rows["model.deploy(alpha) (checks)"],
        target=target,
    )
    out["paired: geometry"], out["paired: model.deploy(alpha) (checks)"] = geometry, checked
    return out


def paired_ms(calls_a, calls_b, *, target=1.0) -> tuple:
    """Median wall times (ms) of two call cycles measured in turn, call by call."""
    gc.collect()
    for call in calls_a + calls_b:  # warm-up
        call()
    times_a, times_b = [], []
    start = time.perf_counter()
    i = 0
    while time.perf_counter() - start < target or i < 10:
        for calls, times in ((calls_a, times_a), (calls_b, times_b)):
            t0 = time.perf_counter()
            calls[i % len(calls)]()
            times.append(time.perf_counter() - t0)
        i += 1
    return 1e3 * statistics.median(times_a), 1e3 * statistics.median(times_b)


def vault_model(segments: int) -> CCUModel:
    document = copy.deepcopy(read_toml(VAULT))
    document["crease"]["segments"] = segments
    return CCUModel(Design(document, name="vault"))


def _collision_ms(thick, alphas, target: float, **options) -> float:
    """Median ms per state of ``thick.collisions(alphas, **options)``."""
    ms = median_ms([lambda: thick.collisions(alphas, **options)], target=target, min_repeats=3)
    return ms / len(alphas)


def bench_collisions(segments_list, target: float) -> dict:
    """ms per state of the collision check; with a ``method`` option (the candidate search),
    also of the brute force (``method="all"``) in the same run."""
    brute = "method" in inspect.signature(ThickModel.collisions).parameters
    out = {}
    cases = [
        (f"vault, {n} segments", ThickModel(vault_model(n)), np.linspace(0.0, 30.0, STATES))
        for n in segments_list
    ]
    funnel = ThickModel(load_model(catalog_path("fig12c-funnel")), thickness=0.008)
    label = f"funnel (fig12c), {funnel.model.segments} segments, colliding"
    cases.append((label, funnel, np.linspace(70.0, 77.3, STATES)))
    for label, thick, alphas in cases:
        out[label] = {"default": _collision_ms(thick, alphas, target)}
        if brute:
            out[label]["brute force"] = _collision_ms(thick, alphas, target, method="all")
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats, up to 128 segments")
    parser.add_argument("--out", help="also write the results as JSON")
    args = parser.parse_args(argv)
    target = 0.3 if args.quick else 2.0
    deploy = bench_deploy(target)
    print("| redeploy, vault (10 plates x 64 segments) | ms |")
    print("|---|---:|")
    for label, ms in deploy.items():
        print(f"| {label} | {ms:.3f} |")
    ratio = deploy["paired: model.deploy(alpha) (checks)"] / deploy["paired: geometry"]
    print(f"\nmodel.deploy(alpha) / geometry only, measured in turn: {ratio:.2f}")
    segments = SEGMENTS[:-1] if args.quick else SEGMENTS
    collisions = bench_collisions(segments, target)
    print("\n| collision check (`ThickModel.collisions`), ms per state | default | brute force |")
    print("|---|---:|---:|")
    for label, ms in collisions.items():
        brute = f"{ms['brute force']:.2f}" if "brute force" in ms else "-"
        print(f"| {label} | {ms['default']:.2f} | {brute} |")
    if args.out:
        results = {"deploy": deploy, "collisions": collisions}
        Path(args.out).write_text(json.dumps(results, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
