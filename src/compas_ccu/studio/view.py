"""What the studio draws: the arrays of one deployed state and their colours and legend.

:func:`view_state` turns a model at one reflection angle into plain arrays (plate vertices and
triangles, crease and ruling segments, thick solids, the flat stack) with the colours of the
chosen colouring, and :func:`legend_html` says what the colours mean *with the numbers they
were made from*: a colour scale spans the values actually drawn, a constant value is named as
constant (not spread over a scale), and every plate's utilisation is listed beside its colour.
Nothing here knows the web page; :mod:`compas_ccu.studio.app` sends the arrays to the browser.
"""

from __future__ import annotations

import html
from dataclasses import dataclass, field

import numpy as np

from compas_ccu.analysis.plate_size import fits_sheet, plate_rectangles
from compas_ccu.design.schema import STOCK_SHEET
from compas_ccu.fabrication.meshes import solid_mesh
from compas_ccu.kinematics.plates import plate_rulings
from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE
from compas_ccu.viz import colors as C
from compas_ccu.viz.patterns import pattern_layout, plate_outline

__all__ = ["COLORINGS", "ViewState", "view_state", "legend_html", "cut_patterns_svg", "SHEET"]
__all__ += ["cmap_colors"]

#: The colourings of the 3D view.
COLORINGS = ("crease kind", "bending utilisation", "reflection angle", "crease planarity")
#: A stock plywood sheet, m (drawn beside the cut patterns for scale, unless the design names
#: its own: the studio passes the design's first [fabrication] sheet).
SHEET = STOCK_SHEET
#: Relative range below which a value is drawn as constant.
CONSTANT = 1e-6
#: Crease planarity (relative to the size) below which a crease counts as planar.
PLANAR = EXACT_RELATIVE


def _rgb(color: str) -> tuple:
    return tuple(int(round(255 * c)) for c in C.hex_to_rgb(color))


def cmap_colors(name: str, values: np.ndarray) -> np.ndarray:
    """sRGB colours (``values.shape + (3,)`` uint8) of ``values`` in [0, 1] on matplotlib
    colour map ``name``."""
    import matplotlib

    return (matplotlib.colormaps[name](values)[..., :3] * 255).round().astype(np.uint8)


@dataclass
class ViewState:
    """One state of the 3D view (world coordinates, metres).

    Attributes
    ----------
    alpha : float
        Reference reflection angle, degrees.
    vertices : (p, v, 3) float
    triangles : (p, 2n, 3) int
        Triangles of every plate (into its own vertices).
    plate_colors : (p, 3) uint8
    creases : (c, n, 2, 3) float
        Crease segments.
    crease_colors : (c, n, 3) uint8
    rulings : (p, n + 1, 2, 3) float
    span, rise : float
        Of the leading crease (``structure.metrics``).
    legend : dict
        ``title``, ``rows`` [(rgb, text)] or ``scale`` (colormap name, lo, hi, unit), ``note``.
    vertex_colors : (p, v, 3) uint8 or None
        sRGB colour of every plate vertex (the plates are then drawn in these, interpolated,
        instead of ``plate_colors``: the distance to a target, :mod:`compas_ccu.studio.target`).
    """

    alpha: float
    vertices: np.ndarray
    triangles: np.ndarray
    plate_colors: np.ndarray
    creases: np.ndarray
    crease_colors: np.ndarray
    rulings: np.ndarray
    span: float
    rise: float
    legend: dict
    plate_ids: list = field(default_factory=list)
    solids: list = field(default_factory=list)
    vertex_colors: np.ndarray | None = None


def _triangles(faces: np.ndarray) -> np.ndarray:
    """(p, n, 4) quads -> (p, 2n, 3) triangles."""
    return np.concatenate([faces[..., [0, 1, 2]], faces[..., [0, 2, 3]]], axis=1)


def _crease_rows(model):
    """Per crease: (output position of plate a, its crease vertex rows)."""
    position = np.argsort(model.plates.order)
    out = []
    for ci, (a, _) in enumerate(model.plates.crease_plates):
        out.append((int(position[a]), model.plates.crease_rows(ci)[0]))
    return out


def _scale_colors(values: np.ndarray, lo: float, hi: float, cmap: str):
    """Colours of ``values`` on [lo, hi]; a degenerate range gives the scale's middle colour."""
    if hi - lo <= CONSTANT * max(abs(hi), abs(lo), DIVISION_FLOOR):
        return cmap_colors(cmap, np.full(values.shape, 0.5))
    return cmap_colors(cmap, np.clip((values - lo) / (hi - lo), 0.0, 1.0))


