"""True-shape packing onto sheets with compas_nest (compas_ccu.fabrication.nfp_packing), the
choice of nester (compas_ccu.fabrication.nesting.nesting_choice) and the warning when none is
installed, on every path it must reach: the CLI, fabrication.json and the report, the studio."""

from __future__ import annotations

import html
import json
import subprocess
import sys
import warnings

import numpy as np
import pytest

from compas_ccu.errors import CCUWarning, GeometryError, LimitError
from compas_ccu.fabrication import nesting
from compas_ccu.fabrication.nesting import nesting_choice
from conftest import EXAMPLES

shapely = pytest.importorskip("shapely")

NO_NESTER = (
    "no true-shape nester is installed (compas_nest or spyrrow: pip install 'compas_ccu[fab]'): "
    "the parts are nested by shelves of bounding boxes, which wastes sheets"
)


def _installed(monkeypatch, *nesters):
    monkeypatch.setattr(nesting, "_installed", lambda nester: nester in nesters)


# ----------------------------------------------------------------------- the choice of nester


@pytest.mark.parametrize(
    ("requested", "installed", "chosen", "warning"),
    [
        ("auto", ("compas_nest", "spyrrow"), "compas_nest", None),
        ("auto", ("spyrrow",), "spyrrow", None),
        ("auto", ("compas_nest",), "compas_nest", None),
        ("auto", (), "shelf", NO_NESTER),
        ("spyrrow", ("compas_nest", "spyrrow"), "spyrrow", None),
        ("compas_nest", ("compas_nest", "spyrrow"), "compas_nest", None),
        (
            "spyrrow",
            ("compas_nest",),
            "compas_nest",
            "spyrrow is not installed (pip install 'compas_ccu[fab]'; it has no wheel for Python "
            "3.9): the parts are nested with compas_nest instead",
        ),
        (
            "compas_nest",
            ("spyrrow",),
            "spyrrow",
            "compas_nest is not installed (pip install 'compas_ccu[fab]'): the parts are nested "
            "with spyrrow instead",
        ),
        (
            "compas_nest",
            (),
            "shelf",
            "compas_nest is not installed (pip install 'compas_ccu[fab]'): the parts are nested "
            "by shelves of bounding boxes, which wastes sheets",
        ),
        ("shelf", (), "shelf", None),
    ],
)
def test_the_nester_is_the_one_named_else_the_first_installed_else_shelves(
    monkeypatch, requested, installed, chosen, warning
):
    _installed(monkeypatch, *installed)
    assert nesting_choice(requested) == (chosen, warning)


def test_an_unknown_nesting_is_refused():
    with pytest.raises(ValueError, match="nesting must be auto, compas_nest, spyrrow or shelf"):
        nesting_choice("bottom-left")


# ------------------------------------------------------------------------------ the packing

cn = pytest.importorskip("compas_nest")

from compas_ccu.fabrication.nfp_packing import (  # noqa: E402
    NESTER,
    POPULATION,
    SheetPacking,
    check_layout,
    nester_version,
    sheet_pack,
)


def _rect(w: float, h: float) -> np.ndarray:
    return np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])


def _arc(r0: float, r1: float, angle: float, n: int = 16) -> np.ndarray:
    """An annular sector (a curved part, like a plate), centred."""
    t = np.linspace(0.0, np.radians(angle), n)
    pts = np.r_[np.c_[r1 * np.cos(t), r1 * np.sin(t)], np.c_[r0 * np.cos(t), r0 * np.sin(t)][::-1]]
    return pts - pts.mean(axis=0)


SHAPES = {
    **{f"R{k}": _rect(400.0, 300.0) for k in range(3)},
    **{f"A{k}": _arc(500.0, 700.0, 60.0 + 5 * k) for k in range(5)},
}
GRAIN = {name: [0.0, 180.0] for name in SHAPES}


def _placed(name: str, rotation: float, shift) -> np.ndarray:
    a = np.radians(rotation)
    r = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return SHAPES[name] @ r.T + np.asarray(shift)


