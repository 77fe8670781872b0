"""The curves of the finite-element validation against the reflection angle α.

:func:`plot_fe_curves` draws, side by side, the deviation of the FE shape from the kinematic
model (largest and mean, % of the span) and the load–deployment curve (the generalised force,
the strain energy on a twin axis) of the analysed states.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_fe_curves"]


def _series(name: str, values, m: int) -> np.ndarray:
    values = np.asarray(values, dtype=float)
    if values.shape != (m,):
        raise ValueError(f"{name} must have shape ({m},) like alphas, got {values.shape}")
    return values


def plot_fe_curves(
    alphas,
    *,
    deviation_max,
    deviation_mean,
    force=None,
    energy=None,
    force_label: str = "generalised force dW/dα [J/rad]",
    energy_label: str = "strain energy W [J]",
    x_label: str = "reflection angle α [deg]",
    title: str | None = None,
    figsize=(10.0, 4.2),
):
    """Deviation from the kinematic model and the load–deployment curve against α.

    Parameters
    ----------
    alphas : (M,) float
        Reflection angles of the analysed states, degrees.
    deviation_max, deviation_mean : (M,) float
        Largest and mean deviation of the FE shape from the kinematic model, % of the span.
    force : (M,) float, optional
        Generalised force (e.g. dW/dα) of each state.
    energy : (M,) float, optional
        Strain energy of each state; on a twin axis when ``force`` is given.
    force_label, energy_label, x_label : str
        Axis labels.
    title : str, optional
        Figure title.
    figsize : (float, float)
        Inches.

    Returns
    -------
    matplotlib.figure.Figure
        Left panel: deviation; right panel: force (and energy), or the text "no load data".

    Raises
    ------
    ValueError
        When a series does not have the shape of ``alphas`` (the message names the shape).

    Examples
    --------
    >>> import numpy as np
    >>> a = np.linspace(0.0, 30.0, 7)
    >>> fig = plot_fe_curves(a, deviation_max=0.02 * a, deviation_mean=0.01 * a)
    >>> [len(ax.lines) for ax in fig.axes]
    [2, 0]
    """
    from matplotlib.figure import Figure

    alphas = np.asarray(alphas, dtype=float)
    if alphas.ndim != 1 or len(alphas) == 0:
        raise ValueError(f"alphas must have shape (M,) with M >= 1, got {alphas.shape}")
    m = len(alphas)
    dmax = _series("deviation_max", deviation_max, m)
    dmean = _series("deviation_mean", deviation_mean, m)
    force = None if force is None else _series("force", force, m)
    energy = None if energy is None else _series("energy", energy, m)
    marker = "o" if m <= 40 else None

    fig = Figure(figsize=figsize, layout="constrained")
    left, right = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    _deviation_panel(left, alphas, dmax, dmean, marker, x_label)
    _load_panel(right, alphas, force, energy, marker, x_label, force_label, energy_label)
    if title:
        fig.suptitle(title, fontsize=12)
    return fig


def _deviation_panel(ax, alphas, dmax, dmean, marker, x_label: str) -> None:
    """The left panel of :func:`plot_fe_curves`: largest and mean deviation against α."""
    ax.plot(alphas, dmax, color="#b2182b", lw=1.6, marker=marker, ms=3.5, label="max")
    ax.plot(alphas, dmean, color="#2166ac", lw=1.4, ls="--", marker=marker, ms=3, label="mean")
    ax.set_xlabel(x_label)
    ax.set_ylabel("deviation from kinematic model [% of span]")
    ax.set_ylim(bottom=0.0)
    ax.grid(True, alpha=0.3)
    ax.legend(frameon=False, fontsize=9)
    ax.set_title("shape deviation", fontsize=10)


def _load_panel(right, alphas, force, energy, marker, x_label, force_label, energy_label):
    """The right panel of :func:`plot_fe_curves`: the force, and the energy (on a twin axis
    when both are given), or the text "no load data"."""
    right.set_title("load–deployment", fontsize=10)
    right.set_xlabel(x_label)
    if force is None and energy is None:
        right.text(
            0.5,
            0.5,
            "no load data",
            transform=right.transAxes,
            ha="center",
            va="center",
            color="#777777",
            fontsize=11,
        )
        right.set_xticks([])
        right.set_yticks([])
        return
    handles = []
    if force is not None:
        handles += right.plot(
            alphas, force, color="#333333", lw=1.6, marker=marker, ms=3.5, label="force"
        )
        right.set_ylabel(force_label)
        right.axhline(0.0, color="#999999", lw=0.8)
        right.grid(True, alpha=0.3)
        twin = right.twinx() if energy is not None else None
    else:
        twin = right
        right.grid(True, alpha=0.3)
    if energy is not None:
        handles += twin.plot(
            alphas,
            energy,
            color="#e08214",
            lw=1.4,
            ls="-.",
            marker=marker,
            ms=3,
            label="energy",
        )
        twin.set_ylabel(energy_label, color="#e08214" if twin is not right else "black")
    if len(handles) > 1:
        right.legend(handles=handles, frameon=False, fontsize=9, loc="upper left")
