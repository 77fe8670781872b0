"""``ccu figures | animate | view | sheet | report``: pictures of designs (the ``viz`` extra).

The viz modules are imported inside the commands, after the check for the extra, so that
``ccu --help`` and the other commands work without it.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

from compas_ccu.cli.common import comma_list, load_model, need_viz, progress, say
from compas_ccu.cli.parser import DESIGN, OUT, QUIET, QUIET_PROGRESS, Command, option
from compas_ccu.errors import OptionError
from compas_ccu.fea.record import last_validation
from compas_ccu.io import read_values
from compas_ccu.viz.animation import ANIMATION_FORMATS, mp4_available, write_animations
from compas_ccu.viz.camera import camera
from compas_ccu.viz.export import FIGURE_FORMATS, save_figure
from compas_ccu.viz.patterns import plot_cut_patterns
from compas_ccu.viz.planarity import plot_planarity
from compas_ccu.viz.quadrants import plot_quadrants
from compas_ccu.viz.record import read_sheets
from compas_ccu.viz.report import write_report
from compas_ccu.viz.sequence import plot_deployment_sequence
from compas_ccu.viz.sheet import plot_contact_sheet
from compas_ccu.viz.viewer import write_viewer
from compas_ccu.viz.views import plot_views

__all__ = ["COMMANDS", "FIGURE_NAMES", "COLOR_BY"]

#: Figure types of ``ccu figures --only``.
FIGURE_NAMES = ("views", "cut-patterns", "sequence", "quadrants", "planarity")
#: Colourings of ``ccu figures --color-by``.
COLOR_BY = ("kind", "curvature", "alpha")


def _colorings(args) -> list:
    """(name, colour_by) of the 3D views: --values (an array from a file) or --color-by."""
    if args.values:
        try:
            return [("values", read_values(args.values))]
        except (OSError, ValueError) as exc:
            raise OptionError(f"cannot read --values {args.values!r}: {exc}") from None
    colorings = [(c, c) for c in args.color_by.split(",")]
    for name, _ in colorings:
        if name not in COLOR_BY:
            raise OptionError(f"--color-by must be kind, curvature or alpha, got {name!r}")
    return colorings


def _size(text):
    """``--size WxH`` (inches) as (w, h), or None."""
    if text is None:
        return None
    try:
        w, h = (float(x) for x in text.lower().replace("×", "x").split("x"))
    except ValueError:
        raise OptionError(
            f"--size must be WIDTHxHEIGHT in inches, e.g. 12x7, got {text!r}"
        ) from None
    if not (0.0 < w <= 200.0 and 0.0 < h <= 200.0):
        raise OptionError(f"--size must be positive inches up to 200, got {text!r}")
    return w, h


def figures(args) -> int:
    need_viz("figures")

    formats = comma_list(args.format, FIGURE_FORMATS, "--format")
    only = comma_list(args.only, FIGURE_NAMES, "--only") if args.only else list(FIGURE_NAMES)
    size = _size(args.size)
    views = ("perspective", "plan", "elevation", "side")
    if args.view is not None:
        camera(args.view)  # a bad --view fails before any work
        views = (args.view,)
    model = load_model(args.design)
    structure = model.deploy(args.alpha)
    alpha = structure.alpha
    out = Path(args.out)
    written = []

    def save(fig, stem):
        return save_figure(fig, out / stem, formats=formats, dpi=args.dpi, size=size)

    if "views" in only:
        for name, color_by in _colorings(args):
            fig = plot_views(structure, color_by=color_by, label=args.label, views=views)
            written += save(fig, f"views-{name}")
    makers = {
        "cut-patterns": lambda: plot_cut_patterns(structure),
        "sequence": lambda: plot_deployment_sequence(model, alpha=alpha, view=views[0]),
        "quadrants": lambda: plot_quadrants(model.design, alpha=alpha),
        "planarity": lambda: plot_planarity(model, alpha=alpha),
    }
    for name in only:
        if name in makers:
            written += save(makers[name](), name)
    for path in written:
        say(args, f"wrote {path}")
    return 0


def animate(args) -> int:
    need_viz("animate")

    if args.format is None:
        formats = ["gif"] + (["mp4"] if mp4_available() else [])
    else:
        formats = comma_list(args.format, ANIMATION_FORMATS, "--format")
    model = load_model(args.design)
    out = Path(args.out)
    written = write_animations(  # the frames are rendered once for every format
        model,
        [out / f"deployment.{fmt}" for fmt in formats],
        frames=args.frames,
        fps=args.fps,
        alpha=args.alpha,
        progress=not args.quiet,
    )
    for path in written:
        say(args, f"wrote {path} ({args.frames} frames)")
    if args.format is None and "mp4" not in formats:
        say(args, "no MP4 encoder (pip install 'compas_ccu[video]'): wrote the GIF only")
    return 0


def view(args) -> int:
    need_viz("view")

    if args.view is not None:
        camera(args.view)  # a bad --view fails before any work
    model = load_model(args.design)
    sheets = None
    if args.fabrication is not None:  # read (and refused) before any work
        design = Path(args.design)
        sha = hashlib.sha256(design.read_bytes()).hexdigest() if design.is_file() else None
        sheets = read_sheets(args.fabrication, design=model.design.name, sha256=sha)
    path = write_viewer(
        model,
        Path(args.out) / "viewer.html",
        steps=args.steps,
        alpha=args.alpha,
        view=args.view,
        sheets=sheets,
    )
    say(args, f"wrote {path} ({path.stat().st_size / 1e6:.1f} MB, works offline)")
    if sheets is not None:
        say(
            args,
            f"the cut patterns are the {len(sheets['sheets'])} sheets of {args.fabrication} "
            f"({len(sheets['parts'])} parts)",
        )
    return 0


def sheet(args) -> int:
    need_viz("sheet")

    formats = comma_list(args.format, FIGURE_FORMATS, "--format")
    if args.columns is not None and args.columns > len(args.designs):
        raise OptionError(
            f"--columns must be <= the number of designs ({len(args.designs)}), got {args.columns}"
        )
    structures = [load_model(d).deploy() for d in args.designs]
    fig = plot_contact_sheet(structures, columns=args.columns, title=args.title)
    for path in save_figure(fig, Path(args.out) / "contact-sheet", formats=formats):
        say(args, f"wrote {path}")
    return 0


def _last_validation(design) -> tuple:
    """The ``validation.json`` of the last ``ccu validate`` of this design file's contents (and
    its load-case picture), if its folder still holds it."""
    record = last_validation(design)
    if not record or not record.get("out"):
        return None, []
    folder = Path(record["out"])
    try:
        summary = json.loads((folder / "validation.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None, []
    if summary.get("design") != record.get("design") or not summary.get("converged", True):
        return None, []
    if "cases" not in (summary.get("checks") or {}):
        return None, []  # no load cases (before they existed, or --no-checks)
    summary["_folder"] = str(folder)
    return summary, [folder / "fe_load_cases.png"]


def report(args) -> int:
    need_viz("report")

    model = load_model(args.design)
    validation, pictures = _last_validation(args.design)
    if validation is not None:
        progress(args, f"with the FE validation in {validation['_folder']}")
    if args.fabrication is not None:
        progress(args, f"with the fabrication files in {args.fabrication}")
    written = write_report(
        model,
        args.out,
        steps=args.steps,
        frames=args.frames,
        progress=not args.quiet,
        validation=validation,
        validation_figures=pictures,
        validation_record=last_validation(args.design),  # the headline, as ccu info has it
        design_file=args.design,
        fabrication=args.fabrication,
        pdf=not args.no_pdf,
    )
    for name, reason in sorted(written.skipped.items()):
        print(f"ccu: warning: {name} not produced: {reason}", file=sys.stderr)
    say(args, f"wrote {len(written.files)} files into {Path(args.out)}")
    say(args, f"report: {written.index.resolve()}")
    if written.pdf is not None:
        say(args, f"report (PDF): {written.pdf.resolve()}")
    return 0


FORMATS = option("--format", default="png,svg", help="png, svg, pdf (default png,svg)")
VIEW_HELP = (
    "camera: perspective, plan (= top), elevation (= front), side, iso, or AZIMUTH,ELEVATION "
    "in degrees (orthographic)"
)

COMMANDS = (
    Command(
        "figures",
        "Write into --out: 3D views (views-<colouring>), the cut patterns, the "
        "deployment sequence, the four quadrants of the leading crease and the crease "
        "planarity along the path.",
        (
            DESIGN,
            OUT,
            option("--alpha", type=float, default=None, help="state to show, degrees"),
            option(
                "--color-by",
                default="kind,curvature,alpha",
                help="colourings of the 3D views: kind, curvature, alpha (comma list; default all)",
            ),
            option(
                "--values",
                default=None,
                help="colour the 3D views by a per-vertex (plates, vertices) or per-face (plates, "
                "faces) array from a .npy or JSON file instead",
            ),
            option("--label", default=None, help="colour bar label for --values"),
            option("--only", default=None, help="comma list of " + ", ".join(FIGURE_NAMES)),
            option(
                "--view",
                default=None,
                help=VIEW_HELP + "; the 3D views and the sequence show this one camera "
                "(default: perspective, plan, elevation and side)",
            ),
            option(
                "--dpi",
                type=int,
                minimum=10,
                maximum=2400,
                default=150,
                help="PNG resolution, dots per inch (default 150)",
            ),
            option(
                "--size",
                default=None,
                help="figure size WIDTHxHEIGHT in inches, e.g. 12x7 (default: each figure's own)",
            ),
            FORMATS,
            QUIET,
        ),
        figures,
    ),
    Command(
        "animate",
        "Write --out/deployment.gif (and .mp4 where an encoder is available) from "
        "the flat-folded stack to the design alpha.",
        (
            DESIGN,
            OUT,
            option(
                "--frames",
                limit="states",
                extra=0,
                type=int,
                minimum=2,
                default=48,
                help="number of frames (default 48)",
            ),
            option(
                "--fps",
                type=float,
                positive=True,
                maximum=1000.0,
                default=12.0,
                help="frames per second (default 12)",
            ),
            option("--alpha", type=float, default=None, help="last state, degrees"),
            option("--format", default=None, help="gif, mp4 (default: gif, and mp4 if possible)"),
            QUIET_PROGRESS,
        ),
        animate,
    ),
    Command(
        "view",
        "Write --out/viewer.html: one self-contained page (works offline) with "
        "orbit / zoom, a deployment slider and toggles for plates, creases, rulings and cut "
        "patterns (with --fabrication: the sheets of the workshop, every part at its nested "
        "place).",
        (
            DESIGN,
            OUT,
            option(
                "--steps",
                limit="states",
                type=int,
                minimum=1,
                default=24,
                help="slider steps (default 24)",
            ),
            option("--alpha", type=float, default=None, help="last state, degrees"),
            option("--view", default=None, help=VIEW_HELP + " (default: perspective)"),
            option(
                "--fabrication",
                default=None,
                metavar="FOLDER",
                help="a folder written by 'ccu fabricate' for this design: the cut patterns "
                "toggle shows its sheets (sheets.json) instead of the compact layout",
            ),
            QUIET,
        ),
        view,
    ),
    Command(
        "sheet",
        "Write --out/contact-sheet.png (and .svg): one perspective per design.",
        (
            option("designs", nargs="+", help="design TOML files"),
            OUT,
            option(
                "--columns",
                type=int,
                minimum=1,
                default=None,
                help="columns (default: about square; at most the number of designs)",
            ),
            option("--title", default=None, help="sheet title"),
            FORMATS,
            QUIET,
        ),
        sheet,
    ),
    Command(
        "report",
        "Write --out/index.html and --out/report.pdf: the engineering record of a design (the "
        "design file as read with its SHA-256, the compas_ccu version, the date, the units and "
        "the material constants), its key figures and checks as 'ccu info' words them, the FE "
        "results of its last 'ccu validate' (of this file's contents), the fabrication files of "
        "--fabrication, the viewer, the figures, the animation and links to every file written.",
        (
            DESIGN,
            OUT,
            option(
                "--steps",
                limit="states",
                type=int,
                minimum=1,
                default=24,
                help="deployment path steps (default 24)",
            ),
            option(
                "--frames",
                limit="states",
                extra=0,
                type=int,
                minimum=2,
                default=48,
                help="animation frames (default 48)",
            ),
            option(
                "--fabrication",
                default=None,
                metavar="FOLDER",
                help="a folder written by 'ccu fabricate' for this design: copied into "
                "--out/fabrication, every file linked, its sheets and bill of materials shown",
            ),
            option("--no-pdf", action="store_true", help="do not write report.pdf"),
            QUIET_PROGRESS,
        ),
        report,
    ),
)
