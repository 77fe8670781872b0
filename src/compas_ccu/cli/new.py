"""``ccu new``: a commented design file from a preset (:mod:`compas_ccu.design.presets`)."""

from __future__ import annotations

from compas_ccu.cli.common import say
from compas_ccu.cli.parser import QUIET, Command, option
from compas_ccu.design.presets import PRESETS, write_preset

__all__ = ["COMMANDS"]


def new(args) -> int:
    design = write_preset(args.preset, args.path, force=args.force)
    say(
        args,
        f"wrote {args.path} (preset {args.preset}: {PRESETS[args.preset]}; "
        f"{design.layout.type} layout, units {design.units})",
    )
    say(args, f"next: ccu info {args.path}; every key is explained in docs/design-files.md")
    return 0


COMMANDS = (
    Command(
        "new",
        "Write NAME.toml, a design file to start from, with a comment on every key: "
        + "; ".join(f"{name}: {text}" for name, text in PRESETS.items())
        + ". Lengths in metres ([design] units changes that). An existing file is not "
        "overwritten without --force.",
        (
            option("path", metavar="NAME.toml", help="the new design file"),
            option(
                "--preset",
                choices=tuple(PRESETS),
                default="vault",
                help="the design to start from (default vault)",
            ),
            option("--force", action="store_true", help="overwrite an existing file"),
            QUIET,
        ),
        new,
    ),
)
