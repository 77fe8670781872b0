"""Command line interface: ``ccu deploy | path | info | planarity | catalog | validate | fabricate |
explore | figures | animate | view | sheet | report``.

Every command takes a design TOML file (see ``docs/design-files.md``). Errors in the input are
printed as one line naming the cause and the value, with exit status 2.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["main"]


def _load(path: str):
    from compas_ccu.design import load_design

    return load_design(path).build()


def _cmd_deploy(args) -> int:
    from compas_ccu.io import write_compas_json, write_obj, write_structure_json

    model = _load(args.design)
    structure = model.deploy(args.alpha)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = [
        write_structure_json(structure, out / "structure.json"),
        write_obj(structure, out / "structure.obj"),
        write_compas_json(structure, out / "structure.compas.json"),
    ]
    m = structure.metrics
    _say(
        args,
        f"deployed {model.design.name} to alpha = {structure.alpha:g} deg "
        f"(limit {model.alpha_limit:.4g} deg): span {m['span']:.4f} m, "
        f"rise {m['rise']:.4f} m",
    )
    _say(
        args,
        f"invariants (relative to size {m['size']:.3f} m): isometry "
        f"{m['isometry_relative']:.1e}, quad planarity {m['quad_planarity_relative']:.1e}, "
        f"hinges {m['hinge_gap_relative']:.1e}, mirror {m['mirror_error_relative']:.1e}, "
        f"crease planarity {m['crease_planarity_max_relative']:.1e}",
    )
    for f in files:
        _say(args, f"wrote {f}")
    return 0


def _cmd_path(args) -> int:
    import numpy as np

    from compas_ccu.io import write_path_table, write_structure_json

    model = _load(args.design)
    target = model.alpha_design if args.alpha is None else args.alpha
    if args.steps < 1:
        raise ValueError(f"--steps must be >= 1, got {args.steps}")
    alphas = np.linspace(0.0, target, args.steps + 1)
    structures = model.path(alphas)
    out = Path(args.out)
    states = out / "states"
    states.mkdir(parents=True, exist_ok=True)
    for k, s in enumerate(structures):
        write_structure_json(s, states / f"state_{k:04d}.json")
    table = write_path_table(structures, out / "path.csv")
    worst = max(s.metrics["crease_planarity_max"] for s in structures)
    _say(
        args,
        f"{len(structures)} states from alpha = 0 to {target:g} deg; largest crease "
        f"planarity deviation along the path {worst:.2e} m",
    )
    _say(args, f"wrote {table} and {len(structures)} files in {states}")
    return 0


def _cmd_info(args) -> int:
    from compas_ccu.io import flat_footprint

    model = _load(args.design)
    s = model.deploy()
    m = s.metrics
    kinds = s.crease_kind_counts()
    width, height = flat_footprint(s)
    lines = [
        f"design            {model.design.name}",
        f"plates            {len(s.plate_ids)}",
        f"creases           {len(s.creases)}"
        + (f" ({', '.join(f'{v} {k}' for k, v in sorted(kinds.items()))})" if kinds else ""),
        f"segments          {model.segments} per crease",
        f"design alpha      {model.alpha_design:g} deg at reference vertex {model.reference}",
        f"deployment limit  {model.alpha_limit:.4f} deg (crease segment {model.limit_vertex} "
        "perpendicular to its plane)",
        f"overlap limit     {model.overlap_alpha:.4f} deg (largest alpha before a crease "
        "overlaps itself)",
        f"span              {m['span']:.4f} m (leading crease chord)",
        f"rise              {m['rise']:.4f} m",
        "bounding box      " + " x ".join(f"{v:.3f}" for v in m["bounding_box"]) + " m",
        f"flat stack        {width:.3f} x {height:.3f} m footprint",
        f"invariants        max relative error {s.max_invariant_error:.1e}, crease planarity "
        f"{m['crease_planarity_max']:.1e} m",
    ]
    lines += _shape_lines(model)
    lines += _thickness_lines(model)
    lines += _validation_lines(args.design)
    print("\n".join(lines))
    return 0


def _thickness_lines(model) -> list:
    """``ccu info`` lines on the thick plates: stack, corrections, collisions, bending."""
    from compas_ccu.errors import GeometryError
    from compas_ccu.thickness import ThickModel

    try:
        summary = ThickModel(model).summary(path_states=21)
    except GeometryError as exc:
        return [f"thickness         not modelled: {exc}"]
    return thickness_lines(summary)


def thickness_lines(summary: dict) -> list:
    """Text lines of a :meth:`compas_ccu.thickness.ThickModel.summary` (info, fabricate)."""
    from compas_ccu.thickness.model import collision_text

    b, c = summary["bending"], summary["collisions"]
    pairs = summary["pairing"]
    lines = [
        f"thickness         {summary['thickness'] * 1e3:.4g} mm {summary['material']}, flat "
        f"stack {summary['stack_height'] * 1e3:.4g} mm (order {summary['stack_order']})",
        f"axis-shift hinges {pairs.count('intrados')} intrados-intrados, "
        f"{pairs.count('extrados')} extrados-extrados; offset crease correction "
        f"{max(summary['correction_design'], default=0.0) * 1e3:.3g} mm at the design, hinge "
        f"gap along the path {summary['hinge_gap_max_path'] * 1e3:.3g} mm",
    ]
    text = collision_text(c)
    lines.append(
        "collisions        "
        + (
            f"** {text} **"
            if c["first"]
            else text.replace("none", "none from the flat stack to the design", 1)
        )
    )
    worst = b["worst"]
    lines.append(
        f"bending check     max curvature {b['max_curvature']:.3g} 1/m, utilisation "
        f"{b['max_utilisation']:.2f} (plate {worst['plate']} at alpha {worst['alpha']:.3g} deg; "
        f"limit f/(E t/2) >= {b['curvature_limit_min']:.3g} 1/m)"
        + ("  ** EXCEEDED: the plates would break **" if b["exceeded"] else "")
    )
    return lines


def _cmd_fabricate(args) -> int:
    from compas_ccu.fabrication.fabricate import fabricate

    model = _load(args.design)
    manifest = fabricate(
        model,
        args.out,
        thickness=args.thickness,
        material=args.material,
        grain=args.grain,
        hinge_width=args.hinge_width,
        allow_collisions=args.allow_collisions,
    )
    for line in thickness_lines(manifest):
        _say(args, line)
    for f in manifest["files"]:
        _say(args, f"wrote {Path(args.out) / f}")
    return 0


def _validation_lines(design: str) -> list:
    """``ccu info`` lines on the last FE validation of this design file, if any."""
    from compas_ccu.fea.record import last_validation

    record = last_validation(design)
    if record is None:
        return ["FE validation     none yet ('ccu validate' to run one)"]
    d = record["deviation"]
    c = record.get("checks") or {}
    line = (
        f"FE validation     {record['engine']} {record['mode']}, alpha {record['alpha']:.4g} deg: "
        f"deviation max {d['max_percent']:.3f} % / mean {d['mean_percent']:.3f} % of span, "
        f"bending {record['stresses']['max_bending_MPa']:.1f} MPa"
    )
    lines = [line]
    if c:
        lines.append(
            f"FE checks         deflection {c['deflection_max_m'] * 1e3:.2f} mm (limit "
            f"{c['deflection_limit_m'] * 1e3:.2f} mm), utilisation {c['utilisation_max']:.2f}"
            + (
                f", buckling factor {c['buckling_factor']:.3g}"
                if c.get("buckling_factor") is not None
                else ""
            )
            + ("" if c["deflection_ok"] and c["utilisation_ok"] else "  ** NOT OK **")
        )
    lines.append(f"                  ({record['when']}, {record['out']})")
    return lines


def _shape_lines(model) -> list:
    """``ccu info`` lines on the plane layout, global shape, path planarity and target fit."""
    import numpy as np

    from compas_ccu.analysis.planarity import planarity_along_path

    lines = [f"layout            {model.design.values['layout']['type']}"]
    planes = model.planes
    if planes is not None:
        inc = planes.inclinations()
        lines.append(
            f"plane inclination about the actuation axis {np.abs(inc[:, 0]).max():.3f} deg, "
            f"perpendicular {np.abs(inc[:, 1]).max():.3f} deg (largest between neighbours)"
        )
        if planes.plates >= 4:
            from compas_ccu.analysis import global_curvature

            states = model.mechanism.deploy(np.radians([model.alpha_design]))
            g = global_curvature(model.plane_curves(states)[0])
            lines.append(
                f"global shape      {g.kind} (principal curvatures "
                f"{g.principal[0]:.4g}, {g.principal[1]:.4g} 1/m at the centre)"
            )
    report = planarity_along_path(model, steps=24)
    worst = report.summary()
    state = "exact" if report.exact else f"at alpha = {worst['planarity_alpha_at_max']:.4g} deg"
    lines.append(
        f"path planarity    {report.max:.2e} m largest crease deviation over 24 states "
        f"({state}; 'ccu planarity' for the table)"
    )
    fit = model.built.target_fit
    if fit is not None:
        lines.append(
            f"target fit        planes {fit.planes} solved, largest miss {fit.max_residual:.2e} m"
        )
    return lines


def _cmd_planarity(args) -> int:
    import csv
    import json

    from compas_ccu.analysis.planarity import planarity_along_path

    if args.steps < 1:
        raise ValueError(f"--steps must be >= 1, got {args.steps}")
    model = _load(args.design)
    report = planarity_along_path(model, steps=args.steps, relax=args.relax)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "planarity.csv", "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["alpha_deg", "crease", "deviation_m"])
        writer.writerows(report.rows())
    with open(out / "planarity.json", "w") as fh:
        json.dump(report.summary(), fh, indent=1)
    files = [out / "planarity.csv", out / "planarity.json"]
    if args.figure:
        _need_viz("planarity --figure")
        from compas_ccu.viz.export import save_figure
        from compas_ccu.viz.planarity import plot_planarity

        files += save_figure(plot_planarity(model, steps=args.steps), out / "planarity")
    _say(args, "crease  kind          max deviation (m)  relative   at alpha (deg)  exact")
    for c in report.creases:
        _say(
            args,
            f"{c['id']:>6}  {c['kind']:<12}  {c['max']:>17.3e}  {c['max_relative']:.2e}  "
            f"{c['alpha_at_max']:>14.4g}  {'yes' if c['exact'] else 'no'}",
        )
    if report.relaxation is not None:
        r = report.relaxation
        _say(
            args,
            f"relaxed at alpha = {r['alpha']:.4g} deg: isometry error {r['kinematic_isometry']:.2e}"
            f" m -> {r['relaxed_isometry']:.2e} m, largest strain {r['initial_max_strain']:.2e} "
            f"-> {r['max_strain']:.2e}, quad planarity {r['quad_planarity']:.2e} m, moved "
            f"{r['displacement']:.2e} m ({'converged' if r['converged'] else 'NOT converged'})",
        )
    for f in files:
        _say(args, f"wrote {f}")
    return 0


def _cmd_catalog(args) -> int:
    import importlib.util

    from compas_ccu.catalog import write_catalog

    figures = not args.no_figures and importlib.util.find_spec("matplotlib") is not None
    if args.steps < 1:
        raise ValueError(f"--steps must be >= 1, got {args.steps}")
    result = write_catalog(
        args.out,
        names=args.only,
        steps=args.steps,
        relax=not args.no_relax,
        figures=figures,
        progress=None if args.quiet else (lambda name: print(f"measuring {name}", flush=True)),
    )
    for row in result["rows"]:
        expected = row["expected"] or "-"
        _say(
            args,
            f"{row['name']:<26} expected {expected:<12} measured "
            f"{row['global_curvature'] or 'n/a':<12} "
            f"planarity {row['crease_planarity_path']:.1e} m",
        )
    _say(args, f"wrote {len(result['files'])} files into {Path(args.out)} (table: catalog.md)")
    return 0


def _cmd_validate(args) -> int:
    import importlib.util
    import json

    from compas_ccu.fea.problem import ConvergenceError
    from compas_ccu.fea.record import agreement, remember
    from compas_ccu.fea.validation import validate

    model = _load(args.design)
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
        control=args.control,
        checks=not args.no_checks,
        area_load=args.area_load,
    )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    _say(args, f"validating {model.design.name} with {args.engine} ({args.mode}) ...")
    try:
        v = validate(model, **options)
    except ConvergenceError as exc:
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
        with open(out / "validation.json", "w") as fh:
            json.dump(failure, fh, indent=1)
        raise
    figures = not args.no_figures and importlib.util.find_spec("matplotlib") is not None
    files = v.write(out, figures=figures)
    summary = v.summary()
    if args.compare:
        other = "opensees" if args.engine == "kratos" else "kratos"
        _say(args, f"cross-checking with {other} ...")
        w = validate(model, **{**options, "engine": other})
        w.write(out / other, figures=False)
        summary["agreement"] = agreement(v, w)
        with open(out / "validation.json", "w") as fh:
            json.dump(summary, fh, indent=1)
    remember(args.design, summary, out)
    d, st, sol = summary["deviation"], summary["stresses"], summary["solver"]
    _say(
        args,
        f"deviation from the kinematic model at alpha = {summary['alpha']:.4g} deg: max "
        f"{d['max_percent']:.3f} %, mean {d['mean_percent']:.4f} % of the span "
        f"{summary['span']:.3f} m (max along the path {d['max_percent_along_path']:.3f} %)",
    )
    _say(
        args,
        f"stresses: bending {st['max_bending_MPa']:.2f} MPa, membrane "
        f"{st['max_membrane_MPa']:.2f} MPa, moment {st['max_moment_Nm_per_m']:.1f} Nm/m",
    )
    c = summary["checks"]
    if c:
        _say(
            args,
            f"checks (self-weight + {c['load']['area_load_N_per_m2']:.0f} N/m2): deflection "
            f"{c['deflection_max_m'] * 1e3:.2f} mm <= {c['deflection_limit_m'] * 1e3:.2f} mm "
            f"{'ok' if c['deflection_ok'] else 'EXCEEDED'}, utilisation "
            f"{c['utilisation_max']:.2f} {'ok' if c['utilisation_ok'] else 'EXCEEDED'}"
            + (
                f", buckling factor {c['buckling_factor']:.3g}"
                if c.get("buckling_factor") is not None
                else ""
            ),
        )
    if "agreement" in summary:
        a = summary["agreement"]
        _say(
            args,
            f"engines agree: positions within {a['position_max_percent']:.2e} % of span, "
            f"deviation {a['deviation_max_relative']:.1e}, moment {a['moment_max_relative']:.1e}"
            " (relative)",
        )
    _say(
        args,
        f"{summary['mesh']['elements']} elements, {sol['steps']} steps, "
        f"{sum(sol['iterations'])} iterations, {sol['cuts']} cuts, {sol['wall_time_s']:.1f} s",
    )
    for f in files:
        _say(args, f"wrote {f}")
    return 0


def _cmd_explore(args) -> int:
    import importlib.util
    import signal

    from compas_ccu.explore import load_sweep, run_sweep

    needed = ["pyarrow", "tqdm"] + ([] if args.in_process else ["distributed"])
    needed += ["bokeh"] if args.dashboard else []
    missing = [m for m in needed if importlib.util.find_spec(m) is None]
    if missing:
        raise ValueError(
            f"ccu explore needs {', '.join(missing)}: pip install 'compas_ccu[explore]'"
            + (" bokeh" if "bokeh" in missing else "")
            + " (make setup installs the extra)"
        )
    sweep = load_sweep(args.sweep)
    if args.in_process and (args.scheduler or args.workers):
        raise ValueError("--in-process runs without Dask: drop --scheduler / --workers")
    plots = not args.no_plots and importlib.util.find_spec("matplotlib") is not None
    _say(
        args,
        f"sweep {sweep.name}: {len(sweep.variants)} variants ({sweep.sampling}"
        + (f", seed {sweep.seed}" if sweep.sampling in ("random", "lhs") else "")
        + f") of {sweep.base_path.name} over {', '.join(sweep.parameter_names)}"
        + (f"; {sweep.duplicates} repeated samples dropped" if sweep.duplicates else ""),
    )

    def stop(signum, frame):  # SIGTERM: stop like Ctrl-C (the cluster shuts down cleanly)
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, stop)
    try:
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
    finally:
        signal.signal(signal.SIGTERM, previous)
    where = {"in-process": "in this process", "local": f"{result.workers} local Dask workers"}
    runner = where.get(result.scheduler, f"{result.workers} workers of {result.scheduler}")
    if result.reused:
        _say(args, f"{result.reused} variants were already in {result.out} (not recomputed)")
    if result.computed:
        _say(
            args,
            f"computed {result.computed} variants in {result.seconds:.1f} s on {runner}: "
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
        _say(
            args,
            f"{s['variants']} variants: {s['ok']} ok, {s['failed']} failed"
            + (f" ({errors})" if errors else "")
            + f"; {s['feasible']} feasible, {len(s['pareto'])} on the Pareto front of "
            + ", ".join(f"{k} ({v})" for k, v in s["objectives"].items()),
        )
        for b in s["best"]:
            params = ", ".join(f"{k} = {v}" for k, v in b["parameters"].items())
            values = ", ".join(f"{k} {v:.4g}" for k, v in b["objectives"].items())
            _say(args, f"  best {b['rank']}: {params}: {values}")
    _say(args, f"wrote {result.out / 'results.parquet'} and the summary in {result.out}")
    return 0


def _need_viz(command: str) -> None:
    import importlib.util

    missing = [m for m in ("matplotlib", "plotly", "tqdm") if importlib.util.find_spec(m) is None]
    if missing:
        raise ValueError(
            f"'ccu {command}' needs the viz extra ({', '.join(missing)} not installed): "
            "pip install 'compas_ccu[viz]'"
        )


def _formats(text: str, allowed, option: str) -> list:
    items = [f.strip().lower() for f in text.split(",") if f.strip()]
    bad = [f for f in items if f not in allowed]
    if bad or not items:
        allowed = ", ".join(allowed)
        raise ValueError(f"{option} must be a comma list of {allowed}, got {text!r}")
    return list(dict.fromkeys(items))


FIGURE_NAMES = (
    "views",
    "cut-patterns",
    "sequence",
    "quadrants",
    "planarity",
)


def _cmd_figures(args) -> int:
    import numpy as np

    _need_viz("figures")
    from compas_ccu.viz.export import FIGURE_FORMATS, save_figure
    from compas_ccu.viz.patterns import plot_cut_patterns
    from compas_ccu.viz.planarity import plot_planarity
    from compas_ccu.viz.quadrants import plot_quadrants
    from compas_ccu.viz.sequence import plot_deployment_sequence
    from compas_ccu.viz.views import plot_views

    formats = _formats(args.format, FIGURE_FORMATS, "--format")
    only = _formats(args.only, FIGURE_NAMES, "--only") if args.only else list(FIGURE_NAMES)
    model = _load(args.design)
    structure = model.deploy(args.alpha)
    alpha = structure.alpha
    out = Path(args.out)
    written = []
    if "views" in only:
        if args.values:
            try:
                values = np.load(args.values) if args.values.endswith(".npy") else None
                if values is None:
                    import json

                    values = np.asarray(json.loads(Path(args.values).read_text()), dtype=float)
            except (OSError, ValueError) as exc:
                raise ValueError(f"cannot read --values {args.values!r}: {exc}") from None
            colorings = [("values", values)]
        else:
            colorings = [(c, c) for c in args.color_by.split(",")]
            for name, _ in colorings:
                if name not in ("kind", "curvature", "alpha"):
                    raise ValueError(f"--color-by must be kind, curvature or alpha, got {name!r}")
        for name, color_by in colorings:
            fig = plot_views(structure, color_by=color_by, label=args.label)
            written += save_figure(fig, out / f"views-{name}", formats=formats)
    makers = {
        "cut-patterns": lambda: plot_cut_patterns(structure),
        "sequence": lambda: plot_deployment_sequence(model, alpha=alpha),
        "quadrants": lambda: plot_quadrants(model.design, alpha=alpha),
        "planarity": lambda: plot_planarity(model, alpha=alpha),
    }
    for name in only:
        if name in makers:
            written += save_figure(makers[name](), out / name, formats=formats)
    for path in written:
        _say(args, f"wrote {path}")
    return 0


def _cmd_animate(args) -> int:
    _need_viz("animate")
    from compas_ccu.viz.animation import ANIMATION_FORMATS, mp4_available, write_animation

    if args.format is None:
        formats = ["gif"] + (["mp4"] if mp4_available() else [])
    else:
        formats = _formats(args.format, ANIMATION_FORMATS, "--format")
    model = _load(args.design)
    out = Path(args.out)
    for fmt in formats:
        path = write_animation(
            model,
            out / f"deployment.{fmt}",
            frames=args.frames,
            fps=args.fps,
            alpha=args.alpha,
            progress=not args.quiet,
        )
        _say(args, f"wrote {path} ({args.frames} frames)")
    if args.format is None and "mp4" not in formats:
        _say(args, "no MP4 encoder (pip install 'compas_ccu[video]'): wrote the GIF only")
    return 0


def _cmd_view(args) -> int:
    _need_viz("view")
    from compas_ccu.viz.viewer import write_viewer

    model = _load(args.design)
    path = write_viewer(model, Path(args.out) / "viewer.html", steps=args.steps, alpha=args.alpha)
    _say(args, f"wrote {path} ({path.stat().st_size / 1e6:.1f} MB, works offline)")
    return 0


def _cmd_sheet(args) -> int:
    _need_viz("sheet")
    from compas_ccu.viz.export import FIGURE_FORMATS, save_figure
    from compas_ccu.viz.sheet import plot_contact_sheet

    formats = _formats(args.format, FIGURE_FORMATS, "--format")
    structures = [_load(d).deploy() for d in args.designs]
    fig = plot_contact_sheet(structures, columns=args.columns, title=args.title)
    for path in save_figure(fig, Path(args.out) / "contact-sheet", formats=formats):
        _say(args, f"wrote {path}")
    return 0


def _cmd_report(args) -> int:
    _need_viz("report")
    from compas_ccu.viz.report import write_report

    model = _load(args.design)
    report = write_report(
        model, args.out, steps=args.steps, frames=args.frames, progress=not args.quiet
    )
    for name, reason in sorted(report.skipped.items()):
        print(f"ccu: warning: {name} not produced: {reason}", file=sys.stderr)
    _say(args, f"wrote {len(report.files)} files into {Path(args.out)}")
    _say(args, f"report: {report.index.resolve()}")
    return 0


def _say(args, text: str) -> None:
    if not getattr(args, "quiet", False):
        print(text)


def _fail(message: str) -> int:
    print(f"ccu: error: {message}", file=sys.stderr)
    return 2


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ccu",
        description="Curved-crease unfolding: deploy CCU designs exactly and write the results.",
    )
    from compas_ccu import __version__

    parser.add_argument("--version", action="version", version=f"compas_ccu {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    p = sub.add_parser(
        "deploy",
        help="deploy a design to one reflection angle",
        description="Deploy DESIGN to --alpha and write structure.json "
        "(SPEC §4), structure.obj and structure.compas.json into --out.",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument(
        "--alpha",
        type=float,
        default=None,
        help="reference reflection angle in degrees (default: the design alpha)",
    )
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_deploy)

    p = sub.add_parser(
        "path",
        help="deploy along a path from the flat stack",
        description="Deploy DESIGN from alpha = 0 to the design alpha (or "
        "--alpha) in --steps equal steps; write states/state_NNNN.json and "
        "path.csv (alpha, span, rise, planarity per state).",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--steps", type=int, default=10, help="number of steps (default 10)")
    p.add_argument("--alpha", type=float, default=None, help="final alpha, degrees")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_path)

    p = sub.add_parser(
        "info",
        help="print the key figures of a design",
        description="Print plates, creases by kind, design alpha, deployment "
        "limit, span, rise and the flat stack footprint of DESIGN.",
    )
    p.add_argument("design", help="design TOML file")
    p.set_defaults(func=_cmd_info)

    p = sub.add_parser(
        "figures",
        help="write the figures of a design (PNG, SVG)",
        description="Write into --out: 3D views (views-<colouring>), the cut patterns, the "
        "deployment sequence, the four quadrants of the leading crease and the crease "
        "planarity along the path.",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--alpha", type=float, default=None, help="state to show, degrees")
    p.add_argument(
        "--color-by",
        default="kind,curvature,alpha",
        help="colourings of the 3D views: kind, curvature, alpha (comma list; default all)",
    )
    p.add_argument(
        "--values",
        default=None,
        help="colour the 3D views by a per-vertex (plates, vertices) or per-face (plates, "
        "faces) array from a .npy or JSON file instead",
    )
    p.add_argument("--label", default=None, help="colour bar label for --values")
    p.add_argument("--only", default=None, help="comma list of " + ", ".join(FIGURE_NAMES))
    p.add_argument("--format", default="png,svg", help="png, svg, pdf (default png,svg)")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_figures)

    p = sub.add_parser(
        "animate",
        help="animate the deployment (GIF, MP4)",
        description="Write --out/deployment.gif (and .mp4 where an encoder is available) from "
        "the flat-folded stack to the design alpha.",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--frames", type=int, default=48, help="number of frames (default 48)")
    p.add_argument("--fps", type=float, default=12.0, help="frames per second (default 12)")
    p.add_argument("--alpha", type=float, default=None, help="last state, degrees")
    p.add_argument("--format", default=None, help="gif, mp4 (default: gif, and mp4 if possible)")
    p.add_argument("--quiet", action="store_true", help="no progress, print nothing on success")
    p.set_defaults(func=_cmd_animate)

    p = sub.add_parser(
        "view",
        help="write the interactive 3D viewer page",
        description="Write --out/viewer.html: one self-contained page (works offline) with "
        "orbit / zoom, a deployment slider and toggles for plates, creases, rulings and cut "
        "patterns.",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--steps", type=int, default=24, help="slider steps (default 24)")
    p.add_argument("--alpha", type=float, default=None, help="last state, degrees")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_view)

    p = sub.add_parser(
        "sheet",
        help="contact sheet of several designs",
        description="Write --out/contact-sheet.png (and .svg): one perspective per design.",
    )
    p.add_argument("designs", nargs="+", help="design TOML files")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--columns", type=int, default=None, help="columns (default: about square)")
    p.add_argument("--title", default=None, help="sheet title")
    p.add_argument("--format", default="png,svg", help="png, svg, pdf (default png,svg)")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_sheet)

    p = sub.add_parser(
        "planarity",
        help="crease planarity along the deployment path",
        description="Measure how far every crease leaves its plane from alpha = 0 to the design "
        "alpha; write planarity.csv (every state and crease) and planarity.json (per-crease "
        "maximum). With --relax, also relax the worst state by least squares and report "
        "the residuals (SPEC §2 fallback).",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--steps", type=int, default=32, help="states along the path (default 32)")
    p.add_argument("--relax", action="store_true", help="relax the worst state")
    p.add_argument("--figure", action="store_true", help="also write the planarity figure")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_planarity)

    p = sub.add_parser(
        "catalog",
        help="regenerate and measure the rule catalog (paper Fig. 9-12)",
        description="Build every catalog design (crease profiles, plane distance, inclination "
        "about and perpendicular to the actuation axis, target curves), measure it and write "
        "DIR/<name>/design.toml + structure.json, catalog.csv / .md / .json and one contact "
        "sheet per figure (viz extra).",
    )
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--only", nargs="+", default=None, metavar="NAME", help="only these designs")
    p.add_argument("--steps", type=int, default=24, help="path states for planarity (24)")
    p.add_argument("--no-relax", action="store_true", help="skip the least-squares relaxation")
    p.add_argument("--no-figures", action="store_true", help="skip the contact sheets")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_catalog)

    p = sub.add_parser(
        "validate",
        help="validate the deployment with a nonlinear FE engine",
        description="Mesh the plates as quad shells (8 mm plywood by default), tie the hinges, "
        "deploy geometrically nonlinearly and compare with the kinematic model; then check "
        "the deployed state under self-weight + an area load. Writes validation.json, "
        "fe_results.npz and fe_stress / fe_deviation / fe_curves pictures into --out.",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--engine", choices=("kratos", "opensees"), default="kratos")
    p.add_argument("--mode", choices=("displacement", "actuation"), default="displacement")
    p.add_argument("--element-size", type=float, default=0.1, help="m (default 0.1)")
    p.add_argument("--steps", type=int, default=8, help="deployment steps (default 8)")
    p.add_argument("--alpha", type=float, default=None, help="target alpha, degrees")
    p.add_argument("--material", default="plywood", help="material name (default plywood)")
    p.add_argument("--thickness", type=float, default=0.008, help="m (default 0.008)")
    p.add_argument("--orthotropic", action="store_true", help="E1 along the crease, E2 across")
    p.add_argument(
        "--hinge-stiffness", type=float, default=0.0, help="rotational hinge spring, Nm/rad/m"
    )
    p.add_argument(
        "--control",
        choices=("supports", "edges"),
        default="supports",
        help="nodes that follow the kinematic path (displacement mode)",
    )
    p.add_argument("--area-load", type=float, default=1500.0, help="check load, N/m2 (1500)")
    p.add_argument("--no-checks", action="store_true", help="skip the structural checks")
    p.add_argument("--compare", action="store_true", help="cross-check with the other engine")
    p.add_argument("--no-figures", action="store_true", help="skip the pictures")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_validate)

    p = sub.add_parser(
        "explore",
        help="explore a design space: a sweep of variants on Dask",
        description="Build, deploy and measure every variant of SWEEP (a TOML file naming a base "
        "design and the parameters to vary, docs/explore.md) on a local Dask cluster or the "
        "cluster at --scheduler. Writes DIR/results.parquet (one row per variant: parameters, "
        "metrics, error), a journal that makes the run resumable (run it again to compute only "
        "what is missing), summary.json, plots/ and best/ (structure files of the best "
        "variants on the Pareto front).",
    )
    p.add_argument("sweep", help="sweep TOML file")
    p.add_argument("--out", required=True, help="output folder (resumes if it holds this sweep)")
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="address of a running Dask scheduler, e.g. tcp://host:8786",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="worker processes of the local cluster (default: one per core)",
    )
    p.add_argument(
        "--in-process",
        action="store_true",
        help="evaluate in this process without Dask (debugging, comparisons)",
    )
    p.add_argument(
        "--dashboard", action="store_true", help="serve the local cluster's Dask dashboard on :8787"
    )
    p.add_argument("--no-plots", action="store_true", help="skip the summary plots")
    p.add_argument("--quiet", action="store_true", help="no progress, print nothing on success")
    p.set_defaults(func=_cmd_explore)

    p = sub.add_parser(
        "fabricate",
        help="write the workshop files (DXF, 3dm, OBJ/glTF, FOLD, assembly sheet)",
        description="Model the plates' thickness (axis-shift hinges), check collisions from "
        "the flat stack to the design state and the bending of the plates, then write into "
        "--out: plates/plate_<id>.dxf (mm; layers CUT, CREASE, RULING_SCORE, LABEL), "
        "hinges.dxf (textile hinge strips), <name>.3dm (m), solids.obj / solids.glb / "
        "stack.obj, <name>.fold, assembly.svg / .pdf and fabrication.json. Defaults come from "
        "the design's [plates] section.",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--thickness", type=float, default=None, help="plate thickness, m")
    p.add_argument("--material", default=None, help="material name (docs/thickness.md)")
    p.add_argument("--grain", type=float, default=None, help="grain direction, degrees")
    p.add_argument("--hinge-width", type=float, default=None, help="hinge strip width, m")
    p.add_argument(
        "--allow-collisions", action="store_true", help="write even if the plates collide"
    )
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(func=_cmd_fabricate)

    p = sub.add_parser(
        "report",
        help="write the design report (index.html)",
        description="Write --out/index.html with the viewer, the figures, the animation, the "
        "key figures of the design and links to every file written (data, figures, viewer).",
    )
    p.add_argument("design", help="design TOML file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--steps", type=int, default=24, help="deployment path steps (default 24)")
    p.add_argument("--frames", type=int, default=48, help="animation frames (default 48)")
    p.add_argument("--quiet", action="store_true", help="no progress, print nothing on success")
    p.set_defaults(func=_cmd_report)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``ccu`` command."""
    from compas_ccu.errors import CCUError

    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (CCUError, ValueError) as exc:
        # CCUError: bad design or state; ValueError: a bad option value, named by the message
        return _fail(str(exc))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
