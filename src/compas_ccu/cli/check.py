"""``ccu check``: the check sheet of a design, every check with its value, limit and clause.

The design's own checks (kinematic invariants, deployment and collision limits, the thick plates
and their bending) are computed here; ``--fabrication DIR`` adds those of a ``ccu fabricate``
folder (``fabrication.json``) and ``--fe DIR`` those of a ``ccu validate`` folder
(``validation.json``). Exit status 3 when a check fails, after listing every failed check.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from compas_ccu.cli.common import load_model
from compas_ccu.cli.model_commands import INFO_PATH_STATES, INFO_THICKNESS_STATES
from compas_ccu.cli.parser import DESIGN, Command, option
from compas_ccu.errors import CCUError, GeometryError
from compas_ccu.key_figures import key_figures
from compas_ccu.key_figures.checks import (
    check_lines,
    design_checks,
    fabrication_checks,
    failed,
    fe_checks,
)
from compas_ccu.outputs import json_text
from compas_ccu.thickness import ThickModel

__all__ = ["COMMANDS", "read_record"]


def read_record(folder, name: str, fmt: str) -> dict:
    """The JSON record ``name`` of an output ``folder``, checked to be of format ``fmt``.

    Raises
    ------
    CCUError
        The folder has no such file, it is not JSON, or it is another record.
    """
    path = Path(folder) / name
    if not path.is_file():
        raise CCUError(f"{path}: no such file (the folder of a ccu command writing {name})")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise CCUError(f"{path}: not a readable JSON record ({exc})") from None
    if not isinstance(data, dict) or data.get("format") != fmt:
        found = data.get("format") if isinstance(data, dict) else type(data).__name__
        raise CCUError(f"{path}: format {found!r}, expected {fmt!r}")
    return data


def sheet(model, *, fabrication=None, fe=None) -> list:
    """Every :class:`~compas_ccu.key_figures.checks.Check` of ``model`` (and the records)."""
    figures = key_figures(model, path=INFO_PATH_STATES).to_dict()
    try:
        summary = ThickModel(model).summary(path_states=INFO_THICKNESS_STATES)
    except GeometryError:
        summary = None
    checks = design_checks(figures, summary)
    if fabrication is not None:
        checks += fabrication_checks(fabrication)
    if fe is not None:
        if fe.get("converged") is False:
            raise CCUError(f"the FE validation did not converge: {fe.get('message', '')}")
        checks += fe_checks(fe)
    return checks


def check(args) -> int:
    model = load_model(args.design)
    fab = (
        None
        if args.fabrication is None
        else read_record(args.fabrication, "fabrication.json", "ccu.fabrication")
    )
    fe = None if args.fe is None else read_record(args.fe, "validation.json", "ccu.validation")
    checks = sheet(model, fabrication=fab, fe=fe)
    if args.json:
        bad = failed(checks)
        doc = {
            "format": "ccu.checks",
            "version": 1,
            "design": model.design.name,
            "checks": [c.to_dict() for c in checks],
            "failed": len(bad),
            "ok": not bad,
        }
        print(json_text(doc, indent=1))
    else:
        print(f"check sheet of {model.design.name}")
        print("\n".join(check_lines(checks)))
    if failed(checks):
        for c in failed(checks):
            print(f"ccu: check failed: {c.brief()} ({c.clause})", file=sys.stderr)
        return 3
    return 0


COMMANDS = (
    Command(
        "check",
        "Print every check of DESIGN an engineer signs (kinematic invariants, deployment and "
        "collision limits, the thick plates' penetration and bending, EN 1995-1-1 / EN 1999-1-1 "
        "clauses), and with --fabrication / --fe those of a ccu fabricate / ccu validate "
        "folder (splice plates, stock sheets, every FE load case's utilisation, deflections "
        "and design buckling factor). Exit status 3 if any check fails, after listing all.",
        (
            DESIGN,
            option("--fabrication", metavar="DIR", default=None, help="a ccu fabricate folder"),
            option("--fe", metavar="DIR", default=None, help="a ccu validate folder"),
            option("--json", action="store_true", help="print the sheet as JSON"),
        ),
        check,
    ),
)
