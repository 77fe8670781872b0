"""``ccu explore``: a sweep of design variants on Dask (the ``explore`` extra).

The explore modules are imported inside the command, after the check for the extra.
"""

from __future__ import annotations

import sys

from compas_ccu.cli.common import missing_modules, say
from compas_ccu.cli.parser import QUIET_PROGRESS, Command, option
from compas_ccu.errors import OptionError, require
from compas_ccu.explore import load_sweep, run_sweep
from compas_ccu.explore.run import runner_label

__all__ = ["COMMANDS"]


def _check(args) -> None:
    """The extra's modules this run needs, and options that exclude each other."""
    needed = ["pyarrow", "tqdm"] + ([] if args.in_process else ["distributed"])
    needed += ["bokeh"] if args.dashboard else []
    bokeh = " bokeh" if "bokeh" in missing_modules(needed) else ""  # the dashboard: no extra
    require(
        needed, "explore", what="'ccu explore'", note=f"{bokeh} (make setup installs the extra)"
    )
    if args.in_process and (args.scheduler or args.workers):
        raise OptionError("--in-process runs without Dask: drop --scheduler / --workers")


def explore(args) -> int:

    _check(args)
    sweep = load_sweep(args.sweep)
    plots = not args.no_plots and not missing_modules(["matplotlib"])
    say(
        args,
        f"sweep {sweep.name}: {len(sweep.variants)} variants ({sweep.sampling}"
        + (f", seed {sweep.seed}" if sweep.sampling in ("random", "lhs") else "")
        + f") of {sweep.base_path.name} over {', '.join(sweep.parameter_names)}"
        + (f"; {sweep.duplicates} repeated samples dropped" if sweep.duplicates else ""),
    )
    # Ctrl-C and SIGTERM stop between two variants (run_sweep listens for them)
    result = run_sweep(
        sweep,
        args.out,
        scheduler=args.scheduler,
        workers=args.workers,
        in_process=args.in_process,
        progress=not args.quiet,
        plots=plots,
        dashboard=args.dashboard,
    )
    runner = runner_label(result.scheduler, result.workers)
    if result.reused:
        say(args, f"{result.reused} variants were already in {result.out} (not recomputed)")
    if result.computed:
        say(
            args,
            f"computed {result.computed} variants in {result.seconds:.1f} s {runner}: "
            f"{result.throughput:.2f} variants/s"
            + (f" (cluster start {result.startup:.1f} s)" if result.startup else ""),
        )
    if result.interrupted:
        print(
            f"ccu explore: interrupted with {len(result.rows)} of {result.total} variants saved "
            f"in {result.out}; run the same command again to compute the rest",
            file=sys.stderr,
        )
        return 130
    s = result.summary
    if s is not None:
        errors = ", ".join(f"{n} {k}" for k, n in s["errors"].items())
        say(
            args,
            f"{s['variants']} variants: {s['ok']} ok, {s['failed']} failed"
            + (f" ({errors})" if errors else "")
            + f"; {s['feasible']} feasible, {len(s['pareto'])} on the Pareto front of "
            + ", ".join(f"{k} ({v})" for k, v in s["objectives"].items()),
        )
        for b in s["best"]:
            params = ", ".join(f"{k} = {v}" for k, v in b["parameters"].items())
            values = ", ".join(f"{k} {v:.4g}" for k, v in b["objectives"].items())
            say(args, f"  best {b['rank']}: {params}: {values}")
    say(args, f"wrote {result.out / 'results.parquet'} and the summary in {result.out}")
    return 0


COMMANDS = (
    Command(
        "explore",
        "Build, deploy and measure every variant of SWEEP (a TOML file naming a base "
        "design and the parameters to vary, docs/explore.md) on a local Dask cluster or the "
        "cluster at --scheduler. Writes DIR/results.parquet (one row per variant: parameters, "
        "metrics, error), a journal that makes the run resumable (run it again to compute only "
        "what is missing), summary.json, plots/ and best/ (structure files of the best "
        "variants on the Pareto front).",
        (
            option("sweep", help="sweep TOML file"),
            option("--out", required=True, help="output folder (resumes if it holds this sweep)"),
            option(
                "--scheduler",
                default=None,
                metavar="ADDRESS",
                help="address of a running Dask scheduler, e.g. tcp://host:8786",
            ),
            option(
                "--workers",
                limit="workers",
                type=int,
                default=None,
                minimum=1,
                metavar="N",
                help="worker processes of the local cluster (default: one per core)",
            ),
            option(
                "--in-process",
                action="store_true",
                help="evaluate in this process without Dask (debugging, comparisons)",
            ),
            option(
                "--dashboard",
                action="store_true",
                help="serve the local cluster's Dask dashboard on :8787",
            ),
            option("--no-plots", action="store_true", help="skip the summary plots"),
            QUIET_PROGRESS,
        ),
        explore,
        staged=False,
    ),
)
