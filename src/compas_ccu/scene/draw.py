"""What a CCU structure looks like in any COMPAS context: plates, creases, rulings, solids.

The scene objects of every context (no context, the COMPAS Viewer, notebooks, Rhino,
Grasshopper) draw the same :class:`DrawItem` list, built here from COMPAS data
(:class:`compas.datastructures.Mesh` for plates and solids, :class:`compas.geometry.Polyline`
for creases, one :class:`compas.datastructures.Graph` of line segments for the rulings of each
plate) with the colours of :mod:`compas_ccu.viz.colors`: creases in the colour of their kind,
plates in a light tint of the kind of their creases, rulings in the ruling colour. One graph per
plate rather than one line per ruling keeps the scenes light: a context draws a graph's edges as
one line-segments buffer (compas_viewer, notebooks) or as one group of lines (Rhino). Nothing
here needs a window or a host application.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from compas.colors import Color
from compas.data import Data
from compas.datastructures import Graph, Mesh
from compas.geometry import Line, Polyline, Scale

from compas_ccu.design import Design
from compas_ccu.errors import OptionError
from compas_ccu.fabrication.meshes import solid_mesh
from compas_ccu.model import CCUModel
from compas_ccu.structure import STATES, Structure
from compas_ccu.thickness import ThickModel
from compas_ccu.viz.colors import KIND_COLORS, PLATE_TONES, RULING_COLOR, hex_to_rgb
from compas_ccu.viz.scene import scene_from_structure

__all__ = [
    "DrawItem",
    "DRAWABLE_TYPES",
    "PLATE_TINT",
    "PLATE_COLORS",
    "draw_items",
    "bounding_box",
    "ruling_graph",
    "ruling_segments",
    "ruling_lines",
    "item_structure",
    "plate_kinds",
    "color",
    "tint",
]

#: The data types a CCU scene object draws.
DRAWABLE_TYPES = (Structure, CCUModel, Design, ThickModel)

#: The plate colourings of :func:`draw_items`.
PLATE_COLORS = ("kind", "tone")

#: How far plate faces are lightened towards white from their crease kind colour (0: the kind
#: colour itself, 1: white), so that the crease lines stay visible on the plates.
PLATE_TINT = 0.55


@dataclass
class DrawItem:
    """One drawable piece of a CCU structure.

    Attributes
    ----------
    role : {"plate", "crease", "ruling", "solid"}
    name : str
        ``plate_<id>``, ``crease_<id>``, ``rulings_<plate id>`` or ``solid_<id>``.
    geometry : compas.data.Data
        A :class:`~compas.datastructures.Mesh` (plates, solids), a
        :class:`~compas.geometry.Polyline` (creases) or a :class:`~compas.datastructures.Graph`
        (the rulings of one plate: one edge per ruling, see :func:`ruling_graph`).
    color : compas.colors.Color
    attributes : dict
        ``plate`` (id) for plates, rulings and solids; ``crease`` (id) and ``kind`` for creases;
        ``kind`` for plates (the kind of their creases, ``None`` for a plate without creases);
        ``count`` (number of rulings) for rulings.
    """

    role: str
    name: str
    geometry: Data
    color: Color
    attributes: dict = field(default_factory=dict)


def color(hex_color: str) -> Color:
    """A :class:`compas.colors.Color` from ``'#rrggbb'``."""
    return Color(*hex_to_rgb(hex_color))


def tint(hex_color: str, amount: float = PLATE_TINT) -> Color:
    """``hex_color`` lightened towards white by ``amount`` (0 .. 1).

    >>> tint("#000000", 0.5).rgb
    (0.5, 0.5, 0.5)
    """
    if not 0.0 <= amount <= 1.0:
        raise OptionError(f"tint amount must be in [0, 1], got {amount!r}")
    r, g, b = hex_to_rgb(hex_color)
    return Color(*(c + (1.0 - c) * amount for c in (r, g, b)))


def ruling_graph(segments, name: str = "rulings") -> Graph:
    """The rulings of one plate as one :class:`~compas.datastructures.Graph`.

    Node ``2 j`` and ``2 j + 1`` are the two ends of ruling ``j`` (attributes ``x, y, z``),
    edge ``(2 j, 2 j + 1)`` is the ruling: every COMPAS context draws a graph, and draws its
    edges as one object (a line-segments buffer in compas_viewer and notebooks).

    >>> g = ruling_graph([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]])
    >>> g.number_of_nodes(), list(g.edges())
    (4, [(0, 1), (2, 3)])
    """
    ends = np.asarray(segments, dtype=float).reshape(-1, 3)
    graph = Graph(name=name)
    for key, (x, y, z) in enumerate(ends.tolist()):
        graph.add_node(key, x=x, y=y, z=z)
    for j in range(len(ends) // 2):
        graph.add_edge(2 * j, 2 * j + 1)
    return graph


def ruling_segments(graph: Graph) -> np.ndarray:
    """``(m, 2, 3)`` end points of the edges of a rulings graph (:func:`ruling_graph`)."""
    xyz = {key: graph.node_attributes(key, "xyz") for key in graph.nodes()}
    return np.array([[xyz[u], xyz[v]] for u, v in graph.edges()], dtype=float).reshape(-1, 2, 3)


def ruling_lines(graph: Graph) -> list:
    """The edges of a rulings graph as :class:`~compas.geometry.Line` s, in ruling order."""
    return [Line(a, b) for a, b in ruling_segments(graph).tolist()]


def bounding_box(items) -> np.ndarray:
    """``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` of the geometry of :class:`DrawItem` s.

    >>> from compas_ccu.model import load_model
    >>> bounding_box(draw_items(load_model("examples/cone.toml"))).shape
    (2, 3)
    """
    points = []
    for piece in items:
        geometry = piece.geometry
        if isinstance(geometry, Mesh):
            points.extend(geometry.vertices_attributes("xyz"))
        elif isinstance(geometry, Graph):
            points.extend(geometry.nodes_attributes("xyz"))
        elif isinstance(geometry, Polyline):
            points.extend(list(p) for p in geometry.points)
        elif isinstance(geometry, Line):
            points.extend([list(geometry.start), list(geometry.end)])
    if not points:
        return np.zeros((2, 3))
    xyz = np.asarray(points, dtype=float)
    return np.array([xyz.min(axis=0), xyz.max(axis=0)])


def plate_kinds(structure: Structure) -> dict[int, str | None]:
    """``{plate id: kind}``: the kind of the creases of each plate.

    ``"mixed"`` when the creases of a plate differ in kind, ``None`` for a plate without
    creases (a single plate).
    """
    kinds: dict = {pid: set() for pid in structure.plate_ids}
    for c in structure.creases:
        for pid in c["plates"]:
            kinds[pid].add(c["kind"])
    return {
        pid: (None if not k else next(iter(k)) if len(k) == 1 else "mixed")
        for pid, k in kinds.items()
    }


def _model(item) -> CCUModel:
    if isinstance(item, ThickModel):
        return item.model
    if isinstance(item, Design):
        return CCUModel(item)
    return item


def item_structure(item, *, alpha: float | None = None) -> Structure:
    """The deployed :class:`Structure` of any drawable item.

    A :class:`Structure` is itself (``alpha`` must be None or its angle); a model, a design
    or a thick model are deployed to ``alpha`` (default: the design angle).

    Raises
    ------
    OptionError
        ``item`` is not drawable, or ``alpha`` differs from a structure's angle.
    """
    if not isinstance(item, DRAWABLE_TYPES):
        names = ", ".join(t.__name__ for t in DRAWABLE_TYPES)
        raise OptionError(f"cannot draw a {type(item).__name__}; expected one of {names}")
    if isinstance(item, Structure):
        if alpha is not None and float(alpha) != item.alpha:
            raise OptionError(
                f"a Structure is one state (alpha = {item.alpha:g} deg); got alpha={alpha!r}: "
                "add the model to draw another angle"
            )
        return item
    return _model(item).deploy(alpha)


def _solids(item, structure: Structure, thickness) -> list:
    if isinstance(item, Structure):
        raise OptionError(
            "thick solids need the model (a Structure does not carry the design): add the "
            f"CCUModel, its Design or a ThickModel; got thickness={thickness!r} for a Structure"
        )
    if isinstance(item, ThickModel) and thickness in (None, True):
        thick = item
    else:
        thick = ThickModel(_model(item), thickness=None if thickness is True else thickness)
    state = thick.deploy(structure.alpha)
    out = []
    ids = sorted(structure.plate_ids)  # ThickState: plates in id order
    for pid, solid in zip(ids, np.asarray(state.solids, dtype=float)):
        vertices, triangles = solid_mesh(solid[0], solid[1])
        mesh = Mesh.from_vertices_and_faces(vertices.tolist(), triangles.tolist())
        mesh.name = f"solid_{pid}"
        out.append((pid, mesh))
    return out


def draw_items(
    item,
    *,
    state: str = "deployed",
    alpha: float | None = None,
    plates: bool = True,
    creases: bool = True,
    rulings: bool = True,
    thickness=None,
    plate_colors: str = "kind",
    scale: float = 1.0,
) -> list:
    """The drawable pieces of a structure, a model, a design or a thick model.

    Parameters
    ----------
    item : Structure, CCUModel, Design or ThickModel
    state : {"deployed", "flat"}
        The deployed plates or the cut patterns (z = 0).
    alpha : float, optional
        Reference reflection angle, degrees (models, designs, thick models; default: the
        design angle).
    plates, creases, rulings : bool
        Which pieces to draw.
    thickness : True or float, optional
        Also draw the thick plates as closed solids (deployed state only): ``True`` for the
        design's thickness, or a thickness in m. A :class:`ThickModel` item always draws its
        solids (of its own thickness unless a number is given).
    plate_colors : {"kind", "tone"}
        ``"kind"``: a light tint of the kind colour of the plate's creases (``mixed`` when its
        two creases differ in kind); ``"tone"``: the two alternating plywood tones of the
        figures.
    scale : float
        Drawing units per metre (1000 for a Rhino document in millimetres).

    Returns
    -------
    list of DrawItem
        Plates, then creases, then rulings (one item per plate), then solids; plates in the
        structure's order.

    Raises
    ------
    OptionError
        An unknown state, an item that cannot be drawn, or solids asked of a Structure or of
        the flat state.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> items = draw_items(load_model("examples/cone.toml"))
    >>> [sum(i.role == r for i in items) for r in ("plate", "crease", "ruling")]
    [2, 1, 2]
    >>> rulings = next(i for i in items if i.role == "ruling")
    >>> rulings.name, rulings.geometry.number_of_edges(), rulings.attributes["count"]
    ('rulings_0', 49, 49)
    >>> crease = next(i for i in items if i.role == "crease")
    >>> crease.attributes["kind"], crease.color.hex
    ('synclastic', '#1f63d6')
    """
    if state not in STATES:
        raise OptionError(f"state must be one of {', '.join(map(repr, STATES))}, got {state!r}")
    if (thickness is not None or isinstance(item, ThickModel)) and state != "deployed":
        raise OptionError(f"thick solids are drawn in the deployed state only, got {state!r}")
    if plate_colors not in PLATE_COLORS:
        raise OptionError(
            f"plate_colors must be one of {', '.join(map(repr, PLATE_COLORS))}, got "
            f"{plate_colors!r}"
        )
    if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not scale > 0.0:
        raise OptionError(f"scale must be a number > 0 (drawing units per metre), got {scale!r}")
    structure = item_structure(item, alpha=alpha)
    scene = scene_from_structure(structure, state=state)
    kinds = plate_kinds(structure)
    out = []
    if plates:
        for i, mesh in enumerate(structure.to_meshes(state=state)):
            pid = structure.plate_ids[i]
            kind = kinds[pid]
            hex_color = PLATE_TONES[i % len(PLATE_TONES)] if kind is None else KIND_COLORS[kind]
            if plate_colors == "tone":
                hex_color = PLATE_TONES[i % len(PLATE_TONES)]
            face = color(hex_color) if kind is None or plate_colors == "tone" else tint(hex_color)
            out.append(DrawItem("plate", mesh.name, mesh, face, {"plate": pid, "kind": kind}))
    if creases:
        for c in scene.creases:
            line = Polyline(np.asarray(c["points"], dtype=float).tolist())
            name = f"crease_{c['id']}"
            line.name = name
            attributes = {"crease": c["id"], "kind": c["kind"], "plates": list(c["plates"])}
            out.append(DrawItem("crease", name, line, color(KIND_COLORS[c["kind"]]), attributes))
    if rulings:
        ruling_color = color(RULING_COLOR)
        for pid, segments in zip(scene.plate_ids, scene.rulings):
            name = f"rulings_{pid}"
            graph = ruling_graph(segments, name=name)
            attributes = {"plate": pid, "count": graph.number_of_edges()}
            out.append(DrawItem("ruling", name, graph, ruling_color, attributes))
    if thickness is not None or isinstance(item, ThickModel):
        for pid, mesh in _solids(item, structure, thickness):
            kind = kinds[pid]
            hex_color = PLATE_TONES[0] if kind is None else KIND_COLORS[kind]
            out.append(DrawItem("solid", mesh.name, mesh, tint(hex_color), {"plate": pid}))
    if scale != 1.0:
        factor = Scale.from_factors([float(scale)] * 3)
        for piece in out:
            piece.geometry.transform(factor)
    return out
