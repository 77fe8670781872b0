"""Time per state of the least-squares relaxation: Levenberg-Marquardt (new) against scipy (old).

Run from the repository root (``make bench-relax``)::

    .venv/bin/python benchmarks/bench_relax.py             # fig12a and fig12c, 3 angles each
    .venv/bin/python benchmarks/bench_relax.py --quick     # one angle each (~20 s)
    .venv/bin/python benchmarks/bench_relax.py --out bench_relax.json

The designs are catalog Fig. 12a (inclined planes, 10 plates) and Fig. 12c (radial funnel,
12 plates), 48 segments each: their creases leave their planes between the flat and the design
state, so :meth:`CCUModel.relax` has work to do. For every state it reports the median wall
time (``time.perf_counter``, after a warm-up call, repeats adapted so that a measurement takes
about one second, at least 3) of one :func:`compas_ccu.kinematics.relaxation.relax` call -- what
``CCUModel.relax`` pays, set-up of the index arrays included -- with

1. ``solver="lm"`` (new default): Levenberg-Marquardt, banded Cholesky of the damped normal
   equations in reverse Cuthill-McKee order;
2. ``solver="scipy"`` (old default, the reference): ``scipy.optimize.least_squares`` (trf, LSMR
   subproblem, ``x_scale="jac"``);

with the residuals each reaches (max strain, quad planarity, cost) and their evaluations. It
also times ``relax_states`` over all angles of a design (set-up shared, per state), and splits
one LM iteration on the 12a state at 17.5 deg: residuals, banded normal equations, and the
damped solve by ``solveh_banded`` against ``splu`` (natural and COLAMD column orders) and
against ``solveh_banded`` with the natural plate-by-plate unknown order (wider band).

BLAS/OpenMP are pinned to one thread (set below, before NumPy is imported).
"""

import os

os.environ["OMP_NUM_THREADS"] = "1"
os.environ["OPENBLAS_NUM_THREADS"] = "1"
os.environ["MKL_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import gc  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import scipy  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from bench_deploy import machine as deploy_machine  # noqa: E402
from scipy.linalg import solveh_banded  # noqa: E402
from scipy.sparse.linalg import splu  # noqa: E402

from compas_ccu.catalog import catalog_design  # noqa: E402
from compas_ccu.kinematics.relaxation import (  # noqa: E402
    links_from_mechanism,
    relax,
    relax_states,
)
from compas_ccu.kinematics.relaxation_problem import RelaxationProblem  # noqa: E402
from compas_ccu.model import CCUModel  # noqa: E402

DESIGNS = (("fig12a-asymmetric", "inclined"), ("fig12c-funnel", "radial"))
ALPHAS_DEG = (10.0, 17.5, 25.0)
QUICK_ALPHAS_DEG = (17.5,)
TARGET_S = 1.0
BAR_MS = 30.0  # the live design studio's budget per state


def measure(call, *, target=TARGET_S, min_repeats=3, max_repeats=500):
    """Median and minimum wall time (s) of ``call`` and the repeat count (after one warm-up)."""
    gc.collect()
    t0 = time.perf_counter()
    call()
    first = time.perf_counter() - t0
    repeats = int(min(max_repeats, max(min_repeats, target / max(first, 1e-9))))
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        call()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), repeats


def residuals(result) -> dict:
    return {
        "converged": bool(result.converged),
        "status": int(result.status),
        "nfev": int(result.nfev),
        "njev": int(result.njev),
        "initial_max_strain": float(result.initial_max_strain),
        "max_strain": float(result.max_strain),
        "quad_planarity": float(result.quad_planarity),
        "cost": float(result.cost),
        "optimality": float(result.optimality),
    }


def bench_design(name: str, layout: str, alphas, *, min_repeats_old: int) -> dict:
    model = CCUModel(catalog_design(name))
    links = links_from_mechanism(model.mechanism)
    ref = model.reference_lengths
    states = model.mechanism.deploy(np.radians(alphas))
    p, m = states.near.shape[1], states.near.shape[2]
    problem = RelaxationProblem(p, m - 1, ref, links, (0,), 1.0)
    rows = []
    for k, alpha in enumerate(alphas):
        near, far = states.near[k], states.far[k]
        row = {"alpha_deg": alpha}
        for solver, lo in (("lm", 5), ("scipy", min_repeats_old)):
            print(f"  {name} alpha {alpha:g}: {solver} ...", file=sys.stderr, flush=True)
            result = relax(near, far, ref, links, solver=solver)
            median, best, n = measure(
                lambda near=near, far=far, solver=solver: relax(
                    near, far, ref, links, solver=solver
                ),
                min_repeats=lo,
            )
            row[solver] = {"ms": 1e3 * median, "min_ms": 1e3 * best, "repeats": n}
            row[solver].update(residuals(result))
        row["speedup"] = row["scipy"]["ms"] / row["lm"]["ms"]
        rows.append(row)
    path, _, _ = measure(lambda: relax_states(states.near, states.far, ref, links))
    return {
        "design": name,
        "layout": layout,
        "plates": int(p),
        "segments": int(m - 1),
        "unknowns": 3 * problem.nfree,
        "band": int(problem.band),
        "rows": rows,
        "relax_states_ms_per_state": 1e3 * path / len(alphas),
    }


