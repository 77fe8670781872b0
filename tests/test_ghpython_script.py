"""scripts/rhino_deploy_curve.py with rhinoscriptsyntax and the Rhino scene replaced by doubles."""

from __future__ import annotations

import runpy
import sys
import types
from pathlib import Path

import compas
import numpy as np
import pytest
from compas.datastructures import Graph, Mesh
from compas.geometry import Line, Polyline
from compas.scene import Scene, SceneObject
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
    """A Rhino scene object double: returns what it would add to the document (the rulings of
    a plate: one group of lines)."""

    def __init__(self, group=None, show_nodes=True, edgecolor=None, facecolor=None, **kwargs):
        super().__init__(**kwargs)
        self.group, self.show_nodes = group, show_nodes

    def draw(self):
        item = self.item
        if isinstance(item, Graph):
            xyz = item.nodes_attributes("xyz")
            lines = [("Line", [xyz[u], xyz[v]]) for u, v in item.edges()]
            self._guids = [(kind, self.name, self.color.hex, p, self.group) for kind, p in lines]
            return self._guids
        points = (
            item.vertices_attributes("xyz")
            if isinstance(item, Mesh)
            else [list(item.start), list(item.end)]
            if isinstance(item, Line)
            else [list(p) for p in item.points]
        )
        self._guids = [(type(item).__name__, self.name, self.color.hex, points, self.group)]
        return self._guids


class _Viewport:
    """``view.ActiveViewport`` double: records the boxes it is zoomed to."""

    def __init__(self):
        self.boxes = []

    def ZoomBoundingBox(self, box):
        self.boxes.append(box)


def _rhino_view_modules(monkeypatch):
    """``Rhino`` (``Geometry.Point3d``, ``Geometry.BoundingBox``) and ``scriptcontext``
    (``doc.Views.ActiveView``) doubles in ``sys.modules``; returns the viewport double."""
    viewport = _Viewport()
    view = types.SimpleNamespace(ActiveViewport=viewport, Redraw=lambda: None)
    geometry = types.SimpleNamespace(
        Point3d=lambda x, y, z: (x, y, z), BoundingBox=lambda lo, hi: (lo, hi)
    )
    rhino = types.ModuleType("Rhino")
    rhino.Geometry = geometry
    sc = types.ModuleType("scriptcontext")
    sc.doc = types.SimpleNamespace(Views=types.SimpleNamespace(ActiveView=view))
    monkeypatch.setitem(sys.modules, "Rhino", rhino)
    monkeypatch.setitem(sys.modules, "scriptcontext", sc)
    return viewport


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
    for geometry_type in (Mesh, Polyline, Line, Graph):
        register(geometry_type, _Drawn, context="Rhino")
    ccu_scene.register_scene_objects_ccu_rhino()
    monkeypatch.setattr(compas.scene.scene, "detect_current_context", lambda: "Rhino")
    answers["viewport"] = _rhino_view_modules(monkeypatch)
    return answers


def test_the_script_deploys_the_picked_curve_in_document_units(rhino):
    main = runpy.run_path(str(SCRIPT), run_name="rhino_deploy_curve")["main"]
    drawn = main()
    assert rhino["messages"] == [] and rhino["real"] == []
    kinds = [d[0] for d in drawn]
    assert kinds.count("Mesh") == 2 and kinds.count("Polyline") == 1
    assert kinds.count("Line") == 2 * 25
    # the rulings of each plate: one Rhino group per plate, a name no other structure shares
    groups = sorted({d[4] for d in drawn if d[0] == "Line"})
    assert len(groups) == 2 and all(g.startswith("grasshopper.rulings_") for g in groups)
    assert {d[4] for d in drawn if d[0] != "Line"} == {None}
    crease = next(d for d in drawn if d[0] == "Polyline")
    assert crease[1] == "crease_0" and crease[2] == "#1f63d6"
    ends = np.array(crease[3])[[0, -1]]
    assert np.all(np.abs(ends[:, 0]) < 2100.0) and ends[1, 0] - ends[0, 0] > 1900.0  # mm
    # the active view zoomed once to the structure's bounding box, in document units
    [(lo, hi)] = rhino["viewport"].boxes
    points = np.array([p for d in drawn for p in (d[3] if d[0] != "Line" else d[3])])
    assert np.allclose(lo, points.min(axis=0)) and np.allclose(hi, points.max(axis=0))


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


def test_the_rhino_scene_object_zooms_only_when_asked(rhino, cone_model):
    viewport = rhino["viewport"]
    scene = Scene(context="Rhino")
    obj = scene.add(cone_model.deploy(), zoom=False)
    assert type(obj) is RhinoCCUObject
    assert len(scene.draw()) == 2 + 1 + 2 * 49 and viewport.boxes == []
    obj = Scene(context="Rhino").add(cone_model.deploy(), scale=1000.0)
    assert obj.draw() == []
    [(lo, hi)] = viewport.boxes
    assert np.allclose([lo, hi], obj.bounding_box()) and np.ptp(obj.bounding_box()[:, 0]) > 100
    sys.modules["scriptcontext"].doc.Views.ActiveView = None  # no view open: nothing to zoom
    assert obj.draw() == [] and len(viewport.boxes) == 1
