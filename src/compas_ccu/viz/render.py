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
}


def camera(view) -> Camera:
    """A :class:`Camera` from a view name (``perspective``, ``plan``, ``elevation``, ``side``)."""
    if isinstance(view, Camera):
        return view
    try:
        return VIEWS[view]
    except KeyError:
        raise OptionError(f"unknown view {view!r}; expected one of {sorted(VIEWS)}") from None


def _face_values(values: np.ndarray, scene) -> np.ndarray:
    p, n = scene.faces.shape[:2]
    values = np.asarray(values, dtype=float)
    if values.shape == (p, n):
        return values
    if values.shape == scene.vertices.shape[:2]:
        return values[np.arange(p)[:, None, None], scene.faces].mean(axis=-1)
    raise OptionError(
        f"per-vertex values must have shape {scene.vertices.shape[:2]} (plates, vertices) or "
        f"{(p, n)} (plates, faces), got {values.shape}"
    )


def _shade(rgb: np.ndarray, normals: np.ndarray, axes: np.ndarray) -> np.ndarray:
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
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize, to_rgba

    cam = camera(view)
    bounds = scene.bounds()
    if centre is None:
        centre = bounds.mean(axis=0)
    if size is None:
        size = float(np.linalg.norm(bounds[1] - bounds[0])) or 1.0
    axes = cam.axes()
    p, n = scene.faces.shape[:2]
    quads = scene.quads.reshape(-1, 4, 3)
    normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), DIVISION_FLOOR)

    mappable = None
    face_rgb = np.repeat(np.array([C.hex_to_rgb(C.plate_tone(i)) for i in range(p)]), n, axis=0)
    crease_values = None
    if isinstance(color_by, str):
        if color_by not in COLOR_MODES:
            raise OptionError(
                f"color_by must be one of {COLOR_MODES} or an array, got {color_by!r}"
            )
        if color_by == "curvature":
            values = _face_values(np.abs(plate_curvature(scene.vertices)), scene)
            cmap = cmap or C.SEQUENTIAL_CMAP
        elif color_by == "alpha":
            crease_values = [0.5 * (a[1:] + a[:-1]) for a in scene.crease_alpha]
            values = None
            cmap = cmap or C.ANGLE_CMAP
        else:
            values = None
    else:
        values = _face_values(color_by, scene).ravel()
        cmap = cmap or C.SEQUENTIAL_CMAP
    if values is not None:
        values = np.asarray(values, dtype=float).ravel()
        mappable = ScalarMappable(norm=Normalize(*value_range(values, vmin, vmax)), cmap=cmap)
        face_rgb = mappable.to_rgba(values)[:, :3]
    if crease_values is not None and crease_values:
        allv = np.concatenate(crease_values)
        mappable = ScalarMappable(norm=Normalize(*value_range(allv, vmin, vmax)), cmap=cmap)
    face_rgb = _shade(face_rgb, normals, axes)

    xy, depth = cam.project(quads, centre, size)
    polys = [*xy]
    order_depth = [depth.mean(axis=1)]
    face_colors = np.c_[face_rgb, np.ones(len(face_rgb))]
    facecolors = [*face_colors]
    edgecolors = [to_rgba(C.EDGE_COLOR, 0.55)] * len(xy)
    widths = [edge_width] * len(xy)

    # crease lines drawn as 2-point polygons in the same depth order, nudged towards the eye by
    # half a quad so they win against the two plates they join
    bias = 0.3 * float(np.median(np.linalg.norm(quads[:, 2] - quads[:, 0], axis=1)))
    for ci, c in enumerate(scene.creases):
        seg = np.stack([c["points"][:-1], c["points"][1:]], axis=1)
        sxy, sd = cam.project(seg, centre, size)
        polys.extend(sxy)
        order_depth.append(sd.mean(axis=1) + bias)
        if crease_values is not None:
            cols = mappable.to_rgba(crease_values[ci])
        else:
            cols = np.tile(to_rgba(C.KIND_COLORS.get(c["kind"], C.EDGE_COLOR)), (len(seg), 1))
        facecolors.extend([(0, 0, 0, 0)] * len(seg))
        edgecolors.extend(cols)
        widths.extend([crease_width] * len(seg))
    if rulings:
        seg = scene.rulings.reshape(-1, 2, 3)
        sxy, sd = cam.project(seg, centre, size)
        polys.extend(sxy)
        order_depth.append(sd.mean(axis=1) + 0.25 * bias)
        facecolors.extend([(0, 0, 0, 0)] * len(seg))
        edgecolors.extend([to_rgba(C.RULING_COLOR)] * len(seg))
        widths.extend([0.4] * len(seg))

    order = np.argsort(np.concatenate(order_depth), kind="stable")
    collection = PolyCollection(
        [polys[i] for i in order],
        facecolors=np.asarray(facecolors)[order],
        edgecolors=np.asarray(edgecolors)[order],
        linewidths=np.asarray(widths)[order],
        closed=True,
        joinstyle="round",
        capstyle="round",
    )
    ax.add_collection(collection)
    if limits is None:
        allxy = xy.reshape(-1, 2)
        lo, hi = allxy.min(axis=0), allxy.max(axis=0)
        pad = 0.04 * max(hi - lo)
        limits = (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad)
    ax.set_xlim(limits[0], limits[1])
    ax.set_ylim(limits[2], limits[3])
    ax.set_aspect("equal")
    ax.set_axis_off()
    return mappable


def value_range(values, vmin=None, vmax=None) -> tuple:
    """Colour range of ``values``; a constant field (to rounding) gets a ±1 % range around it,
    so that rounding noise is not painted as a gradient."""
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    lo = vmin if vmin is not None else (float(finite.min()) if finite.size else 0.0)
    hi = vmax if vmax is not None else (float(finite.max()) if finite.size else 1.0)
    if hi - lo <= EXACT_RELATIVE * max(abs(hi), abs(lo), DIVISION_FLOOR):
        mid = 0.5 * (lo + hi)
        pad = 0.01 * abs(mid) or 1.0
        lo, hi = mid - pad, mid + pad
    return lo, hi


def add_colorbar(fig, mappable, ax, label: str):
    """A colour bar beside ``ax``, with plain tick labels (no offset notation)."""
    from matplotlib.ticker import ScalarFormatter

    bar = fig.colorbar(mappable, ax=ax, shrink=0.7, pad=0.02)
    fmt = ScalarFormatter(useOffset=False)
    bar.formatter = fmt
    bar.update_ticks()
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
