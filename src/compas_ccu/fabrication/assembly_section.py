"""The assembly sheet's stack section: the flat-folded stack drawn schematically, the accordion.

:func:`draw_stack` draws the plates to scale in height, bottom to top, and the creases joining
them as arcs; consecutive creases alternate sides (:func:`_crease_sides`), as the plates fold
into the stack. matplotlib is imported inside the function.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.viz import colors as C

__all__ = ["draw_stack"]


def _row(indices, n: int):
    """'near' / 'far' if every crease vertex index lies on that boundary row, else None."""
    idx = np.asarray(indices)
    if (idx <= n).all():
        return "near"
    if (idx > n).all():
        return "far"
    return None


def _crease_sides(data, order, position: dict) -> dict:
    """Side of the stack (+1 right, -1 left) of every crease's arc, ``{(lower, upper): side}``
    by stack position: consecutive creases alternate sides (the accordion) unless they leave
    a plate from different boundary rows; a crease between plates further apart goes on the
    side of a neighbour crease of either plate if on the same boundary row of that plate, else
    on the other side."""
    n = data.segments
    p = len(order)
    side, row_up = {}, {}
    for k, i in enumerate(order):
        for _, other, idx in data.plate_creases(i):
            row_up.setdefault((k, position.get(int(other), -1)), _row(idx, n))
    current = 1.0
    for k in range(p - 1):
        if (k, k + 1) not in row_up:
            continue
        below = row_up.get((k, k - 1))
        above = row_up[(k, k + 1)]
        if k > 0 and (k - 1, k) in side:
            flip = below is None or above is None or below != above
            current = -side[(k - 1, k)] if flip else side[(k - 1, k)]
        side[(k, k + 1)] = current
    for k, m in list(row_up):
        key = (min(k, m), max(k, m))
        if m < 0 or abs(m - k) < 2 or key in side:
            continue
        side[key] = 1.0
        for plate, other in ((k, m), (m, k)):
            mine = row_up.get((plate, other))
            refs = [
                (nb, side[tuple(sorted((plate, nb)))])
                for nb in (plate - 1, plate + 1)
                if tuple(sorted((plate, nb))) in side and (plate, nb) in row_up
            ]
            if mine is not None and refs:
                nb, ref = refs[0]
                side[key] = ref if row_up[(plate, nb)] == mine else -ref
                break
    return side


def _draw_creases(ax, data, position: dict, side: dict, t: float, width: float, font) -> None:
    """Every crease as an arc between its two plates (stack ``position`` by plate id), on its
    ``side``; dashed between plates that are not neighbours in the stack."""
    t_theta = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 25)
    for c in data.creases:
        a, b = (int(v) for v in c["plates"])
        if a not in position or b not in position:
            continue
        ka, kb = sorted((position[a], position[b]))
        s = side.get((ka, kb), 1.0)
        x0 = width if s > 0 else 0.0
        yc = 0.5 * (ka + kb + 1) * t
        ry = 0.5 * (kb - ka) * t
        rx = 0.06 + 0.04 * (kb - ka - 1)
        color = C.KIND_COLORS.get(c.get("kind", ""), C.FREE_EDGE_COLOR)
        ax.plot(
            x0 + s * rx * np.cos(t_theta),
            yc + ry * np.sin(t_theta),
            color=color,
            linewidth=1.6,
            linestyle="-" if kb - ka == 1 else "--",
        )
        ax.plot([x0 + s * rx], [yc], marker="o", markersize=3.5, color=color)
        ax.text(
            x0 + s * (rx + 0.04),
            yc,
            f"c{c['id']}",
            ha="left" if s > 0 else "right",
            va="center",
            fontsize=font,
            color=color,
        )


def draw_stack(ax, data, order) -> None:
    """The stack section of ``data`` on ``ax``, plates in ``order`` (array indices, bottom of
    the stack first); heights in mm."""
    from matplotlib.patches import Rectangle

    t = float(data.thickness) * 1000.0
    p = len(order)
    width = 1.0
    position = {int(data.plate_ids[i]): k for k, i in enumerate(order)}
    for k in range(p):
        ax.add_patch(
            Rectangle(
                (0.0, k * t),
                width,
                t,
                facecolor=C.plate_tone(k),
                edgecolor=C.EDGE_COLOR,
                linewidth=0.8,
            )
        )
    side = _crease_sides(data, order, position)
    ax.set_xlim(-0.45, 1.45)
    ax.set_ylim(-0.6 * t, (p + 0.6) * t)
    bbox = ax.get_window_extent()
    rect_pts = bbox.height / ((p + 1.2) * t) * t * 72.0 / ax.figure.dpi
    font = min(14.0, max(5.0, 0.55 * rect_pts))
    for k, i in enumerate(order):
        ax.text(
            0.5 * width,
            (k + 0.5) * t,
            f"P{data.plate_ids[i]}",
            ha="center",
            va="center",
            fontsize=font,
            fontweight="bold",
        )
    _draw_creases(ax, data, position, side, t, width, font)
    ax.set_xticks([])
    for spine in ("top", "right", "bottom"):
        ax.spines[spine].set_visible(False)
    ax.set_ylabel("height in the flat-folded stack (mm)", fontsize=9)
    ax.tick_params(labelsize=8)
    ax.set_title(
        f"Stack section (schematic; heights to scale, t = {t:g} mm)\n"
        "bottom = stack 1; arcs: creases (hinges) joining plates",
        fontsize=11,
        loc="left",
    )