def view_state(
    model,
    alpha: float,
    *,
    coloring: str = "crease kind",
    vertices=None,
    thick=None,
    solids: bool = False,
) -> ViewState:
    """The arrays of ``model`` deployed to ``alpha`` degrees, coloured by ``coloring``.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    alpha : float
    coloring : str
        One of :data:`COLORINGS`.
    vertices : (p, v, 3) float, optional
        Plate vertices to draw instead of the kinematic state (a relaxed state).
    thick : compas_ccu.thickness.ThickModel, optional
        For the bending utilisation and the thick solids.
    solids : bool
        Also the thick solids (vertices, triangles) of every plate.

    Raises
    ------
    ValueError
        An unknown ``coloring``.
    """
    if coloring not in COLORINGS:
        raise ValueError(f"coloring must be one of {', '.join(COLORINGS)}, got {coloring!r}")
    structure = model.deploy(alpha, check=False)
    if vertices is None:
        vertices = structure.deployed
    p, v = vertices.shape[:2]
    n = model.segments
    rows = _crease_rows(model)
    creases = np.stack([vertices[pos, r] for pos, r in rows]) if rows else np.zeros((0, n + 1, 3))
    segments = np.stack([creases[:, :-1], creases[:, 1:]], axis=2)
    ruling_index = plate_rulings(n)
    rulings = vertices[:, ruling_index]
    tones = np.array([_rgb(C.plate_tone(i)) for i in range(p)], dtype=np.uint8)
    plate_colors = tones
    legend: dict
    c = len(rows)
    if coloring == "crease kind":
        kinds = [k for k, _, _ in model.crease_kinds()]
        colors = np.array([_rgb(C.kind_color(k)) for k in kinds], dtype=np.uint8).reshape(c, 3)
        crease_colors = np.repeat(colors[:, None], n, axis=1)
        seen = list(dict.fromkeys(kinds))
        legend = {
            "title": "crease kind",
            "rows": [
                (_rgb(C.kind_color(k)), f"{C.KIND_LABELS.get(k, k)}: {kinds.count(k)}")
                for k in seen
            ],
        }
    elif coloring == "bending utilisation":
        crease_colors = np.zeros((c, n, 3), dtype=np.uint8) + np.array(_rgb(C.EDGE_COLOR), np.uint8)
        if thick is None:
            legend = {"title": "bending utilisation", "note": "thick plates not modelled"}
        else:
            u = thick.bending([alpha]).per_plate[0]
            hi = max(1.0, float(u.max()))
            plate_colors = cmap_colors("viridis", np.clip(u / hi, 0.0, 1.0))
            plate_colors[u > 1.0] = _rgb("#d62728")
            ids = model.plate_ids
            legend = {
                "title": f"bending utilisation at α = {alpha:.4g}° ({thick.material.name}, "
                f"t = {thick.thickness * 1000:.3g} mm)",
                "scale": ("viridis", 0.0, hi, ""),
                "rows": [
                    (tuple(int(x) for x in plate_colors[i]), f"plate {ids[i]}: {u[i]:.3f}")
                    for i in range(p)
                ],
                "note": "each plate in the colour of its largest utilisation; red: above 1",
            }
    elif coloring == "reflection angle":
        alphas = np.array([cr["alpha"] for cr in structure.creases], dtype=float).reshape(c, n + 1)
        mid = 0.5 * (alphas[:, :-1] + alphas[:, 1:])
        finite = mid[np.isfinite(mid)]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
        crease_colors = _scale_colors(np.nan_to_num(mid, nan=lo), lo, hi, C.ANGLE_CMAP)
        constant = hi - lo <= CONSTANT * max(abs(hi), DIVISION_FLOOR)
        legend = {
            "title": "reflection angle α along the creases",
            **(
                {
                    "rows": [
                        (
                            tuple(int(x) for x in crease_colors.reshape(-1, 3)[0]),
                            f"constant {lo:.4f}°",
                        )
                    ]
                }
                if constant
                else {"scale": (C.ANGLE_CMAP, lo, hi, "°")}
            ),
        }
    else:  # crease planarity
        values = np.array([cr["planarity"] for cr in structure.creases], dtype=float)
        hi = float(values.max()) if values.size else 0.0
        if hi <= PLANAR * model.size:
            color = np.array(_rgb(C.KIND_COLORS["ccf"]), np.uint8)
            crease_colors = np.zeros((c, n, 3), np.uint8) + color
            legend = {
                "title": "crease planarity",
                "rows": [(tuple(int(x) for x in color), f"every crease planar (≤ {hi:.1e} m)")],
            }
        else:
            crease_colors = np.repeat(_scale_colors(values, 0.0, hi, "viridis")[:, None], n, axis=1)
            legend = {
                "title": "crease planarity: largest distance from the crease plane",
                "scale": ("viridis", 0.0, hi * 1000, " mm"),
            }
    state = ViewState(
        alpha=float(alpha),
        vertices=vertices,
        triangles=_triangles(model.faces),
        plate_colors=plate_colors,
        creases=segments,
        crease_colors=crease_colors,
        rulings=rulings,
        span=structure.metrics["span"],
        rise=structure.metrics["rise"],
        legend=legend,
        plate_ids=list(model.plate_ids),
    )
    if solids and thick is not None:
        st = thick.deploy(alpha)
        order = model.plates.order
        state.solids = [solid_mesh(st.solids[i, 0], st.solids[i, 1]) for i in range(len(order))]
    return state


