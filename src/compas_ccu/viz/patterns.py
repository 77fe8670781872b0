"""Cut patterns: every plate developed flat, laid out side by side, creases coloured by kind."""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.analysis.plate_size import plate_rectangles
from compas_ccu.key_figures import figure, state_figures
from compas_ccu.kinematics.plates import plate_rulings
from compas_ccu.viz import colors as C
from compas_ccu.viz.views import kind_legend_handles

__all__ = ["plot_cut_patterns", "pattern_layout", "plate_outline"]


def plate_outline(flat: np.ndarray) -> np.ndarray:
    """(2n + 2, 2) closed outline of a plate's cut pattern: near boundary, then far reversed."""
    flat = np.asarray(flat, dtype=float)
    n = flat.shape[0] // 2 - 1
    return np.concatenate([flat[: n + 1, :2], flat[n + 1 :, :2][::-1]])


def _area(outline: np.ndarray) -> float:
    x, y = outline[:, 0], outline[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def pattern_layout(flats, *, gap: float | None = None, aspect: float = 1.6) -> np.ndarray:
    """Offsets that lay the cut patterns out in rows without overlap.

    Parameters
    ----------
    flats : (p, v, 3) float
        Cut patterns (z = 0), all in the same plane coordinates (the flat-folded stack).
    gap : float, optional
        Space between patterns (default: 8 % of the largest pattern size).
    aspect : float
        Width / height of the sheet the columns are chosen for.

    Returns
    -------
    (p, 2) float
        Translation of every plate.
    """
    flats = np.asarray(flats, dtype=float)
    lo = flats[..., :2].min(axis=1)
    hi = flats[..., :2].max(axis=1)
    size = hi - lo
    if gap is None:
        gap = 0.08 * float(size.max())
    w, h = float(size[:, 0].max()) + gap, float(size[:, 1].max()) + gap
    p = len(flats)
    best = min(range(1, p + 1), key=lambda c: abs(c * w / (math.ceil(p / c) * h) - aspect))
    i = np.arange(p)
    cell = np.c_[(i % best) * w, -(i // best) * h]
    return cell - lo


def plot_cut_patterns(structure, *, rulings: bool = True, labels: bool = True, title=None):
    """The cut pattern of every plate, with creases, score lines (rulings) and labels.

    Parameters
    ----------
    structure : compas_ccu.structure.Structure
    rulings : bool
        Draw the rulings as dashed score lines.
    labels : bool
        Plate id, area and length (the long side of its smallest rectangle) on every plate,
        crease id at the middle of every crease.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> s = load_model("examples/vault.toml").deploy()
    >>> fig = plot_cut_patterns(s)
    >>> fig.axes[0].get_title(loc="left")
    'vault: 10 cut patterns, 7.62 m² in all, plate length 2.72 m'
    """
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.figure import Figure

    flats = np.asarray(structure.flat, dtype=float)
    p = len(flats)
    n = flats.shape[1] // 2 - 1
    offsets = pattern_layout(flats)
    xy = flats[..., :2] + offsets[:, None, :]
    outlines = [plate_outline(f) for f in xy]
    areas = [_area(o) for o in outlines]
    lengths = plate_rectangles(flats)[:, 0]
    extent = np.ptp(np.concatenate(outlines), axis=0)
    scale = 10.0 / max(extent[0], extent[1] * 1.6)
    fig = Figure(figsize=(11.0, max(3.5, 11.0 * extent[1] / extent[0] + 1.2)), layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    ax.add_collection(
        PolyCollection(
            outlines,
            facecolors=[C.plate_tone(i) for i in range(p)],
            edgecolors=C.FREE_EDGE_COLOR,
            linewidths=0.9,
        )
    )
    if rulings:
        seg = xy[:, plate_rulings(n)[1:-1]].reshape(-1, 2, 2)
        ax.add_collection(
            LineCollection(seg, colors=C.RULING_COLOR, linewidths=0.5, linestyles=(0, (3, 2)))
        )
    _draw_creases(ax, structure, xy, labels)
    if labels:
        _label_plates(ax, structure, xy, n, areas, lengths, scale)
    _scale_bar(ax, outlines, extent)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_axis_off()
    kinds = [c["kind"] for c in structure.creases]
    if kinds:
        ax.legend(
            handles=kind_legend_handles(kinds),
            loc="upper center",
            bbox_to_anchor=(0.5, 0.0),
            ncol=3,
            fontsize=8,
            frameon=False,
        )
    name = structure.name or "structure"
    longest = (
        f"plate length {state_figures(structure)['plate_length']:.2f} {figure('plate_length').unit}"
    )
    ax.set_title(
        title or f"{name}: {p} cut patterns, {sum(areas):.2f} m² in all, {longest}",
        loc="left",
        fontsize=11,
    )
    return fig


def _draw_creases(ax, structure, xy: np.ndarray, labels: bool) -> None:
    """Both sides of every crease on the laid-out patterns ``xy`` (p, v, 2), coloured by kind,
    with the crease id at its middle (``labels``)."""
    index = {pid: i for i, pid in enumerate(structure.plate_ids)}
    for c in structure.creases:
        color = C.KIND_COLORS.get(c["kind"], C.EDGE_COLOR)
        for side, verts in zip(c["plates"], c["vertices"]):
            pts = xy[index[side], np.asarray(verts, dtype=int)]
            ax.plot(pts[:, 0], pts[:, 1], color=color, lw=2.2, solid_capstyle="round")
            if labels:
                mid = pts[len(pts) // 2]
                ax.annotate(
                    f"c{c['id']}",
                    mid,
                    fontsize=6.5,
                    color=color,
                    ha="center",
                    va="center",
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8},
                )


def _label_plates(ax, structure, xy, n: int, areas, lengths, scale: float) -> None:
    """Plate id, area and length on every plate, off its middle (where the crease labels
    are)."""
    m = max(1, n // 4)
    ends = plate_rulings(n)[m]
    for i, pid in enumerate(structure.plate_ids):
        at = 0.5 * (xy[i, ends[0]] + xy[i, ends[1]])
        ax.text(
            *at,
            f"P{pid}\n{areas[i]:.3f} m²\n{lengths[i]:.2f} m long",
            ha="center",
            va="center",
            fontsize=max(6.0, min(9.0, 9.0 * scale)),
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.7},
            color="#222222",
        )


def _scale_bar(ax, outlines: list, extent: np.ndarray) -> None:
    """A scale bar under the patterns: 5, 2, 1, 0.5 … 0.05 m, about a fifth of the sheet."""
    bar = next((b for b in (5.0, 2.0, 1.0, 0.5, 0.2, 0.1, 0.05) if b <= 0.25 * extent[0]), 0.05)
    lo = np.concatenate(outlines).min(axis=0)
    y0 = lo[1] - 0.06 * max(extent)
    ax.plot([lo[0], lo[0] + bar], [y0, y0], color="#222222", lw=3, solid_capstyle="butt")
    ax.text(lo[0] + bar / 2, y0, f"{bar:g} m", ha="center", va="bottom", fontsize=8)
