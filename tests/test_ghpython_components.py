"""The Grasshopper components: their logic on CPython, and their code.py with host doubles."""

from __future__ import annotations

import inspect
import json
import runpy
import sys
import types
from pathlib import Path

import numpy as np
import pytest
from compas.datastructures import Mesh
from compas.geometry import Line, Polyline

import compas_ccu.ghpython as gh
from compas_ccu.design import Design
from compas_ccu.errors import DesignError, GeometryError, OptionError
from compas_ccu.fabrication.workshop import WorkshopOptions
from compas_ccu.ghpython import convert
from compas_ccu.model import CCUModel
from conftest import EXAMPLES

COMPONENTS = Path(gh.__file__).parent / "components"
NAMES = ["CCU_Design", "CCU_Deploy", "CCU_Checks", "CCU_CutPatterns", "CCU_Fabricate"]


def _arch(n=33, span=2.0, rise=0.6, y=0.0, scale=1.0):
    """An arch in the world XZ plane, as a point list."""
    t = np.linspace(0.0, np.pi, n)
    return (np.c_[0.5 * span * (1 - np.cos(t)), np.full(n, y), rise * np.sin(t)] * scale).tolist()


@pytest.fixture(autouse=True)
def no_rhino(monkeypatch):
    monkeypatch.setattr(convert, "_HOSTS", {"compas_rhino.conversions": None, "Rhino": None})


# -- the logic -----------------------------------------------------------------------------------


def test_design_from_a_curve_is_a_polyline_profile_design():
    result = gh.design_component(crease=Polyline(_arch()), segments=24, width=0.25, alpha=35.0)
    assert isinstance(result.design, Design) and isinstance(result.model, CCUModel)
    crease = result.design.document["crease"]
    assert (crease["profile"], crease["segments"], len(crease["points"])) == ("polyline", 24, 33)
    assert result.model.alpha_design == 35.0
    structure = result.model.deploy()
    assert structure.crease_kind_counts() == {"synclastic": 1}
    # the crease at the design angle is the curve: its end points are the curve's
    ends = structure.deployed[0, [0, 24]]
    assert np.allclose(ends, [[0, 0, 0], [2, 0, 0]], atol=1e-9)
    assert result.info.splitlines()[0] == "design grasshopper: 2 plates, 24 segments per crease"


def test_a_curve_in_millimetres_makes_the_same_design_as_in_metres():
    metres = gh.crease_design(_arch(), segments=16)
    millimetres = gh.crease_design(_arch(scale=1000.0), segments=16, unit_scale=0.001)
    assert np.allclose(millimetres["crease"]["points"], metres["crease"]["points"], atol=1e-12)


def test_a_corrugated_design_from_a_curve():
    doc = gh.crease_design(_arch(), segments=16, plates=4, spacing=0.25)
    assert doc["layout"] == {"type": "parallel", "plates": 4, "spacing": 0.25}
    model = CCUModel(Design(doc))
    assert len(model.plate_ids) == 4


def test_design_from_a_file_ignores_the_curve():
    result = gh.design_component(path=str(EXAMPLES / "cone.toml"), crease=_arch())
    assert result.design.name == "cone"


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({}, OptionError, "connect a design file path or a crease curve"),
        ({"crease": _arch(), "plates": 3}, OptionError, "plates=3 needs a crease plane spacing"),
        ({"crease": _arch(), "unit_scale": 0}, OptionError, "unit_scale must be a finite number"),
        ({"crease": _arch(), "segments": 1}, DesignError, "segments"),
        ({"crease": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}, GeometryError, "straight"),
        ({"path": "no/such/design.toml"}, DesignError, "no/such/design.toml"),
    ],
)
def test_design_errors_name_the_cause(kwargs, error, message):
    with pytest.raises(error, match=message):
        gh.design_component(**kwargs)


def test_deploy_gives_plates_creases_rulings_and_kind_colours(vault_model):
    result = gh.deploy_component(vault_model, 20.0)
    n = vault_model.segments
    assert (len(result.plates), len(result.creases), len(result.rulings)) == (10, 9, 10 * (n + 1))
    assert all(isinstance(p, Mesh) for p in result.plates)
    assert all(isinstance(c, Polyline) for c in result.creases)
    assert all(isinstance(r, Line) for r in result.rulings)
    assert result.structure.alpha == 20.0
    assert set(result.crease_colors) == {(31, 99, 214), (214, 48, 127)}
    assert len(result.plate_colors) == 10
    assert result.info.startswith("alpha 20 deg (deployed); max invariant error ")


