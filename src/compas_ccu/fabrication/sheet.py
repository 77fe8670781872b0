"""The assembly sheet: every cut pattern, the stack section and the assembly steps on one page.

:func:`write_assembly_sheet` draws an A3 landscape page with matplotlib (imported inside the
function; the figure is rendered off-screen, no pyplot): left, the cut patterns in a grid in
stack order (plate id in large type and stack position on each); right, a schematic section of
the flat-folded stack (plates to scale in height, bottom to top, the creases joining them as
arcs on alternating sides: the accordion) above the assembly steps; on top, the design name,
material, thickness and stack height.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np

from compas_ccu.fabrication.assembly import assembly_steps
from compas_ccu.fabrication.dxf import label_frame
from compas_ccu.viz import colors as C
from compas_ccu.viz.patterns import pattern_layout

__all__ = ["write_assembly_sheet", "SHEET_FORMATS"]

#: File suffixes :func:`write_assembly_sheet` writes.
SHEET_FORMATS = (".pdf", ".svg", ".png")
A3_LANDSCAPE = (16.54, 11.69)  # inches


def _stack_order(data) -> list:
    """Array indices of the plates, bottom of the stack first."""
    return sorted(range(len(data.plate_ids)), key=lambda i: int(data.stack_position[i]))


def _row(indices, n: int):
    """'near' / 'far' if every crease vertex index lies on that boundary row, else None."""
    idx = np.asarray(indices)
    if (idx <= n).all():
        return "near"
    if (idx > n).all():
        return "far"
    return None


def _font_points(ax, length: float) -> float:
    """Points that ``length`` data units span on ``ax`` (equal aspect, after layout)."""
    ax.apply_aspect()
    p = ax.transData.transform([[0.0, 0.0], [length, 0.0]])
    return float(abs(p[1, 0] - p[0, 0])) * 72.0 / ax.figure.dpi


def _id_frame(outline: np.ndarray):
    """(anchor, direction, height) of a plate's id on the sheet.

    In the plate's hollow, at its centroid of area, in large type, where the centroid lies
    outside the plate and the text clears it (crescent plates); else inside the plate, as the
    DXF label (:func:`compas_ccu.fabrication.dxf.label_frame`).
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


def _draw_patterns(ax, data, order, records=()) -> None:
    from matplotlib.patches import Polygon as MplPolygon

    flat = np.asarray(data.flat, dtype=float)[order]
    box = ax.get_position()
    fig_w, fig_h = ax.figure.get_size_inches()
    aspect = (box.width * fig_w) / (box.height * fig_h)
    shifts = pattern_layout(flat, aspect=aspect)
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
            from matplotlib.collections import LineCollection

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
    lo = (flat + shifts[:, None, :]).reshape(-1, 2).min(axis=0)
    hi = (flat + shifts[:, None, :]).reshape(-1, 2).max(axis=0)
    pad = 0.03 * float(np.max(hi - lo))
    lo, hi = lo - pad, hi + pad
    # limits of the axes' own aspect (panel title and layout stay put), patterns at the top
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
    # text sized in data units: the same proportion of the plate as in the DXF label
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
    # scale bar: 1 m (or 0.1 m for small plates)
    bar = 1.0 if float(np.max(hi - lo)) > 2.0 else 0.1
    lo_pat = (flat + shifts[:, None, :]).reshape(-1, 2).min(axis=0)
    x0, y0 = lo_pat[0], lo_pat[1] - 0.5 * pad
    ax.plot([x0, x0 + bar], [y0, y0], color="black", linewidth=2.0, solid_capstyle="butt")
    ax.text(x0 + 0.5 * bar, y0 + 0.3 * pad, f"{bar:g} m", ha="center", va="bottom", fontsize=8)
    ax.set_title(
        "Cut patterns seen from above (cut face up as drawn), in stack order; "
        "creases coloured by kind, thin lines: rulings",
        fontsize=11,
        loc="left",
    )


def _draw_stack(ax, data, order) -> None:
    from matplotlib.patches import Rectangle

    t = float(data.thickness) * 1000.0
    n = data.segments
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
    # creases: arcs between the plates they join; consecutive ones alternate sides (accordion)
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
    # creases between plates further apart: on the side of a neighbour crease of either plate if
    # on the same boundary row of that plate, else on the other side
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


def _legend(ax, data, spliced: bool = False) -> None:
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


def _group_text(group: list, total: int) -> str:
    """One line of the sheet for consecutive steps of one plate (:func:`_step_groups`)."""
    first, last = group[0]["step"], group[-1]["step"]
    head = f"{first}." if first == last else f"{first}-{last}."
    words = []
    for s in group:
        name = ", ".join(s["parts"])
        if s["action"] == "splice":
            words.append(f"{name} {'under' if s['face'] == 'lower' else 'over'}")
        elif s["action"] == "join":
            cuts = ", ".join(str(j) for j in s["where"]["rulings"])
            words.append(f"{' + '.join(s['parts'])} UP face up, cut edges at ruling {cuts}")
        elif s["action"] == "lay":
            on = s["where"]["on"]
            words.append(
                f"lay P{s['plate']} UP face up "
                + ("on the table" if on is None else f"on P{on}")
                + f" (stack {s['where']['stack']} of {total})"
            )
        else:
            lo, hi = s["where"]["plates"]
            faces = f" {s['face'][:3]}" if s["face"] else ""
            words.append(f"glue {name} P{lo}/P{hi}{faces}")
    if group[0]["action"] in ("splice", "join"):
        return f"{head} P{group[0]['plate']} on the table: " + ", ".join(words)
    return f"{head} " + "; ".join(words)


