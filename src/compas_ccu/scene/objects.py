"""Scene objects of CCU structures: one context-independent object, thin per-context ones.

:class:`CCUSceneObject` turns a :class:`~compas_ccu.structure.Structure`, a
:class:`~compas_ccu.model.CCUModel`, a :class:`~compas_ccu.design.Design` or a
:class:`~compas_ccu.thickness.ThickModel` into child scene objects: one mesh per plate, one
polyline per crease, one graph per plate holding the rulings of that plate (and one closed mesh
per thick plate), each with its colour (:mod:`compas_ccu.scene.draw`). The children are COMPAS
meshes, polylines and graphs, so every context draws them with its own objects; a graph's edges
become one line-segments buffer (compas_viewer) or one group of lines (Rhino), not one object
per ruling. The notebook's object draws the whole structure as two pythreejs objects (faces,
lines), so that a notebook stores a few widget models rather than thousands. The COMPAS Viewer's
object sets the camera on the structure (target and distance from its bounding box), the Rhino
object zooms the active view to it. None of them imports a host application at module level
(Rhino, Grasshopper, compas_viewer, compas_notebook / pythreejs); the plugins in
:mod:`compas_ccu.scene` register each one only where its host can be imported. The COMPAS
Viewer's class also derives from compas_viewer's own base class, so it is built on first use
(:func:`viewer_object_class`).
"""

from __future__ import annotations

import importlib
import math
import uuid
from dataclasses import dataclass

import numpy as np
from compas.datastructures import Graph, Mesh
from compas.geometry import Line, Polyline
from compas.scene import SceneObject

from compas_ccu.scene.draw import bounding_box, draw_items
from compas_ccu.tolerances import EXACT_RELATIVE
from compas_ccu.viz.colors import RULING_COLOR, hex_to_rgb

__all__ = [
    "CCUSceneObject",
    "RhinoCCUObject",
    "GrasshopperCCUObject",
    "viewer_object_class",
    "NotebookCCUObject",
    "CONTEXT_OBJECTS",
    "frame_camera",
    "zoom_rhino_view",
    "notebook_buffers",
    "NotebookBuffers",
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
    zoom : bool
        Bring the structure into view where the context has a view: the COMPAS Viewer sets its
        camera on the structure's bounding box, Rhino zooms the active view to it (default
        True; no effect in plain Python, Grasshopper and notebooks).
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
    >>> obj = scene.add(load_model("examples/cone.toml").deploy())
    >>> [(c.name, type(c.item).__name__) for c in obj.children_by_role("ruling")]
    [('rulings_0', 'Graph'), ('rulings_1', 'Graph')]
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
        zoom: bool = True,
        **kwargs,
    ):
        super().__init__(item=item, **kwargs)
        self.state = state
        self.zoom = bool(zoom)
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
            self._add_child(piece)

    def _child_options(self, piece) -> dict:
        """Keyword arguments of the child scene object of ``piece`` (a :class:`DrawItem`)."""
        if isinstance(piece.geometry, Mesh):
            # facecolor too: some contexts (compas_notebook) default it to grey
            return {"color": piece.color, "facecolor": piece.color}
        if isinstance(piece.geometry, Graph):
            # the rulings: edges only, one object per plate
            return {"color": piece.color, "edgecolor": piece.color, "show_nodes": False}
        return {"color": piece.color}

    def _add_child(self, piece):
        child = self.add(piece.geometry, name=piece.name, **self._child_options(piece))
        if not isinstance(piece.geometry, Mesh):
            # curves drawn in their contrast colour (compas_notebook) keep the kind colour
            child.contrastcolor = piece.color
        return child

    def children_by_role(self, role: str) -> list:
        """The child scene objects of one role: ``plate``, ``crease``, ``ruling``, ``solid``.

        ``ruling``: one child per plate (a graph with one edge per ruling)."""
        return [c for c, p in zip(self.children, self.draw_items) if p.role == role]

    def bounding_box(self) -> np.ndarray:
        """``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` of what the children show (drawing
        units)."""
        return bounding_box(self.draw_items)

    def draw(self) -> list:
        """Nothing of its own: the scene draws the children (plates, creases, rulings)."""
        return []

    def clear(self) -> None:
        """Nothing of its own to clear: the children clear theirs."""
        self._guids = []