def test_deploy_in_millimetres_and_flat(cone_model):
    metres = gh.deploy_component(cone_model, 30.0, rulings=False)
    mm = gh.deploy_component(cone_model, 30.0, rulings=False, unit_scale=0.001)
    a = np.array(metres.creases[0].points)
    b = np.array(mm.creases[0].points)
    assert np.allclose(b, 1000.0 * a)
    flat = gh.deploy_component(cone_model, state="flat", rulings=False)
    assert {round(p[2], 12) for p in flat.creases[0].points} == {0.0}


def test_surfaces_fall_back_to_meshes_outside_rhino(cone_model):
    result = gh.deploy_component(cone_model, surfaces=True, rulings=False)
    assert all(isinstance(p, Mesh) for p in result.plates)


def test_checks_pass_for_the_cone_and_fail_where_the_plates_overlap(cone_model):
    ok = gh.checks_component(cone_model, 30.0, thickness=0.004)
    assert ok.ok is True
    assert ok.report.splitlines()[0].startswith("ok   invariants")
    assert ok.values["thick"]["collisions"]["interpenetration"] is False
    alpha = 0.5 * (cone_model.overlap_alpha + cone_model.alpha_limit)
    bad = gh.checks_component(cone_model, alpha, thickness=0.004)
    assert bad.ok is False
    assert bad.report.startswith("FAIL deployment: self-intersection at alpha = ")
    assert bad.values["error"] == bad.report[len("FAIL deployment: ") :]
    beyond = gh.checks_component(cone_model, cone_model.alpha_limit + 1.0)
    assert beyond.ok is False and beyond.report.startswith("FAIL deployment:")


def test_checks_skip_the_thick_model_of_ccf_creases(quadrants_model):
    result = gh.checks_component(quadrants_model)
    assert "not checked (CCF creases have no thick model)" in result.report


def test_cut_patterns_lie_on_xy_by_layer(vault_model):
    result = gh.cut_patterns_component(vault_model, gap=0.05)
    n = vault_model.segments
    counts = {k: len(v) for k, v in result.by_layer.items()}
    assert counts == {"CUT": 10, "CREASE": 18, "RULING_SCORE": 10 * (n - 1)}
    assert len(result.curves) == len(result.layers) == len(result.plates) == sum(counts.values())
    zs = {p[2] for c in result.by_layer["CUT"] for p in c.points}
    assert zs == {0.0}
    cut = result.by_layer["CUT"][0]
    assert cut.is_closed
    # laid out apart: no two outlines' bounding boxes overlap by more than the nesting allows
    boxes = [np.array(c.points)[:, :2] for c in result.by_layer["CUT"]]
    assert min(b[:, 1].min() for b in boxes) < max(b[:, 1].max() for b in boxes) - 0.5


def test_cut_patterns_refuse_a_zero_gap(cone_model):
    with pytest.raises(OptionError, match="gap must be > 0 m, got 0"):
        gh.cut_patterns_component(cone_model, gap=0)


def test_fabricate_writes_only_when_run(tmp_path, cone_model):
    idle = gh.fabricate_component(cone_model, tmp_path / "fab")
    assert idle.files == [] and not (tmp_path / "fab").exists()
    # shelf nesting (spyrrow's search is the fabrication tests' job): the component only passes
    # its options on to fabricate
    shelf = WorkshopOptions(nesting="shelf")
    result = gh.fabricate_component(
        cone_model, tmp_path / "fab", run=True, thickness=0.004, workshop=shelf
    )
    # 2 plates, the sheets (the cone's plates are split and nested), sheets.json, bom.csv and 9
    # more files
    sheets = [f for f in result.files if Path(f).parent.name == "sheets"]
    assert len(sheets) >= 1 and len(result.files) == 13 + len(sheets)
    assert all(Path(f).is_file() for f in result.files)
    assert Path(result.files[-1]).name == "fabrication.json"
    with pytest.raises(OptionError, match="connect a folder"):
        gh.fabricate_component(cone_model, " ", run=True)


def test_a_model_input_that_is_not_a_model_is_refused():
    with pytest.raises(OptionError, match="expected a CCU model, a design or a design file path"):
        gh.as_model(None)


# -- the components' files and code.py with host doubles -----------------------------------------


