"""The deployment sequence in one strip: flat-folded stack to the design state (paper Fig. 1)."""

from __future__ import annotations

from compas_ccu.key_figures import state_figures
from compas_ccu.viz.camera import path_frames
from compas_ccu.viz.render import draw_scene
from compas_ccu.viz.views import readout

__all__ = ["plot_deployment_sequence"]


def plot_deployment_sequence(
    model,
    *,
    count: int = 6,
    alpha: float | None = None,
    view="perspective",
    color_by="kind",
    title: str | None = None,
):
    """``count`` states from α = 0 to ``alpha`` side by side, at one scale and camera.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    count : int
        Number of states (>= 2), equally spaced in α.
    alpha : float, optional
        Last state, degrees (default: the design α).
    view : str or Camera
    color_by : see :func:`compas_ccu.viz.render.draw_scene`

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> fig = plot_deployment_sequence(load_model("examples/vault.toml"), count=4)
    >>> [ax.get_title() for ax in fig.axes]
    ['α = 0°', 'α = 10°', 'α = 20°', 'α = 30°']
    """
    from matplotlib.figure import Figure

    path = path_frames(model, count, alpha, view)
    alphas, structures, scenes = path.alphas, path.structures, path.scenes
    centre, size, limits = path.centre, path.size, path.limits
    target = float(alphas[-1])
    aspect = (limits[3] - limits[2]) / (limits[1] - limits[0])
    fig = Figure(figsize=(2.6 * count, 2.6 * aspect + 0.9), layout="constrained")
    for i, (a, scene, s) in enumerate(zip(alphas, scenes, structures)):
        ax = fig.add_subplot(1, int(count), i + 1)
        draw_scene(ax, scene, view, color_by=color_by, centre=centre, size=size, limits=limits)
        ax.set_title(f"α = {a:.4g}°", fontsize=10)
        ax.text(
            0.5,
            -0.02,
            readout(state_figures(s), names=("crease_span", "crease_rise")),
            transform=ax.transAxes,
            ha="center",
            va="top",
            fontsize=7.5,
            color="#555555",
        )
    name = model.design.name
    fig.suptitle(
        title or f"{name}: deployment from the flat-folded stack (α = 0) to α = {target:g}°",
        fontsize=11,
    )
    return fig
