"""``ccu fabricate``: the workshop files of a design (the ``fab`` extra)."""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

from compas_ccu.cli.common import FAB, load_model, need_extra, progress, say, sheet_option
from compas_ccu.cli.parser import (
    DESIGN,
    MAX_THICKNESS,
    OUT,
    QUIET,
    Command,
    option,
)
from compas_ccu.cli.text import thickness_lines
from compas_ccu.design import load_design
from compas_ccu.design.schema import MAX_LENGTH
from compas_ccu.design.writer import design_toml
from compas_ccu.errors import OptionError
from compas_ccu.fabrication.fabricate import fabricate as write_fabrication
from compas_ccu.fabrication.importing import import_design, import_structure
from compas_ccu.fabrication.workshop import WorkshopOptions
from compas_ccu.key_figures.text import rows_lines, workshop_rows
from compas_ccu.model import CCUModel

__all__ = ["COMMANDS"]


def fabricate(args) -> int:
    need_extra("fabricate", "fab", FAB)
    need_extra("fabricate", "viz", ("matplotlib",))  # the assembly sheet

    model = load_model(args.design)
    progress(
        args, f"{model.design.name}: thick plates, collision and bending checks, then the files ..."
    )
    workshop = WorkshopOptions.from_section(
        model.design.fabrication,
        sheets=None if args.sheet is None else tuple(tuple(s) for s in args.sheet),
        kerf=args.kerf,
        score_rulings=True if args.score_rulings else None,
        nesting=args.nesting,
        nesting_seed=args.nesting_seed,
        nesting_steps=args.nesting_steps,
    )
    manifest = write_fabrication(
        model,
        args.out,
        thickness=args.thickness,
        material=args.material,
        grain=args.grain,
        hinge_width=args.hinge_width,
        allow_collisions=args.allow_collisions,
        workshop=workshop,
        design_sha256=_file_sha256(args.design),
    )
    for line in thickness_lines(manifest):
        say(args, line)
    for line in workshop_lines(manifest):
        say(args, line)
    for f in manifest["files"]:
        say(args, f"wrote {Path(args.out) / f}")
    failed = manifest["failed_checks"]
    for reason in failed:
        print(f"ccu: check failed: {reason}", file=sys.stderr)
    if failed and not args.allow_exceeded:
        print(
            "ccu: the files are written for inspection; exit status 3 (--allow-exceeded: 0)",
            file=sys.stderr,
        )
        return 3
    return 0


def _file_sha256(design) -> str | None:
    """SHA-256 of the design file's bytes (as the report and ``ccu view`` hash it), or None."""
    path = Path(design)
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None


def workshop_lines(manifest: dict) -> list:
    """The sheets, the bill of materials and the assembly of a ``fabrication.json`` as text
    (:func:`compas_ccu.key_figures.text.workshop_rows`)."""
    return rows_lines(workshop_rows(manifest))


def _correction_text(undone) -> str:
    if undone is None:
        return "the patterns as drawn"
    return (
        f"the thickness correction of {undone['thickness'] * 1e3:g} mm plates undone "
        f"(up to {undone['largest'] * 1e3:.3g} mm, {undone['iterations']} iterations)"
    )


def import_plates(args) -> int:
    need_extra("import", "fab", ("ezdxf",))
    target = Path(args.toml)
    if target.suffix.lower() != ".toml":
        raise OptionError(f"--out must name a design file ending in .toml, got {str(target)!r}")
    if target.exists() and not args.force:
        raise OptionError(f"{str(target)!r} exists; give --force to overwrite it")
    options = dict(
        crease=args.crease,
        alpha=args.alpha,
        reference=args.reference,
        name=args.name,
        units=args.units,
        as_drawn=args.as_drawn,
    )
    if args.leading_pair_only:
        document, report = import_design(args.folder, **options)
        correction = _correction_text(report["thickness_correction"])
        header = (
            f"Imported by `ccu import --leading-pair-only` from the plate files in "
            f"{args.folder}:\n{report['crease']}, leading plate {report['leading']}, partner "
            f"{report['partner']} (its mirror image to {report['partner_error']:.2g}), "
            f"{report['segments']} segments;\n{correction}."
        )
    else:
        imported = import_structure(args.folder, **options)
        document, report = imported.document, imported.report
        correction = _correction_text(report["thickness_correction"])
        ids = "the plate ids of the files" if report["ids_written"] else "plate ids 0, 1, ..."
        header = (
            f"Imported by `ccu import` from the plate files in {args.folder}:\n"
            f"{len(report['attached'])} plates, leading {report['crease']} ({report['leading']},"
            f" partner {report['partner']}), {report['segments']} segments, {ids};\n"
            f"{correction}."
        )
    text = design_toml(document, header=header)
    target.parent.mkdir(parents=True, exist_ok=True)
    partial = target.with_name(target.name + ".part")
    partial.write_text(text, encoding="utf-8")
    try:
        design = load_design(partial)
        structure = CCUModel(design).deploy()  # the design must deploy before it is kept
    except Exception:
        partial.unlink()
        raise
    partial.replace(target)
    say(args, f"{len(report['plates'])} plate files, creases: {', '.join(report['pairs'])}")
    if args.leading_pair_only:
        say(
            args,
            f"{report['crease']}: {report['leading']} (leading) and {report['partner']}, "
            f"{report['segments']} segments; deployed to alpha = {structure.alpha:g} deg",
        )
    else:
        say(
            args,
            f"{len(report['attached'])} plates joined from {report['crease']} "
            f"({report['leading']} leading, {report['partner']} its partner), "
            f"{report['segments']} segments; deployed to alpha = {structure.alpha:g} deg",
        )
    say(args, correction)
    say(args, f"wrote {target}")
    return 0