def test_every_component_has_code_metadata_and_a_small_icon():
    assert sorted(p.name for p in COMPONENTS.iterdir() if p.is_dir()) == sorted(NAMES)
    for name in NAMES:
        folder = COMPONENTS / name
        first = (folder / "code.py").read_text().splitlines()[0]
        assert first.startswith("# r: compas_ccu") and (first == "# r: compas_ccu") == (
            name != "CCU_Fabricate"
        )
        icon = (folder / "icon.png").read_bytes()
        assert icon[:8] == b"\x89PNG\r\n\x1a\n" and len(icon) < 2048
        meta = json.loads((folder / "metadata.json").read_text())
        assert meta["category"] == "COMPAS CCU" and meta["ghpython"]["isAdvancedMode"] is True


class _Component:
    def __init__(self):
        self.messages = []

    def AddRuntimeMessage(self, level, text):
        self.messages.append((level, text))


@pytest.fixture()
def host(monkeypatch):
    """Grasshopper / Rhino / System doubles: classes and values, no behaviour beyond data."""

    class GH_ScriptInstance:
        pass

    grasshopper = types.ModuleType("Grasshopper")
    grasshopper.Kernel = types.SimpleNamespace(
        GH_ScriptInstance=GH_ScriptInstance,
        GH_RuntimeMessageLevel=types.SimpleNamespace(Error="Error", Warning="Warning"),
    )
    rhino = types.ModuleType("Rhino")
    rhino.Geometry = types.SimpleNamespace(Curve=object)
    rhino.RhinoDoc = types.SimpleNamespace(ActiveDoc=types.SimpleNamespace(ModelUnitSystem="mm"))
    rhino.UnitSystem = types.SimpleNamespace(Meters="m")
    rhino.RhinoMath = types.SimpleNamespace(UnitScale=lambda a, b: 0.001 if a == "mm" else 1.0)
    system = types.ModuleType("System")
    system.Drawing = types.SimpleNamespace(
        Color=types.SimpleNamespace(FromArgb=lambda r, g, b: ("argb", r, g, b))
    )
    for name, module in (("Grasshopper", grasshopper), ("Rhino", rhino), ("System", system)):
        monkeypatch.setitem(sys.modules, name, module)
    monkeypatch.setattr(convert, "_HOSTS", {"compas_rhino.conversions": None, "Rhino": rhino})
    return GH_ScriptInstance


def _component(name, base):
    ghenv = types.SimpleNamespace(Component=_Component())
    namespace = runpy.run_path(str(COMPONENTS / name / "code.py"), init_globals={"ghenv": ghenv})
    cls = next(
        v
        for v in namespace.values()
        if isinstance(v, type) and issubclass(v, base) and v is not base
    )
    meta = json.loads((COMPONENTS / name / "metadata.json").read_text())
    inputs = [p["name"] for p in meta["ghpython"]["inputParameters"]]
    assert list(inspect.signature(cls.RunScript).parameters)[1:] == inputs
    return cls(), ghenv.Component, len(meta["ghpython"]["outputParameters"])


def test_the_components_run_with_host_doubles(host, tmp_path):
    design, design_host, outputs = _component("CCU_Design", host)
    curve = _arch(scale=1000.0)  # a document in millimetres
    out = design.RunScript(None, curve, 24, 0.25, None, None, 30.0)
    assert len(out) == outputs and isinstance(out[1], CCUModel)
    model = out[1]
    assert np.allclose(model.deploy().deployed[0, 24], [2.0, 0.0, 0.0], atol=1e-9)  # metres

    deploy, _, outputs = _component("CCU_Deploy", host)
    out = deploy.RunScript(model, 20.0, False, False, None)
    assert len(out) == outputs
    structure, plates, creases, rulings, plate_colors, crease_colors, info = out
    assert (len(plates), len(creases), len(rulings)) == (2, 1, 50)
    assert crease_colors == [("argb", 31, 99, 214)]
    assert np.allclose(np.array(creases[0].points)[-1], 1000.0 * structure.deployed[0, 24])

    checks, _, outputs = _component("CCU_Checks", host)
    out = checks.RunScript(model, None, 0.004)
    assert len(out) == outputs and out[0] is True

    cut, _, outputs = _component("CCU_CutPatterns", host)
    out = cut.RunScript(model, 0.004, None)
    assert len(out) == outputs and out[1].count("CUT") == 2
    assert max(abs(p[0]) for c in out[3] for p in c.points) > 100.0  # millimetres

    fab, fab_host, outputs = _component("CCU_Fabricate", host)
    assert fab.RunScript(model, str(tmp_path), 0.004, False) == (
        [],
        "set run to True to write the files",
    )
    files, info = fab.RunScript(model, str(tmp_path / "out"), 0.004, True)
    sheets = [f for f in files if Path(f).parent.name == "sheets"]
    assert len(files) == 13 + len(sheets) and info.startswith(f"wrote {len(files)} files")
    assert fab_host.messages == []


