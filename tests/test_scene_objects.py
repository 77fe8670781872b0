"""CCU structures in COMPAS scenes: plugin registration, children, colours, per-context draw."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from types import SimpleNamespace

import compas
import numpy as np
import pytest
from compas.colors import Color
from compas.datastructures import Graph, Mesh
from compas.geometry import Line, Polyline
from compas.scene import Scene, SceneObject
from compas.scene.context import ITEM_SCENEOBJECT, register, register_scene_objects

import compas_ccu
import compas_ccu.scene as ccu_scene
import compas_ccu.scene.objects as objects_module
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
    # the rulings of a plate: one child (a graph, one edge per ruling), not one per ruling
    assert (len(plates), len(creases), len(rulings)) == (10, 9, 10)
    assert len(scene.objects) == 1 + 10 + 9 + 10
    assert all(isinstance(c.item, Mesh) and c.item.number_of_faces() == n for c in plates)
    assert all(isinstance(c.item, Polyline) and len(c.item.points) == n + 1 for c in creases)
    assert all(isinstance(c.item, Graph) and c.item.number_of_edges() == n + 1 for c in rulings)
    assert [c.name for c in rulings] == [f"rulings_{pid}" for pid in structure.plate_ids]
    assert all(c.show_nodes is False for c in rulings)
    # the ruling graph of a plate joins its vertex rows: ruling j from near[j] to far[j]
    segments = ccu_scene.draw.ruling_segments(rulings[0].item)
    deployed = structure.deployed[0]
    assert np.allclose(segments[:, 0], deployed[: n + 1]) and np.allclose(
        segments[:, 1], deployed[n + 1 :]
    )
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


def test_compas_notebook_draws_the_structure_as_one_mesh_and_one_line_set(vault_model):
    """Runs where the notebook extra is installed (pip install "compas_ccu[notebook]")."""
    viewer_module = pytest.importorskip("compas_notebook.viewer")
    viewer = viewer_module.Viewer()
    obj = viewer.scene.add(vault_model, alpha=20.0)
    assert type(obj) is NotebookCCUObject
    assert [len(obj.children_by_role(r)) for r in ("plate", "crease", "ruling")] == [10, 9, 10]
    viewer.scene.draw()
    assert [g for child in obj.children for g in child.guids] == []  # the parent draws them
    mesh, lines = obj.guids
    assert (type(mesh).__name__, type(lines).__name__) == ("Mesh", "LineSegments")
    n = vault_model.segments
    positions = mesh.geometry.attributes["position"].array
    colors = mesh.geometry.attributes["color"].array
    assert positions.shape == (10 * 2 * (n + 1), 3) and colors.shape == positions.shape
    assert len(mesh.geometry.index.array) == 10 * n * 2 * 3  # two triangles per quad
    rgb = [round(float(c), 4) for c in colors[0]]
    assert rgb == [round(c, 4) for c in obj.children[0].color.rgb]  # the plate's tint
    # lines: plate outlines, then rulings (10 x 65), then creases (9 x 64) in the kind colours
    index = lines.geometry.index.array
    outline = 10 * (2 * n + 2)
    assert len(index) == 2 * (outline + 10 * (n + 1) + 9 * n)
    line_rgb = lines.geometry.attributes["color"].array[index[2 * (outline + 10 * (n + 1)) :]]
    kinds = {Color(*map(float, c)).hex for c in line_rgb}
    assert kinds == {KIND_COLORS["synclastic"], KIND_COLORS["anticlastic"]}
    # a hidden child is left out of the buffers
    for child in obj.children_by_role("ruling"):
        child.show = False
    obj.draw()
    assert len(obj.guids[1].geometry.index.array) == 2 * (outline + 9 * n)


def test_the_notebook_scene_of_the_vault_makes_at_most_50_widget_models(vault_model):
    """Was 2,763 (one pythreejs line, geometry, attribute and material per ruling and crease);
    now the structure is 12 models and the viewer's own page (buttons, layouts, camera) 27."""
    viewer_module = pytest.importorskip("compas_notebook.viewer")
    widgets = pytest.importorskip("ipywidgets")
    registry = getattr(widgets.widgets.widget, "_instances", None)  # ipywidgets 8
    if registry is None:
        registry = widgets.Widget.widgets  # ipywidgets 7
    before = set(registry)
    viewer = viewer_module.Viewer()
    viewer.scene.add(vault_model)
    viewer.show()  # draws the scene and builds the viewer's widgets (no frontend here)
    created = set(registry) - before
    assert len(created) <= 50, len(created)