def zoom_rhino_view(box, *, rhino=None, scriptcontext=None) -> bool:
    """Zoom Rhino's active view to ``box`` (``[[xmin, ymin, zmin], [xmax, ymax, zmax]]``).

    ``rhino`` / ``scriptcontext``: the ``Rhino`` and ``scriptcontext`` modules (default: imported
    here, inside Rhino). Returns False when there is no active view (nothing zoomed).
    """
    rhino = importlib.import_module("Rhino") if rhino is None else rhino
    sc = importlib.import_module("scriptcontext") if scriptcontext is None else scriptcontext
    view = sc.doc.Views.ActiveView
    if view is None:
        return False
    (x0, y0, z0), (x1, y1, z1) = np.asarray(box, dtype=float).tolist()
    point = rhino.Geometry.Point3d
    view.ActiveViewport.ZoomBoundingBox(
        rhino.Geometry.BoundingBox(point(x0, y0, z0), point(x1, y1, z1))
    )
    view.Redraw()
    return True


class RhinoCCUObject(CCUSceneObject):
    """:class:`CCUSceneObject` in Rhino (the children are compas_rhino objects).

    The rulings of each plate are drawn as the lines of one Rhino group (named
    ``<name>.rulings_<plate id>.<8 hex digits>``, so that two structures never share a group);
    ``draw()`` zooms the active view to the structure (``zoom=False``: it does not).
    """

    def __init__(self, item=None, **kwargs):
        self._group_tag = uuid.uuid4().hex[:8]
        super().__init__(item=item, **kwargs)

    def _child_options(self, piece) -> dict:
        options = super()._child_options(piece)
        if isinstance(piece.geometry, Graph):
            options["group"] = f"{self.name}.{piece.name}.{self._group_tag}"
        return options

    def draw(self) -> list:
        """Zoom the active view to the structure; the scene draws the children."""
        if self.zoom and self.draw_items:
            zoom_rhino_view(self.bounding_box())
        return []


class GrasshopperCCUObject(CCUSceneObject):
    """:class:`CCUSceneObject` in Grasshopper (``scene.draw()`` returns the children's
    Rhino geometry; the rulings of a plate: a list of lines)."""


def _triangles(faces: list) -> list:
    """Fan triangles of polygon faces (vertex index lists)."""
    return [[f[0], f[k], f[k + 1]] for f in faces for k in range(1, len(f) - 1)]


class _Buffer:
    """Positions, colours and an index of one pythreejs geometry, filled piece by piece."""

    def __init__(self):
        self.positions, self.colors, self.index = [], [], []
        self.count = 0

    def add(self, points, cells, rgb) -> None:
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        cells = np.asarray(cells, dtype=np.int64)
        if not len(points) or not cells.size:
            return
        self.positions.append(points)
        self.colors.append(np.tile(np.asarray(rgb, dtype=float), (len(points), 1)))
        self.index.append(cells.reshape(-1) + self.count)
        self.count += len(points)

    def arrays(self) -> tuple:
        """``(positions, colors, index)``: float32, float32, uint16 or uint32 arrays."""
        if not self.count:
            return None
        index = np.concatenate(self.index)
        dtype = np.uint16 if self.count < 2**16 else np.uint32
        return (
            np.concatenate(self.positions).astype(np.float32),
            np.concatenate(self.colors).astype(np.float32),
            index.astype(dtype),
        )


