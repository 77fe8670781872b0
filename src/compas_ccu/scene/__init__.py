"""CCU structures in COMPAS scenes: ``Scene().add(model_or_structure)``.

COMPAS finds these plugins through ``compas_ccu.__all_plugins__`` and registers
:class:`~compas_ccu.scene.objects.CCUSceneObject` for :class:`~compas_ccu.structure.Structure`,
:class:`~compas_ccu.model.CCUModel`, :class:`~compas_ccu.design.Design` and
:class:`~compas_ccu.thickness.ThickModel` in every context whose host can be imported: no
context (plain Python), Rhino, Grasshopper, the COMPAS Viewer (``compas_viewer``) and notebooks
(``compas_notebook``). The host checks are the plugins' ``requires``: nothing here imports a
host.

>>> from compas.scene import Scene
>>> from compas_ccu.model import load_model
>>> obj = Scene().add(load_model("examples/vault.toml"))
>>> [len(obj.children_by_role(r)) for r in ("plate", "crease", "ruling")]
[10, 9, 10]
"""

from __future__ import annotations

from compas.plugins import plugin
from compas.scene import register

from compas_ccu.scene.draw import DRAWABLE_TYPES, DrawItem, draw_items
from compas_ccu.scene.objects import (
    CONTEXT_OBJECTS,
    CCUSceneObject,
    GrasshopperCCUObject,
    NotebookCCUObject,
    RhinoCCUObject,
    viewer_object_class,
)

__all__ = [
    "CCUSceneObject",
    "RhinoCCUObject",
    "GrasshopperCCUObject",
    "viewer_object_class",
    "NotebookCCUObject",
    "CONTEXT_OBJECTS",
    "DrawItem",
    "draw_items",
    "register_context",
]


def register_context(context, cls=None) -> None:
    """Register ``cls`` (default: the CCU scene object of ``context``) for every drawable type."""
    cls = CONTEXT_OBJECTS[context] if cls is None else cls
    for data_type in DRAWABLE_TYPES:
        register(data_type, cls, context=context)


@plugin(category="factories", pluggable_name="register_scene_objects")
def register_scene_objects_ccu() -> None:
    register_context(None)


@plugin(category="factories", pluggable_name="register_scene_objects", requires=["Rhino"])
def register_scene_objects_ccu_rhino() -> None:
    register_context("Rhino")


@plugin(category="factories", pluggable_name="register_scene_objects", requires=["Grasshopper"])
def register_scene_objects_ccu_grasshopper() -> None:
    register_context("Grasshopper")


@plugin(category="factories", pluggable_name="register_scene_objects", requires=["compas_viewer"])
def register_scene_objects_ccu_viewer() -> None:
    register_context("Viewer", viewer_object_class())


@plugin(category="factories", pluggable_name="register_scene_objects", requires=["compas_notebook"])
def register_scene_objects_ccu_notebook() -> None:
    register_context("Notebook")
