"""Planarity deviation of every crease along the deployment path (paper Fig. 6d)."""

from __future__ import annotations

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.tolerances import EXACT_RELATIVE, MACHINE, ROUND_OFF

__all__ = ["plot_planarity"]


def plot_planarity(model, *, steps: int = 60, alpha: float | None = None, title=None):
    """Largest distance of each crease from its plane, from α = 0 to ``alpha``.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    steps : int
        Number of intervals along the path (``steps + 1`` states).
    alpha : float, optional
        Last state, degrees (default: the design α).

    Returns
    -------
    matplotlib.figure.Figure
        Log scale; zeros (exactly planar) are drawn at the floor of the axis. The dashed line is
        the docs/geometry.md §3 bar (1e-9 of the structure size).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> fig = plot_planarity(load_model("examples/vault.toml"), steps=10)
    >>> len(fig.axes[0].lines)  # 9 creases and the 1e-9 bar
    10
    """
    from matplotlib.figure import Figure
    from matplotlib.ticker import LogLocator

    if int(steps) != steps or steps < 1:
        raise OptionError(f"steps must be an integer >= 1, got {steps!r}")
    target = model.alpha_design if alpha is None else float(alpha)
    alphas = np.linspace(0.0, target, int(steps) + 1)
    dev = model.crease_planarity(alphas)  # (k, c) metres
    size = model.size
    floor = 1e-18 * max(size, 1.0)
    fig = Figure(figsize=(8.0, 4.6), layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    cmap = _crease_colors(dev.shape[1])
    for ci in range(dev.shape[1]):
        ax.semilogy(alphas, np.maximum(dev[:, ci], floor), color=cmap[ci], lw=1.4, label=f"c{ci}")
    ax.axhline(EXACT_RELATIVE * size, color="#aa0000", ls="--", lw=1.0)
    ax.text(
        alphas[0],
        EXACT_RELATIVE * size * 1.6,
        "exactness bar: 1e-9 × size",
        color="#aa0000",
        fontsize=8,
    )
    ax.axhspan(floor, ROUND_OFF * size, color="#dddddd", alpha=0.5, lw=0)
    ax.text(
        alphas[-1], 2 * MACHINE * size, "rounding level", ha="right", fontsize=8, color="#666666"
    )
    ax.set_xlabel("reference reflection angle α (°)")
    ax.set_ylabel("crease distance from its plane (m)")
    ax.set_ylim(floor, max(10 * float(dev.max()), 100 * EXACT_RELATIVE * size))
    ax.yaxis.set_major_locator(LogLocator(numticks=8))
    ax.grid(True, which="major", alpha=0.3)
    if dev.shape[1] <= 12 and dev.shape[1]:
        ax.legend(ncol=min(6, dev.shape[1]), fontsize=7.5, loc="upper left", frameon=False)
    worst = float(dev.max()) if dev.size else 0.0
    at = float(alphas[np.unravel_index(np.argmax(dev), dev.shape)[0]]) if dev.size else 0.0
    ax.set_title(
        title
        or f"{model.design.name}: crease planarity along the path, largest {worst:.2e} m "
        f"({worst / size:.1e} of the size) at α = {at:.3g}°",
        fontsize=10,
    )
    return fig


def _crease_colors(count: int) -> list:
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    return [cmap(x) for x in np.linspace(0.05, 0.9, max(count, 1))]
