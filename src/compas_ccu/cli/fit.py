"""``ccu asbuilt`` and ``ccu fit``: fit to geometry (docs/fit.md)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from compas_ccu.cli.common import load_model, missing_modules, progress, say
from compas_ccu.cli.parser import OUT, QUIET, Command, option
from compas_ccu.design import load_design
from compas_ccu.design.document import read_toml
from compas_ccu.design.inverse import write_design
from compas_ccu.design.schema import MAX_LENGTH
from compas_ccu.design.units import LENGTH_UNITS
from compas_ccu.errors import OptionError
from compas_ccu.fit.design_fit import fit_design, free_keys, parse_free
from compas_ccu.fit.picture import deviation_figure
from compas_ccu.fit.points import DEFAULT_SAMPLES, read_points
from compas_ccu.fit.register import MIN_COVERAGE, register
from compas_ccu.outputs import write_json
from compas_ccu.viz.export import save_figure

__all__ = ["COMMANDS", "FIT_KEYS"]

#: Bounds of the integer options (they are sizes of the fits, not counts of a work limit).
MAX_SEED = 2**32 - 1
MAX_FIT_POINTS = 200_000
MAX_EVALUATIONS = 100_000

#: The keys of a FIT.toml file's [fit] table (besides [free]).
FIT_KEYS = {"points": int, "seed": int, "max_evaluations": int, "f_scale": float, "name": str}


def _mm(value) -> str:
    return "-" if value is None else f"{1000.0 * value:.1f}"


def asbuilt(args) -> int:
    model = load_model(args.design)
    progress(args, f"reading {args.scan}")
    scan = read_points(args.scan, count=args.samples, seed=args.seed, units=args.units)
    progress(args, f"registering {len(scan)} points to {model.design.name}")
    result = register(
        model,
        scan.points,
        per_plate=args.per_plate,
        tolerance=args.tolerance,
        outlier_distance=args.outlier,
        noise=args.noise,
        sample=args.sample,
        seed=args.seed,
        max_evaluations=args.max_evaluations,
    )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    record = {"design": model.design.name, "scan": str(args.scan), **result.to_dict()}
    write_json(out / "asbuilt.json", record)
    say(args, f"alpha {result.alpha:.2f} deg (design {model.alpha_design:g})")
    say(
        args,
        f"inliers {result.inliers} of {result.points}: RMS {_mm(result.rms)} mm, max "
        f"{_mm(result.max)} mm; outliers {result.outliers}; beyond {_mm(result.tolerance)} mm: "
        f"{result.beyond_tolerance}; coverage {100 * result.coverage:.0f} %",
    )
    for p in result.plates:
        line = (
            f"plate {p.id}: RMS {_mm(p.rms)} mm, max {_mm(p.max)} mm, coverage "
            f"{100 * p.coverage:.0f} %"
        )
        if p.slip is not None:
            line += f", own deviation {_mm(p.slip)} mm" + (" SLIPPED" if p.slipped else "")
        say(args, line)
    say(args, f"wrote {out / 'asbuilt.json'}")
    if not missing_modules(["matplotlib"]):
        inlier = np.abs(result.signed) <= result.outlier_distance  # outliers are not drawn
        fig = deviation_figure(
            result.design_points[inlier],
            result.signed[inlier],
            [p.to_dict() for p in result.plates],
            title=f"{model.design.name} as built: alpha {result.alpha:.2f} deg, RMS "
            f"{_mm(result.rms)} mm",
            limit=result.tolerance,
            outlines=model.vertices([result.alpha])[0],
        )
        for path in save_figure(fig, out / "asbuilt", formats=("png",)):
            say(args, f"wrote {path}")
    if not result.coverage_ok:
        print(
            f"ccu: the scan covers {100 * result.coverage:.0f} % of the plate area, less than "
            f"{100 * MIN_COVERAGE:.0f} %: the files are written for inspection; exit status 3",
            file=sys.stderr,
        )
        return 3
    return 0


def fit(args) -> int:
    base = load_design(args.base)
    free, options = [], {}
    if args.fit is not None:
        doc = read_toml(args.fit, error=OptionError, what="fit file")
        unknown = set(doc) - {"free", "fit"}
        if unknown:
            raise OptionError(
                f"{args.fit}: unknown table {sorted(unknown)[0]!r}; allowed: free, fit"
            )
        free = free_keys(doc.get("free", {})) if doc.get("free") else []
        for key, value in doc.get("fit", {}).items():
            if key not in FIT_KEYS:
                raise OptionError(
                    f"{args.fit}: unknown key fit.{key}; allowed: {', '.join(FIT_KEYS)}"
                )
            if not isinstance(value, FIT_KEYS[key]) or isinstance(value, bool):
                raise OptionError(
                    f"{args.fit}: fit.{key} must be {FIT_KEYS[key].__name__}, got {value!r}"
                )
            options[key] = value
    if args.free is not None:
        free += parse_free(args.free)
    free = free_keys(free)
    for key in ("points", "seed", "max_evaluations"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    progress(args, f"reading {args.target}")
    target = read_points(
        args.target, count=args.samples, seed=options.get("seed", 0), units=args.units
    )
    progress(
        args, f"fitting {', '.join(f.key for f in free)} of {base.name} to {len(target)} points"
    )
    result = fit_design(base, target, free, **options)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    name = result.design.name
    write_design(
        result.design,
        out / f"{name}.toml",
        header=f"{name}: {base.name} fitted to {args.target} by ccu fit (fit.json)",
    )
    write_json(
        out / "fit.json", {"target": str(args.target), "base": str(args.base), **result.to_dict()}
    )
    for key, value in result.parameters.items():
        say(args, f"{key} = {value:.6g} (start {result.start[key]:.6g})")
    say(
        args,
        f"RMS {_mm(result.rms)} mm, max {_mm(result.max)} mm, Hausdorff {_mm(result.hausdorff)} mm "
        f"after {result.evaluations} evaluations",
    )
    say(args, f"wrote {out / (name + '.toml')}")
    say(args, f"wrote {out / 'fit.json'}")
    if not missing_modules(["matplotlib"]):
        model = load_model(out / f"{name}.toml")
        fig = deviation_figure(
            target.points,
            result.signed,
            list(result.plates),
            title=f"{name}: target to plates, RMS {_mm(result.rms)} mm",
            limit=max(result.max, 1e-4),
            outlines=model.vertices([model.alpha_design])[0],
        )
        for path in save_figure(fig, out / "fit", formats=("png",)):
            say(args, f"wrote {path}")
    return 0


_UNITS = option(
    "--units",
    choices=tuple(LENGTH_UNITS),
    default="m",
    help="length units of the file's coordinates (default m; a .3dm file names its own)",
)
_SEED = option(
    "--seed",
    type=int,
    minimum=0,
    maximum=MAX_SEED,
    default=None,
    help="seed of every random subset (default 0)",
)
_SAMPLES = option(
    "--samples",
    type=int,
    minimum=1,
    maximum=20_000_000,
    default=DEFAULT_SAMPLES,
    help=f"points sampled on a mesh file's surface (default {DEFAULT_SAMPLES})",
)

COMMANDS = (
    Command(
        "asbuilt",
        "Read SCAN (a mesh: OBJ / STL / PLY / OFF / 3dm, sampled; or points: PLY, XYZ / CSV), "
        "find the reflection angle alpha and the pose that fit it best (principal axes and a "
        "coarse alpha grid, then a robust least-squares fit), and measure every point: "
        "inliers' RMS and largest distance, outliers, points beyond --tolerance, every plate's "
        "coverage and (--per-plate) its own rigid deviation (a slipped plate). Writes "
        "asbuilt.json and asbuilt.png into --out. Exit status 3 if the scan covers less than "
        f"{100 * MIN_COVERAGE:.0f} % of the plate area (files written); a scan that fits no "
        "state is an error (exit 2, nothing written).",
        (
            option("scan", help="scan file"),
            option("--design", required=True, help="design TOML file"),
            OUT,
            option("--per-plate", action="store_true", help="fit each plate's own deviation"),
            option(
                "--tolerance",
                type=float,
                positive=True,
                maximum=MAX_LENGTH,
                default=0.01,
                help="m: points and plates beyond it are reported (default 0.01)",
            ),
            option(
                "--outlier",
                type=float,
                positive=True,
                maximum=MAX_LENGTH,
                default=None,
                help="m: points farther are outliers (default max(5 noise, 3 tolerances))",
            ),
            option(
                "--noise",
                type=float,
                positive=True,
                maximum=MAX_LENGTH,
                default=None,
                help="m: standard deviation of the scan noise (default: estimated)",
            ),
            option(
                "--sample",
                type=int,
                minimum=100,
                maximum=MAX_FIT_POINTS,
                default=3000,
                help="points the fit uses (default 3000)",
            ),
            option(
                "--max-evaluations",
                type=int,
                minimum=4,
                maximum=MAX_EVALUATIONS,
                default=200,
                help="distance evaluations per least-squares pass (default 200)",
            ),
            _SAMPLES,
            _UNITS,
            option(
                "--seed",
                type=int,
                minimum=0,
                maximum=MAX_SEED,
                default=0,
                help="seed of the subsets (default 0)",
            ),
            QUIET,
        ),
        asbuilt,
    ),
    Command(
        "fit",
        "Free design keys within bounds (--free crease.rise=0.5:1.5,layout.spacing=0.1:0.2 or "
        "a FIT.toml with [free] and [fit]) so that the deployed design meets TARGET (in the "
        "design's world frame): a robust two-sided distance on the exact model, bounded "
        "least squares from the base design, seeded, at most --max-evaluations models. Writes "
        "<name>-fit.toml (a design file), fit.json and fit.png into --out; a key that is not "
        "a design key or has no bounds, a target far larger than any design within the bounds "
        "or a fit that does not converge is an error (nothing written).",
        (
            option("target", help="target file (mesh or points)"),
            option("--base", required=True, help="the base design TOML file"),
            OUT,
            option("--free", default=None, help="KEY=LOWER:UPPER[,KEY=LOWER:UPPER ...]"),
            option(
                "--fit", default=None, help="a FIT.toml: [free] KEY = [LOWER, UPPER]; [fit] options"
            ),
            option(
                "--points",
                type=int,
                minimum=50,
                maximum=MAX_FIT_POINTS,
                default=None,
                help="residual points (default 3000)",
            ),
            option(
                "--max-evaluations",
                type=int,
                minimum=2,
                maximum=MAX_EVALUATIONS,
                default=None,
                help="models built at most (default 100)",
            ),
            _SEED,
            _SAMPLES,
            _UNITS,
            QUIET,
        ),
        fit,
    ),
)