def _step_groups(steps) -> list:
    """The steps grouped: a split plate's joining steps, and a plate laid with its hinges."""
    groups = []
    for s in steps:
        joining = s["action"] in ("splice", "join")
        key = ("join", s["plate"]) if joining else ("stack", s["plate"])
        if s["action"] == "glue" and groups and groups[-1][0][0] == "stack":
            key = groups[-1][0]
        if groups and groups[-1][0] == key:
            groups[-1][1].append(s)
        else:
            groups.append((key, [s]))
    return [g for _, g in groups]


def _assembly_text(data, order, steps) -> str:
    t = float(data.thickness) * 1000.0
    w = float(data.hinge_width) * 1000.0
    lines = [
        f"Cut every part ({data.material}, {t:g} mm) face up as drawn ('UP' reads from above); "
        f"hinge strips {w:g} mm, centred on the creases (int / ext: intrados / extrados faces). "
        "Steps as in fabrication.json:",
    ]
    lines += [_group_text(g, len(order)) for g in _step_groups(steps)]
    return "\n".join(
        textwrap.fill(s, 98, subsequent_indent="     ", break_on_hyphens=False) for s in lines
    )


def write_assembly_sheet(data, path, *, steps=None, stack=None) -> Path:
    """Write the assembly sheet of a design as PDF, SVG or PNG (by the suffix of ``path``).

    Parameters
    ----------
    data : compas_ccu.fabrication.data.FabricationData
    path : str or Path
        Output file, ``.pdf``, ``.svg`` or ``.png``. SVG text stays text (searchable).
    steps : list of dict, optional
        The assembly steps (:func:`compas_ccu.fabrication.assembly.assembly_steps`, as in
        ``fabrication.json``); default: the steps of the plates whole.
    stack : dict, optional
        ``fabrication.json``'s ``splices`` (:func:`compas_ccu.fabrication.splices.splice_summary`):
        the splice plates drawn on their plates and the stack height with them.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If the suffix is not one of :data:`SHEET_FORMATS`.
    """
    import matplotlib
    from matplotlib.figure import Figure

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in SHEET_FORMATS:
        raise ValueError(
            f"assembly sheet format must be one of {SHEET_FORMATS}, got {path.suffix!r} ({path})"
        )
    order = _stack_order(data)
    p = len(order)
    t = float(data.thickness) * 1000.0
    steps = assembly_steps(data, {}) if steps is None else steps
    records = [] if stack is None else stack["records"]
    height = f"stack height \u03a3t = {p * t:g} mm"
    if records:
        height += (
            f", {stack['stack_height'] * 1000:.4g} mm with the {len(records)} splice plates "
            f"(highest pile {stack['max_pile'] * 1000:.4g} mm)"
        )
    # a fixed salt for the SVG's ids and no date in the PDF: the same design, the same bytes
    rc = {
        "svg.fonttype": "none",
        "pdf.fonttype": 42,
        "font.family": "DejaVu Sans",
        "svg.hashsalt": "compas_ccu",
    }
    with matplotlib.rc_context(rc):
        fig = Figure(figsize=A3_LANDSCAPE, dpi=100)
        gs = fig.add_gridspec(
            2,
            2,
            width_ratios=[2.15, 1.0],
            height_ratios=[0.9, 1.35],
            left=0.025,
            right=0.985,
            top=0.885,
            bottom=0.03,
            wspace=0.12,
            hspace=0.16,
        )
        fig.suptitle(
            f"{data.name}: cut patterns and assembly",
            x=0.025,
            y=0.975,
            ha="left",
            fontsize=20,
            fontweight="bold",
        )
        fig.text(
            0.025,
            0.925,
            f"{p} plates of {data.material}, thickness t = {t:g} mm, "
            f"{height}; hinge strips {data.hinge_width * 1000:g} mm wide; design reflection "
            f"angle \u03b1 = {data.alpha:g}\u00b0",
            ha="left",
            va="center",
            fontsize=12,
        )
        _draw_patterns(fig.add_subplot(gs[:, 0]), data, order, records)
        _draw_stack(fig.add_subplot(gs[0, 1]), data, order)
        ax = fig.add_subplot(gs[1, 1])
        ax.set_axis_off()
        ax.set_title("Assembly", fontsize=11, loc="left")
        ax.text(
            0.0,
            0.97,
            _assembly_text(data, order, steps),
            transform=ax.transAxes,
            ha="left",
            va="top",
            fontsize=7.5,
            linespacing=1.3,
        )
        _legend(ax, data, spliced=bool(records))
        metadata = {
            "Title": f"{data.name} assembly sheet",
            "Creator": "compas_ccu",
            "CreationDate": None,
        }
        if suffix == ".svg":
            metadata = {"Title": metadata["Title"], "Creator": "compas_ccu", "Date": None}
        elif suffix == ".png":
            metadata = {"Title": metadata["Title"], "Software": "compas_ccu"}
        fig.savefig(path, metadata=metadata)
    return path
