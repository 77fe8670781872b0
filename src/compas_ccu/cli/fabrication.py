"""``ccu fabricate``: the workshop files of a design (the ``fab`` extra)."""

from __future__ import annotations

from pathlib import Path

from compas_ccu.cli.common import FAB, load_model, need_extra, say
from compas_ccu.cli.parser import DESIGN, OUT, QUIET, Command, option
from compas_ccu.cli.text import thickness_lines
from compas_ccu.fabrication.fabricate import fabricate as write_fabrication

__all__ = ["COMMANDS"]


def fabricate(args) -> int:
    need_extra("fabricate", "fab", FAB)
    need_extra("fabricate", "viz", ("matplotlib",))  # the assembly sheet

    model = load_model(args.design)
    say(
        args, f"{model.design.name}: thick plates, collision and bending checks, then the files ..."
    )
    manifest = write_fabrication(
        model,
        args.out,
        thickness=args.thickness,
        material=args.material,
        grain=args.grain,
        hinge_width=args.hinge_width,
        allow_collisions=args.allow_collisions,
    )
    for line in thickness_lines(manifest):
        say(args, line)
    for f in manifest["files"]:
        say(args, f"wrote {Path(args.out) / f}")
    return 0


COMMANDS = (
    Command(
        "fabricate",
        "write the workshop files (DXF, 3dm, OBJ/glTF, FOLD, assembly sheet)",
        "Model the plates' thickness (axis-shift hinges), check collisions from "
        "the flat stack to the design state and the bending of the plates, then write into "
        "--out: plates/plate_<id>.dxf (mm; layers CUT, CREASE, RULING_SCORE, LABEL), "
        "hinges.dxf (textile hinge strips), <name>.3dm (m), solids.obj / solids.glb / "
        "stack.obj, <name>.fold, assembly.svg / .pdf and fabrication.json. Defaults come from "
        "the design's [plates] section.",
        (
            DESIGN,
            OUT,
            option("--thickness", type=float, default=None, help="plate thickness, m"),
            option("--material", default=None, help="material name (docs/thickness.md)"),
            option("--grain", type=float, default=None, help="grain direction, degrees"),
            option("--hinge-width", type=float, default=None, help="hinge strip width, m"),
            option(
                "--allow-collisions", action="store_true", help="write even if the plates collide"
            ),
            QUIET,
        ),
        fabricate,
    ),
)
