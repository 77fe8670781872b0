"""``ccu catalog``: regenerate and measure the rule catalog (paper Fig. 9-12)."""

from __future__ import annotations

from pathlib import Path

from compas_ccu.catalog import write_catalog
from compas_ccu.cli.common import missing_modules, progress, say
from compas_ccu.cli.parser import OUT, QUIET, Command, option

__all__ = ["COMMANDS"]


def catalog(args) -> int:
    figures = not args.no_figures and not missing_modules(["matplotlib"])
    result = write_catalog(
        args.out,
        names=args.only,
        steps=args.steps,
        relax=not args.no_relax,
        figures=figures,
        progress=None if args.quiet else (lambda name: progress(args, f"measuring {name}")),
    )
    for row in result["rows"]:
        expected = row["expected"] or "-"
        measured = row["global_curvature"] or "n/a"
        say(
            args,
            f"{row['name']:<26} expected {expected:<12} measured {measured:<12} "
            f"planarity {row['crease_planarity_path']:.1e} m",
        )
    say(args, f"wrote {len(result['files'])} files into {Path(args.out)} (table: catalog.md)")
    return 0


COMMANDS = (
    Command(
        "catalog",
        "Build every catalog design (crease profiles, plane distance, inclination "
        "about and perpendicular to the actuation axis, target curves), measure it and write "
        "DIR/<name>/design.toml + structure.json, catalog.csv / .md / .json and one contact "
        "sheet per figure (viz extra).",
        (
            OUT,
            option("--only", nargs="+", default=None, metavar="NAME", help="only these designs"),
            option(
                "--steps",
                limit="states",
                type=int,
                default=24,
                minimum=1,
                help="path states for planarity (24)",
            ),
            option("--no-relax", action="store_true", help="skip the least-squares relaxation"),
            option("--no-figures", action="store_true", help="skip the contact sheets"),
            QUIET,
        ),
        catalog,
    ),
)
