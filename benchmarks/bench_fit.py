"""CPU time of fitting to geometry (docs/fit.md, docs/benchmarks.md).

Run from the repository root (``make bench-fit``)::

    .venv/bin/python benchmarks/bench_fit.py [--quick]

1. ``fit_design``: crease.rise, deployment.alpha and layout.spacing of examples/vault.toml
   fitted to a 50,000-point target (the vault with rise 1.1 m, alpha 28 deg, spacing 0.13 m);
2. ``register``: a 10^6-point scan of the vault at alpha 27 deg (40 % missing, 2 mm noise,
   10 % outliers, moved), registered and every point measured.

CPU seconds (``time.process_time``), one run each; BLAS/OpenMP pinned to one thread. ``--quick``
uses 10^5 scan points and a 10,000-point target. The issue's budget (issue 30) is 30 s of CPU on
one core for each; the line says whether it holds.

Recorded in docs/benchmarks.md: the 10^6-point registration took 71.8-85.7 s of CPU before the
speed-up (fit-speed) and 17.7-18.3 s after, the same α, RMS and noise; the 50,000-point fit
13.1-13.7 s before and 4.1-4.2 s after, the same results.
"""

import os

os.environ["OMP_NUM_THREADS"] = "1"
os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import subprocess  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from compas_ccu.design import Design, load_design  # noqa: E402
from compas_ccu.fit import (  # noqa: E402
    PointSet,
    fit_design,
    parse_free,
    plate_triangles,
    register,
    sample_triangles,
)
from compas_ccu.fit.rigid import apply, matrix, rotation  # noqa: E402
from compas_ccu.model import CCUModel, load_model  # noqa: E402

VAULT = "examples/vault.toml"
#: CPU seconds each fit may take (issue 30).
BUDGET = 30.0


def plate_points(model, alpha, count, seed):
    tri, _ = plate_triangles(model.vertices([alpha])[0], model.faces)
    flat = np.arange(len(tri) * 3).reshape(-1, 3)
    return sample_triangles(tri.reshape(-1, 3), flat, count, seed=seed)


def bench_fit(points):
    base = load_design(VAULT)
    doc = base.metric_document()
    doc["crease"]["rise"] = 1.1
    doc["deployment"]["alpha"] = 28.0
    doc["layout"]["spacing"] = 0.13
    truth = CCUModel(Design(doc))
    pts, normals, _ = plate_points(truth, truth.alpha_design, points, 3)
    target = PointSet(pts, normals, "target", "mesh")
    free = parse_free("crease.rise=0.8:1.4,deployment.alpha=20:40,layout.spacing=0.08:0.2")
    t = time.process_time()
    r = fit_design(base, target, free)
    cpu = time.process_time() - t
    print(f"fit_design, {points} target points: {cpu:.1f} s CPU, {r.evaluations} models")
    print(f"  {'within' if cpu <= BUDGET else 'OVER'} the {BUDGET:.0f} s budget")
    for key, value in r.parameters.items():
        print(f"  {key} = {value:.5f}")
    print(
        f"  RMS {1000 * r.rms:.3f} mm, max {1000 * r.max:.2f} mm, "
        f"Hausdorff {1000 * r.hausdorff:.1f} mm"
    )


def bench_register(count):
    model = load_model(VAULT)
    _ = model.collision_free_alpha  # the model's certificate, as every command pays it once
    rng = np.random.default_rng(1)
    pts, _, _ = plate_points(model, 27.0, int(count * 0.9 / 0.6), 1)
    pts = pts[pts[:, 0] < np.quantile(pts[:, 0], 0.6)]
    pts = pts + rng.normal(scale=0.002, size=pts.shape)
    lo, hi = pts.min(0), pts.max(0)
    out = rng.uniform(lo - 0.1, hi + 0.1, (count - len(pts), 3))
    scan = apply(matrix(rotation([0.3, -0.5, 1.2]), [5.0, -2.0, 1.5]), np.concatenate([pts, out]))
    t = time.process_time()
    r = register(model, scan, per_plate=True)
    cpu = time.process_time() - t
    print(f"register, {len(scan)} scan points: {cpu:.1f} s CPU, {r.evaluations} evaluations")
    print(f"  {'within' if cpu <= BUDGET else 'OVER'} the {BUDGET:.0f} s budget")
    print(
        f"  alpha {r.alpha:.3f} deg (27), inlier RMS {1000 * r.rms:.2f} mm, noise "
        f"{1000 * r.noise:.2f} mm, outliers {r.outliers}, coverage {100 * r.coverage:.1f} %"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    print("load before:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    bench_fit(10_000 if args.quick else 50_000)
    bench_register(100_000 if args.quick else 1_000_000)
    print("load after:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())


if __name__ == "__main__":
    main()
