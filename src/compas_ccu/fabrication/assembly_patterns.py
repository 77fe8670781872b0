"""The assembly sheet's cut-pattern panel: every plate in stack order, labelled, and its legend.

:func:`draw_patterns` draws the cut patterns seen from above in a grid
(:func:`compas_ccu.viz.patterns.pattern_layout`), in stack order, in named steps: the plates
(outline, rulings, creases coloured by kind, cuts and splice plates; :func:`_draw_plates`), the
axes fitted to the panel's aspect (:func:`_fit_axes`), the plate ids and crease tags sized like
the DXF label (:func:`_draw_labels`), and a scale bar. :func:`pattern_legend` is its key (crease
kinds, rulings, cuts, splice plates). matplotlib and shapely are imported inside the functions.
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.fabrication.label_placement import label_frame
from compas_ccu.viz import colors as C
from compas_ccu.viz.patterns import pattern_layout

__all__ = ["draw_patterns", "pattern_legend"]


def _font_points(ax, length: float) -> float:
    """Points that ``length`` data units span on ``ax`` (equal aspect, after layout)."""
    ax.apply_aspect()
    p = ax.transData.transform([[0.0, 0.0], [length, 0.0]])
    return float(abs(p[1, 0] - p[0, 0])) * 72.0 / ax.figure.dpi


def _id_frame(outline: np.ndarray):
    """(anchor, direction, height) of a plate's id on the sheet.

    In the plate's hollow, at its centroid of area, in large type, where the centroid lies
    outside the plate and the text clears it (crescent plates); else inside the plate, as the
    DXF label (:func:`compas_ccu.fabrication.label_placement.label_frame`).
    """
    from shapely import Point, Polygon, box

    poly = Polygon(outline)
    if not poly.is_valid:
        poly = poly.buffer(0)
    c = poly.centroid
    size = np.ptp(outline, axis=0)
    inside = label_frame(outline, lines=3, chars=14)
    if not poly.contains(Point(c.x, c.y)):
        h = 0.12 * float(min(size.max(), 3.0 * size.min()))
        while h > 1.5 * inside[2]:
            half = np.array([0.5 * 0.62 * 9 * 1.5 * h, 1.6 * h])  # about 9 characters, two lines
            if not box(c.x - half[0], c.y - half[1], c.x + half[0], c.y + half[1]).intersects(poly):
                return np.array([c.x, c.y]), np.array([1.0, 0.0]), h
            h *= 0.85
    return inside


def _draw_splices(ax, data, i: int, shift, records) -> None:
    """The cuts of plate ``i`` (array index) and its splice plates' footprints, shifted."""
    pid = int(data.plate_ids[i])
    n = data.segments
    pts = np.asarray(data.flat[i], dtype=float) + shift
    for r in records:
        if int(r["plate"]) != pid or r["face"] != "upper":
            continue
        j = int(r["ruling"])
        ax.plot(*pts[[j, n + 1 + j]].T, color="black", linewidth=1.3, zorder=4)
        rect = np.asarray(r["footprint"], dtype=float) + shift
        ring = np.r_[rect, rect[:1]]
        ax.plot(ring[:, 0], ring[:, 1], color="black", linewidth=0.7, linestyle="--", zorder=4)


def _draw_plates(ax, data, order, flat, shifts, records) -> list:
    """Every plate's outline, rulings, creases and splices in its grid cell ``shifts``;
    returns the labels to write (:func:`_draw_labels`) once the axes are fitted."""
    from matplotlib.collections import LineCollection
    from matplotlib.patches import Polygon as MplPolygon

    n = data.segments
    p = len(order)
    kinds = {int(c["id"]): c.get("kind", "") for c in data.creases}
    frames = []
    for cell, i in enumerate(order):
        d = shifts[cell]
        outline = np.asarray(data.outline(i), dtype=float) + d
        ax.add_patch(
            MplPolygon(
                outline,
                closed=True,
                facecolor=C.plate_tone(cell),
                edgecolor=C.EDGE_COLOR,
                linewidth=0.8,
                zorder=1,
            )
        )
        pts = flat[cell] + d
        seg = np.stack([pts[1:n], pts[n + 2 : 2 * n + 1]], axis=1)
        if len(seg):
            ax.add_collection(LineCollection(seg, colors=C.RULING_COLOR, linewidths=0.35, zorder=2))
        for cid, _, idx in data.plate_creases(i):
            q = pts[idx]
            color = C.KIND_COLORS.get(kinds.get(int(cid), ""), C.FREE_EDGE_COLOR)
            ax.plot(q[:, 0], q[:, 1], color=color, linewidth=1.6, zorder=3, solid_capstyle="butt")
            frames.append(("crease", q, f"c{cid}", color))
        _draw_splices(ax, data, i, d, records)
        k = int(data.stack_position[i])
        anchor, u, h = _id_frame(outline)
        frames.append(("plate", anchor, u, h, f"P{data.plate_ids[i]}", f"stack {k + 1} of {p}"))
    return frames


