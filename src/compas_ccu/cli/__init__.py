# PYTHON_ARGCOMPLETE_OK  (argcomplete's global completion: this module completes ``ccu``)
"""Command line interface: ``ccu new | deploy | path | info | planarity | catalog | validate |
fabricate | explore | optimize | scale | figures | animate | view | sheet | report | studio |
check | import | asbuilt | fit``; ``python -m compas_ccu`` is the same command.

Every command takes a design TOML file (see ``docs/design-files.md``; ``ccu new`` writes one), a
sweep or a study file.
The commands are declared as data, one module per group (:mod:`.new`, :mod:`.model_commands`,
:mod:`.pictures`, :mod:`.catalog`, :mod:`.fea`, :mod:`.fabrication`, :mod:`.explore`,
:mod:`.optimize`, :mod:`.scale`, :mod:`.check`, :mod:`.studio`; the parser is built by
:mod:`.parser`); each parses its options, calls the library and formats the result
(:mod:`.text`).

A command's module is imported only when that command runs (or ``ccu NAME --help`` asks for its
options): the command table (:mod:`.table`) lists every command by name and help line, so
``ccu --help`` and ``ccu --version`` import neither COMPAS nor SciPy and start at once
(docs/cli.md). Tab completion of the commands and their options is argcomplete's: the shell
runs ``ccu`` with ``_ARGCOMPLETE`` set, and :func:`main` answers with the completions and exits
(``eval "$(register-python-argcomplete ccu)"``, README).

Errors: a :class:`compas_ccu.errors.CCUError` (a bad design, option or state; a missing extra)
or an OSError on the user's files is printed as one line ``ccu: error: ...`` naming the cause
and the value, with exit status 2, like argparse's usage errors. Anything else is a bug in
compas_ccu: the traceback and a request to report it, exit status 1.

Process habits (:mod:`.process`): a reader that leaves (``ccu ... | head``) ends nothing early
and prints no "Broken pipe"; Ctrl-C and SIGTERM print one line and exit 130 / 143, removing the
staging folder of the output folder being written.
"""

from __future__ import annotations

import os
import sys
import traceback
import warnings

from compas_ccu.cli.parser import OUT, check_options
from compas_ccu.cli.parser import build_parser as _build_parser
from compas_ccu.cli.process import process_habits, stop_report
from compas_ccu.cli.table import EXPORTS, TABLE, command_word, export, load, load_all
from compas_ccu.errors import CCUError, CCUWarning
from compas_ccu.limits import apply, raised
from compas_ccu.outputs import check_output_folder, staged_folder

__all__ = ["main", "build_parser", "COMMANDS", "thickness_lines"]


def __getattr__(name: str):
    """``COMMANDS`` (every command, in the order ``ccu --help`` lists them) and the names of
    :data:`compas_ccu.cli.table.EXPORTS` import their modules when first asked for."""
    if name == "COMMANDS":
        return load_all()
    if name in EXPORTS:
        return export(name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


BUG = (
    "ccu: this is a bug in compas_ccu, not a problem with your input: please report it with "
    "the command you ran and the traceback above"
)


def build_parser(argv=None):
    """The ``ccu`` argument parser: with ``argv`` (the arguments after ``ccu``), the options of
    the command it names only (the others are listed by name, their modules not imported);
    without, of every command."""
    if argv is None:
        return _build_parser(TABLE, load_all())
    name = command_word(argv)
    return _build_parser(TABLE, () if name is None else (load(name),))


def _complete() -> None:
    """Answer the shell's tab completion and exit, if this process was started for it
    (argcomplete's protocol: ``_ARGCOMPLETE``, ``COMP_LINE`` and ``COMP_POINT`` in the
    environment); the parser has the options of the command on the line, if it names one."""
    try:
        import argcomplete
    except ImportError:  # pragma: no cover - a dependency; without it nothing is completed
        return
    words = argcomplete.split_line(os.environ["COMP_LINE"], int(os.environ["COMP_POINT"]))[3]
    start = int(os.environ["_ARGCOMPLETE"])  # 1: ccu ARGS, 3: python -m compas_ccu ARGS
    argcomplete.autocomplete(build_parser(words[start:]))


def _fail(message: str) -> int:
    """One line on stderr, exit 2: a message quoted from a library (ezdxf's "Invalid group
    code ... at line") can hold line breaks, which are folded."""
    print("ccu: error: " + " ".join(str(message).split()), file=sys.stderr)
    return 2


def _os_message(exc: OSError) -> str:
    if exc.filename is not None and exc.strerror:
        return f"{exc.filename}: {exc.strerror}"
    return str(exc)


def _run(args) -> int:
    """Run the command; one that writes an output folder writes it as one transaction."""
    if not args.spec.staged or OUT not in args.spec.options:
        if getattr(args, "out", None) is not None:
            check_output_folder(args.out)
        return args.spec.run(args)
    final = args.out
    with staged_folder(final) as stage:
        args.out, args.final_out, args.staging = str(stage), final, str(stage)
        return args.spec.run(args)


_PYTHON_SHOWWARNING = warnings.showwarning


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """Print a compas_ccu warning as one line ``ccu: warning: ...``; others as Python does."""
    if issubclass(category, CCUWarning):
        print(f"ccu: warning: {message}", file=sys.stderr if file is None else file)
    else:  # pragma: no cover - a library's own warning
        _PYTHON_SHOWWARNING(message, category, filename, lineno, file, line)


def main(argv=None) -> int:
    """Entry point of the ``ccu`` command: the exit status.

    compas_ccu warnings (:class:`compas_ccu.errors.CCUWarning`, e.g. a length implausible for
    the design's units) are printed to stderr as ``ccu: warning: ...``. Ctrl-C and SIGTERM
    are one line on stderr and the exit status 130 / 143; a closed stdout is not an error
    (:mod:`compas_ccu.cli.process`).
    """
    with process_habits():
        try:
            return _main(argv)
        except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM (process.Terminated)
            line, status = stop_report(exc)
            print(line, file=sys.stderr)
            return status


def _main(argv) -> int:
    if argv is None and "_ARGCOMPLETE" in os.environ:
        _complete()
    args = build_parser(sys.argv[1:] if argv is None else argv).parse_args(argv)
    try:
        with raised(**apply(args.limit)), warnings.catch_warnings():
            warnings.showwarning = _show_warning
            warnings.simplefilter("default", CCUWarning)
            # NumPy's floating-point warnings on extreme input (an overflow in a norm) are not
            # for the user: the value is checked and refused by name where it matters
            warnings.filterwarnings("ignore", category=RuntimeWarning, module="numpy")
            check_options(args.spec, args)
            return _run(args)
    except CCUError as exc:
        return _fail(str(exc))
    except OSError as exc:
        return _fail(_os_message(exc))
    except Exception:
        traceback.print_exc()
        print(BUG, file=sys.stderr)
        return 1
