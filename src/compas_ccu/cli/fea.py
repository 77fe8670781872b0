"""``ccu validate``: the deployment checked by a nonlinear FE engine (the ``fea`` extra).

The FE modules are imported inside the command: ``ccu --help`` and the other commands do not
load them.
"""

from __future__ import annotations

import sys
from pathlib import Path

from compas_ccu.cli.common import load_model, missing_modules, progress, say
from compas_ccu.cli.parser import (
    DESIGN,
    MAX_AREA_LOAD,
    MAX_HINGE_STIFFNESS,
    MAX_THICKNESS,
    OUT,
    QUIET,
    Command,
    option,
)
from compas_ccu.cli.text import basis_text, load_case_lines
from compas_ccu.design.schema import MAX_LENGTH
from compas_ccu.fea.loads import CASE_NAMES
from compas_ccu.fea.problem import ConvergenceError
from compas_ccu.fea.record import agreement, remember
from compas_ccu.fea.validation import validate as run_validation
from compas_ccu.key_figures.checks import failed, fe_checks
from compas_ccu.key_figures.text import deployment_utilisation_text
from compas_ccu.outputs import write_json

__all__ = ["COMMANDS", "drive_lines"]


def _write_failure(out: Path, model, args, exc) -> None:
    """validation.json of a deployment that did not converge (the step and the residual)."""
    failure = {
        "format": "ccu.validation",
        "version": 1,
        "design": model.design.name,
        "engine": args.engine,
        "mode": args.mode,
        "converged": False,
        "failed_step": exc.step,
        "residual": exc.residual,
        "message": str(exc),
    }
    write_json(out / "validation.json", failure)


def validate(args) -> int:

    model = load_model(args.design)
    options = dict(
        engine=args.engine,
        mode=args.mode,
        element_size=args.element_size,
        steps=args.steps,
        alpha=args.alpha,
        material=args.material,
        thickness=args.thickness,
        orthotropic=args.orthotropic,
        hinge_stiffness=args.hinge_stiffness,
        hinge_eccentricity=args.hinge_eccentricity,
        control=args.control,
        drive=args.drive,
        prebend=args.prebend,
        checks=not args.no_checks,
        area_load=args.area_load,
        load_cases=args.load_case,
    )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    progress(args, f"validating {model.design.name} with {args.engine} ({args.mode}) ...")
    try:
        v = run_validation(model, **options)
    except ConvergenceError as exc:
        # the failure record is a result: it is written, and the command fails with the cause
        _write_failure(out, model, args, exc)
        print(f"ccu: error: {exc}", file=sys.stderr)
        return 2
    figures = not args.no_figures and not missing_modules(["matplotlib"])
    files = v.write(out, figures=figures)
    summary = v.summary()
    if args.compare:
        other = "opensees" if args.engine == "kratos" else "kratos"
        progress(args, f"cross-checking with {other} ...")
        w = run_validation(model, **{**options, "engine": other})
        w.write(out / other, figures=False)
        summary["agreement"] = agreement(v, w).to_dict()
        write_json(out / "validation.json", summary)
    remember(args.design, summary, getattr(args, "final_out", out))
    for line in _summary_lines(summary):
        say(args, line)
    for f in files:
        say(args, f"wrote {f}")
    bad = failed(fe_checks(summary))
    for c in bad:
        print(f"ccu: check failed: {c.brief()} ({c.clause})", file=sys.stderr)
    if bad and not args.allow_exceeded:
        print(
            f"ccu: {len(bad)} FE check{'s' if len(bad) != 1 else ''} failed; the files are "
            "written for inspection; exit status 3 (--allow-exceeded: 0)",
            file=sys.stderr,
        )
        return 3
    return 0


def _hinge_line(settings: dict) -> str:
    """Where the hinges are and what joins them (the FE settings used)."""
    on = (
        "on the plates' faces (axis-shift, eccentric shells)"
        if settings.get("hinge_eccentricity", "none") == "axis-shift"
        else "on the mid-surfaces"
    )
    k = settings.get("hinge_translational_stiffness")
    ties = "tied" if k is None else f"translational springs {k:.4g} N/m/m"
    r = settings.get("hinge_stiffness", 0.0) or 0.0
    turn = "free to turn" if r == 0.0 else f"rotational springs {r:.4g} Nm/rad/m"
    return f"hinges: {on}, {ties}, {turn}"


def drive_lines(drive: dict) -> list:
    """What ``--drive leading`` found: every crease's alpha at the end, FE against kinematic.

    >>> row = {"crease": 1, "fe_alpha": [3.5, 29.9], "kinematic_alpha": [3.75, 30.0],
    ...        "residual": [-0.25, -0.1], "residual_max": [0.3, 0.2], "follow": 0.99}
    >>> drive_lines({"prebend_deg": 3.75, "creases": [row]})[1]
    'crease 1: alpha 29.90 deg (kinematic 30.00), residual -0.10 (edges up to 0.20), follows 99 %'
    """
    lines = [
        f"driven: the leading crease's plates alone after pre-bending to "
        f"{drive['prebend_deg']:.4g} deg; every crease's mean alpha at the end:"
    ]
    for c in drive["creases"]:
        follow = "" if c["follow"] is None else f", follows {100.0 * c['follow']:.0f} %"
        lines.append(
            f"crease {c['crease']}: alpha {c['fe_alpha'][-1]:.2f} deg (kinematic "
            f"{c['kinematic_alpha'][-1]:.2f}), residual {c['residual'][-1]:+.2f} (edges up to "
            f"{c['residual_max'][-1]:.2f}){follow}"
        )
    return lines


