"""The ``ccu`` command line as data: every command with its help texts and options.

Each command module declares its commands as :class:`Command` records (name, help, description,
options, the function that runs it) and :func:`build_parser` turns them into the argparse
parser. An option's ``minimum`` is checked after parsing (:func:`check_options`) and a value
below it is an :class:`compas_ccu.errors.OptionError` naming the option.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, field, fields
from typing import Callable

from compas_ccu import __version__
from compas_ccu.errors import OptionError
from compas_ccu.limits import LIMITS, check

__all__ = ["Option", "Command", "option", "DESIGN", "OUT", "QUIET", "QUIET_PROGRESS"]
__all__ += ["build_parser", "check_options"]

DESCRIPTION = "Curved-crease unfolding: deploy CCU designs exactly and write the results."


@dataclass(frozen=True)
class Option:
    """One argument of a command: argparse's flags and settings, and a lower bound."""

    flags: tuple
    help: str
    settings: dict = field(default_factory=dict)
    minimum: float | None = None
    limit: str | None = None  # a work limit of compas_ccu.limits the value counts against

    @property
    def dest(self) -> str:
        return self.flags[-1].lstrip("-").replace("-", "_")


def option(*flags, help: str, minimum=None, limit=None, **settings) -> Option:
    """An :class:`Option` from argparse's ``add_argument`` arguments."""
    return Option(flags, help, settings, minimum, limit)


@dataclass(frozen=True)
class Command:
    """One ``ccu`` command: what ``ccu --help`` and ``ccu NAME --help`` say, and what it runs."""

    name: str
    help: str
    description: str
    options: tuple
    run: Callable  # (argparse.Namespace) -> exit status
    #: The output folder is written as one transaction (a staging folder moved into place);
    #: False for commands that continue what a folder holds (explore, optimize).
    staged: bool = True


DESIGN = option("design", help="design TOML file")
OUT = option("--out", required=True, help="output folder")
QUIET = option("--quiet", action="store_true", help="print nothing on success")
QUIET_PROGRESS = option(
    "--quiet", action="store_true", help="no progress, print nothing on success"
)


def build_parser(commands) -> argparse.ArgumentParser:
    """The ``ccu`` parser of ``commands`` (sequence of :class:`Command`)."""
    parser = argparse.ArgumentParser(prog="ccu", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"compas_ccu {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for command in commands:
        p = sub.add_parser(command.name, help=command.help, description=command.description)
        for o in command.options:
            p.add_argument(*o.flags, help=o.help, **o.settings)
        p.add_argument(
            "--limit",
            action="append",
            metavar="NAME=VALUE",
            help="raise a work limit, e.g. --limit segments=100000 (limits: "
            + ", ".join(f"{f.name} {getattr(LIMITS, f.name):g}" for f in fields(LIMITS))
            + ")",
        )
        p.set_defaults(spec=command)
    return parser


def check_options(command: Command, args) -> None:
    """Refuse option values below their ``minimum`` (OptionError naming the option)."""
    for o in command.options:
        value = getattr(args, o.dest, None)
        if o.minimum is not None and value is not None and value < o.minimum:
            raise OptionError(f"{o.flags[-1]} must be >= {o.minimum:g}, got {value}")
        if o.limit is not None and value is not None:
            # a path of N steps (frames) has up to N + 1 states: the flat stack and N more
            check(o.limit, value + 1, what=f"{o.limit} ({o.flags[-1]} {value})")
