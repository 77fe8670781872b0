"""A missing optional extra: one helper (``compas_ccu.errors.require``), one message."""

from __future__ import annotations

import re
from argparse import Namespace
from pathlib import Path

import pytest

from compas_ccu import errors
from compas_ccu.errors import MissingExtraError, require

SRC = Path(__file__).resolve().parents[1] / "src" / "compas_ccu"

#: The one message: what needs it, the extra, the modules not installed, the pip line.
MESSAGE = re.compile(
    r"^(?P<what>.+) needs the (?P<extra>\w+) extra \((?P<missing>[\w, ]+) not installed\): "
    r"pip install 'compas_ccu\[(?P=extra)\]'"
)


def test_require_names_what_needs_the_extra_and_the_modules_missing():
    assert require("json", "viz", what="'ccu figures'") is None
    assert require(["json", "math"], "viz", what="'ccu figures'") is None
    with pytest.raises(MissingExtraError) as info:
        require(["json", "no_such_module_ccu", "no_such_either"], "fab", what="'ccu x'")
    assert str(info.value) == (
        "'ccu x' needs the fab extra (no_such_module_ccu, no_such_either not installed): "
        "pip install 'compas_ccu[fab]'"
    )
    with pytest.raises(MissingExtraError, match=r"\[viz\]' \(or --no-figures\)$"):
        require("no_such_module_ccu", "viz", what="x", note=" (or --no-figures)")


def _everything_missing(monkeypatch):
    monkeypatch.setattr(errors, "missing_modules", lambda names: list(names))


def test_every_missing_extra_says_it_the_same_way(monkeypatch):
    """Each place that needs an extra raises through the helper: one message format."""
    from compas_ccu.cli import explore, optimize
    from compas_ccu.cli.common import need_extra
    from compas_ccu.curves import candidates
    from compas_ccu.fabrication import nfp_packing, packing

    _everything_missing(monkeypatch)
    args = Namespace(in_process=False, dashboard=True, scheduler=None, workers=None)
    calls = {
        "reading DXF files": lambda: candidates.need_module("ezdxf", "fab", "DXF files"),
        "nesting the parts onto sheets": packing.solver_version,
        "nesting the parts onto sheets with compas_nest": nfp_packing.nester_version,
        "'ccu fabricate'": lambda: need_extra("fabricate", "fab", ("ezdxf", "trimesh")),
        "'ccu explore'": lambda: explore._check(args),
        "'ccu optimize'": lambda: optimize._check(args),
    }
    pytest.importorskip("shapely")  # compas_ccu.fabrication.importing imports it
    from compas_ccu.fabrication import plate_drawings

    calls["'ccu import'"] = plate_drawings._ezdxf
    for what, call in calls.items():
        with pytest.raises(MissingExtraError) as info:
            call()
        found = MESSAGE.match(str(info.value))
        assert found and found["what"] == what, str(info.value)
    with pytest.raises(MissingExtraError) as info:
        explore._check(args)
    assert str(info.value) == (
        "'ccu explore' needs the explore extra (pyarrow, tqdm, distributed, bokeh not "
        "installed): pip install 'compas_ccu[explore]' bokeh (make setup installs the extra)"
    )


def hand_raised(root: Path) -> list:
    """``raise MissingExtraError(`` outside ``errors.py``: the places that bypass the helper."""
    return [
        f"{path.relative_to(root)}:{number}"
        for path in sorted(root.rglob("*.py"))
        if path.name != "errors.py" or path.parent != root
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if re.search(r"raise\s+MissingExtraError\b", line)
    ]


def test_no_missing_extra_error_is_raised_by_hand(tmp_path):
    assert hand_raised(SRC) == []
    (tmp_path / "errors.py").write_text("raise MissingExtraError('x')\n")  # the helper's own
    (tmp_path / "viz").mkdir()
    (tmp_path / "viz" / "plot.py").write_text("    raise MissingExtraError(\n")
    assert hand_raised(tmp_path) == ["viz/plot.py:1"]  # the check finds one


def exception_classes_outside_errors(root: Path) -> list:
    """``class X(...Error / ...Warning / Exception)`` defined anywhere but ``errors.py``."""
    pattern = re.compile(r"^class\s+(\w+)\s*\(([^)]*)\)")
    return [
        f"{path.relative_to(root)}:{number} {match.group(1)}"
        for path in sorted(root.rglob("*.py"))
        if path.name != "errors.py" or path.parent != root
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        for match in [pattern.match(line)]
        if match and re.search(r"(Error|Warning|Exception)\b", match.group(2))
    ]


def test_every_exception_of_the_package_is_defined_in_errors_py(tmp_path):
    assert exception_classes_outside_errors(SRC) == []
    (tmp_path / "fea").mkdir()
    (tmp_path / "fea" / "problem.py").write_text("class FEError(CCUError):\n    pass\n")
    (tmp_path / "fea" / "ok.py").write_text("class Result(Data):\n    pass\n")
    assert exception_classes_outside_errors(tmp_path) == ["fea/problem.py:1 FEError"]


def test_errors_moved_to_errors_py_are_still_importable_where_they_were_raised():
    from compas_ccu.fea import ConvergenceError, FEError
    from compas_ccu.materials import MaterialError

    assert (FEError, ConvergenceError, MaterialError) == (
        errors.FEError,
        errors.ConvergenceError,
        errors.MaterialError,
    )
    assert all(issubclass(cls, errors.CCUError) for cls in (FEError, ConvergenceError))
