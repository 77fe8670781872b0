"""3D views of a structure: perspective, plan, elevation and side, coloured by a chosen field."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.key_figures import figure, state_figures
from compas_ccu.tolerances import DIVISION_FLOOR
from compas_ccu.viz import colors as C
from compas_ccu.viz.camera import camera
from compas_ccu.viz.colour_scale import add_colorbar
from compas_ccu.viz.render import draw_scene
from compas_ccu.viz.scene import scene_from_structure

__all__ = [
    "plot_views",
    "kind_legend_handles",
    "dimension_points",
    "DimensionPoints",
    "readout",
    "DIMENSION_COLOR",
]

DIMENSION_COLOR = "#3a3a3a"


def readout(figures: dict, names=("crease_span", "crease_rise", "plate_length")) -> str:
    """``span 2.50 m · rise 1.00 m · plate length 2.72 m``: key figures (of
    :func:`compas_ccu.key_figures.state_figures`) as one line, units from their definitions.

    Examples
    --------
    >>> readout({"crease_span": 2.5, "crease_rise": 1.0, "plate_length": 2.7231})
    'span 2.50 m · rise 1.00 m · plate length 2.72 m'
    """
    words = {"crease_span": "span", "crease_rise": "rise", "plate_length": "plate length"}
    parts = []
    for name in names:
        unit = figure(name).unit
        parts.append(f"{words.get(name, name)} {figures[name]:.2f}{' ' + unit if unit else ''}")
    return " · ".join(parts)


@dataclass(frozen=True)
class DimensionPoints:
    """World points of the span and rise dimensions of a state (:func:`dimension_points`), m.

    Attributes
    ----------
    span : (2, 3) float
        The chord ends of the leading crease.
    rise : (2, 3) float
        Its crown and the crown's foot on the chord.
    """

    span: np.ndarray
    rise: np.ndarray


def dimension_points(vertices, segments: int) -> DimensionPoints:
    """World points of the span and rise dimensions: the leading crease (the near boundary of
    the first plate, as the key figures measure it).

    Parameters
    ----------
    vertices : (p, v, 3) float
        Plate vertices of a state.
    segments : int

    Returns
    -------
    DimensionPoints
        ``span``: (2, 3) the chord ends; ``rise``: (2, 3) the crown and its foot on the chord.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> s = load_model("examples/vault.toml").deploy()
    >>> d = dimension_points(s.deployed, 64)
    >>> [round(float(np.linalg.norm(a - b)), 6) for a, b in (d.span, d.rise)]
    [2.5, 1.0]
    """
    pts = np.asarray(vertices, dtype=float)[0, : segments + 1]
    a, b = pts[0], pts[-1]
    chord = b - a
    t = (pts - a) @ chord / max(float(chord @ chord), DIVISION_FLOOR)
    foot = a + t[:, None] * chord
    k = int(np.argmax(np.linalg.norm(pts - foot, axis=1)))
    return DimensionPoints(span=np.array([a, b]), rise=np.array([pts[k], foot[k]]))


def _draw_dimensions(ax, points: DimensionPoints, figures: dict, view, centre, size) -> bool:
    """Span and rise dimension lines (arrows both ends, the value beside) in a 2D view that
    shows both in true length (an elevation); False if the view does not."""
    cam = camera(view)
    world = (points.span, points.rise)
    xy = [cam.project(v, centre, size)[0] for v in world]
    for pts, flat in zip(world, xy):
        true = float(np.linalg.norm(pts[1] - pts[0]))
        if float(np.linalg.norm(flat[1] - flat[0])) < 0.98 * true:
            return False
    (a, b), (crown, foot) = xy
    down = foot - crown
    down /= max(float(np.linalg.norm(down)), DIVISION_FLOOR)
    off = 0.07 * size * down  # the span line below the feet, away from the crown
    style = {"arrowstyle": "<|-|>", "color": DIMENSION_COLOR, "lw": 0.9, "shrinkA": 0, "shrinkB": 0}
    thin = {"color": DIMENSION_COLOR, "lw": 0.5, "zorder": 5}
    text = {"fontsize": 8, "color": DIMENSION_COLOR, "zorder": 6}
    box = {"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.85}
    for end in (a, b):  # extension lines
        ax.plot(*np.c_[end + 0.15 * off, end + 1.2 * off], **thin)
    ax.annotate("", xy=b + off, xytext=a + off, arrowprops=style, zorder=5)
    span = f"span {figures['crease_span']:.2f} {figure('crease_span').unit}"
    ax.text(*(0.5 * (a + b) + 1.1 * off), span, ha="center", va="top", bbox=box, **text)
    ax.annotate("", xy=foot, xytext=crown, arrowprops=style, zorder=5)
    rise = f"rise {figures['crease_rise']:.2f} {figure('crease_rise').unit}"
    ax.text(*(0.5 * (crown + foot)), " " + rise, ha="left", va="center", bbox=box, **text)
    lo = np.minimum(a, b) + 1.6 * off
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    ax.set_xlim(min(x0, lo[0]), x1)
    ax.set_ylim(min(y0, lo[1]), y1)
    return True


_LABELS = {
    "curvature": "plate bending curvature |κ| (1/m)",
    "alpha": "reflection angle α along the creases (°)",
}


def kind_legend_handles(kinds) -> list:
    """Legend handles for the crease kinds present, in a fixed order."""
    from matplotlib.lines import Line2D

    order = [k for k in C.KIND_COLORS if k in set(kinds)]
    return [Line2D([], [], color=C.KIND_COLORS[k], lw=2.5, label=C.KIND_LABELS[k]) for k in order]


def plot_views(
    structure,
    *,
    color_by="kind",
    views=("perspective", "plan", "elevation", "side"),
    label: str | None = None,
    cmap=None,
    vmin=None,
    vmax=None,
    title: str | None = None,
    ground: bool = True,
    figsize=(12.0, 7.0),
    dimensions: bool = True,
):
    """The structure seen from several sides.

    Parameters
    ----------
    structure : compas_ccu.structure.Structure
    color_by : {"kind", "curvature", "alpha"} or (p, v) / (p, n) float
        See :func:`compas_ccu.viz.render.draw_scene`; an array is a per-vertex (or per-face)
        value such as a stress, shown with ``label`` on the colour bar.
    views : sequence of str
        The first is drawn large on the left, the others stacked on the right.
    title : str, optional
        Default: design name, α and the crease kinds.
    ground : bool
        Put the lowest point on z = 0.
    dimensions : bool
        Span and rise dimension lines on the orthographic views that show them, and a read-out
        of span, rise and the longest plate under the title (key figures of the state).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> s = load_model("examples/vault.toml").deploy()
    >>> fig = plot_views(s, color_by="curvature")
    >>> len(fig.axes)  # four views and a colour bar
    5
    """
    from matplotlib.figure import Figure

    views = list(views)
    if not views:
        raise OptionError("views must name at least one view")
    scene = scene_from_structure(structure, ground=ground)
    fig = Figure(figsize=figsize, layout="constrained")
    if len(views) == 1:
        axes = [fig.add_subplot(1, 1, 1)]
    else:
        grid = fig.add_gridspec(len(views) - 1, 2, width_ratios=[1.9, 1.0])
        axes = [fig.add_subplot(grid[:, 0])]
        axes += [fig.add_subplot(grid[i, 1]) for i in range(len(views) - 1)]
    bounds = scene.bounds()
    centre, size = bounds.mean(axis=0), float(np.linalg.norm(bounds[1] - bounds[0])) or 1.0
    figures = state_figures(structure)
    points = dimension_points(scene.vertices, scene.segments)
    mappable = None
    for ax, view in zip(axes, views):
        mappable = draw_scene(
            ax,
            scene,
            view,
            color_by=color_by,
            cmap=cmap,
            vmin=vmin,
            vmax=vmax,
            centre=centre,
            size=size,
        )
        ax.set_title(str(view), fontsize=10, color="#444444")
        if dimensions and camera(view).distance is None:
            _draw_dimensions(ax, points, figures, view, centre, size)
    if mappable is not None:
        text = label or (_LABELS.get(color_by) if isinstance(color_by, str) else None) or "value"
        add_colorbar(fig, mappable, axes, text)
    kinds = [c["kind"] for c in structure.creases]
    if kinds and not (isinstance(color_by, str) and color_by == "alpha"):
        axes[0].legend(
            handles=kind_legend_handles(kinds), loc="lower left", fontsize=8, frameon=False
        )
    if title is None:
        parts = ", ".join(f"{v} {k}" for k, v in structure.crease_kind_counts().items())
        title = f"{structure.name}: α = {structure.alpha:g}°, {len(structure.plate_ids)} plates" + (
            f", creases: {parts}" if parts else ""
        )
    if dimensions:
        title = f"{title}\n{readout(figures)}"
    fig.suptitle(title, fontsize=12)
    return fig