def test_parts_lie_on_their_sheets_the_gap_apart_in_the_turns_the_grain_allows():
    """An independent check: shapely's distance between the placed true outlines."""
    p = sheet_pack(SHAPES, GRAIN, length=1500.0, width=1000.0, gap=12.0, seed=0, generations=2)
    assert isinstance(p, SheetPacking) and p.solver == NESTER and p.version == nester_version()
    assert p.unplaced == () and p.layouts == 2 * POPULATION and p.seed == 0
    assert sorted(m for sheet in p.sheets for m in sheet) == sorted(SHAPES)
    assert 2 <= len(p.sheets) <= 4
    for sheet in p.sheets:
        polys = {}
        for m, (rotation, shift) in sheet.items():
            assert rotation in (0.0, 180.0), m
            poly = shapely.Polygon(_placed(m, rotation, shift))
            x0, y0, x1, y1 = poly.bounds
            assert min(x0, y0) >= -1e-9 and x1 <= 1500.0 + 1e-9 and y1 <= 1000.0 + 1e-9, m
            polys[m] = poly
        names = sorted(polys)
        for i, a in enumerate(names):
            for b in names[i + 1 :]:
                assert polys[a].distance(polys[b]) >= 12.0 - 1e-9, (a, b)


@pytest.mark.slow  # it keeps a core busy on purpose, the other worker's core in `make test-fast`
def test_the_same_input_gives_the_same_layout_twice_even_with_a_core_busy():
    kwargs = dict(length=1500.0, width=1000.0, gap=12.0, seed=3, generations=2)
    first = sheet_pack(SHAPES, GRAIN, **kwargs)
    busy = subprocess.Popen([sys.executable, "-c", "while 1: pass"])
    try:
        second = sheet_pack(SHAPES, GRAIN, **kwargs)
    finally:
        busy.kill()
        busy.wait()
    assert second == first  # every rotation and translation, to the last bit


def test_a_grain_across_the_sheet_turns_every_part_by_90_or_270_degrees():
    across = {name: [90.0, 270.0] for name in SHAPES}
    p = sheet_pack(SHAPES, across, length=1500.0, width=1000.0, gap=12.0, generations=1)
    assert {rot for sheet in p.sheets for rot, _ in sheet.values()} <= {90.0, 270.0}
    with pytest.raises(ValueError, match="not such turns"):
        sheet_pack(SHAPES, {**across, "R0": [0.0, 90.0, 270.0]}, length=1500.0, width=1000.0,
                   gap=12.0)  # fmt: skip


def test_identical_outlines_are_packed_as_copies_and_each_placed_once():
    shapes = {f"P{k}": _arc(500.0, 700.0, 60.0) for k in range(6)}
    p = sheet_pack(shapes, {m: [0.0, 180.0] for m in shapes}, length=1500.0, width=1000.0,
                   gap=10.0, generations=1)  # fmt: skip
    assert sorted(m for sheet in p.sheets for m in sheet) == sorted(shapes)
    for sheet in p.sheets:
        check_layout(shapes, sheet, 1500.0, 1000.0, 10.0)


def test_a_layout_with_parts_too_close_or_off_the_sheet_is_refused():
    shapes = {"a": _rect(100.0, 100.0), "b": _rect(100.0, 100.0)}
    with pytest.raises(GeometryError, match=r"parts a and b 5\.0000 mm apart, less than the 10"):
        check_layout(shapes, {"a": (0.0, (50, 50)), "b": (0.0, (155, 50))}, 500, 500, 10.0)
    with pytest.raises(GeometryError, match="placed part b off its sheet"):
        check_layout(shapes, {"a": (0.0, (50, 50)), "b": (0.0, (470, 50))}, 500, 500, 10.0)
    check_layout(shapes, {"a": (0.0, (50, 50)), "b": (0.0, (160, 50))}, 500, 500, 10.0)


def test_a_search_past_its_time_limit_is_refused_never_returned():
    with pytest.raises(LimitError, match=r"did not end in the time limit of 0\.001 s"):
        sheet_pack(SHAPES, GRAIN, length=1500.0, width=1000.0, gap=12.0, generations=50,
                   time_limit=0.001)  # fmt: skip


