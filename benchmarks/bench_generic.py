"""The closed-form kinematics against a generic solver of the same mechanism (issue 31 item 2).

Run from the repository root (results are recorded in ``docs/benchmarks.md``)::

    .venv/bin/python benchmarks/bench_generic.py                 # 64, 200 and 1000 segments
    .venv/bin/python benchmarks/bench_generic.py --quick         # 64 and 200 segments
    .venv/bin/python benchmarks/bench_generic.py --out generic.json
    PYTHONPATH=<old checkout>/src .venv/bin/python benchmarks/bench_generic.py   # an older commit

The design is the vault of ``examples/vault.toml`` (10 plates) with ``crease.segments`` = 64,
200 and 1000. A state is asked for at alpha = 25 deg, coming from its neighbour at 24 deg (a
slider step of 1 deg) and at 24.9 deg (0.1 deg).

* **closed form**: ``mechanism.deploy(alpha)`` (:mod:`compas_ccu.kinematics.mechanism`), one
  state from nothing but alpha.
* **generic solver**: what solving the mechanism as a set of equations costs. The unknowns are
  the vertices of plates 1 ... p - 1 (each plate's near boundary merged with its parent's
  crease row, so the hinges are shared exactly); the leading plate is held at its closed-form
  placement at the new alpha (the actuation); the residuals are, per quad, the six relative
  length errors of its sides and diagonals (isometry) and its planarity residual, without
  which a warped quad would cost lengths only to second order (the residuals and the banded
  normal equations of :class:`compas_ccu.kinematics.relaxation_problem.RelaxationProblem`).
  It starts from the neighbouring state's vertices. Two solvers:

  - **banded Gauss-Newton** (the best of the two): undamped steps, each a banded Cholesky
    solve of ``J^T J`` (unknowns in reverse Cuthill-McKee order, band ~30 for 10 plates,
    :func:`scipy.linalg.solveh_banded`), stopped as soon as its largest residual is at most
    the closed form's own at that state (equal accuracy); the index arrays and the ordering
    are built once per model and not timed;
  - **relax**: :func:`compas_ccu.kinematics.relaxation.relax` (Levenberg-Marquardt on the same
    banded system, its default tolerances), set-up included: what ``CCUModel.relax`` pays.

Every figure is CPU time (``time.process_time``; the machine is shared), the median of the
repeats after a warm-up call; BLAS/OpenMP are pinned to one thread (set below, before NumPy is
imported). The ratio is the solver's median over the closed form's. The accuracy columns are
the largest relative length error (isometry) of either result and the largest distance between
the two solutions. The 1-minute load average is printed with every row.
"""

import os