def _hex(rgb) -> str:
    r, g, b = (int(x) for x in rgb)
    return f"#{r:02x}{g:02x}{b:02x}"


def legend_html(legend: dict) -> str:
    """The legend as HTML: swatches with their values, or a colour scale with its end values."""
    parts = [f"<div style='font-size:0.85em'><b>{html.escape(legend['title'])}</b>"]
    scale = legend.get("scale")
    if scale is not None:
        name, lo, hi, unit = scale
        stops = cmap_colors(name, np.linspace(0.0, 1.0, 9))
        grad = ", ".join(_hex(s) for s in stops)
        parts.append(
            f"<div style='height:10px;background:linear-gradient(to right, {grad});"
            f"border:1px solid #999;margin:3px 0'></div>"
            f"<div style='display:flex;justify-content:space-between'>"
            f"<span>{lo:.4g}{unit}</span><span>{0.5 * (lo + hi):.4g}{unit}</span>"
            f"<span>{hi:.4g}{unit}</span></div>"
        )
    for rgb, text in legend.get("rows", []):
        parts.append(
            f"<div><span style='display:inline-block;width:12px;height:12px;background:"
            f"{_hex(rgb)};border:1px solid #666;margin-right:5px;vertical-align:middle'></span>"
            f"{html.escape(text)}</div>"
        )
    if legend.get("note"):
        parts.append(f"<div style='color:#666'>{html.escape(legend['note'])}</div>")
    parts.append("</div>")
    return "".join(parts)


def cut_patterns_svg(model, *, sheet=SHEET, width: int = 560) -> tuple:
    """The cut patterns laid out in rows, with plate labels and a stock sheet for scale.

    Returns
    -------
    svg : str
    too_large : list of int
        Plate ids whose cut pattern does not fit on ``sheet`` (in any orientation).
    """
    flat = model.flat()
    ids = model.plate_ids
    offsets = pattern_layout(flat)
    outlines = [plate_outline(f) + o for f, o in zip(flat, offsets)]
    fits = fits_sheet(plate_rectangles(flat), sheet)
    too_large = [pid for pid, ok in zip(ids, fits) if not ok]
    pts = np.concatenate(outlines)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    gap = 0.05 * float(max(hi - lo))
    sheet_origin = np.array([lo[0], lo[1] - gap - sheet[1]])
    lo = np.minimum(lo, sheet_origin) - gap
    hi = np.maximum(hi, sheet_origin + sheet) + gap
    size = hi - lo
    scale = width / size[0]
    height = int(round(size[1] * scale))

    def xy(points):
        q = (np.asarray(points) - lo) * scale
        return " ".join(f"{x:.1f},{height - y:.1f}" for x, y in q)

    out = [
        f"<svg xmlns='http://www.w3.org/2000/svg' width='100%' viewBox='0 0 {width} {height}' "
        "style='background:#fbfaf7'>"
    ]
    n = model.segments
    rulings = plate_rulings(n)
    for k, (pid, ring, f, o) in enumerate(zip(ids, outlines, flat, offsets)):
        fill = "#f3c6c6" if pid in too_large else C.plate_tone(k)
        out.append(
            f"<polygon points='{xy(ring)}' fill='{fill}' stroke='#3b3326' stroke-width='1'/>"
        )
        step = max(1, n // 16)
        for j in range(0, n + 1, step):
            seg = f[rulings[j], :2] + o
            out.append(
                f"<polyline points='{xy(seg)}' stroke='#9a8c74' stroke-width='0.5' fill='none'/>"
            )
        c = (ring.mean(axis=0) - lo) * scale
        out.append(
            f"<text x='{c[0]:.1f}' y='{height - c[1]:.1f}' font-size='13' text-anchor='middle' "
            f"font-family='sans-serif' fill='#222'>{pid}</text>"
        )
    s0 = (sheet_origin - lo) * scale
    out.append(
        f"<rect x='{s0[0]:.1f}' y='{height - s0[1] - sheet[1] * scale:.1f}' "
        f"width='{sheet[0] * scale:.1f}' height='{sheet[1] * scale:.1f}' fill='none' "
        f"stroke='#1f63d6' stroke-dasharray='6 3'/>"
        f"<text x='{s0[0] + 4:.1f}' y='{height - s0[1] - 4:.1f}' font-size='11' "
        f"font-family='sans-serif' fill='#1f63d6'>stock sheet {sheet[0] * 1000:.0f} × "
        f"{sheet[1] * 1000:.0f} mm</text>"
    )
    out.append("</svg>")
    return "".join(out), too_large
