"""Draw a :class:`~compas_ccu.viz.scene.Scene` into a matplotlib axes.

matplotlib's own 3D axes sort polygons poorly and cannot keep an equal scale; here the scene is
projected by a :class:`~compas_ccu.viz.camera.Camera` (orthographic or perspective) and painted
back to front as one 2D ``PolyCollection`` holding the quads and the crease / edge lines
together, so lines are hidden behind plates correctly. Faces are shaded by the angle between
their normal and the light. The cameras are :mod:`compas_ccu.viz.camera`, the face colours
:mod:`compas_ccu.viz.colouring`, the colour range and bar :mod:`compas_ccu.viz.colour_scale`;
their public names are importable from here too.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE
from compas_ccu.viz import colors as C
from compas_ccu.viz.camera import VIEWS, Camera, PathFrames, camera, path_frames, projected_limits
from compas_ccu.viz.colour_scale import add_colorbar, colour_scale, value_range
from compas_ccu.viz.colouring import COLOR_MODES, SUBDIVISIONS, scene_colouring

__all__ = [
    "Camera",
    "VIEWS",
    "COLOR_MODES",
    "camera",
    "draw_scene",
    "shade",
    "value_range",
    "colour_scale",
    "SUBDIVISIONS",
    "RASTER_ABOVE",
    "add_colorbar",
    "projected_limits",
    "path_frames",
    "PathFrames",
]


def _crease_width(creases, cam, centre, size, limits, ax, width: float) -> float:
    """Crease line width (points) thin enough that distinct creases stay apart on screen.

    Creases that nearly coincide on screen (a deployment just begun, α of a few degrees) would
    merge into one band at the full ``width``: the width is cut to 60 % of the smallest screen
    distance between two distinct creases (the 20th percentile over the points of one, to the
    nearest point of the other), and never below 0.5 pt. Creases that coincide (the flat
    stack) do not count: they are one line.
    """
    if len(creases) < 2:
        return width
    pts = [cam.project(c["points"], centre, size)[0] for c in creases]
    xmin, xmax, ymin, ymax = limits
    bbox = ax.get_position()
    fig_w, fig_h = ax.figure.get_size_inches()
    per_metre = 72.0 * min(bbox.width * fig_w / (xmax - xmin), bbox.height * fig_h / (ymax - ymin))
    gaps = []
    for a in range(len(pts)):
        for b in range(a + 1, len(pts)):
            d = np.linalg.norm(pts[a][:, None] - pts[b][None], axis=-1).min(axis=1)
            gaps.append(float(np.percentile(d, 20)))
    gaps = np.array(gaps) * per_metre
    apart = gaps[gaps > 0.05]  # points; below this the creases coincide on screen
    if apart.size == 0:
        return width
    return float(np.clip(0.6 * apart.min(), 0.5, width))


def shade(rgb: np.ndarray, normals: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """(m, 3) colours ``rgb`` lit by a fixed light in the camera's ``axes`` (3, 3) on faces
    with unit ``normals`` (m, 3)."""
    light = 0.35 * axes[0] + 0.55 * axes[1] + 0.76 * axes[2]
    light /= np.linalg.norm(light)
    lambert = np.abs(normals @ light)
    return np.clip(rgb * (0.52 + 0.48 * lambert)[:, None], 0.0, 1.0)


def draw_scene(
    ax,
    scene,
    view="perspective",
    *,
    color_by="kind",
    cmap=None,
    vmin=None,
    vmax=None,
    centre=None,
    size=None,
    limits=None,
    rulings: bool = False,
    crease_width: float = 2.2,
    edge_width: float = 0.25,
):
    """Paint a scene into ``ax`` and return the colour mapping, if any.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    scene : Scene
    view : str or Camera
    color_by : {"kind", "curvature", "alpha"} or (p, v) / (p, n) float
        ``kind``: plates in plywood tones, creases coloured by kind; ``curvature``: plates by
        the magnitude of their bending curvature (1/m); ``alpha``: creases by the reflection
        angle at their vertices (degrees); an array: plates by a per-vertex or per-face value.
    cmap, vmin, vmax
        Colour map and range of a value colouring (defaults: the project's maps, data range).
    centre, size, limits
        Fix the camera target, the perspective scale and the axes limits
        ``(xmin, xmax, ymin, ymax)`` (to draw several states at one scale).
    rulings : bool
        Draw every ruling as a thin line (the quad edges already show them).

    Returns
    -------
    matplotlib.cm.ScalarMappable or None
        For a colour bar when plates or creases are coloured by a value.
    """
    cam = camera(view)
    bounds = scene.bounds()
    if centre is None:
        centre = bounds.mean(axis=0)
    if size is None:
        size = float(np.linalg.norm(bounds[1] - bounds[0])) or 1.0
    p, n = scene.faces.shape[:2]
    quads = scene.quads.reshape(-1, 4, 3)
    normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), DIVISION_FLOOR)
    face_polys, face_rgb, normals, mappable, crease_values = scene_colouring(
        scene, color_by, cmap, vmin, vmax, quads, normals
    )
    face_rgb = shade(face_rgb, normals, cam.axes())

    xy, depth = cam.project(quads, centre, size)
    limits = _set_limits(ax, xy, limits)
    paint = _Paint()
    _add_faces(paint, cam, centre, size, face_polys, face_rgb, xy, depth, n, edge_width)
    # crease lines drawn as 2-point polygons in the same depth order, nudged towards the eye by
    # half a quad so they win against the two plates they join; thinner where they crowd
    width = _crease_width(scene.creases, cam, centre, size, limits, ax, crease_width)
    bias = 0.3 * float(np.median(np.linalg.norm(quads[:, 2] - quads[:, 0], axis=1)))
    _add_creases(paint, scene, cam, centre, size, bias, width, crease_values, mappable)
    if rulings:
        _add_rulings(paint, scene, cam, centre, size, bias)
    ax.add_collection(paint.collection(size))
    return mappable


def _set_limits(ax, xy: np.ndarray, limits) -> tuple:
    """Set the axes limits (default: the projected quads ``xy``, padded), equal aspect, no
    axes; return the limits ``(xmin, xmax, ymin, ymax)``."""
    if limits is None:
        allxy = xy.reshape(-1, 2)
        lo, hi = allxy.min(axis=0), allxy.max(axis=0)
        pad = 0.04 * max(hi - lo)
        limits = (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad)
    ax.set_xlim(limits[0], limits[1])
    ax.set_ylim(limits[2], limits[3])
    ax.set_aspect("equal")
    ax.set_axis_off()
    return limits


class _Paint:
    """Every drawable of a scene: polygon, depth, plate (ties of coincident plates go to the
    higher plate, for whole plates: no stripes of one stacked plate through another), rank
    within a quad, face and edge colour, line width; painted back to front as one collection.
    """

    def __init__(self):
        self.polys, self.facecolors, self.edgecolors, self.widths = [], [], [], []
        self.depth, self.plate, self.rank = [], [], []

    def add(self, polys, depth, plate, rank, facecolors, edgecolors, widths) -> None:
        """Polygons (k, m, 2) with their depths, plates, ranks (k,) and colours and widths."""
        self.polys.extend(polys)
        self.depth.append(depth)
        self.plate.append(plate)
        self.rank.append(rank)
        self.facecolors.extend(facecolors)
        self.edgecolors.extend(edgecolors)
        self.widths.extend(widths)

    def collection(self, size: float):
        """The ``PolyCollection``, sorted by depth to a tolerance of the scene ``size``
        (coincident plates tie exactly), then plate, then rank."""
        from matplotlib.collections import PolyCollection

        tie = np.round(np.concatenate(self.depth) / (_DEPTH_TIE * size))
        order = np.lexsort((np.concatenate(self.rank), np.concatenate(self.plate), tie))
        collection = PolyCollection(
            [self.polys[i] for i in order],
            facecolors=np.asarray(self.facecolors)[order],
            edgecolors=np.asarray(self.edgecolors)[order],
            linewidths=np.asarray(self.widths)[order],
            closed=True,
            joinstyle="round",
            capstyle="round",
        )
        # a field painted on many sub-quads is embedded as one image in vector files (SVG,
        # PDF), at the figure's dpi: 5.9 MB of polygons for the vault's curvature; text stays
        # text
        collection.set_rasterized(len(self.polys) > RASTER_ABOVE)
        return collection


def _add_faces(paint, cam, centre, size, face_polys, face_rgb, xy, depth, n, edge_width):
    """The faces (quads or sub-quads) and, over sub-quads, the quad outlines."""
    from matplotlib.colors import to_rgba

    fxy, _ = cam.project(face_polys, centre, size)
    quad_depth = depth.mean(axis=1)
    plate_of = np.repeat(np.arange(len(xy) // n), n)
    sub = len(face_polys) // len(xy)  # sub-quads per quad
    faces = np.c_[face_rgb, np.ones(len(face_rgb))]
    depths, plates, ranks = np.repeat(quad_depth, sub), np.repeat(plate_of, sub), np.zeros(len(fxy))
    if sub > 1:  # sub-quads: edges in their own colour (no seams), the quad outline on top
        paint.add(fxy, depths, plates, ranks, faces, faces, [0.3] * len(fxy))
        outline = [to_rgba(C.EDGE_COLOR, 0.55)] * len(xy)
        clear = [(0, 0, 0, 0)] * len(xy)
        paint.add(
            xy, quad_depth, plate_of, np.ones(len(xy)), clear, outline, [edge_width] * len(xy)
        )
    else:
        edges = [to_rgba(C.EDGE_COLOR, 0.55)] * len(xy)
        paint.add(fxy, depths, plates, ranks, faces, edges, [edge_width] * len(xy))


def _add_creases(paint, scene, cam, centre, size, bias, width, crease_values, mappable):
    """Every crease as segments, by kind colour or by value (``crease_values``)."""
    from matplotlib.colors import to_rgba

    p = scene.faces.shape[0]
    for ci, c in enumerate(scene.creases):
        seg = np.stack([c["points"][:-1], c["points"][1:]], axis=1)
        sxy, sd = cam.project(seg, centre, size)
        if crease_values is not None:
            cols = mappable.to_rgba(crease_values[ci])
        else:
            cols = np.tile(to_rgba(C.KIND_COLORS.get(c["kind"], C.EDGE_COLOR)), (len(seg), 1))
        paint.add(
            sxy,
            sd.mean(axis=1) + bias,
            np.full(len(seg), p),
            np.full(len(seg), 2.0),
            [(0, 0, 0, 0)] * len(seg),
            cols,
            [width] * len(seg),
        )


def _add_rulings(paint, scene, cam, centre, size, bias):
    """Every ruling as a thin line."""
    from matplotlib.colors import to_rgba

    p = scene.faces.shape[0]
    seg = scene.rulings.reshape(-1, 2, 3)
    sxy, sd = cam.project(seg, centre, size)
    paint.add(
        sxy,
        sd.mean(axis=1) + 0.25 * bias,
        np.repeat(np.arange(p), scene.rulings.shape[1]),
        np.full(len(seg), 1.5),
        [(0, 0, 0, 0)] * len(seg),
        [to_rgba(C.RULING_COLOR)] * len(seg),
        [0.4] * len(seg),
    )


#: More polygons (quads, sub-quads and lines) than this in one view are rasterised in vector
#: files (:func:`draw_scene`).
RASTER_ABOVE = 6000

#: Depths closer than this fraction of the scene size are a tie (coincident, stacked plates).
_DEPTH_TIE = EXACT_RELATIVE
