"""3D views of a structure: perspective, plan, elevation and side, coloured by a chosen field."""

from __future__ import annotations

from compas_ccu.errors import OptionError
from compas_ccu.viz import colors as C
from compas_ccu.viz.render import add_colorbar, draw_scene
from compas_ccu.viz.scene import scene_from_structure

__all__ = ["plot_views", "kind_legend_handles"]

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
    mappable = None
    for ax, view in zip(axes, views):
        mappable = draw_scene(ax, scene, view, color_by=color_by, cmap=cmap, vmin=vmin, vmax=vmax)
        ax.set_title(str(view), fontsize=10, color="#444444")
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
    fig.suptitle(title, fontsize=12)
    return fig