def iteration_split(name: str = "fig12a-asymmetric", alpha: float = 17.5) -> dict:
    """Median ms of the parts of one LM iteration, and of other ways to solve its system."""
    model = CCUModel(catalog_design(name))
    links = links_from_mechanism(model.mechanism)
    st = model.mechanism.deploy(np.radians([alpha]))
    p, m = st.near.shape[1], st.near.shape[2]
    problem = RelaxationProblem(p, m - 1, model.reference_lengths, links, (0,), 1.0)
    pos = problem.start(st.near[0], st.far[0])
    r = problem.quad_residuals(pos)
    ab, g = problem.normal_equations(pos, r)
    damping = 1e-6 * ab[0]

    def banded(ab=ab, g=g):
        a = ab.copy()
        a[0] += damping
        return solveh_banded(a, -g, lower=True, overwrite_ab=True, check_finite=False)

    jac = problem.jacobian(pos)[:, problem.columns]
    matrix = (jac.T @ jac + sp.diags(damping)).tocsc()
    # the natural order (plate by plate, node ids) as band storage, for its bandwidth
    natural = np.argsort(problem.columns)  # banded unknown of every jacobian column
    full = matrix[natural][:, natural].toarray()
    lower = np.tril(full)
    rows, cols = np.nonzero(lower)
    wide = int((rows - cols).max())
    ab_natural = np.zeros((wide + 1, full.shape[0]))
    ab_natural[rows - cols, cols] = lower[rows, cols]
    g_natural = g[natural]

    def ms(call):
        return 1e3 * measure(call, target=0.5, min_repeats=20)[0]

    return {
        "design": name,
        "alpha_deg": alpha,
        "unknowns": int(g.size),
        "band_rcm": int(problem.band),
        "band_natural": wide,
        "residuals_ms": ms(lambda: problem.quad_residuals(pos)),
        "normal_equations_ms": ms(lambda: problem.normal_equations(pos, r)),
        "sparse_jacobian_ms": ms(lambda: problem.jacobian(pos)),
        "solveh_banded_rcm_ms": ms(banded),
        "solveh_banded_natural_ms": ms(
            lambda: solveh_banded(ab_natural, -g_natural, lower=True, check_finite=False)
        ),
        "splu_natural_ms": ms(lambda: splu(matrix, permc_spec="NATURAL").solve(-g)),
        "splu_colamd_ms": ms(lambda: splu(matrix, permc_spec="COLAMD").solve(-g)),
    }


def machine() -> dict:
    """:func:`bench_deploy.machine` and the SciPy version."""
    return {**deploy_machine(), "scipy": scipy.__version__}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one angle per design")
    parser.add_argument("--out", metavar="FILE.json", help="also write the results as JSON")
    args = parser.parse_args(argv)
    alphas = QUICK_ALPHAS_DEG if args.quick else ALPHAS_DEG
    info = machine()
    print(
        f"# bench_relax: python {info['python']}, numpy {info['numpy']}, scipy {info['scipy']}, "
        f"{info['cpu_count']} CPUs, BLAS/OpenMP pinned to 1 thread"
    )
    designs = [
        bench_design(name, layout, alphas, min_repeats_old=1 if args.quick else 3)
        for name, layout in DESIGNS
    ]
    print()
    print(
        "| design | alpha | solver | ms / state | reps | nfev | njev | converged "
        "| max strain | quad planarity m | cost |"
    )
    print("|---|---:|---|---:|---:|---:|---:|---|---:|---:|---:|")
    for d in designs:
        label = f"{d['design']} ({d['layout']}, {d['unknowns']} unknowns, band {d['band']})"
        for row in d["rows"]:
            for solver in ("scipy", "lm"):
                s = row[solver]
                print(
                    f"| {label} | {row['alpha_deg']:g} | {solver} | {s['ms']:.1f} "
                    f"| {s['repeats']} | {s['nfev']} | {s['njev']} | {s['converged']} "
                    f"| {s['max_strain']:.6e} | {s['quad_planarity']:.6e} | {s['cost']:.10e} |"
                )
    print()
    worst = 0.0
    for d in designs:
        speed = [row["speedup"] for row in d["rows"]]
        lm = [row["lm"]["ms"] for row in d["rows"]]
        worst = max(worst, max(lm))
        print(
            f"{d['design']}: lm {min(lm):.1f}-{max(lm):.1f} ms / state, "
            f"{min(speed):.0f}-{max(speed):.0f}x faster than scipy; relax_states "
            f"{d['relax_states_ms_per_state']:.1f} ms / state"
        )
    split = iteration_split()
    print()
    print(
        f"One LM iteration, {split['design']} at {split['alpha_deg']:g} deg "
        f"({split['unknowns']} unknowns, band {split['band_rcm']} in RCM order, "
        f"{split['band_natural']} plate by plate), median ms:"
    )
    for key in (
        "residuals_ms",
        "normal_equations_ms",
        "sparse_jacobian_ms",
        "solveh_banded_rcm_ms",
        "solveh_banded_natural_ms",
        "splu_natural_ms",
        "splu_colamd_ms",
    ):
        print(f"  {key[:-3]:28s} {split[key]:.3f}")
    verdict = "PASS" if worst <= BAR_MS else "FAIL"
    print(f"\nbar: {BAR_MS:g} ms per state, slowest lm state {worst:.1f} ms: {verdict}")
    if args.out:
        with open(args.out, "w", encoding="utf-8") as fh:
            json.dump({"machine": info, "designs": designs, "iteration": split}, fh, indent=2)
        print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
