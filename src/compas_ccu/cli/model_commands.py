"""``ccu deploy | path | info | planarity``: a design's states, key figures and crease planarity."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from compas_ccu.analysis.planarity import planarity_along_path
from compas_ccu.cli.common import load_model, need_viz, say
from compas_ccu.cli.parser import DESIGN, OUT, QUIET, Command, option
from compas_ccu.cli.text import info_lines, thickness_lines, validation_lines
from compas_ccu.errors import GeometryError
from compas_ccu.fea.record import last_validation
from compas_ccu.io import write_compas_json, write_obj, write_path, write_structure_json
from compas_ccu.key_figures import FIGURES, key_figures
from compas_ccu.outputs import json_text
from compas_ccu.thickness import ThickModel
from compas_ccu.viz.export import save_figure
from compas_ccu.viz.planarity import plot_planarity

__all__ = ["COMMANDS", "INFO_PATH_STATES", "INFO_THICKNESS_STATES", "info_data"]

#: Path states of the planarity line of ``ccu info`` (above the flat stack).
INFO_PATH_STATES = 24
#: Path states of the thickness summary of ``ccu info`` (from the flat stack to the design).
INFO_THICKNESS_STATES = 21


def deploy(args) -> int:
    model = load_model(args.design)
    structure = model.deploy(args.alpha)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = [
        write_structure_json(structure, out / "structure.json"),
        write_obj(structure, out / "structure.obj"),
        write_compas_json(structure, out / "structure.compas.json"),
    ]
    m = structure.metrics
    say(
        args,
        f"deployed {model.design.name} to alpha = {structure.alpha:g} deg "
        f"(limit {model.alpha_limit:.4g} deg): span {m['span']:.4f} m, "
        f"rise {m['rise']:.4f} m",
    )
    say(
        args,
        f"invariants (relative to size {m['size']:.3f} m): isometry "
        f"{m['isometry_relative']:.1e}, quad planarity {m['quad_planarity_relative']:.1e}, "
        f"hinges {m['hinge_gap_relative']:.1e}, mirror {m['mirror_error_relative']:.1e}, "
        f"crease planarity {m['crease_planarity_max_relative']:.1e}",
    )
    for f in files:
        say(args, f"wrote {f}")
    return 0


def path(args) -> int:
    model = load_model(args.design)
    target = model.alpha_design if args.alpha is None else args.alpha
    structures = model.path(np.linspace(0.0, target, args.steps + 1))
    table, states = write_path(structures, args.out)
    worst = max(s.metrics["crease_planarity_max"] for s in structures)
    say(
        args,
        f"{len(structures)} states from alpha = 0 to {target:g} deg; largest crease "
        f"planarity deviation along the path {worst:.2e} m",
    )
    say(args, f"wrote {table} and {len(structures)} files in {states}")
    return 0


def info(args) -> int:
    model = load_model(args.design)
    figures = key_figures(model, path=INFO_PATH_STATES)
    try:
        summary, problem = ThickModel(model).summary(path_states=INFO_THICKNESS_STATES), None
    except GeometryError as exc:
        summary, problem = None, str(exc)
    record = last_validation(args.design)
    if getattr(args, "json", False):
        print(json_text(info_data(model, figures, summary, problem, record), indent=1))
        return 0
    lines = info_lines(figures)
    if model.design.units != "m":
        lines.insert(1, f"units             the file's lengths are {model.design.units}; below: m")
    if summary is None:
        lines.append(f"thickness         not modelled: {problem}")
    else:
        lines += thickness_lines(summary)
    lines += validation_lines(record)
    print("\n".join(lines))
    return 0


def info_data(model, figures, summary, problem, record) -> dict:
    """What ``ccu info --json`` prints: the numbers of ``ccu info`` as plain data.

    ``key_figures`` holds every key figure (:data:`compas_ccu.key_figures.FIGURES`, None where
    it does not apply) and ``figure_units`` its unit; ``thickness`` is
    :meth:`compas_ccu.thickness.ThickModel.summary` (or None, with ``thickness_error``);
    ``validation`` the last FE validation record (or None). Lengths are metres, angles
    degrees, whatever the design file's ``[design] units`` (``design_units``).
    """
    return {
        "format": "ccu.info",
        "version": 1,
        "units": {"length": "m", "angle": "deg"},
        "design": model.design.name,
        "design_units": model.design.units,
        "key_figures": figures.to_dict(),
        "figure_units": {f.name: f.unit for f in FIGURES if f.unit},
        "path_states": INFO_PATH_STATES,
        "thickness_path_states": INFO_THICKNESS_STATES,
        "thickness": summary,
        "thickness_error": problem,
        "validation": record,
    }


def planarity(args) -> int:
    model = load_model(args.design)
    report = planarity_along_path(model, steps=args.steps, relax=args.relax)
    files = report.write(args.out)
    if args.figure:
        need_viz("planarity --figure")

        fig = plot_planarity(model, steps=args.steps)
        files += save_figure(fig, Path(args.out) / "planarity")
    say(args, "crease  kind          max deviation (m)  relative   at alpha (deg)  exact")
    for c in report.creases:
        say(
            args,
            f"{c['id']:>6}  {c['kind']:<12}  {c['max']:>17.3e}  {c['max_relative']:.2e}  "
            f"{c['alpha_at_max']:>14.4g}  {'yes' if c['exact'] else 'no'}",
        )
    if report.relaxation is not None:
        r = report.relaxation
        say(
            args,
            f"relaxed at alpha = {r['alpha']:.4g} deg: isometry error {r['kinematic_isometry']:.2e}"
            f" m -> {r['relaxed_isometry']:.2e} m, largest strain {r['initial_max_strain']:.2e} "
            f"-> {r['max_strain']:.2e}, quad planarity {r['quad_planarity']:.2e} m, moved "
            f"{r['displacement']:.2e} m ({'converged' if r['converged'] else 'NOT converged'})",
        )
    for f in files:
        say(args, f"wrote {f}")
    return 0


COMMANDS = (
    Command(
        "deploy",
        "Deploy DESIGN to --alpha and write structure.json "
        "(docs/structure-json.md), structure.obj and structure.compas.json into --out.",
        (
            DESIGN,
            option(
                "--alpha",
                type=float,
                default=None,
                help="reference reflection angle in degrees (default: the design alpha)",
            ),
            OUT,
            QUIET,
        ),
        deploy,
    ),
    Command(
        "path",
        "Deploy DESIGN from alpha = 0 to the design alpha (or "
        "--alpha) in --steps equal steps; write states/state_NNNN.json and "
        "path.csv (alpha, span, rise, planarity per state).",
        (
            DESIGN,
            option(
                "--steps",
                limit="states",
                type=int,
                default=10,
                minimum=1,
                help="number of steps (default 10)",
            ),
            option("--alpha", type=float, default=None, help="final alpha, degrees"),
            OUT,
            QUIET,
        ),
        path,
    ),
    Command(
        "info",
        "Print plates, creases by kind, design alpha, deployment "
        "limit, span, rise and the flat stack footprint of DESIGN. With --json, the same "
        "figures as one JSON object on stdout (lengths in metres, angles in degrees; every "
        "key figure with its unit, the thickness summary and the last FE validation).",
        (
            DESIGN,
            option("--json", action="store_true", help="print the figures as JSON"),
        ),
        info,
    ),
    Command(
        "planarity",
        "Measure how far every crease leaves its plane from alpha = 0 to the design "
        "alpha; write planarity.csv (every state and crease) and planarity.json (per-crease "
        "maximum). With --relax, also relax the worst state by least squares and report "
        "the residuals (the fallback of docs/shape-control.md).",
        (
            DESIGN,
            OUT,
            option(
                "--steps",
                limit="states",
                type=int,
                default=32,
                minimum=1,
                help="states along the path (default 32)",
            ),
            option("--relax", action="store_true", help="relax the worst state"),
            option("--figure", action="store_true", help="also write the planarity figure"),
            QUIET,
        ),
        planarity,
    ),
)