os.environ["OMP_NUM_THREADS"] = "1"
os.environ["OPENBLAS_NUM_THREADS"] = "1"
os.environ["MKL_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import copy  # noqa: E402
import gc  # noqa: E402
import itertools  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from functools import partial  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.linalg import solveh_banded  # noqa: E402

from compas_ccu import limits  # noqa: E402
from compas_ccu.design import Design  # noqa: E402
from compas_ccu.design.document import read_toml  # noqa: E402
from compas_ccu.kinematics.relaxation import links_from_mechanism, relax  # noqa: E402
from compas_ccu.kinematics.relaxation_problem import RelaxationProblem  # noqa: E402
from compas_ccu.model import CCUModel  # noqa: E402
from compas_ccu.strips.intrinsics import quad_lengths  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SEGMENTS = (64, 200, 1000)
TARGET_DEG = 25.0
STEPS_DEG = (1.0, 0.1)  # the neighbouring state: alpha - step
MAX_ITERATIONS = 30


def vault(segments: int) -> CCUModel:
    document = copy.deepcopy(read_toml(ROOT / "examples" / "vault.toml"))
    document["crease"]["segments"] = segments
    with limits.raised(segments=10**5, vertices=10**7):
        return CCUModel(Design(document, name="vault"))


def cpu_times(call, *, target: float, min_repeats: int = 5, max_repeats: int = 2000) -> list:
    """CPU times (s) of ``call`` repeated for about ``target`` CPU seconds, after a warm-up."""
    gc.collect()
    call()
    times = []
    start = time.process_time()
    while len(times) < max_repeats and (
        len(times) < min_repeats or time.process_time() - start < target
    ):
        t0 = time.process_time()
        call()
        times.append(time.process_time() - t0)
    return times


def gauss_newton(problem: RelaxationProblem, base: np.ndarray, worst: float):
    """Undamped banded Gauss-Newton from node positions ``base`` (N, 3) until the largest
    residual is at most ``worst``: the positions, the iterations and the residual reached."""
    pos = base
    x = base[problem.order].ravel()
    for iteration in range(MAX_ITERATIONS + 1):
        r = problem.quad_residuals(pos)
        reached = float(np.abs(r).max())
        if reached <= worst or iteration == MAX_ITERATIONS:
            return pos, iteration, reached
        ab, g = problem.normal_equations(pos, r)
        x = x + solveh_banded(ab, -g, lower=True, overwrite_ab=True, check_finite=False)
        pos = base.copy()
        pos[problem.order] = x.reshape(-1, 3)


def load() -> float:
    return round(os.getloadavg()[0], 2)


def bench(segments: int, target: float) -> list:
    """The rows of one model: one per neighbouring step."""
    model = vault(segments)
    mech = model.mechanism
    ref = model.reference_lengths
    links = links_from_mechanism(mech)
    problem = RelaxationProblem(len(mech.plates), mech.segments, ref, links, (0,), 1.0)
    alpha = np.radians(TARGET_DEG)
    other = np.radians(TARGET_DEG - 2.0)  # the closed form alternates, so nothing is kept
    angles = itertools.cycle((alpha, other))
    deploy = cpu_times(lambda: mech.deploy(next(angles)), target=target)
    exact = mech.deploy(alpha)
    exact_nodes = problem.start(exact.near[0], exact.far[0])
    worst = float(np.abs(problem.quad_residuals(exact_nodes)).max())
    isometry = float(np.abs(quad_lengths(exact.near[0], exact.far[0]) / ref - 1.0).max())
    rows = []
    for step in STEPS_DEG:
        start = mech.deploy(np.radians(TARGET_DEG - step))
        near, far = start.near[0].copy(), start.far[0].copy()
        near[0], far[0] = exact.near[0, 0], exact.far[0, 0]  # the actuation: the leading plate
        base = problem.start(near, far)
        gn = cpu_times(partial(gauss_newton, problem, base, worst), target=target, min_repeats=3)
        pos, iterations, reached = gauss_newton(problem, base, worst)
        gn_near, gn_far = problem.plates(pos)
        lm = cpu_times(partial(relax, near, far, ref, links), target=target, min_repeats=3)
        relaxed = relax(near, far, ref, links)
        deploy_ms = 1e3 * statistics.median(deploy)
        gn_ms = 1e3 * statistics.median(gn)
        lm_ms = 1e3 * statistics.median(lm)
        rows.append(
            {
                "segments": segments,
                "vertices": int(exact.near[0].size // 3 * 2),
                "step_deg": step,
                "deploy_ms": deploy_ms,
                "deploy_repeats": len(deploy),
                "gauss_newton_ms": gn_ms,
                "gauss_newton_iterations": iterations,
                "gauss_newton_repeats": len(gn),
                "relax_ms": lm_ms,
                "relax_nfev": int(relaxed.nfev),
                "ratio_gauss_newton": gn_ms / deploy_ms,
                "ratio_relax": lm_ms / deploy_ms,
                "isometry_closed_form": isometry,
                "isometry_gauss_newton": float(
                    np.abs(quad_lengths(gn_near, gn_far) / ref - 1.0).max()
                ),
                "isometry_relax": float(relaxed.max_strain),
                "largest_residual_gauss_newton": reached,
                "distance_gauss_newton": float(np.abs(pos - exact_nodes).max()),
                "load": load(),
            }
        )
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="64 and 200 segments only")
    parser.add_argument("--out", help="also write the results as JSON")
    args = parser.parse_args(argv)
    segments = SEGMENTS[:2] if args.quick else SEGMENTS
    target = 0.5 if args.quick else 2.0
    print(
        "| segments | step | closed form ms | Gauss-Newton ms (iterations) | ratio | relax ms "
        "(nfev) | ratio | isometry closed form / GN / relax | GN distance m | load |"
    )
    print("|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|")
    rows = []
    for n in segments:
        for r in bench(n, target):
            rows.append(r)
            print(
                f"| {n} | {r['step_deg']:g} deg | {r['deploy_ms']:.3f} | "
                f"{r['gauss_newton_ms']:.2f} ({r['gauss_newton_iterations']}) | "
                f"{r['ratio_gauss_newton']:.1f} | {r['relax_ms']:.2f} ({r['relax_nfev']}) | "
                f"{r['ratio_relax']:.1f} | {r['isometry_closed_form']:.1e} / "
                f"{r['isometry_gauss_newton']:.1e} / {r['isometry_relax']:.1e} | "
                f"{r['distance_gauss_newton']:.1e} | {r['load']} |",
                flush=True,
            )
    if args.out:
        Path(args.out).write_text(json.dumps({"rows": rows}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
