"""The table of the ``ccu`` commands, and the one place the package imports its own modules by
name.

``ccu --help`` lists every command and ``ccu --version`` prints a line, but the modules that
declare the commands import COMPAS, NumPy and SciPy (a second of CPU): so the commands are listed
here as data -- the name, the line ``ccu --help`` gives it, the module that declares it (its
:class:`~compas_ccu.cli.parser.Command`: description, options, what it runs) -- and
:func:`load` imports that module only when the command runs, when ``ccu NAME --help`` is asked
for or when the shell completes its options.

This is the package's one exception to "a module of the package is imported by a module-level
``import`` statement" (docs/architecture.md): :func:`load` and :func:`export` import, by
:func:`importlib.import_module`, only the ``compas_ccu.cli`` modules named in :data:`TABLE` and
:data:`EXPORTS`; ``tests/test_architecture.py`` checks that no other module imports one of the
package's modules by name and that every module named here is a ``compas_ccu.cli`` module, so
the import contracts, which see ``import`` statements only, lose nothing.

>>> [e.name for e in TABLE[:3]], TABLE[0].module
(['new', 'deploy', 'path'], 'compas_ccu.cli.new')
>>> command_word(["deploy", "a.toml", "--alpha", "30"]), command_word(["--help", "deploy"])
('deploy', None)
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

__all__ = ["Entry", "TABLE", "EXPORTS", "NAMES", "command_word", "load", "load_all", "export"]


@dataclass(frozen=True)
class Entry:
    """One line of ``ccu --help``: a command, the module of ``compas_ccu.cli`` that declares it,
    what it does."""

    name: str
    module: str  # "compas_ccu.cli.<module>"
    help: str


def _entry(name: str, module: str, text: str) -> Entry:
    return Entry(name, f"compas_ccu.cli.{module}", text)


#: Every command, in the order ``ccu --help`` lists them.
TABLE = (
    _entry("new", "new", "write a commented design file from a preset"),
    _entry("deploy", "model_commands", "deploy a design to one reflection angle"),
    _entry("path", "model_commands", "deploy along a path from the flat stack"),
    _entry("info", "model_commands", "print the key figures of a design"),
    _entry("figures", "pictures", "write the figures of a design (PNG, SVG)"),
    _entry("animate", "pictures", "animate the deployment (GIF, MP4)"),
    _entry("view", "pictures", "write the interactive 3D viewer page"),
    _entry("sheet", "pictures", "contact sheet of several designs"),
    _entry("planarity", "model_commands", "crease planarity along the deployment path"),
    _entry("catalog", "catalog", "regenerate and measure the rule catalog (paper Fig. 9-12)"),
    _entry("validate", "fea", "validate the deployment with a nonlinear FE engine"),
    _entry("explore", "explore", "explore a design space: a sweep of variants on Dask"),
    _entry(
        "optimize",
        "optimize",
        "optimise a design: the best designs under constraints (Optuna on Dask)",
    ),
    _entry("scale", "scale", "scale a design to other spans (a span scaling study)"),
    _entry(
        "fabricate",
        "fabrication",
        "write the workshop files (DXF, 3dm, OBJ/glTF, FOLD, assembly sheet)",
    ),
    _entry("check", "check", "the check sheet: every check with value, limit and clause"),
    _entry("import", "fabrication", "rebuild a design from plate DXFs (the reverse of fabricate)"),
    _entry("report", "pictures", "write the design report (index.html, report.pdf)"),
    _entry("studio", "studio", "edit a design live in the browser"),
    _entry("asbuilt", "fit", "register a scan to the design's 1-DOF deployment (as-built check)"),
    _entry("fit", "fit", "fit free design keys to a target surface or point cloud"),
)

NAMES = {e.name: e for e in TABLE}

#: Names that ``compas_ccu.cli`` exports from a module it does not import up front (its
#: ``__getattr__``): name -> the module that defines it.
EXPORTS = {"thickness_lines": "compas_ccu.cli.text"}

#: The options of the ``ccu`` parser itself (none takes a value).
_TOP_OPTIONS = ("-h", "--help", "--version")


def command_word(argv) -> str | None:
    """The command ``argv`` (the arguments after ``ccu``) runs: its first word that is not an
    option, if that names a command; None if ``--help`` or ``--version`` comes first (the
    ``ccu`` parser answers those before any command) or no command is named."""
    for word in argv:
        if word in _TOP_OPTIONS:
            return None
        if word == "--" or word.startswith("-"):
            continue
        return word if word in NAMES else None
    return None


def _module(name: str):
    """The module ``name``, imported: one of :data:`TABLE`'s or :data:`EXPORTS`' only."""
    if name not in {e.module for e in TABLE} | set(EXPORTS.values()):
        raise ValueError(f"{name!r} is not a module of the command table")
    return importlib.import_module(name)


def load(name: str):
    """The :class:`~compas_ccu.cli.parser.Command` ``name``, its module imported."""
    entry = NAMES[name]
    return next(c for c in _module(entry.module).COMMANDS if c.name == name)


def load_all() -> tuple:
    """Every command, in :data:`TABLE`'s order (every command module imported)."""
    return tuple(load(e.name) for e in TABLE)


def export(name: str):
    """The value of :data:`EXPORTS` ``name``, its module imported."""
    return getattr(_module(EXPORTS[name]), name)