def _summary_lines(summary: dict) -> list:
    d, st, sol = summary["deviation"], summary["stresses"], summary["solver"]
    p = summary["plates"]
    source = (
        "the design's [plates]"
        if p["thickness_from"] == p["material_from"] == "design [plates]"
        else f"thickness from {p['thickness_from']}, material from {p['material_from']}"
    )
    lines = [
        f"plates: {p['thickness'] * 1e3:.4g} mm {p['material']} ({source})",
        f"deviation from the kinematic model at alpha = {summary['alpha']:.4g} deg: max "
        f"{d['max_percent']:.3f} %, mean {d['mean_percent']:.4f} % of the span "
        f"{summary['span']:.3f} m (max along the path {d['max_percent_along_path']:.3f} %)",
        f"stresses: bending {st['max_bending_MPa']:.2f} MPa, membrane "
        f"{st['max_membrane_MPa']:.2f} MPa, moment {st['max_moment_Nm_per_m']:.1f} Nm/m",
    ]
    lines.insert(1, _hinge_line(summary["settings"]))
    c = summary["checks"]
    if not c:  # actuation mode (or --no-checks): the deployed state against f_d alone
        lines.append(deployment_utilisation_text(summary))
    if c:
        lines.extend(load_case_lines(c))
        if c.get("basis"):
            lines.append(
                f"strength of the governing case: {c['strength_MPa']:.4g} MPa, "
                f"{basis_text(c['basis'])}"
            )
        if c.get("stiffness"):
            lines.append(f"stiffness of the governing buckling case: {c['stiffness']['text']}")
    if "drive" in summary:
        lines.extend(drive_lines(summary["drive"]))
    if "agreement" in summary:
        a = summary["agreement"]
        lines.append(
            f"engines agree: positions within {a['position_max_percent']:.2e} % of span, "
            f"deviation {a['deviation_max_relative']:.1e}, moment {a['moment_max_relative']:.1e}"
            " (relative)"
        )
    lines.append(
        f"{summary['mesh']['elements']} elements, {sol['steps']} steps, "
        f"{sum(sol['iterations'])} iterations, {sol['cuts']} cuts, {sol['wall_time_s']:.1f} s"
    )
    return lines


COMMANDS = (
    Command(
        "validate",
        "Mesh the plates as quad shells (8 mm plywood by default), tie the hinges, "
        "deploy geometrically nonlinearly and compare with the kinematic model; then check "
        "the deployed state under the design's load cases ([loads], [supports], [hinges]: "
        "self-weight, wet concrete, construction, snow, half-span snow, wind). Writes "
        "validation.json, fe_results.npz and the fe_stress / fe_deviation / fe_curves / "
        "fe_load_cases pictures into --out. Exit status 3 if a load case fails a check "
        "(every failed check listed), unless --allow-exceeded.",
        (
            DESIGN,
            OUT,
            option("--engine", choices=("kratos", "opensees"), default="kratos", help=None),
            option(
                "--mode", choices=("displacement", "actuation"), default="displacement", help=None
            ),
            option(
                "--element-size",
                type=float,
                positive=True,
                maximum=MAX_LENGTH,
                default=0.1,
                help="m (default 0.1)",
            ),
            option(
                "--steps",
                limit="states",
                type=int,
                minimum=1,
                default=8,
                help="deployment steps (default 8)",
            ),
            option("--alpha", type=float, default=None, help="target alpha, degrees"),
            option(
                "--material", default=None, help="material name (default: the design's [plates])"
            ),
            option(
                "--thickness",
                type=float,
                positive=True,
                maximum=MAX_THICKNESS,
                default=None,
                help="plate thickness, m (default: the design's [plates])",
            ),
            option("--orthotropic", action="store_true", help="E1 along the crease, E2 across"),
            option(
                "--hinge-stiffness",
                type=float,
                minimum=0.0,
                maximum=MAX_HINGE_STIFFNESS,
                default=None,
                help="rotational hinge spring, Nm/rad/m (default: the design's [hinges])",
            ),
            option(
                "--hinge-eccentricity",
                choices=("none", "axis-shift"),
                default=None,
                help="hinges on the mid-surfaces or on the faces (default: the design's [hinges])",
            ),
            option(
                "--control",
                choices=("supports", "edges"),
                default="supports",
                help="nodes that follow the kinematic path (displacement mode)",
            ),
            option(
                "--drive",
                choices=("all", "leading"),
                default="all",
                help="displacement mode: drive the end rulings of every plate, or (leading) "
                "after pre-bending those of the leading crease's two plates alone and measure "
                "how every crease follows (no load cases)",
            ),
            option(
                "--prebend",
                type=float,
                positive=True,
                default=None,
                help="pre-bending angle, degrees (actuation: default a quarter of the target; "
                "--drive leading: an eighth)",
            ),
            option(
                "--area-load",
                type=float,
                minimum=0.0,
                maximum=MAX_AREA_LOAD,
                default=None,
                help="an extra uniform load case on the plates, N/m2 (default: 1500 if the "
                "design's [loads] define no action, else none)",
            ),
            option(
                "--load-case",
                action="append",
                choices=CASE_NAMES,
                default=None,
                help="run only this load case (repeat for several; default: all the design's)",
            ),
            option("--no-checks", action="store_true", help="skip the structural checks"),
            option("--compare", action="store_true", help="cross-check with the other engine"),
            option("--no-figures", action="store_true", help="skip the pictures"),
            option(
                "--allow-exceeded",
                action="store_true",
                help="exit 0 even if a load case fails its checks (utilisation, deflection, "
                "design buckling factor)",
            ),
            QUIET,
        ),
        validate,
    ),
)