def test_parts_the_engine_leaves_unplaced_get_sheets_of_their_own(monkeypatch):
    """_nfp_sheets: what the engine does not place is packed again; a part it cannot place
    on an empty sheet gets one by shelves."""
    calls = []

    def engine(shapes, orientations, **kwargs):
        calls.append(sorted(shapes))
        names = sorted(shapes)
        if len(calls) == 1:  # places nothing
            return SheetPacking([], tuple(names), 1, 10, 0, NESTER, "x")
        return SheetPacking([{m: (0.0, (300.0, 300.0 + 700 * k)) for k, m in enumerate(names)}],
                            (), 1, 10, 0, NESTER, "x")  # fmt: skip

    monkeypatch.setattr(nesting, "sheet_pack", engine)
    from compas_ccu.fabrication.plan import WorkshopOptions

    shapes = {"big": _rect(600.0, 500.0), "small": _rect(400.0, 300.0)}
    out = nesting._nfp_sheets(shapes, {m: [0.0, 180.0] for m in shapes}, 2468.0, 1218.0,
                              WorkshopOptions(nesting="compas_nest"), None)  # fmt: skip
    assert calls == [["big", "small"], ["small"]]
    assert [sorted(s) for s in out] == [["big"], ["small"]]  # the largest alone, by shelves
    assert out[0]["big"][2][:, 0].min() == pytest.approx(0.0)


# ----------------------------------------- the warning: CLI, fabrication.json, report, studio


def test_without_a_nester_the_warning_reaches_the_cli_the_report_and_the_studio(
    monkeypatch, tmp_path, capsys
):
    pytest.importorskip("ezdxf")
    from compas_ccu.cli import main
    from compas_ccu.studio.export import export_warnings
    from compas_ccu.viz.record import read_fabrication
    from compas_ccu.viz.report_page import fabrication_section

    _installed(monkeypatch)
    out = tmp_path / "fab"
    cone = str(EXAMPLES / "cone.toml")
    assert main(["fabricate", cone, "--out", str(out), "--allow-exceeded"]) == 0
    captured = capsys.readouterr()
    assert f"ccu: warning: {NO_NESTER}" in captured.err.splitlines()
    assert f"warning           ** {NO_NESTER} **" in captured.out.splitlines()
    manifest = json.loads((out / "fabrication.json").read_text())
    assert manifest["workshop"]["warnings"] == [NO_NESTER]
    assert manifest["workshop"]["nesting"] == "shelf"
    fab = read_fabrication(out, design="cone")
    assert ("warning", f"** {NO_NESTER} **") in fab["workshop_rows"]
    page = fabrication_section({**fab, "copies": []}, tmp_path)
    assert f'<b class="skip">{html.escape(NO_NESTER)}</b>' in page
    assert export_warnings({"fabrication": out}) == [NO_NESTER]
    assert export_warnings({"structure": tmp_path}) == []


def test_the_default_nesting_gives_no_warning_where_a_nester_is_installed(tmp_path):
    from compas_ccu.fabrication import fabrication_data
    from compas_ccu.fabrication.hinges import hinge_strips
    from compas_ccu.fabrication.workshop import WorkshopOptions, plan_workshop
    from compas_ccu.model import load_model

    data = fabrication_data(load_model(EXAMPLES / "cone.toml"))
    with warnings.catch_warnings():
        warnings.simplefilter("error", CCUWarning)
        plan = plan_workshop(data, hinge_strips(data), WorkshopOptions(), density=500.0)
    assert plan.warnings == [] and plan.options.nesting == "compas_nest"
    summary = plan.summary()
    assert summary["nesting"] == "compas_nest" and summary["warnings"] == []
    search = summary["nesting_search"]
    assert (search["solver"], search["generations"], search["packings"]) == ("compas_nest", 3, 2)
    assert len(plan.sheets) == 2  # the cone's 8 parts (shelves: 4 sheets)


def test_the_studio_says_the_warning_of_an_export(tmp_path):
    """The export runs in another process: the studio reads the warning from the
    fabrication.json it wrote and says it in the export's line, in the warning colour."""
    import types
    from concurrent.futures import Future

    pytest.importorskip("viser")
    from compas_ccu.studio.app import Studio

    folder = tmp_path / "fabrication"
    folder.mkdir()
    (folder / "fabrication.json").write_text(json.dumps({"workshop": {"warnings": [NO_NESTER]}}))
    said = []
    studio = types.SimpleNamespace(_say=lambda text, status: said.append((text, status)))
    future = Future()
    future.set_result((1, {"fabrication": folder}))
    Studio._exported(studio, future)
    assert said == [(f"exported fabrication to {folder}; warning: {NO_NESTER}", "warn")]
    (folder / "fabrication.json").write_text(json.dumps({"workshop": {"warnings": []}}))
    Studio._exported(studio, future)
    assert said[-1] == (f"exported fabrication to {folder}", "ok")