COMMANDS = (
    Command(
        "fabricate",
        "Model the plates' thickness (axis-shift hinges), check collisions from "
        "the flat stack to the design state and the bending of the plates; split the plates "
        "that fit no sheet along rulings (splice plates) and nest every part onto the sheets; "
        "then write into --out: plates/plate_<id>.dxf (mm; layers CUT, CREASE, RULING_SCORE "
        "or RULING, LABEL), sheets/sheet_<k>.dxf (kerf-compensated toolpaths), bom.csv, "
        "hinges.dxf (textile hinge strips), <name>.3dm (m), solids.obj / solids.glb / "
        "stack.obj, <name>.fold, assembly.svg / .pdf and fabrication.json. Defaults come from "
        "the design's [plates] and [fabrication] sections. Exit status 3 when a check fails "
        "(the files are written) unless --allow-exceeded.",
        (
            DESIGN,
            OUT,
            option(
                "--thickness",
                type=float,
                positive=True,
                maximum=MAX_THICKNESS,
                default=None,
                help="plate thickness, m",
            ),
            option("--material", default=None, help="material name (docs/thickness.md)"),
            option(
                "--grain",
                type=float,
                minimum=-360.0,
                maximum=360.0,
                default=None,
                help="grain direction, degrees",
            ),
            option(
                "--hinge-width",
                type=float,
                positive=True,
                maximum=MAX_LENGTH,
                default=None,
                help="hinge strip width, m",
            ),
            option(
                "--allow-collisions", action="store_true", help="write even if the plates collide"
            ),
            option(
                "--allow-exceeded",
                action="store_true",
                help="exit 0 even if a check fails (bending utilisation above 1)",
            ),
            sheet_option(repeat=True),
            option("--kerf", type=float, minimum=0.0, maximum=0.1, default=None, help="kerf, m"),
            option(
                "--nesting",
                default=None,
                choices=("auto", "compas_nest", "spyrrow", "shelf"),
                help="true-shape nesting (auto: compas_nest, else spyrrow, else shelves with a "
                "warning) or bounding boxes in rows (shelf, fast)",
            ),
            option(
                "--nesting-seed",
                type=int,
                minimum=0,
                maximum=2**32 - 1,
                default=None,
                help="seed of the nesting search (default [fabrication] nesting_seed, 0)",
            ),
            option(
                "--nesting-steps",
                type=int,
                minimum=1,
                maximum=100_000,
                default=None,
                help="steps per packing of the nesting search (default [fabrication] "
                "nesting_steps, 500)",
            ),
            option("--score-rulings", action="store_true", help="score the rulings on the sheets"),
            QUIET,
        ),
        fabricate,
    ),
    Command(
        "import",
        "Read a folder of plate cut files (layers CUT, CREASE, RULING_SCORE; as ccu fabricate "
        "writes them or drawn by hand to the same convention, docs/import.md) and write the "
        "design of the whole structure: the leading plate's crease polyline and ruling ends "
        '(crease.state = "flat", rulings.type = "explicit") and every other plate\'s cut '
        'pattern and where it attaches (layout.type = "patterns"); --leading-pair-only writes '
        "the leading crease pair alone (a single-crease design). The leading crease is "
        "--crease, else fabrication.json's leading_crease, else the middle one. Inconsistent "
        "drawings (missing layers, crossing rulings, partner creases of different length) are "
        "refused, naming the plate file and the entity. With fabrication.json's plate "
        "thickness, the thickness correction of the cut patterns is undone (--as-drawn: not). "
        "The design is deployed once before it is written.",
        (
            option("folder", help="folder of plate DXFs (ccu fabricate's output folder)"),
            option("--out", dest="toml", required=True, help="design TOML file to write"),
            option(
                "--crease",
                default=None,
                help="the leading crease: crease id (or a plate file)",
            ),
            option(
                "--leading-pair-only",
                action="store_true",
                help="write the leading crease pair alone (layout single), not the structure",
            ),
            option(
                "--alpha",
                type=float,
                default=None,
                help="design reflection angle, degrees (default: fabrication.json's)",
            ),
            option(
                "--reference",
                type=float,
                minimum=0.0,
                maximum=1.0,
                default=0.5,
                help="arc-length fraction of the reference vertex (default 0.5)",
            ),
            option("--name", default=None, help="design name"),
            option(
                "--units",
                default=None,
                choices=("mm", "cm", "m", "in", "ft"),
                help="units of the DXF files (default: $INSUNITS, unitless: mm)",
            ),
            option(
                "--as-drawn",
                action="store_true",
                help="take the patterns as drawn: do not undo the thickness correction of "
                "fabrication.json's plates",
            ),
            option("--force", action="store_true", help="overwrite the design file"),
            QUIET,
        ),
        import_plates,
        staged=False,
    ),
)
