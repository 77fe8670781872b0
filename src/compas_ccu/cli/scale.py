"""``ccu scale``: a span scaling study of a design (docs/explore.md)."""

from __future__ import annotations

from pathlib import Path

from compas_ccu.cli.common import load_model, missing_modules, say, sheet_option
from compas_ccu.cli.parser import (
    DESIGN,
    MAX_AREA_LOAD,
    MAX_THICKNESS,
    OUT,
    QUIET,
    Command,
    numbers,
    option,
)
from compas_ccu.design.schema import MAX_LENGTH, design_sheet
from compas_ccu.errors import OptionError
from compas_ccu.explore.scale import THICKNESS_LAWS, plot_scale, scale_study, write_csv
from compas_ccu.fea.loads import CASE_NAMES
from compas_ccu.key_figures.text import utilisation_text
from compas_ccu.viz.export import save_figure

__all__ = ["COMMANDS"]


def scale(args) -> int:
    thicknesses = None
    if args.thickness is not None:
        thicknesses = numbers(
            args.thickness,
            "--thickness",
            maximum=MAX_THICKNESS,
            form="thicknesses in m separated by commas",
            example="0.008,0.01",
        )
    law = args.thickness_law or ("given" if thicknesses else "constant")
    model = load_model(args.design)
    sheet = design_sheet(model.design.values) if args.sheet is None else tuple(args.sheet)
    base = model.deploy().metrics["span"]
    if (args.area_load is not None or args.load_case) and not args.fe:
        raise OptionError(
            "--area-load and --load-case choose the load of the FE checks: give --fe as well"
        )
    fe = None
    if args.fe:
        fe = {} if args.area_load is None else {"area_load": args.area_load}
        if args.load_case:
            fe["load_cases"] = list(args.load_case)

    def progress(row):
        if row["status"] == "ok":
            say(
                args,
                f"span {row['span']:6.3f} m  t {row['thickness'] * 1000:5.2f} mm  "
                f"mass {row['mass']:8.1f} kg  bending "
                f"{utilisation_text(row['bending_utilisation'])}  "
                f"actuation {row['actuation_force']:7.0f} N  plate "
                f"{row['plate_length']:.3f} x {row['plate_width']:.3f} m"
                + ("" if row["fits_sheet"] else " (larger than the sheet)"),
            )
        else:
            say(args, f"span {row['span_target']:6.3f} m  failed: {row['error']}")

    rows = scale_study(
        model.design.metric_document(),
        base,
        to_span=args.to,
        steps=args.steps,
        law=law,
        thicknesses=thicknesses,
        sheet=tuple(sheet),
        collisions=True,
        fe=fe,
        progress=progress,
    )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "scale.csv")
    say(args, f"wrote {out / 'scale.csv'}")
    if not missing_modules(["matplotlib"]):
        fig = plot_scale(
            rows, sheet=tuple(sheet), title=f"{model.design.name}: span scaling ({law})"
        )
        for path in save_figure(fig, out / "scale"):
            say(args, f"wrote {path}")
    if fe is None:
        say(args, NO_FE_NOTE)
    return 0


#: What a study without ``--fe`` leaves out (the published trend: as the span grows at
#: constant thickness, the bending stress falls and buckling governs; docs/explore.md).
NO_FE_NOTE = (
    "note: without --fe, self-weight and buckling are not in this table: the bending "
    "utilisation above is the deployment's active bending alone, and buckling governs as the "
    "span grows (run with --fe for the FE checks)"
)


COMMANDS = (
    Command(
        "scale",
        "Scale every length of DESIGN from its crease span to --to in --steps equal steps, the "
        "plate thickness following --thickness-law, and measure every span as ccu explore does "
        "(stack and plate size, mass, bending utilisation, actuation force, collisions; FE "
        "load cases with --fe). Writes "
        "scale.csv and scale.png / .svg (the columns against the span) into --out.",
        (
            DESIGN,
            OUT,
            option(
                "--to",
                type=float,
                positive=True,
                maximum=MAX_LENGTH,
                required=True,
                help="the largest span, m",
            ),
            option(
                "--steps",
                limit="variants",
                extra=1,
                type=int,
                default=7,
                minimum=1,
                help="steps after the base span (default 7)",
            ),
            option(
                "--thickness-law",
                choices=THICKNESS_LAWS,
                default=None,
                help="constant (default), proportional, cuberoot (t0 (s)^(2/3)) or given",
            ),
            option(
                "--thickness",
                default=None,
                help="with law 'given': one thickness per span, m, comma separated",
            ),
            sheet_option(),
            option(
                "--fe",
                action="store_true",
                help="also run the FE validation at every span (minutes each): deflection, "
                "utilisation, linear buckling factor and hinge forces under the design's load "
                "cases ([loads]) or self-weight + --area-load",
            ),
            option(
                "--area-load",
                type=float,
                minimum=0.0,
                maximum=MAX_AREA_LOAD,
                default=None,
                help="with --fe: a uniform load case, N/m2 (default 1500 if the design's [loads] "
                "define no action)",
            ),
            option(
                "--load-case",
                action="append",
                choices=CASE_NAMES,
                default=None,
                help="with --fe: run only this load case (repeat for several)",
            ),
            QUIET,
        ),
        scale,
    ),
)