@dataclass(frozen=True)
class NotebookBuffers:
    """The arrays a notebook draws (:func:`notebook_buffers`): each ``(positions, colours,
    index)`` with positions (k, 3) float32, colours (k, 3) float32 in 0 .. 1 and index uint16
    (uint32 from 2**16 points) into them, or None when there is nothing of that kind.

    Attributes
    ----------
    faces : tuple of ndarray or None
        The plates and solids as triangles: index (3t,).
    lines : tuple of ndarray or None
        The plate outlines (in the ruling colour), the rulings and the creases (last, so they
        are drawn over the outlines) as segments: index (2s,).
    """

    faces: tuple | None
    lines: tuple | None


def notebook_buffers(pieces) -> NotebookBuffers:
    """The arrays a notebook draws (:class:`NotebookBuffers`) of ``pieces``, the shown
    :class:`~compas_ccu.scene.draw.DrawItem` s."""
    faces, lines = _Buffer(), _Buffer()
    outline_rgb = hex_to_rgb(RULING_COLOR)
    for piece in pieces:  # faces, and the plate outlines first among the lines
        geometry = piece.geometry
        if isinstance(geometry, Mesh):
            vertices, polygons = geometry.to_vertices_and_faces()  # faces: vertex indices
            faces.add(vertices, _triangles(polygons), piece.color.rgb)
            if piece.role == "plate":
                index = geometry.vertex_index()  # edges: vertex keys
                edges = [(index[u], index[v]) for u, v in geometry.edges_on_boundary()]
                lines.add(vertices, edges, outline_rgb)
    for piece in pieces:  # the rulings
        if isinstance(piece.geometry, Graph):
            nodes, edges = piece.geometry.to_nodes_and_edges()
            lines.add(nodes, edges, piece.color.rgb)
    for piece in pieces:  # the creases last: drawn over the outlines they lie on
        geometry, rgb = piece.geometry, piece.color.rgb
        if isinstance(geometry, Polyline):
            points = [list(p) for p in geometry.points]
            lines.add(points, [(i, i + 1) for i in range(len(points) - 1)], rgb)
        elif isinstance(geometry, Line):
            lines.add([list(geometry.start), list(geometry.end)], [(0, 1)], rgb)
    return NotebookBuffers(faces=faces.arrays(), lines=lines.arrays())


class _Drawn(SceneObject):
    """A child of :class:`NotebookCCUObject`: its parent draws it (nothing of its own)."""

    def __init__(self, item=None, sceneobject_type=None, **kwargs):
        super().__init__(item=item, **kwargs)

    def draw(self) -> list:
        self._guids = []
        return []


class NotebookCCUObject(CCUSceneObject):
    """:class:`CCUSceneObject` in Jupyter notebooks (compas_notebook).

    Draws the whole structure as two pythreejs objects, faces (plates and solids, one ``Mesh``
    with vertex colours) and lines (plate outlines, rulings and creases, one ``LineSegments``
    with vertex colours): 12 widget models for any structure, where one three.js object per
    plate, crease and ruling made thousands (2,763 for the vault, a 3.9 MB notebook). The
    children carry the data (``children_by_role`` as in every context) and draw nothing
    themselves; a child whose ``show`` is False is left out of the buffers.
    """

    def _add_child(self, piece):
        return self.add(piece.geometry, name=piece.name, color=piece.color, sceneobject_type=_Drawn)

    def draw(self) -> list:
        """The pythreejs ``Mesh`` (faces) and ``LineSegments`` (lines) of the shown children."""
        three = importlib.import_module("pythreejs")
        shown = [p for c, p in zip(self.children, self.draw_items) if c.show]
        buffers = notebook_buffers(shown)
        guids = []
        if buffers.faces is not None:
            material = three.MeshBasicMaterial(
                side="DoubleSide",
                vertexColors="VertexColors",
                # faces a little behind: the rulings and creases on them stay visible
                polygonOffset=True,
                polygonOffsetFactor=1.0,
                polygonOffsetUnits=1.0,
            )
            guids.append(three.Mesh(_three_geometry(three, buffers.faces), material))
        if buffers.lines is not None:
            material = three.LineBasicMaterial(vertexColors="VertexColors")
            guids.append(three.LineSegments(_three_geometry(three, buffers.lines), material))
        self._guids = guids
        return guids


