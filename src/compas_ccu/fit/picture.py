"""The deviation picture of an as-built check or a design fit: the points in plan coloured by
their signed distance to the plates (mm), and every plate's RMS and largest distance (mm)."""

from __future__ import annotations

import numpy as np

from compas_ccu.errors import require

__all__ = ["deviation_figure"]


def deviation_figure(points, signed, plates, *, title: str, limit: float, outlines=None):
    """A matplotlib figure of deviations.

    Parameters
    ----------
    points : (n, 3) float
        Points in the design frame, m (drawn in plan, world x-y).
    signed : (n,) float
        Their signed distances to the plates, m.
    plates : sequence of dict
        ``{"id", "rms", "max"}`` per plate, m (None: no points).
    title : str
    limit : float
        Colour scale limit, m (deviations beyond are drawn at the end colours).
    outlines : (p, m, 3) float, optional
        Plate vertices, drawn as outlines in plan.

    Returns
    -------
    matplotlib.figure.Figure
    """
    require("matplotlib", "viz", what="the deviation picture")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 4.8), layout="constrained")
    ax, bars = fig.subplots(1, 2, width_ratios=[2.2, 1])
    mm = 1000.0 * np.asarray(signed)
    lim = 1000.0 * limit
    if outlines is not None:
        for v in np.asarray(outlines):  # the crease-side and the far boundary of every plate
            half = len(v) // 2
            ax.plot(v[:half, 0], v[:half, 1], color="0.6", lw=0.4)
            ax.plot(v[half:, 0], v[half:, 1], color="0.6", lw=0.4)
    p = np.asarray(points)
    step = max(1, len(p) // 200_000)
    art = ax.scatter(
        p[::step, 0], p[::step, 1], c=mm[::step], s=1.0, cmap="RdBu_r", vmin=-lim, vmax=lim
    )
    fig.colorbar(art, ax=ax, label="deviation from the plates, mm")
    ax.set_aspect("equal")
    ax.set_xlabel("x, m")
    ax.set_ylabel("y, m")
    ax.set_title(title, fontsize=10)
    ids = [str(r["id"]) for r in plates]
    rms = [np.nan if r["rms"] is None else 1000.0 * r["rms"] for r in plates]
    top = [np.nan if r["max"] is None else 1000.0 * r["max"] for r in plates]
    x = np.arange(len(ids))
    bars.bar(x - 0.2, rms, width=0.4, label="RMS, mm", color="tab:blue")
    bars.bar(x + 0.2, top, width=0.4, label="largest, mm", color="tab:orange")
    bars.set_xticks(x, ids)
    bars.set_xlabel("plate")
    bars.set_ylabel("distance, mm")
    bars.legend(title="per plate")
    return fig