def test_a_component_error_becomes_a_runtime_message(host):
    design, component, _ = _component("CCU_Design", host)
    out = design.RunScript(None, [[0, 0, 0], [1, 0, 0], [2, 0, 0]], None, None, None, None, None)
    assert out[:2] == (None, None)
    assert component.messages == [("Error", out[2])]
    assert "straight" in out[2]


def test_a_missing_nester_is_a_runtime_warning_not_a_python_warning(host, tmp_path, monkeypatch):
    """Without compas_nest and spyrrow the shelves nest the parts: the component says so as a
    runtime message (and in info), and no Python warning reaches Grasshopper's output."""
    import warnings

    from compas_ccu.errors import CCUWarning
    from compas_ccu.fabrication import nesting

    monkeypatch.setattr(nesting, "_installed", lambda nester: False)
    fab, component, _ = _component("CCU_Fabricate", host)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        files, info = fab.RunScript(str(EXAMPLES / "cone.toml"), str(tmp_path / "f"), None, True)
    assert not [w for w in caught if issubclass(w.category, CCUWarning)]
    assert files and Path(files[-1]).name == "fabrication.json"
    text = (
        "no true-shape nester is installed (compas_nest or spyrrow: pip install "
        "'compas_ccu[fab]'): the parts are nested by shelves of bounding boxes, which wastes "
        "sheets"
    )
    assert component.messages == [("Warning", text)]
    assert info.splitlines()[1] == f"warning: {text}"
    manifest = json.loads(Path(files[-1]).read_text())
    assert manifest["workshop"]["warnings"] == [text]
    assert manifest["workshop"]["nesting"] == "shelf"


#: Every component's instance GUID, fixed in its metadata.json: COMPAS' componentizer gives a
#: component without one a new GUID at every build, and Grasshopper then treats the rebuilt
#: component as another one.
INSTANCE_GUIDS = {
    "CCU_Checks": "8c3ce686-6c07-5522-805b-355946869550",
    "CCU_CutPatterns": "55c31d8b-c63c-5894-8407-e98859e3d908",
    "CCU_Deploy": "3e26eae6-4638-5660-b9f8-27fd391497c0",
    "CCU_Design": "b8523c7c-9223-58a6-8ec0-82390e03c922",
    "CCU_Fabricate": "5fde1f48-a1d0-516f-9aed-141f7fc27890",
}


def test_every_component_has_a_fixed_instance_guid():
    import uuid

    for name in NAMES:
        meta = json.loads((COMPONENTS / name / "metadata.json").read_text())
        assert str(uuid.UUID(meta["instanceGuid"])) == meta["instanceGuid"] == INSTANCE_GUIDS[name]
    assert len(set(INSTANCE_GUIDS.values())) == len(NAMES)


def test_the_fabricate_requirements_line_installs_what_fabricate_imports():
    """Its `# r:` line: compas_ccu and the modules `fabricate` needs beyond the core (the fab
    and viz extras' writers), and compas_nest at the version the fab extra pins (the nester
    with wheels for Rhino's Python 3.9)."""
    tomllib = pytest.importorskip("tomllib")
    from packaging.requirements import Requirement

    from compas_ccu.fabrication.fabricate import REQUIRED_MODULES

    first = (COMPONENTS / "CCU_Fabricate" / "code.py").read_text().splitlines()[0]
    listed = {Requirement(r.strip()).name.replace("-", "_"): Requirement(r.strip()) for r in
              first[len("# r: "):].split(",")}  # fmt: skip
    assert set(REQUIRED_MODULES) - {"shapely"} | {"compas_ccu", "compas_nest"} == set(listed)
    project = tomllib.loads((EXAMPLES.parent / "pyproject.toml").read_text())
    extras = project["project"]["optional-dependencies"]
    pinned = {Requirement(r).name: Requirement(r) for r in extras["fab"] + extras["viz"]}
    assert str(listed["compas_nest"].specifier) == str(pinned["compas-nest"].specifier) == "==0.1.0"
    for module in ("ezdxf", "rhino3dm", "trimesh", "matplotlib"):
        assert listed[module].specifier == pinned[module].specifier, module
