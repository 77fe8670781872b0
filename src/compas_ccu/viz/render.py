"""Draw a :class:`~compas_ccu.viz.scene.Scene` into a matplotlib axes.

matplotlib's own 3D axes sort polygons poorly and cannot keep an equal scale; here the scene is
projected by a :class:`Camera` (orthographic or perspective) and painted back to front as one
2D ``PolyCollection`` holding the quads and the crease / edge lines together, so lines are hidden
behind plates correctly. Faces are shaded by the angle between their normal and the light.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.strips.curvature import plate_curvature
from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE
from compas_ccu.viz import colors as C
from compas_ccu.viz.scene import scene_from_structure

__all__ = [
    "Camera",
    "VIEWS",
    "COLOR_MODES",
    "camera",
    "draw_scene",
    "value_range",
    "colour_scale",
    "SUBDIVISIONS",
    "add_colorbar",
    "projected_limits",
    "path_frames",
    "PathFrames",
]

COLOR_MODES = ("kind", "curvature", "alpha")


@dataclass(frozen=True)
class Camera:
    """A view of the scene.

    Parameters
    ----------
    azimuth, elevation : float
        Direction from the scene towards the eye, degrees (azimuth from +x in the xy plane,
        elevation above it).
    distance : float or None
        Eye distance in units of the scene size for a perspective view; None: orthographic.
    """

    azimuth: float = -60.0
    elevation: float = 28.0
    distance: float | None = 3.0

    def axes(self) -> np.ndarray:
        """(3, 3) rows: screen right, screen up, towards the eye."""
        az, el = math.radians(self.azimuth), math.radians(self.elevation)
        eye = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
        right = np.array([-math.sin(az), math.cos(az), 0.0])
        up = np.cross(eye, right)
        return np.array([right, up, eye])

    def project(self, points, centre, size: float) -> tuple:
        """Project points.

        Parameters
        ----------
        points : (..., 3) float
        centre : (3,) float
            The point the camera looks at.
        size : float
            Scene size (sets the eye distance of a perspective view).

        Returns
        -------
        xy : (..., 2) float
            Screen coordinates (metres at the centre's depth).
        depth : (...,) float
            Towards the eye: larger is nearer.
        """
        rel = np.asarray(points, dtype=float) - np.asarray(centre, dtype=float)
        screen = rel @ self.axes().T
        xy, depth = screen[..., :2], screen[..., 2]
        if self.distance is not None:
            eye = self.distance * size
            xy = xy * (eye / np.maximum(eye - depth, EXACT_RELATIVE * eye))[..., None]
        return xy, depth


VIEWS = {
    "perspective": Camera(-60.0, 28.0, 3.0),
    "plan": Camera(-90.0, 90.0, None),
    "elevation": Camera(-90.0, 0.0, None),
    "side": Camera(0.0, 0.0, None),
    "top": Camera(-90.0, 90.0, None),
    "front": Camera(-90.0, 0.0, None),
    "iso": Camera(-45.0, math.degrees(math.atan(1.0 / math.sqrt(2.0))), None),
}


def camera(view) -> Camera:
    """A :class:`Camera` from a view name or ``"azimuth,elevation"`` (degrees, orthographic).

    Names: ``perspective``, ``plan`` (= ``top``), ``elevation`` (= ``front``), ``side``,
    ``iso`` (the isometric view, orthographic, elevation 35.26°).

    Examples
    --------
    >>> camera("iso").azimuth, round(camera("iso").elevation, 2), camera("iso").distance
    (-45.0, 35.26, None)
    >>> camera("30,20")
    Camera(azimuth=30.0, elevation=20.0, distance=None)
    """
    if isinstance(view, Camera):
        return view
    if isinstance(view, str) and "," in view:
        try:
            az, el = (float(x) for x in view.split(","))
        except ValueError:
            raise OptionError(
                f"a view 'azimuth,elevation' needs two numbers of degrees, got {view!r}"
            ) from None
        if not (math.isfinite(az) and math.isfinite(el) and -90.0 <= el <= 90.0):
            raise OptionError(f"view elevation must be within -90 to 90 degrees, got {view!r}")
        return Camera(az, el, None)
    try:
        return VIEWS[view]
    except (KeyError, TypeError):
        raise OptionError(
            f"unknown view {view!r}; expected one of {sorted(VIEWS)} or 'azimuth,elevation'"
        ) from None


def _values_per(values, scene) -> tuple:
    """``("vertex", (p, v))`` or ``("face", (p, n))`` values of a colouring array."""
    p, n = scene.faces.shape[:2]
    values = np.asarray(values, dtype=float)
    if values.shape == (p, n):
        return "face", values
    if values.shape == scene.vertices.shape[:2]:
        return "vertex", values
    raise OptionError(
        f"per-vertex values must have shape {scene.vertices.shape[:2]} (plates, vertices) or "
        f"{(p, n)} (plates, faces), got {values.shape}"
    )


def _face_values(values: np.ndarray, scene) -> np.ndarray:
    """(p, n) values: per-face values as given, per-vertex values averaged over the corners."""
    where, values = _values_per(values, scene)
    if where == "face":
        return values
    p = values.shape[0]
    return values[np.arange(p)[:, None, None], scene.faces].mean(axis=-1)


#: Most sub-quads per quad where a per-vertex field is painted (bilinear, like Gouraud
#: shading); they go to the quad direction(s) along which the field changes.
SUBDIVISIONS = 16
_COLOUR_STEP = 1.0 / 8.0  # largest change of a field within one sub-quad, of its colour range


def _divisions(corner_values: np.ndarray, span: float) -> tuple:
    """Sub-quads along the two quad directions (corner 0 -> 1, corner 0 -> 3): enough that no
    sub-quad spans more than 1/8 of the colour range, at most :data:`SUBDIVISIONS` in all.

    Examples
    --------
    >>> _divisions(np.array([[0.0, 0.0, 1.0, 1.0]]), 1.0)  # changes along 0 -> 3 only
    (1, 8)
    >>> _divisions(np.array([[0.0, 1.0, 2.0, 1.0]]), 1.0)
    (4, 4)
    """
    v = np.asarray(corner_values, dtype=float)
    step = _COLOUR_STEP * max(span, DIVISION_FLOOR)
    along_u = np.nanmax(np.abs(np.r_[v[:, 1] - v[:, 0], v[:, 2] - v[:, 3]]), initial=0.0)
    along_v = np.nanmax(np.abs(np.r_[v[:, 3] - v[:, 0], v[:, 2] - v[:, 1]]), initial=0.0)
    su, sv = (max(1, math.ceil(x / step - 1e-9)) for x in (along_u, along_v))
    while su * sv > SUBDIVISIONS:  # share the budget in proportion
        su, sv = (max(1, x - 1) if x >= y else x for x, y in ((su, sv), (sv, su)))
    return int(su), int(sv)


def _subdivide(quads: np.ndarray, corner_values: np.ndarray, su: int, sv: int) -> tuple:
    """Split quads into ``su x sv`` bilinear sub-quads with the field at their centres.

    Parameters
    ----------
    quads : (q, 4, 3) float
    corner_values : (q, 4) float
    su, sv : int
        Sub-quads along the quad directions corner 0 -> 1 and corner 0 -> 3.

    Returns
    -------
    sub : (q, su * sv, 4, 3) float
    values : (q, su * sv) float
        The bilinear interpolation of the corner values at every sub-quad's centre.
    """
    tu, tv = np.arange(su + 1) / su, np.arange(sv + 1) / sv
    i, j = np.meshgrid(np.arange(su), np.arange(sv), indexing="ij")
    i, j = i.ravel(), j.ravel()
    # (su*sv, 4) parameters (u, v) of the sub-quad corners, counter-clockwise like the quad
    u = np.stack([tu[i], tu[i + 1], tu[i + 1], tu[i]], axis=1)
    v = np.stack([tv[j], tv[j], tv[j + 1], tv[j + 1]], axis=1)

    def weights(u, v):  # bilinear weights of the quad corners 0, 1, 2, 3
        return np.stack([(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v], axis=-1)

    sub = np.einsum("kcq,fqd->fkcd", weights(u, v), quads)
    centre = weights((tu[i] + tu[i + 1]) / 2, (tv[j] + tv[j + 1]) / 2)  # (su*sv, 4)
    return sub, corner_values @ centre.T


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
    face_polys, face_rgb, normals, mappable, crease_values = _colouring(
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


def _colouring(scene, color_by, cmap, vmin, vmax, quads, normals) -> tuple:
    """The painted faces and their colours by ``color_by`` (see :func:`draw_scene`).

    Returns
    -------
    face_polys : (f, 4, 3) float
        The quads, or their sub-quads where a per-vertex field is painted.
    face_rgb : (f, 3) float
        Their colours (not yet shaded).
    normals : (f, 3) float
        Their normals.
    mappable : matplotlib.cm.ScalarMappable or None
    crease_values : list of (k_i,) float or None
        The value of every crease segment (``color_by="alpha"``).
    """
    p, n = scene.faces.shape[:2]
    mappable = None
    face_rgb = np.repeat(np.array([C.hex_to_rgb(C.plate_tone(i)) for i in range(p)]), n, axis=0)
    crease_values = None
    values = None  # (q,) per face, or (q, 4) per quad corner (painted on sub-quads)
    if isinstance(color_by, str):
        if color_by not in COLOR_MODES:
            raise OptionError(
                f"color_by must be one of {COLOR_MODES} or an array, got {color_by!r}"
            )
        if color_by == "curvature":
            corner = np.abs(plate_curvature(scene.vertices))
            values = corner[np.arange(p)[:, None, None], scene.faces].reshape(-1, 4)
            cmap = cmap or C.SEQUENTIAL_CMAP
        elif color_by == "alpha":
            crease_values = [0.5 * (a[1:] + a[:-1]) for a in scene.crease_alpha]
            cmap = cmap or C.ANGLE_CMAP
    else:
        where, given = _values_per(color_by, scene)
        if where == "vertex":
            values = given[np.arange(p)[:, None, None], scene.faces].reshape(-1, 4)
        else:
            values = given.ravel()
        cmap = cmap or C.SEQUENTIAL_CMAP
    face_polys = quads
    if values is not None:
        # the colour range is that of the values themselves (vertex values, not face means)
        mappable = _mappable(values, vmin, vmax, cmap)
        if values.ndim == 2:
            su, sv = _divisions(values, mappable.norm.vmax - mappable.norm.vmin)
            face_polys, sub_values = _subdivide(quads, values, su, sv)
            face_rgb = mappable.to_rgba(sub_values.ravel())[:, :3]
            normals = np.repeat(normals, su * sv, axis=0)
            face_polys = face_polys.reshape(-1, 4, 3)
        else:
            face_rgb = mappable.to_rgba(values)[:, :3]
    if crease_values is not None and crease_values:
        mappable = _mappable(np.concatenate(crease_values), vmin, vmax, cmap)
    return face_polys, face_rgb, normals, mappable, crease_values


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
_DEPTH_TIE = 1e-9


def _mappable(values, vmin, vmax, cmap):
    """A ScalarMappable over :func:`colour_scale`; a constant field is marked ``constant``."""
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    lo, hi, constant = colour_scale(values, vmin, vmax)
    mappable = ScalarMappable(norm=Normalize(lo, hi), cmap=cmap)
    mappable.constant = constant
    return mappable


def colour_scale(values, vmin=None, vmax=None) -> tuple:
    """Colour range of ``values`` and, for a constant field, its value.

    A field that is constant (to rounding: a spread below 1e-9 of its size) is not painted
    as a gradient of rounding noise, nor in the middle of a degenerate scale (where a constant
    α of 30° would look like the anticlastic pink): its scale is widened to run from 0 to the
    value (a zero field: -1 to 1), and the colour bar says "constant".

    Parameters
    ----------
    values : array_like of float
    vmin, vmax : float, optional
        Fixed ends (kept as given).

    Returns
    -------
    lo, hi : float
    constant : float or None
        The value of a constant field, else None.

    Examples
    --------
    >>> colour_scale([30.0, 30.0, 30.0])
    (0.0, 30.0, 30.0)
    >>> colour_scale([0.390, 0.466])
    (0.39, 0.466, None)
    >>> colour_scale([30.0, 30.0], vmin=20.0)
    (20.0, 30.0, 30.0)
    """
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    dlo = float(finite.min()) if finite.size else 0.0
    dhi = float(finite.max()) if finite.size else 1.0
    constant = None
    if finite.size and dhi - dlo <= EXACT_RELATIVE * max(abs(dhi), abs(dlo), DIVISION_FLOOR):
        constant = 0.5 * (dlo + dhi)
    lo = vmin if vmin is not None else dlo
    hi = vmax if vmax is not None else dhi
    if hi < lo:
        raise OptionError(f"the colour range must have vmin < vmax, got {lo!r} to {hi!r}")
    if hi - lo <= EXACT_RELATIVE * max(abs(hi), abs(lo), DIVISION_FLOOR):
        mid = 0.5 * (lo + hi)
        lo, hi = (0.0, mid) if mid > 0.0 else (mid, 0.0) if mid < 0.0 else (-1.0, 1.0)
    return lo, hi, constant


def value_range(values, vmin=None, vmax=None) -> tuple:
    """``(lo, hi)`` of :func:`colour_scale`: a constant field runs from 0 to its value."""
    return colour_scale(values, vmin, vmax)[:2]


def add_colorbar(fig, mappable, ax, label: str):
    """A colour bar beside ``ax``, with plain tick labels (no offset notation); the label of a
    constant field (``mappable.constant``, see :func:`colour_scale`) ends with
    ``constant = <value>`` and a tick marks the value."""
    from matplotlib.ticker import ScalarFormatter

    bar = fig.colorbar(mappable, ax=ax, shrink=0.7, pad=0.02)
    fmt = ScalarFormatter(useOffset=False)
    bar.formatter = fmt
    bar.update_ticks()
    constant = getattr(mappable, "constant", None)
    if constant is not None:
        label = f"{label}: constant = {constant:.4g}"
        lo, hi = mappable.norm.vmin, mappable.norm.vmax
        bar.set_ticks(sorted({lo, constant, hi}))
    bar.set_label(label)
    return bar


@dataclass
class PathFrames:
    """The grounded states of a deployment path, framed by one camera at one scale."""

    alphas: np.ndarray
    structures: list
    scenes: list
    centre: np.ndarray
    size: float
    limits: tuple


def path_frames(model, count, alpha=None, view="perspective", *, what="count") -> PathFrames:
    """``count`` states from α = 0 to ``alpha`` (default: the design α), framed together.

    Raises OptionError naming ``what`` for a count below 2 and for ``alpha <= 0``.
    """

    if int(count) != count or count < 2:
        raise OptionError(f"{what} must be an integer >= 2, got {count!r}")
    target = model.alpha_design if alpha is None else float(alpha)
    if not target > 0.0:
        raise OptionError(f"alpha must be > 0 degrees, got {target!r}")
    alphas = np.linspace(0.0, target, int(count))
    structures = model.path(alphas)
    scenes = [scene_from_structure(s, ground=True) for s in structures]
    pts = np.concatenate([s.vertices.reshape(-1, 3) for s in scenes])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    size = float(np.linalg.norm(np.ptp(pts, axis=0)))
    limits = projected_limits(scenes, view, centre=centre, size=size)
    return PathFrames(alphas, structures, scenes, centre, size, limits)


def projected_limits(scenes, view="perspective", *, centre=None, size=None, pad=0.04) -> tuple:
    """Common axes limits ``(xmin, xmax, ymin, ymax)`` of several scenes in one view."""
    cam = camera(view)
    pts = np.concatenate([s.vertices.reshape(-1, 3) for s in scenes])
    if centre is None:
        centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    if size is None:
        size = float(np.linalg.norm(np.ptp(pts, axis=0))) or 1.0
    xy, _ = cam.project(pts, centre, size)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    m = pad * max(hi - lo)
    return (lo[0] - m, hi[0] + m, lo[1] - m, hi[1] + m)
