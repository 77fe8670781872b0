"""What the command modules share: loading a design, printing, the extras a command needs, the
``--sheet`` option."""

from __future__ import annotations

import sys

from compas_ccu.cli.parser import MAX_SHEET, Option, option
from compas_ccu.design.schema import STOCK_SHEET
from compas_ccu.errors import OptionError, missing_modules, require
from compas_ccu.model import load_model

__all__ = ["load_model", "say", "progress", "missing_modules", "need_extra", "need_viz"]
__all__ += ["comma_list", "sheet_option"]

#: Modules of the optional extras the commands check for before they import them.
VIZ = ("matplotlib", "plotly", "tqdm")
FAB = ("ezdxf", "rhino3dm", "trimesh")


def say(args, text: str) -> None:
    """Print ``text`` (a result: a figure, a table row, a file written) on stdout unless the
    command runs with ``--quiet``.

    Paths in the staging folder are printed as the output folder they are moved into.
    """
    if not getattr(args, "quiet", False):
        staging = getattr(args, "staging", None)
        print(text.replace(staging, args.final_out) if staging else text)


def progress(args, text: str) -> None:
    """Print ``text`` (what the command is doing: "validating ...") on stderr unless the
    command runs with ``--quiet``: stdout carries results only."""
    if not getattr(args, "quiet", False):
        print(text, file=sys.stderr, flush=True)


def need_extra(command: str, extra: str, modules) -> None:
    """MissingExtraError unless ``modules`` of the extra ``extra`` are installed."""
    require(modules, extra, what=f"'ccu {command}'")


def need_viz(command: str) -> None:
    """MissingExtraError unless the viz extra is installed."""
    need_extra(command, "viz", VIZ)


def comma_list(text: str, allowed, option: str) -> list:
    """The distinct items of a comma list, each one of ``allowed`` (OptionError otherwise)."""
    items = [f.strip().lower() for f in text.split(",") if f.strip()]
    bad = [f for f in items if f not in allowed]
    if bad or not items:
        allowed = ", ".join(allowed)
        raise OptionError(f"{option} must be a comma list of {allowed}, got {text!r}")
    return list(dict.fromkeys(items))


def sheet_option(*, repeat: bool = False) -> Option:
    """The ``--sheet LENGTH WIDTH`` option: one syntax and one default for every command that
    takes a stock sheet (``ccu fabricate``, repeatable; ``ccu scale``). Without it the design's
    ``[fabrication] sheets`` are used, :data:`compas_ccu.design.schema.STOCK_SHEET` unless it
    names its own (the studio draws the same sheet).

    >>> sheet_option().flags, sheet_option(repeat=True).settings["action"]
    (('--sheet',), 'append')
    """
    default = f"{STOCK_SHEET[0]:g} x {STOCK_SHEET[1]:g}"
    more = {"action": "append"} if repeat else {}
    return option(
        "--sheet",
        type=float,
        positive=True,
        maximum=MAX_SHEET,
        nargs=2,
        default=None,
        metavar=("LENGTH", "WIDTH"),
        help="a stock sheet, m, length along the face grain"
        + (" (repeat for several)" if repeat else "")
        + f"; default: the design's {'' if repeat else 'first '}[fabrication] "
        + f"sheet{'s' if repeat else ''} ({default} unless it names its own)",
        **more,
    )
