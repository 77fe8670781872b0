"""The deployment sequence in one strip: flat-folded stack to the design state (paper Fig. 1)."""

from __future__ import annotations

import numpy as np

from compas_ccu.viz.render import draw_scene, projected_limits
from compas_ccu.viz.scene import scene_from_structure

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
    >>> from compas_ccu.design import load_design
    >>> fig = plot_deployment_sequence(load_design("examples/vault.toml").build(), count=4)
    >>> [ax.get_title() for ax in fig.axes]
    ['α = 0°', 'α = 10°', 'α = 20°', 'α = 30°']
    """
    from matplotlib.figure import Figure

    if int(count) != count or count < 2:
        raise ValueError(f"count must be an integer >= 2, got {count!r}")
    target = model.alpha_design if alpha is None else float(alpha)
    if not target > 0.0:
        raise ValueError(f"alpha must be > 0 degrees, got {target!r}")
    alphas = np.linspace(0.0, target, int(count))
    structures = model.path(alphas)
    scenes = [scene_from_structure(s, ground=True) for s in structures]
    pts = np.concatenate([s.vertices.reshape(-1, 3) for s in scenes])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    size = float(np.linalg.norm(np.ptp(pts, axis=0)))
    limits = projected_limits(scenes, view, centre=centre, size=size)
    aspect = (limits[3] - limits[2]) / (limits[1] - limits[0])
    fig = Figure(figsize=(2.6 * count, 2.6 * aspect + 0.9), layout="constrained")
    for i, (a, scene, s) in enumerate(zip(alphas, scenes, structures)):
        ax = fig.add_subplot(1, int(count), i + 1)
        draw_scene(ax, scene, view, color_by=color_by, centre=centre, size=size, limits=limits)
        ax.set_title(f"α = {a:.4g}°", fontsize=10)
        m = s.metrics
        ax.text(
            0.5,
            -0.02,
            f"span {m['span']:.2f} m · rise {m['rise']:.2f} m",
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