def _three_geometry(three, arrays):
    positions, colors, index = arrays
    return three.BufferGeometry(
        index=three.BufferAttribute(index, normalized=False),
        attributes={
            "position": three.BufferAttribute(positions, normalized=False),
            "color": three.BufferAttribute(colors, normalized=False),
        },
    )


#: ``{context name: scene object class}`` registered by the plugins of :mod:`compas_ccu.scene`
#: (the Viewer's class: :func:`viewer_object_class`).
CONTEXT_OBJECTS = {
    None: CCUSceneObject,
    "Rhino": RhinoCCUObject,
    "Grasshopper": GrasshopperCCUObject,
    "Notebook": NotebookCCUObject,
}


def frame_camera(camera, box, *, margin: float = 1.15) -> float:
    """Set a COMPAS Viewer camera on ``box`` (``[[xmin, ymin, zmin], [xmax, ymax, zmax]]``).

    The target becomes the centre of the box, the distance the one at which the box's bounding
    sphere fills the field of view (``camera.fov``, degrees) times ``margin``; the far clipping
    plane moves out if the box would reach past it. Only ``target``, ``distance``, ``fov``,
    ``far`` and ``scale`` of the camera are used (compas_viewer's ``Camera``). Returns the
    distance.

    >>> from types import SimpleNamespace
    >>> camera = SimpleNamespace(fov=90.0, far=1000.0, scale=1.0, target=None, distance=None)
    >>> round(frame_camera(camera, [[-1, -1, 0], [1, 1, 0]], margin=1.0), 6), camera.target
    (2.0, [0.0, 0.0, 0.0])
    """
    lo, hi = np.asarray(box, dtype=float)
    centre = (lo + hi) / 2.0
    radius = max(float(np.linalg.norm(hi - lo)) / 2.0, EXACT_RELATIVE)
    fov = float(getattr(camera, "fov", 45.0) or 45.0)
    distance = margin * radius / math.sin(math.radians(fov) / 2.0)
    camera.target = centre.tolist()
    camera.distance = distance
    scale = float(getattr(camera, "scale", 1.0) or 1.0)
    far = getattr(camera, "far", None)
    if far is not None and (distance + radius) > far * scale:
        camera.far = 2.0 * (distance + radius) / scale
    return distance


class _ViewerFraming:
    """Mixin of the COMPAS Viewer's object: ``init()`` (called by the viewer's renderer before
    it computes the view) also sets the camera on the structure."""

    def init(self, *args, **kwargs):
        result = super().init(*args, **kwargs)
        if self.zoom and self.draw_items:
            frame_camera(self.viewer.renderer.camera, self.bounding_box())
        return result


_VIEWER_CLASS: list = []


def _viewer_class(base: type) -> type:
    return type(
        "ViewerCCUObject",
        (_ViewerFraming, CCUSceneObject, base),
        {"__module__": __name__, "__doc__": viewer_object_class.__doc__},
    )


def viewer_object_class() -> type:
    """:class:`CCUSceneObject` in the COMPAS Viewer: ``ViewerCCUObject``.

    Built on first use, since it derives from compas_viewer's ``ViewerSceneObject`` (an
    optional dependency: ``pip install "compas_ccu[viewer]"``): the viewer's renderer needs its
    display settings on every scene object. It has no geometry of its own (no GL buffers); its
    children are the viewer's mesh / polyline / graph objects. Its ``init()`` sets the viewer's
    camera on the structure (:func:`frame_camera`; ``zoom=False``: it does not).

    Raises
    ------
    ImportError
        compas_viewer is not installed.
    """
    if not _VIEWER_CLASS:
        from compas_viewer.scene import ViewerSceneObject

        _VIEWER_CLASS.append(_viewer_class(ViewerSceneObject))
    return _VIEWER_CLASS[0]
