"""Scene objects of CCU structures: one context-independent object, thin per-context ones.

:class:`CCUSceneObject` turns a :class:`~compas_ccu.structure.Structure`, a
:class:`~compas_ccu.model.CCUModel`, a :class:`~compas_ccu.design.Design` or a
:class:`~compas_ccu.thickness.ThickModel` into child scene objects: one mesh per plate, one
polyline per crease, one line per ruling (and one closed mesh per thick plate), each with its
colour (:mod:`compas_ccu.scene.draw`). The children are COMPAS meshes, polylines and lines, so
every context draws them with its own mesh / polyline / line objects: the per-context classes
here only name their context. None of them imports a host application (Rhino, Grasshopper,
compas_viewer, compas_notebook); the plugins in :mod:`compas_ccu.scene` register each one only
where its host can be imported. The COMPAS Viewer's class also derives from compas_viewer's own
base class, so it is built on first use (:func:`viewer_object_class`).
"""

from __future__ import annotations

from compas.datastructures import Mesh
from compas.scene import SceneObject

from compas_ccu.scene.draw import draw_items

__all__ = [
    "CCUSceneObject",
    "RhinoCCUObject",
    "GrasshopperCCUObject",
    "viewer_object_class",
    "NotebookCCUObject",
    "CONTEXT_OBJECTS",
]


class CCUSceneObject(SceneObject):
    """A CCU structure in a COMPAS scene: ``Scene().add(structure)`` creates one.

    Parameters
    ----------
    item : Structure, CCUModel, Design or ThickModel
    state : {"deployed", "flat"}
        The deployed plates or the cut patterns.
    alpha : float, optional
        Reference reflection angle of a model / design / thick model, degrees (default: the
        design angle).
    show_plates, show_creases, show_rulings : bool
        Which children to create.
    thickness : True or float, optional
        Also the thick plates as closed solids (see :func:`compas_ccu.scene.draw.draw_items`).
    plate_colors : {"kind", "tone"}
    scale : float
        Drawing units per metre (1000 for a Rhino document in millimetres).
    **kwargs
        Passed on to :class:`compas.scene.SceneObject` (name, context, ...).

    Attributes
    ----------
    draw_items : list of compas_ccu.scene.draw.DrawItem
        What the children show (geometry, colour, role), for tests and for hosts that want the
        data rather than the objects.

    Examples
    --------
    >>> from compas.scene import Scene
    >>> from compas_ccu.model import load_model
    >>> scene = Scene()
    >>> obj = scene.add(load_model("examples/cone.toml").deploy(), show_rulings=False)
    >>> type(obj).__name__, [type(c).__name__ for c in obj.children]
    ('CCUSceneObject', ['MeshObject', 'MeshObject', 'GeometryObject'])
    """

    def __init__(
        self,
        item=None,
        *,
        state: str = "deployed",
        alpha: float | None = None,
        show_plates: bool = True,
        show_creases: bool = True,
        show_rulings: bool = True,
        thickness=None,
        plate_colors: str = "kind",
        scale: float = 1.0,
        **kwargs,
    ):
        super().__init__(item=item, **kwargs)
        self.state = state
        self.draw_items = draw_items(
            item,
            state=state,
            alpha=alpha,
            plates=show_plates,
            creases=show_creases,
            rulings=show_rulings,
            thickness=thickness,
            plate_colors=plate_colors,
            scale=scale,
        )
        for piece in self.draw_items:
            if isinstance(piece.geometry, Mesh):
                # facecolor too: some contexts (compas_notebook) default it to grey
                self.add(piece.geometry, name=piece.name, color=piece.color, facecolor=piece.color)
            else:
                child = self.add(piece.geometry, name=piece.name, color=piece.color)
                # curves drawn in their contrast colour (compas_notebook) keep the kind colour
                child.contrastcolor = piece.color

    def children_by_role(self, role: str) -> list:
        """The child scene objects of one role: ``plate``, ``crease``, ``ruling``, ``solid``."""
        return [c for c, p in zip(self.children, self.draw_items) if p.role == role]

    def draw(self) -> list:
        """Nothing of its own: the scene draws the children (plates, creases, rulings)."""
        return []

    def clear(self) -> None:
        """Nothing of its own to clear: the children clear theirs."""
        self._guids = []


class RhinoCCUObject(CCUSceneObject):
    """:class:`CCUSceneObject` in Rhino (the children are compas_rhino objects)."""


class GrasshopperCCUObject(CCUSceneObject):
    """:class:`CCUSceneObject` in Grasshopper (``scene.draw()`` returns the children's
    Rhino geometry)."""


class NotebookCCUObject(CCUSceneObject):
    """:class:`CCUSceneObject` in Jupyter notebooks (compas_notebook)."""


#: ``{context name: scene object class}`` registered by the plugins of :mod:`compas_ccu.scene`
#: (the Viewer's class: :func:`viewer_object_class`).
CONTEXT_OBJECTS = {
    None: CCUSceneObject,
    "Rhino": RhinoCCUObject,
    "Grasshopper": GrasshopperCCUObject,
    "Notebook": NotebookCCUObject,
}


_VIEWER_CLASS: list = []


def viewer_object_class() -> type:
    """:class:`CCUSceneObject` in the COMPAS Viewer: ``ViewerCCUObject``.

    Built on first use, since it derives from compas_viewer's ``ViewerSceneObject`` (an
    optional dependency: ``pip install "compas_ccu[viewer]"``): the viewer's renderer needs its
    display settings on every scene object. It has no geometry of its own (no GL buffers); its
    children are the viewer's mesh / polyline / line objects.

    Raises
    ------
    ImportError
        compas_viewer is not installed.
    """
    if not _VIEWER_CLASS:
        from compas_viewer.scene import ViewerSceneObject

        _VIEWER_CLASS.append(
            type(
                "ViewerCCUObject",
                (CCUSceneObject, ViewerSceneObject),
                {"__module__": __name__, "__doc__": viewer_object_class.__doc__},
            )
        )
    return _VIEWER_CLASS[0]
