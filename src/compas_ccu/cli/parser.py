"""The ``ccu`` command line as data: every command with its help texts and options.

Each command module declares its commands as :class:`Command` records (name, description,
options, the function that runs it; the line ``ccu --help`` gives a command is in the command
table, :mod:`compas_ccu.cli.table`) and :func:`build_parser` turns them into the argparse
parser: every command of the table is listed, the commands loaded have their options. This
module imports neither COMPAS nor NumPy (``ccu --help`` builds its parser).

After parsing, :func:`check_options` checks every value (an
:class:`compas_ccu.errors.OptionError` naming the option and the value otherwise): a number
option (``type=float``) must be finite, ``positive`` ones > 0, and every number lies within its
``minimum`` / ``maximum``; an integer count with a ``limit`` counts against that work limit of
:mod:`compas_ccu.limits` (``--limit NAME=VALUE`` raises it). Options whose text holds numbers
(``2.44x1.22``, ``0.008,0.01``) are parsed by :func:`numbers`, with the same rules.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass, field, fields
from typing import Callable

from compas_ccu import __version__
from compas_ccu.errors import OptionError
from compas_ccu.limits import LIMITS, check

__all__ = ["Option", "Command", "option", "DESIGN", "OUT", "QUIET", "QUIET_PROGRESS"]
__all__ += ["build_parser", "check_options", "numbers", "COUNT_LIMITS"]
__all__ += ["MAX_THICKNESS", "MAX_SHEET", "MAX_AREA_LOAD", "MAX_HINGE_STIFFNESS"]

#: The largest plate thickness an option takes, m (the bound of ``plates.thickness``).
MAX_THICKNESS = 0.1
#: The largest sheet length, m (the bound of ``fabrication.sheets``).
MAX_SHEET = 100.0
#: The largest uniform area load, N/m² (the bound of ``loads.live``).
MAX_AREA_LOAD = 1.0e5
#: The largest rotational hinge stiffness, Nm/rad/m (``hinges.rotational_stiffness``).
MAX_HINGE_STIFFNESS = 1.0e12

#: What an integer count option counts against: the limit, and what the count adds (a path of
#: N steps has N + 1 states: the flat stack and N more).
COUNT_LIMITS = {"states": 1, "variants": 0, "workers": 0}

DESCRIPTION = "Curved-crease unfolding: deploy CCU designs exactly and write the results."


@dataclass(frozen=True)
class Option:
    """One argument of a command: argparse's flags and settings, and the checks of its value."""

    flags: tuple
    help: str
    settings: dict = field(default_factory=dict)
    minimum: float | None = None
    limit: str | None = None  # a work limit of compas_ccu.limits the value counts against
    maximum: float | None = None
    positive: bool = False  # a number > 0
    extra: int | None = None  # added to the value counted against ``limit`` (COUNT_LIMITS)

    @property
    def dest(self) -> str:
        return self.flags[-1].lstrip("-").replace("-", "_")


def option(
    *flags,
    help: str,
    minimum=None,
    limit=None,
    maximum=None,
    positive=False,
    extra=None,
    **settings,
) -> Option:
    """An :class:`Option` from argparse's ``add_argument`` arguments and its checks."""
    return Option(flags, help, settings, minimum, limit, maximum, positive, extra)


@dataclass(frozen=True)
class Command:
    """One ``ccu`` command: what ``ccu NAME --help`` says, and what it runs (the line of
    ``ccu --help`` is its entry in :data:`compas_ccu.cli.table.TABLE`)."""

    name: str
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


def build_parser(entries, commands=()) -> argparse.ArgumentParser:
    """The ``ccu`` parser: every command of ``entries`` (:class:`compas_ccu.cli.table.Entry`,
    the lines of ``ccu --help``), with the options of those in ``commands`` (:class:`Command`);
    the others are listed only."""
    parser = argparse.ArgumentParser(prog="ccu", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"compas_ccu {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    loaded = {c.name: c for c in commands}
    for entry in entries:
        command = loaded.get(entry.name)
        if command is None:
            sub.add_parser(entry.name, help=entry.help)
            continue
        p = sub.add_parser(command.name, help=entry.help, description=command.description)
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


def _g(value) -> str:
    """``1e+06`` as ``1e6``."""
    return f"{value:g}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


def _bounds(name: str, value, *, positive: bool, minimum, maximum) -> None:
    if isinstance(value, float) and not math.isfinite(value):
        raise OptionError(f"{name} must be a finite number, got {value!r}")
    if positive and not value > 0:
        raise OptionError(f"{name} must be > 0, got {value!r}")
    if minimum is not None and value < minimum:
        raise OptionError(f"{name} must be >= {_g(minimum)}, got {value!r}")
    if maximum is not None and value > maximum:
        raise OptionError(f"{name} must be <= {_g(maximum)}, got {value!r}")


def _flat(value) -> list:
    """The scalars of an option's value (``nargs`` and ``append`` give (nested) lists)."""
    if isinstance(value, (list, tuple)):
        return [v for item in value for v in _flat(item)]
    return [value]


def check_options(command: Command, args) -> None:
    """Refuse option values outside their checks (OptionError naming the option and value)."""
    for o in command.options:
        value = getattr(args, o.dest, None)
        if value is None:
            continue
        name = o.flags[-1]
        for v in _flat(value):
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                _bounds(name, v, positive=o.positive, minimum=o.minimum, maximum=o.maximum)
        if o.limit is not None:
            extra = COUNT_LIMITS[o.limit] if o.extra is None else o.extra
            check(o.limit, value + extra, what=f"{o.limit} ({name} {value})")


def numbers(
    text,
    option: str,
    *,
    count=None,
    positive=True,
    maximum=None,
    form="numbers separated by commas",
    example="0.5,1",
) -> list:
    """The numbers of an option's text (``"2.44x1.22"``, ``"0.008, 0.01"``): finite, > 0 if
    ``positive``, at most ``maximum``, exactly ``count`` of them if given.

    Raises
    ------
    OptionError
        Names the option, the rule and the text (or the number) that breaks it.

    Examples
    --------
    >>> numbers("2.44x1.22", "--sheet", count=2)
    [2.44, 1.22]
    >>> numbers("nan,1", "--thickness")
    Traceback (most recent call last):
    ...
    compas_ccu.errors.OptionError: --thickness must be finite numbers, got 'nan,1'
    """
    shape = f"{option} must be {form}, e.g. {example}, got {text!r}"
    try:
        values = [float(v) for v in str(text).replace("x", ",").split(",") if v.strip()]
    except ValueError:
        raise OptionError(shape) from None
    if not values or (count is not None and len(values) != count):
        raise OptionError(shape)
    if not all(math.isfinite(v) for v in values):
        raise OptionError(f"{option} must be finite numbers, got {text!r}")
    if positive and min(values) <= 0:
        raise OptionError(f"{option} must be numbers > 0, got {text!r}")
    if maximum is not None and max(values) > maximum:
        raise OptionError(f"{option} must be numbers <= {_g(maximum)}, got {text!r}")
    return values
