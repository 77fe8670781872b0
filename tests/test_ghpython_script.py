"""scripts/rhino_deploy_curve.py with rhinoscriptsyntax and the Rhino scene replaced by doubles."""

from __future__ import annotations

import runpy
import sys
import types
from pathlib import Path

import compas
import numpy as np
import pytest
from compas.datastructures import Mesh
from compas.geometry import Line, Polyline
from compas.scene import SceneObject
from compas.scene.context import ITEM_SCENEOBJECT, register

import compas_ccu.scene as ccu_scene
from compas_ccu.ghpython import convert
from compas_ccu.scene import RhinoCCUObject
from compas_ccu.scene.draw import draw_items

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "rhino_deploy_curve.py"


class _Point3d:
    def __init__(self, x, y, z):
        self.X, self.Y, self.Z = x, y, z


class _ArchCurve:
    """A Rhino curve double: an arch of span 2000 and rise 600 (millimetres) in the XZ plane."""

    def DivideByCount(self, count, include_ends):
        return [np.pi * k / count for k in range(count + 1)]

    def PointAt(self, t):
        return _Point3d(1000.0 * (1.0 - np.cos(t)), 0.0, 600.0 * np.sin(t))


class _Drawn(SceneObject):
    """A Rhino scene object double: returns what it would add to the document."""

    def draw(self):
        item = self.item
        points = (
            item.vertices_attributes("xyz")
            if isinstance(item, Mesh)
            else [list(item.start), list(item.end)]
            if isinstance(item, Line)
            else [list(p) for p in item.points]
        )
        self._guids = [(type(item).__name__, self.name, self.color.hex, points)]
        return self._guids


@pytest.fixture()
def rhino(monkeypatch):
    answers = {"real": [35.0, 0.25, 20.0], "messages": []}
    rs = types.ModuleType("rhinoscriptsyntax")
    rs.filter = types.SimpleNamespace(curve=4)
    rs.GetObject = lambda prompt, kind: "curve-guid" if kind == 4 else None
    rs.coercecurve = lambda guid: _ArchCurve() if guid == "curve-guid" else None
    rs.GetReal = lambda prompt, default, *limits: answers["real"].pop(0)
    rs.GetInteger = lambda prompt, default, lo, hi: 24
    rs.MessageBox = lambda text, buttons, title: answers["messages"].append(text)
    monkeypatch.setitem(sys.modules, "rhinoscriptsyntax", rs)
    rhino_module = types.SimpleNamespace(
        RhinoDoc=types.SimpleNamespace(ActiveDoc=types.SimpleNamespace(ModelUnitSystem="mm")),
        UnitSystem=types.SimpleNamespace(Meters="m"),
        RhinoMath=types.SimpleNamespace(UnitScale=lambda a, b: 0.001),
    )
    hosts = {"compas_rhino.conversions": None, "Rhino": rhino_module}
    monkeypatch.setattr(convert, "_HOSTS", hosts)
    monkeypatch.setattr(compas.scene.context, "ITEM_SCENEOBJECT", ITEM_SCENEOBJECT.copy())
    compas.scene.context.ITEM_SCENEOBJECT["Rhino"] = {}
    for geometry_type in (Mesh, Polyline, Line):
        register(geometry_type, _Drawn, context="Rhino")
    ccu_scene.register_scene_objects_ccu_rhino()
    monkeypatch.setattr(compas.scene.scene, "detect_current_context", lambda: "Rhino")
    return answers


def test_the_script_deploys_the_picked_curve_in_document_units(rhino):
    main = runpy.run_path(str(SCRIPT), run_name="rhino_deploy_curve")["main"]
    drawn = main()
    assert rhino["messages"] == [] and rhino["real"] == []
    kinds = [d[0] for d in drawn]
    assert kinds.count("Mesh") == 2 and kinds.count("Polyline") == 1
    assert kinds.count("Line") == 2 * 25
    crease = next(d for d in drawn if d[0] == "Polyline")
    assert crease[1] == "crease_0" and crease[2] == "#1f63d6"
    ends = np.array(crease[3])[[0, -1]]
    assert np.all(np.abs(ends[:, 0]) < 2100.0) and ends[1, 0] - ends[0, 0] > 1900.0  # mm


def test_the_script_reports_an_impossible_curve(rhino, monkeypatch):
    flat_line = types.SimpleNamespace(
        DivideByCount=lambda count, ends: list(range(count + 1)),
        PointAt=lambda t: _Point3d(float(t), 0.0, 0.0),
    )
    monkeypatch.setattr(sys.modules["rhinoscriptsyntax"], "coercecurve", lambda guid: flat_line)
    main = runpy.run_path(str(SCRIPT), run_name="rhino_deploy_curve")["main"]
    assert main() is None
    assert rhino["messages"] == ["the crease curve is straight: a CCU crease is curved"]


def test_the_scene_object_of_rhino_scales_to_document_units(cone_model):
    metres = draw_items(cone_model, rulings=False)
    mm = draw_items(cone_model, rulings=False, scale=1000.0)
    a = np.array(metres[-1].geometry.points)
    assert np.allclose(np.array(mm[-1].geometry.points), 1000.0 * a)
    assert issubclass(RhinoCCUObject, SceneObject)