def _fit_axes(ax, placed: np.ndarray, aspect: float) -> tuple:
    """Limits around the placed patterns ``placed`` (m, 2), padded, at the axes' own aspect
    (panel title and layout stay put), patterns at the top; returns ``(lo, hi, pad)``."""
    lo = placed.min(axis=0)
    hi = placed.max(axis=0)
    pad = 0.03 * float(np.max(hi - lo))
    lo, hi = lo - pad, hi + pad
    span = hi - lo
    need = span[1] / span[0]
    if need < 1.0 / aspect:
        lo[1] = hi[1] - span[0] / aspect
    else:
        mid = 0.5 * (lo[0] + hi[0])
        lo[0], hi[0] = mid - 0.5 * span[1] * aspect, mid + 0.5 * span[1] * aspect
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_axis_off()
    return lo, hi, pad


def _draw_labels(ax, frames: list) -> None:
    """Plate ids and stack positions, crease tags: text sized in data units, the same
    proportion of the plate as in the DXF label."""
    for f in frames:
        if f[0] == "plate":
            _, anchor, u, h, name, stack = f
            v = np.array([-u[1], u[0]])
            angle = math.degrees(math.atan2(u[1], u[0]))
            big = min(max(_font_points(ax, 1.5 * h), 7.0), 36.0)
            small = min(max(_font_points(ax, 0.8 * h), 6.0), 14.0)
            ax.text(
                *(anchor + 0.55 * h * v),
                name,
                rotation=angle,
                rotation_mode="anchor",
                ha="center",
                va="center",
                fontsize=big,
                fontweight="bold",
                zorder=5,
            )
            ax.text(
                *(anchor - 1.0 * h * v),
                stack,
                rotation=angle,
                rotation_mode="anchor",
                ha="center",
                va="center",
                fontsize=small,
                zorder=5,
            )
        else:
            _, q, tag, color = f
            m = len(q) // 4
            ax.text(
                *q[m],
                tag,
                fontsize=7.5,
                color=color,
                ha="center",
                va="center",
                zorder=6,
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8},
            )


def draw_patterns(ax, data, order, records=()) -> None:
    """The cut patterns of ``data`` on ``ax``, plates in ``order`` (array indices, bottom of the
    stack first), with the cuts and splice plates of ``records`` (``fabrication.json``'s
    ``splices.records``)."""
    flat = np.asarray(data.flat, dtype=float)[order]
    box = ax.get_position()
    fig_w, fig_h = ax.figure.get_size_inches()
    aspect = (box.width * fig_w) / (box.height * fig_h)
    shifts = pattern_layout(flat, aspect=aspect)
    frames = _draw_plates(ax, data, order, flat, shifts, records)
    placed = (flat + shifts[:, None, :]).reshape(-1, 2)
    lo, hi, pad = _fit_axes(ax, placed, aspect)
    _draw_labels(ax, frames)
    # scale bar: 1 m (or 0.1 m for small plates)
    bar = 1.0 if float(np.max(hi - lo)) > 2.0 else 0.1
    lo_pat = placed.min(axis=0)
    x0, y0 = lo_pat[0], lo_pat[1] - 0.5 * pad
    ax.plot([x0, x0 + bar], [y0, y0], color="black", linewidth=2.0, solid_capstyle="butt")
    ax.text(x0 + 0.5 * bar, y0 + 0.3 * pad, f"{bar:g} m", ha="center", va="bottom", fontsize=8)
    ax.set_title(
        "Cut patterns seen from above (cut face up as drawn), in stack order; "
        "creases coloured by kind, thin lines: rulings",
        fontsize=11,
        loc="left",
    )


def pattern_legend(ax, data, spliced: bool = False) -> None:
    """The key of the pattern panel on ``ax``: crease kinds, rulings and, if ``spliced``, cuts
    and splice plates."""
    from matplotlib.lines import Line2D

    kinds = sorted({c.get("kind", "") for c in data.creases})
    handles = [
        Line2D(
            [],
            [],
            color=C.KIND_COLORS.get(k, C.FREE_EDGE_COLOR),
            linewidth=2.0,
            label=f"crease: {C.KIND_LABELS.get(k, k)}",
        )
        for k in kinds
    ]
    handles.append(Line2D([], [], color=C.RULING_COLOR, linewidth=1.0, label="ruling"))
    if spliced:
        handles.append(Line2D([], [], color="black", linewidth=1.3, label="cut"))
        handles.append(
            Line2D([], [], color="black", linewidth=0.7, linestyle="--", label="splice plate")
        )
    ax.legend(handles=handles, loc="lower left", fontsize=9, frameon=False)
