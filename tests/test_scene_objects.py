"""CCU structures in COMPAS scenes: plugin registration, children, colours, per-context draw."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import compas
import pytest
from compas.datastructures import Mesh
from compas.geometry import Line, Polyline
from compas.scene import Scene, SceneObject
from compas.scene.context import ITEM_SCENEOBJECT, register, register_scene_objects

import compas_ccu
import compas_ccu.scene as ccu_scene
from compas_ccu.design import Design
from compas_ccu.errors import OptionError
from compas_ccu.model import CCUModel
from compas_ccu.scene import (
    CCUSceneObject,
    GrasshopperCCUObject,
    NotebookCCUObject,
    RhinoCCUObject,
    viewer_object_class,
)
from compas_ccu.structure import Structure
from compas_ccu.thickness import ThickModel
from compas_ccu.viz.colors import KIND_COLORS, RULING_COLOR

DRAWABLE = (Structure, CCUModel, Design, ThickModel)


def test_plugin_discovery_finds_this_copy_of_the_package():
    assert "compas_ccu.scene" in compas_ccu.__all_plugins__
    assert ccu_scene.__file__.startswith(compas_ccu.__path__[0])
    register_scene_objects()
    for data_type in DRAWABLE:
        assert ITEM_SCENEOBJECT[None][data_type] is CCUSceneObject
    # a host plugin registers only where its host imports (here: none, or the notebook extra)
    hosts = {"Rhino": "Rhino", "Grasshopper": "Grasshopper", "Viewer": "compas_viewer",
             "Notebook": "compas_notebook"}  # fmt: skip
    for context, module in hosts.items():
        present = importlib.util.find_spec(module) is not None
        assert (Structure in ITEM_SCENEOBJECT.get(context, {})) is present, context


def test_each_context_plugin_registers_its_own_class(monkeypatch):
    monkeypatch.setattr(compas.scene.context, "ITEM_SCENEOBJECT", ITEM_SCENEOBJECT.copy())
    table = compas.scene.context.ITEM_SCENEOBJECT
    for context in ("Rhino", "Grasshopper", "Viewer", "Notebook"):
        table[context] = {}  # the per-context dicts must not leak into the shared table
    ccu_scene.register_scene_objects_ccu_rhino()
    ccu_scene.register_scene_objects_ccu_grasshopper()
    ccu_scene.register_scene_objects_ccu_notebook()
    expected = {
        "Rhino": RhinoCCUObject,
        "Grasshopper": GrasshopperCCUObject,
        "Notebook": NotebookCCUObject,
    }
    if importlib.util.find_spec("compas_viewer") is None:
        with pytest.raises(ImportError, match="compas_viewer"):
            ccu_scene.register_scene_objects_ccu_viewer()
    else:
        ccu_scene.register_scene_objects_ccu_viewer()
        expected["Viewer"] = viewer_object_class()
    for context, cls in expected.items():
        assert {table[context][t] for t in DRAWABLE} == {cls}
        assert issubclass(cls, CCUSceneObject)


def test_scene_add_structure_makes_plates_creases_rulings_with_kind_colours(vault_model):
    structure = vault_model.deploy(30.0)
    scene = Scene()
    obj = scene.add(structure)
    assert type(obj) is CCUSceneObject
    n = structure.faces.shape[1]
    plates, creases, rulings = (obj.children_by_role(r) for r in ("plate", "crease", "ruling"))
    assert (len(plates), len(creases), len(rulings)) == (10, 9, 10 * (n + 1))
    assert len(scene.objects) == 1 + 10 + 9 + 650
    assert all(isinstance(c.item, Mesh) and c.item.number_of_faces() == n for c in plates)
    assert all(isinstance(c.item, Polyline) and len(c.item.points) == n + 1 for c in creases)
    assert all(isinstance(c.item, Line) for c in rulings)
    by_kind = {}
    for child, record in zip(creases, structure.creases):
        by_kind.setdefault(record["kind"], set()).add(child.color.hex)
    assert by_kind == {"synclastic": {KIND_COLORS["synclastic"]},
                       "anticlastic": {KIND_COLORS["anticlastic"]}}  # fmt: skip
    assert {c.color.hex for c in rulings} == {RULING_COLOR}
    # end plates have one synclastic crease; inner plates one of each kind: "mixed"
    kinds = [p.attributes["kind"] for p in obj.draw_items if p.role == "plate"]
    assert kinds == ["synclastic"] + ["mixed"] * 8 + ["synclastic"]
    assert plates[0].color.hex == "#9ab8ec"  # the synclastic blue, 55 % towards white
    assert plates[0].name == "plate_0" and creases[0].name == "crease_0"
    # contexts that draw faces in facecolor and curves in contrastcolor get the same colours
    assert plates[0].facecolor.default.hex == "#9ab8ec"
    assert creases[0].contrastcolor.hex == creases[0].color.hex


def test_compas_notebook_draws_the_children_in_their_colours(vault_model):
    """Runs where the notebook extra is installed (pip install "compas_ccu[notebook]")."""
    viewer_module = pytest.importorskip("compas_notebook.viewer")
    viewer = viewer_module.Viewer()
    obj = viewer.scene.add(vault_model, alpha=20.0)
    assert type(obj) is NotebookCCUObject
    viewer.scene.draw()
    three = [g for child in obj.children for g in child.guids]
    counts = {}
    for g in three:
        counts[type(g).__name__] = counts.get(type(g).__name__, 0) + 1
    assert counts == {"LineSegments": 10, "Mesh": 10, "Line": 9 + 650}
    crease = obj.children_by_role("crease")[0]
    assert crease.guids[0].material.color == crease.color.hex
    plate = next(g for g in obj.children[0].guids if type(g).__name__ == "Mesh")
    rgb = plate.geometry.attributes["color"].array[0]
    assert [round(float(c), 4) for c in rgb] == [round(c, 4) for c in obj.children[0].color.rgb]


def test_scene_add_model_design_and_thick_model(cone_model):
    scene = Scene()
    from_model = scene.add(cone_model, show_rulings=False)
    from_design = scene.add(cone_model.design, show_rulings=False, alpha=20.0)
    thick = scene.add(ThickModel(cone_model, thickness=0.004), show_rulings=False)
    assert [len(o.children) for o in (from_model, from_design)] == [3, 3]
    assert len(thick.children_by_role("solid")) == 2
    solid = thick.children_by_role("solid")[0].item
    assert solid.number_of_faces() == 8 * cone_model.segments + 4  # closed triangle mesh
    assert solid.is_closed()
    deployed = from_design.children[0].item.vertices_attributes("xyz")
    assert deployed == cone_model.deploy(20.0).deployed[0].tolist()


def test_cut_patterns_lie_on_the_xy_plane(cone_model):
    obj = Scene().add(cone_model.deploy(), state="flat")
    zs = {z for c in obj.children for z in _zs(c.item)}
    assert zs == {0.0}


def _zs(item) -> list:
    if isinstance(item, Mesh):
        return [xyz[2] for xyz in item.vertices_attributes("xyz")]
    if isinstance(item, Line):
        return [item.start[2], item.end[2]]
    return [p[2] for p in item.points]


@pytest.mark.parametrize(
    ("item", "options", "message"),
    [
        ("structure", {"thickness": 0.01}, "thick solids need the model"),
        ("structure", {"alpha": 10.0}, "a Structure is one state .alpha = 30 deg.; got alpha=10.0"),
        ("model", {"state": "folded"}, "state must be one of 'deployed', 'flat', got 'folded'"),
        ("model", {"state": "flat", "thickness": True}, "deployed state only, got 'flat'"),
        ("model", {"plate_colors": "rainbow"}, "plate_colors must be one of .*'rainbow'"),
        ("model", {"scale": 0}, "scale must be a number > 0 .drawing units per metre., got 0"),
    ],
)
def test_impossible_options_are_refused(cone_model, item, options, message):
    data = cone_model.deploy(30.0) if item == "structure" else cone_model
    with pytest.raises(OptionError, match=message):
        Scene().add(data, **options)


def test_an_object_that_is_not_ccu_data_is_refused():
    with pytest.raises(OptionError, match="cannot draw a Mesh; expected one of Structure"):
        ccu_scene.draw_items(Mesh.from_polyhedron(4))


class _Recorder(SceneObject):
    """A host double: records what it would draw (the role of a Rhino / GH object)."""

    def draw(self):
        self._guids = [(type(self.item).__name__, self.name, self.color.hex)]
        return self._guids


def test_grasshopper_scene_draws_every_child_through_the_context_objects(monkeypatch, cone_model):
    monkeypatch.setattr(compas.scene.context, "ITEM_SCENEOBJECT", ITEM_SCENEOBJECT.copy())
    table = compas.scene.context.ITEM_SCENEOBJECT
    table["Grasshopper"] = {}
    for geometry_type in (Mesh, Polyline, Line):
        register(geometry_type, _Recorder, context="Grasshopper")
    ccu_scene.register_scene_objects_ccu_grasshopper()
    scene = Scene(context="Grasshopper")
    obj = scene.add(cone_model.deploy(), show_rulings=False)
    assert type(obj) is GrasshopperCCUObject
    drawn = scene.draw()
    assert drawn == [
        ("Mesh", "plate_0", "#9ab8ec"),
        ("Mesh", "plate_1", "#9ab8ec"),
        ("Polyline", "crease_0", KIND_COLORS["synclastic"]),
    ]


def test_compas_viewer_builds_buffers_of_the_children(monkeypatch, cone_model):
    """Runs where the viewer extra is installed; no window: Qt's offscreen platform, and the
    renderer's buffer manager fed by hand (it needs no GL context)."""
    monkeypatch.setenv("QT_QPA_PLATFORM", "offscreen")
    viewer_module = pytest.importorskip("compas_viewer")
    viewer_scene = pytest.importorskip("compas_viewer.scene")
    viewer = viewer_module.Viewer()
    obj = viewer.scene.add(cone_model, alpha=20.0)
    assert type(obj) is viewer_object_class() and isinstance(obj, CCUSceneObject)
    assert isinstance(obj, viewer_scene.ViewerSceneObject)
    ours = [obj, *obj.children]
    for o in ours:
        o.init()
    assert (obj._points_data, obj._lines_data, obj._frontfaces_data) == (None, None, None)
    manager = viewer.renderer.buffer_manager
    for o in ours:
        manager.add_object(o)
    n = cone_model.segments
    crease = obj.children_by_role("crease")[0]
    positions, colors, _ = crease._lines_data
    assert len(positions) == 2 * n and {c.hex for c in colors} == {"#1f63d6"}
    plate = obj.children_by_role("plate")[0]
    assert {c.hex for c in plate._frontfaces_data[1]} == {"#9ab8ec"}
    assert len(manager.objects) == 1 + 2 + 1 + 2 * (n + 1)


def test_import_stays_cheap_and_discovery_loads_no_plotting_or_writers():
    code = (
        "import sys; import compas_ccu; "
        "print(sorted({m.split('.')[0] for m in sys.modules} & {'compas', 'numpy', 'scipy'})); "
        "from compas.scene.context import register_scene_objects; register_scene_objects(); "
        "print('compas_ccu.scene' in sys.modules, sorted({m.split('.')[0] for m in sys.modules} "
        "& {'matplotlib', 'plotly', 'ezdxf', 'rhino3dm', 'trimesh', 'Rhino', 'viser'}))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.split("\n")
    assert out[0] == "[]"
    assert out[1] == "True []"