def test_the_notebook_buffers_of_a_flat_cone(cone_model):
    items = ccu_scene.draw_items(cone_model, state="flat")
    buffers = objects_module.notebook_buffers(items)
    positions, colors, index = buffers.faces
    assert positions.dtype == np.float32 and index.dtype == np.uint16
    assert set(np.asarray(positions)[:, 2].tolist()) == {0.0}
    assert index.max() < len(positions)
    assert objects_module.notebook_buffers([]) == objects_module.NotebookBuffers(None, None)
    # a mesh whose vertex keys are not 0 .. n - 1: the faces and outline index its vertices
    mesh = Mesh()
    for key, xyz in zip((7, 3, 9, 5), ([0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0])):
        mesh.add_vertex(key, x=xyz[0], y=xyz[1], z=xyz[2])
    mesh.add_face([7, 3, 9, 5])
    piece = ccu_scene.DrawItem("plate", "plate_0", mesh, Color(0.5, 0.5, 0.5))
    buffers = objects_module.notebook_buffers([piece])
    positions, _, index = buffers.faces
    assert positions[index].tolist() == [
        [0, 0, 0],
        [1, 0, 0],
        [1, 1, 0],
        [0, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
    ]
    positions, _, index = buffers.lines
    assert sorted(map(tuple, positions[index.reshape(-1, 2)].sum(axis=1).tolist())) == sorted(
        [(1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0)]
    )


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
    if isinstance(item, Graph):
        return [xyz[2] for xyz in item.nodes_attributes("xyz")]
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
    assert len(manager.objects) == 1 + 2 + 1 + 2  # the rulings: one object per plate
    rulings = obj.children_by_role("ruling")[0]
    positions, colors, _ = rulings._lines_data
    assert len(positions) == 2 * (n + 1) and {c.hex for c in colors} == {RULING_COLOR}


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


class _ViewerSceneObjectDouble(SceneObject):
    """compas_viewer's ``ViewerSceneObject`` double: ``init()`` (called by the renderer before
    it computes the view) and ``viewer.renderer.camera`` (``target``, ``distance``, ``fov``,
    ``far``, ``scale``, as compas_viewer's ``Camera``)."""

    viewer = None

    def __init__(self, **kwargs):
        kwargs.pop("show_nodes", None), kwargs.pop("edgecolor", None), kwargs.pop("facecolor", None)
        super().__init__(**kwargs)
        self.initialised = False

    def init(self):
        self.initialised = True

    def draw(self):
        return []


def test_the_viewer_scene_object_sets_the_camera_on_the_structure(monkeypatch, vault_model):
    camera = SimpleNamespace(fov=45.0, near=0.1, far=1000.0, scale=1.0, target=[0, 0, 0],
                             distance=17.3)  # fmt: skip
    monkeypatch.setattr(
        _ViewerSceneObjectDouble, "viewer", SimpleNamespace(renderer=SimpleNamespace(camera=camera))
    )
    cls = objects_module._viewer_class(_ViewerSceneObjectDouble)
    assert cls.__mro__[1:3] == (objects_module._ViewerFraming, CCUSceneObject)
    monkeypatch.setattr(compas.scene.context, "ITEM_SCENEOBJECT", ITEM_SCENEOBJECT.copy())
    compas.scene.context.ITEM_SCENEOBJECT["Viewer"] = {}
    for geometry_type in (Mesh, Polyline, Graph):
        register(geometry_type, _ViewerSceneObjectDouble, context="Viewer")
    ccu_scene.register_context("Viewer", cls)
    scene = Scene(context="Viewer")
    obj = scene.add(vault_model.deploy(30.0))
    assert type(obj) is cls and len(obj.children) == 10 + 9 + 10
    obj.init()
    assert obj.initialised  # the viewer's own init ran
    lo, hi = obj.bounding_box()
    assert np.allclose(camera.target, (lo + hi) / 2)
    radius = np.linalg.norm(hi - lo) / 2
    # the bounding sphere inside the field of view, with a margin, and not much more
    assert radius < camera.distance * np.sin(np.radians(camera.fov / 2)) < 1.3 * radius
    assert 1.0 < camera.distance < 10.0 and camera.far == 1000.0  # the vault: about 3 m
    # millimetres: 1000 times further, the far plane moved out to keep it in view
    mm = scene.add(vault_model.deploy(30.0), scale=1000.0)
    mm.init()
    assert 1000.0 < camera.distance < 10000.0 and camera.far > camera.distance + 1000 * radius
    # zoom=False leaves the camera alone
    camera.distance = 17.3
    scene.add(vault_model.deploy(30.0), zoom=False).init()
    assert camera.distance == 17.3
