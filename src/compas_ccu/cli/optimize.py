"""``ccu optimize``: an optimisation study of a design on Dask (the ``explore`` extra).

Exit status: 0 with a feasible design; 3 when the study finished without one (every file is
written; the least-violating designs are listed on stderr); 130 when interrupted; 2 for a bad
study file or option (as every command).
"""

from __future__ import annotations

import sys

from compas_ccu.cli.common import missing_modules, say
from compas_ccu.cli.parser import QUIET_PROGRESS, Command, option
from compas_ccu.errors import OptionError, require
from compas_ccu.explore.optimize import run_study
from compas_ccu.explore.run import runner_label
from compas_ccu.explore.study import load_study

__all__ = ["COMMANDS", "NO_FEASIBLE"]

#: Exit status of a study that ran but found no design meeting every constraint.
NO_FEASIBLE = 3


def _check(args) -> None:
    """The extra's modules this run needs, and options that exclude each other."""
    needed = ["optuna", "pyarrow", "tqdm"] + ([] if args.in_process else ["distributed"])
    needed += ["bokeh"] if args.dashboard else []
    bokeh = " bokeh" if "bokeh" in missing_modules(needed) else ""  # the dashboard: no extra
    require(
        needed, "explore", what="'ccu optimize'", note=f"{bokeh} (make setup installs the extra)"
    )
    if args.in_process and (args.scheduler or args.workers):
        raise OptionError("--in-process runs without Dask: drop --scheduler / --workers")


def _value(value) -> str:
    return f"{value:.4g}" if isinstance(value, float) else repr(value)


def _design(entry: dict) -> str:
    return ", ".join(f"{k} = {_value(v)}" for k, v in entry["parameters"].items())


def optimize(args) -> int:
    _check(args)
    study = load_study(args.study, seed=args.seed)
    plots = not args.no_plots and not missing_modules(["matplotlib"])
    budget = args.trials or study.trials
    say(
        args,
        f"study {study.name}: {budget} trials ({study.sampler_name}, seed {study.seed}) of "
        f"{study.base_path.name} over {', '.join(study.parameter_names)}; "
        + ", ".join(f"{k} ({v})" for k, v in study.objectives.items())
        + (f"; FE after the cheap checks ({len(study.cheap_constraints)})" if study.fe else ""),
    )
    # Ctrl-C and SIGTERM stop between two trials (run_study listens for them)
    result = run_study(
        study,
        args.out,
        trials=args.trials,
        scheduler=args.scheduler,
        workers=args.workers,
        in_process=args.in_process,
        progress=not args.quiet,
        plots=plots,
        dashboard=args.dashboard,
    )
    runner = runner_label(result.scheduler, result.workers)
    if result.earlier:
        say(args, f"{result.earlier} trials were already in {result.out} (continued)")
    if result.computed:
        say(
            args,
            f"ran {result.computed} trials in {result.seconds:.1f} s {runner}: "
            f"{result.evaluations} designs evaluated"
            + (f" ({result.gated} without FE: a cheap check failed)" if study.fe else "")
            + f", {result.computed - result.evaluations} proposed again"
            + (f" (cluster start {result.startup:.1f} s)" if result.startup else ""),
        )
    s = result.summary
    errors = ", ".join(f"{n} {k}" for k, n in s["errors"].items())
    say(
        args,
        f"{s['trials']} trials: {s['ok']} evaluated, {s['failed']} failed"
        + (f" ({errors})" if errors else "")
        + f"; {s['feasible']} feasible",
    )
    for b in s["best"]:
        values = ", ".join(f"{k} {_value(v)}" for k, v in b["objectives"].items())
        say(args, f"  best {b['rank']}: trial {b['trial']}: {values}; {_design(b)}")
        say(args, "    " + ", ".join(f"{k} {_value(v)}" for k, v in b["constraints"].items()))
    say(args, f"wrote {result.out / 'results.parquet'} and the summary in {result.out}")
    if result.interrupted:
        print(
            f"ccu optimize: interrupted with {len(result.rows)} of {result.budget} trials saved "
            f"in {result.out}; run the same command again to continue the study",
            file=sys.stderr,
        )
        return 130
    if not s["best"]:
        print(
            f"ccu optimize: no feasible design in {s['trials']} trials: none meets every "
            "constraint. The least violating:",
            file=sys.stderr,
        )
        for e in s["least_violating"]:
            print(
                f"  trial {e['trial']} (violation {e['violation']:.3g}): {e['violations']}; "
                f"{_design(e)}",
                file=sys.stderr,
            )
        print(
            "Relax the constraints, widen the parameter ranges or run more trials "
            f"(--trials); the table is {result.out / 'results.parquet'}",
            file=sys.stderr,
        )
        return NO_FEASIBLE
    return 0


COMMANDS = (
    Command(
        "optimize",
        "Search the parameters of STUDY (a TOML file naming a base design, the parameters and "
        "their ranges, the objectives and the constraints, docs/optimize.md) with Optuna (TPE "
        "for one objective, NSGA-II for several) and evaluate every proposed design on a local "
        "Dask cluster or the cluster at --scheduler; FE only for designs that pass the cheap "
        "checks. Writes DIR/results.parquet (one row per trial), a journal that makes the "
        "study resumable (run it again to continue it, or with more --trials), summary.json, "
        "plots/ (convergence, Pareto front) and best/ (the best designs' files). Exit status "
        "3: no design met every constraint (the least violating are listed).",
        (
            option("study", help="study TOML file"),
            option("--out", required=True, help="output folder (continues this study)"),
            option(
                "--trials",
                limit="variants",
                type=int,
                default=None,
                minimum=1,
                metavar="N",
                help="trials the study is to have (default: study.trials)",
            ),
            option(
                "--seed",
                type=int,
                default=None,
                minimum=0,
                maximum=2**32 - 1,
                metavar="S",
                help="the sampler's seed (default: study.seed; another seed is another study)",
            ),
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
                help="worker processes of the local cluster (default: one per core); one "
                "trial per worker is in flight",
            ),
            option(
                "--in-process",
                action="store_true",
                help="evaluate in this process without Dask, one trial after the other",
            ),
            option(
                "--dashboard",
                action="store_true",
                help="serve the local cluster's Dask dashboard on :8787",
            ),
            option("--no-plots", action="store_true", help="skip the plots"),
            QUIET_PROGRESS,
        ),
        optimize,
        staged=False,
    ),
)
