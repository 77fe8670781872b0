"""A contact sheet: many designs at a glance, one small perspective each, with key numbers."""

from __future__ import annotations

import math

from compas_ccu.errors import OptionError
from compas_ccu.viz.render import draw_scene
from compas_ccu.viz.scene import scene_from_structure

__all__ = ["plot_contact_sheet"]


def plot_contact_sheet(
    structures,
    *,
    titles=None,
    captions=None,
    columns: int | None = None,
    view="perspective",
    color_by="kind",
    title: str | None = None,
):
    """One panel per structure, in a grid.

    Parameters
    ----------
    structures : sequence of compas_ccu.structure.Structure
    titles : sequence of str, optional
        Panel titles (default: structure names).
    captions : sequence of str, optional
        Text under each panel (default: α, plates, span, rise).
    columns : int, optional
        Default: about square.
    view, color_by
        See :func:`compas_ccu.viz.render.draw_scene`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> s = [load_model(f"examples/{n}.toml").deploy() for n in ("vault", "cone")]
    >>> fig = plot_contact_sheet(s)
    >>> [ax.get_title() for ax in fig.axes]
    ['vault', 'cone']
    """
    from matplotlib.figure import Figure

    structures = list(structures)
    if not structures:
        raise OptionError("a contact sheet needs at least one structure")
    count = len(structures)
    for name, seq in (("titles", titles), ("captions", captions)):
        if seq is not None and len(seq) != count:
            raise OptionError(f"{name} must have one entry per structure ({count}), got {len(seq)}")
    if columns is None:
        columns = math.ceil(math.sqrt(count))
    if int(columns) != columns or columns < 1:
        raise OptionError(f"columns must be an integer >= 1, got {columns!r}")
    columns = int(columns)
    rows = math.ceil(count / columns)
    fig = Figure(figsize=(3.4 * columns, 3.1 * rows + 0.5), layout="constrained")
    for i, s in enumerate(structures):
        ax = fig.add_subplot(rows, columns, i + 1)
        draw_scene(ax, scene_from_structure(s, ground=True), view, color_by=color_by)
        ax.set_title(titles[i] if titles else (s.name or f"design {i}"), fontsize=10)
        m = s.metrics
        text = (
            captions[i]
            if captions
            else f"α {s.alpha:g}° · {len(s.plate_ids)} plates\n"
            f"span {m.get('span', float('nan')):.2f} m · rise {m.get('rise', float('nan')):.2f} m"
        )
        ax.text(
            0.5,
            -0.02,
            text,
            transform=ax.transAxes,
            ha="center",
            va="top",
            fontsize=7.5,
            color="#444444",
        )
    if title:
        fig.suptitle(title, fontsize=12)
    return fig
