"""The offline viewer: one self-contained HTML page to explore a deployment in 3D.

:func:`viewer_figure` builds a plotly figure of a model along its deployment path, from the
flat-folded stack (α = 0) to a target angle: plates, creases coloured by kind, rulings and
(hidden at first) the cut patterns laid out on the ground behind the structure, or the sheets of
the fabrication output with every part at its nested place (``sheets=``: a workshop plan or the
``sheets.json`` that ``ccu fabricate`` writes). A slider (with
Play / Pause) moves through the states; toggle buttons show and hide plates,
creases, rulings and cut patterns. :func:`write_viewer` writes it as a single HTML file that works
offline (plotly.js is bundled, nothing is loaded from the network).

Everything is drawn from :func:`compas_ccu.viz.scene.scene_from_structure` in the colours of
:mod:`compas_ccu.viz.colors`, like every other picture of the package. Plotly is imported only
when a figure is built.
"""

from __future__ import annotations

import math
from html import escape as html_escape
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.key_figures import state_figures
from compas_ccu.kinematics.plates import plate_rulings
from compas_ccu.tolerances import EXACT_RELATIVE
from compas_ccu.viz.colors import (
    EDGE_COLOR,
    KIND_COLORS,
    KIND_LABELS,
    RULING_COLOR,
    plate_tone,
)
from compas_ccu.viz.render import camera
from compas_ccu.viz.scene import scene_from_structure
from compas_ccu.viz.views import readout

if TYPE_CHECKING:  # plotly is imported when a figure is built, not with this module
    import plotly.graph_objects as go

__all__ = [
    "viewer_figure",
    "write_viewer",
    "cut_pattern_layout",
    "sheet_grid_layout",
    "sheet_document",
    "VIEWER_DIV_ID",
]

VIEWER_DIV_ID = "ccu-viewer"
"""``id`` of the plot ``<div>`` in the page written by :func:`write_viewer`."""

_KIND_ORDER = ("synclastic", "anticlastic", "ccf", "mixed")
_MAX_RULINGS = 32  # rulings drawn per plate (every k-th ruling, both ends always)
_PAD = 0.04  # axis padding, fraction of the largest extent
_PAPER = "#ffffff"
_PANE = "#f3f1ec"
_GRID = "#dedad2"
_FONT = "#2b2b2b"
_PATTERN_TAG = "cut pattern"
_SLIDER_LABELS = 6  # slider steps labelled (about; the ends always)
_BOARD = "#dfe3e6"  # the sheets (stock boards) under the nested parts
_BOARD_EDGE = "#5d6468"
_MARK_COLOR = "#7a6a52"  # where the splice plates go (engraved)

_ON, _OFF = "☑", "☐"
_TOGGLES = (
    ("plates", "Plates"),
    ("creases", "Creases"),
    ("rulings", "Rulings"),
    ("cut", "Cut patterns"),
)
# legend groups: the first three change with the state, the cut patterns are static
_GROUPS = ("plates", "creases", "rulings", "cut")


# -- geometry helpers (vectorised) -----------------------------------------------------------
def _f32(a) -> np.ndarray:
    """Coordinates for display: float32 (≲ 1e-6 m for structures up to ~10 m), NaN gaps."""
    return np.ascontiguousarray(a, dtype=np.float32)


def _polylines(lines) -> np.ndarray:
    """(m, 3) points of several polylines, each followed by a NaN row (a gap in the line).

    Parameters
    ----------
    lines : sequence of (k_i, 3) float, or (q, k, 3) float

    Returns
    -------
    (sum(k_i + 1), 3) float
    """
    if isinstance(lines, np.ndarray) and lines.ndim == 3:
        q, k, _ = lines.shape
        out = np.full((q, k + 1, 3), np.nan)
        out[:, :k] = lines
        return out.reshape(-1, 3)
    if len(lines) == 0:
        return np.zeros((0, 3))
    gap = np.full((1, 3), np.nan)
    return np.concatenate([np.concatenate([np.asarray(pts, float), gap]) for pts in lines])


def _outline_index(n: int) -> np.ndarray:
    """(2n + 3,) vertex order of a closed plate outline: near 0..n, far 2n+1..n+1, back to 0."""
    return np.r_[np.arange(n + 1), np.arange(2 * n + 1, n, -1), 0]


def _ruling_index(n: int) -> np.ndarray:
    """Rulings drawn: at most ``_MAX_RULINGS`` per plate, evenly spaced, both ends included."""
    count = min(n + 1, _MAX_RULINGS)
    return np.unique(np.round(np.linspace(0, n, count)).astype(int))


def _triangles(faces: np.ndarray, v: int) -> np.ndarray:
    """(2 p n, 3) triangle indices into the (p v,) stacked vertices, two per quad.

    Parameters
    ----------
    faces : (p, n, 4) int
        Quad vertex indices per plate.
    v : int
        Vertices per plate.
    """
    p = faces.shape[0]
    glob = faces + (np.arange(p) * v)[:, None, None]
    tri = np.stack([glob[..., [0, 1, 2]], glob[..., [0, 2, 3]]], axis=2)  # (p, n, 2, 3)
    return tri.reshape(-1, 3)


def _envelopes(outline: np.ndarray, xs: np.ndarray):
    """Lowest and highest ``y`` of a closed 2D polygon along vertical lines ``x = xs``.

    Parameters
    ----------
    outline : (m, 2) float
        Closed polygon (first point repeated last).
    xs : (g,) float

    Returns
    -------
    lower, upper : (g,) float
        NaN where the line misses the polygon.
    """
    a, b = outline[:-1], outline[1:]
    x0, x1 = a[:, 0:1], b[:, 0:1]
    lo, hi = np.minimum(x0, x1), np.maximum(x0, x1)
    hit = (xs >= lo) & (xs <= hi) & (hi > lo)  # (m - 1, g)
    t = np.where(hit, (xs - x0) / np.where(hi > lo, x1 - x0, 1.0), 0.0)
    y = a[:, 1:2] + t * (b[:, 1:2] - a[:, 1:2])
    with np.errstate(invalid="ignore"):
        lower = np.where(hit, y, np.inf).min(axis=0)
        upper = np.where(hit, y, -np.inf).max(axis=0)
    miss = ~hit.any(axis=0)
    lower[miss] = np.nan
    upper[miss] = np.nan
    return lower, upper


def _pattern_offsets(flat: np.ndarray, n: int, gap: float) -> np.ndarray:
    """(p,) downward shifts (−y) that lay the cut patterns one below the other without overlap.

    Each plate drops (in −y) until it is ``gap`` below everything placed before it, measured
    along vertical lines, so nesting shapes (arcs in arcs) pack closely and others stack.

    Parameters
    ----------
    flat : (p, v, 3) float
        Cut patterns (z = 0), all in the same plane coordinates.
    n : int
        Segments per plate.
    gap : float
        Clearance between patterns, metres.
    """
    outlines = flat[:, _outline_index(n), :2]
    xs = np.linspace(outlines[..., 0].min(), outlines[..., 0].max(), 512)
    floor = np.full(xs.shape, np.inf)  # lowest placed point along each vertical line
    offsets = np.zeros(len(flat))
    for i, outline in enumerate(outlines):
        lower, upper = _envelopes(outline, xs)
        both = np.isfinite(upper) & np.isfinite(floor)
        if i > 0:
            if both.any():
                offsets[i] = float(np.min(floor[both] - upper[both])) - gap
            else:
                offsets[i] = float(np.nanmin(floor)) - float(np.nanmax(upper)) - gap
        inside = np.isfinite(lower)
        floor[inside] = np.minimum(floor[inside], lower[inside] + offsets[i])
    return offsets


def cut_pattern_layout(flat: np.ndarray, n: int, *, gap: float, beside=None) -> np.ndarray:
    """(p, 2) translations that lay the cut patterns out compactly, without overlap.

    The plates are split into columns of consecutive plates; in every column each plate
    drops (−y) until it is ``gap`` below the plates above it (:func:`_pattern_offsets`: arcs
    nest in arcs), and the columns stand side by side, ``gap`` apart. The number of columns is
    the one that makes the whole picture (the structure's plan ``beside`` and the block in
    front of it) most nearly square, the smallest larger side: many plates neither make one
    long row nor one long column, and the structure beside them stays large on the screen.

    This is the viewer's own layout; it is kept apart from the figure so that the sheet
    nesting of the fabrication output can replace it (``viewer_figure(pattern_offsets=...)``).

    Parameters
    ----------
    flat : (p, v, 3) float
        Cut patterns (z = 0), all in the same plane coordinates (the flat-folded stack).
    n : int
        Segments per plate.
    gap : float
        Clearance between patterns, metres.
    beside : (float, float), optional
        Plan width (x) and depth (y) of the structure the block lies beside (behind it, +y, in
        the viewer); default: none (the block alone is made square).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> s = load_model("examples/vault.toml").deploy()
    >>> off = cut_pattern_layout(np.asarray(s.flat), 64, gap=0.1)
    >>> off.shape
    (10, 2)
    """
    flat = np.asarray(flat, dtype=float)
    p = len(flat)
    best = None
    for columns in range(1, p + 1):
        rows = math.ceil(p / columns)
        if columns > 1 and math.ceil(p / (columns - 1)) == rows:
            continue  # same rows as fewer columns
        offsets = np.zeros((p, 2))
        x = 0.0
        for start in range(0, p, rows):
            part = slice(start, min(p, start + rows))
            offsets[part, 1] = _pattern_offsets(flat[part], n, gap)
            lo = float(flat[part, :, 0].min())
            offsets[part, 0] = x - lo
            x += float(flat[part, :, 0].max()) - lo + gap
        moved = flat[..., :2] + offsets[:, None, :]
        width, depth = np.ptp(moved.reshape(-1, 2), axis=0)
        if beside is not None:
            width, depth = max(width, beside[0]), depth + beside[1] + 2.0 * gap
        side = float(max(width, depth))
        if best is None or side < best[0] - 1e-9:
            best = (side, offsets)
    return best[1]


def sheet_grid_layout(sizes, *, gap: float, structure=None) -> np.ndarray:
    """(s, 2) corners that lay the sheets out in a grid around the structure's plan.

    The sheets go into cells of one size (the largest sheet plus ``gap``), in rows from the
    front of the structure (its lowest y) backwards and, in every row, from left to right; a
    cell that would overlap the structure's plan (widened by half a gap) is skipped, so the
    sheets fill the ground beside and behind the structure. The grid is centred on the
    structure in x, and its number of columns is the one that makes the whole picture (the
    structure and the sheets) most nearly square, the smallest larger side: the structure stays
    large on the screen and the sheets neither make one long row nor one long column.

    Parameters
    ----------
    sizes : (s, 2) float
        Sheet length (x) and width (y), m, in sheet order.
    gap : float
        Clearance between sheets (and between the sheets and the structure), m.
    structure : (float, float, float, float), optional
        The structure's plan box ``(x0, y0, x1, y1)``; default none (a grid alone, from the
        origin).

    Returns
    -------
    (s, 2) float
        Where each sheet's corner (its origin, the sheet DXF's (0, 0)) lies.

    Examples
    --------
    >>> corners = sheet_grid_layout([[2.5, 1.25]] * 8, gap=0.1, structure=(0, 0, 2.7, 2.6))
    >>> corners.shape, np.ptp(corners, axis=0).round(2).tolist()
    ((8, 2), [5.2, 2.7])
    """
    sizes = np.asarray(sizes, dtype=float).reshape(-1, 2)
    count = len(sizes)
    if count == 0:
        return np.zeros((0, 2))
    gap = float(gap)
    cell = sizes.max(axis=0) + gap
    if structure is None:
        box = None
        cx, y0 = 0.0, 0.0
    else:
        box = np.asarray(structure, dtype=float)
        cx, y0 = 0.5 * (box[0] + box[2]), float(box[1])
        wide = box + np.array([-0.5, -0.5, 0.5, 0.5]) * gap
    span = 0 if box is None else int(math.ceil((box[2] - box[0]) / cell[0])) + 2
    best = None
    for columns in range(1, count + span + 1):
        x0 = 0.0 if box is None else cx - 0.5 * columns * cell[0]
        corners, row = [], 0
        while len(corners) < count:
            ys = y0 + row * cell[1]
            for c in range(columns):
                xs = x0 + c * cell[0]
                if box is not None and (
                    xs < wide[2]
                    and xs + cell[0] > wide[0]
                    and ys < wide[3]
                    and ys + cell[1] > wide[1]
                ):
                    continue  # the structure stands there
                corners.append((xs + 0.5 * gap, ys + 0.5 * gap))
                if len(corners) == count:
                    break
            row += 1
            if row > count + span + 64:  # pragma: no cover - every row beyond the plan is free
                break
        corners = np.asarray(corners)
        lo, hi = corners.min(axis=0), (corners + sizes).max(axis=0)
        if box is not None:
            lo, hi = np.minimum(lo, box[:2]), np.maximum(hi, box[2:])
        side = float(max(hi - lo))
        if best is None or side < best[0] - 1e-9:
            best = (side, corners)
    return best[1]


def sheet_document(sheets, plate_ids=None, *, design=None) -> dict:
    """The nesting to show: a workshop plan's :meth:`layout` or a ``sheets.json`` document,
    checked.

    Parameters
    ----------
    sheets : dict or object with a ``layout()`` method
        ``compas_ccu.fabrication.workshop.WorkshopPlan`` or its ``layout()`` (the
        ``sheets.json`` that ``ccu fabricate`` writes, parsed).
    plate_ids : sequence of int, optional
        The model's plate ids: the document's ``model_plate_ids`` must be the same plates.
    design : str, optional
        The model's design name: a document of another design is refused.

    Returns
    -------
    dict
        The document, with ``tone_index`` added to every part (the index of its plate in
        ``plate_ids``, for its colour).

    Raises
    ------
    compas_ccu.errors.OptionError
        Not a nesting document (no ``sheets`` / ``parts`` lists), another design, other
        plates, or a part on a sheet that does not exist (the message names it).

    Examples
    --------
    >>> doc = {"sheets": [{"size": [2.0, 1.0], "utilisation": 0.5, "parts": ["P0"]}],
    ...        "parts": [{"name": "P0", "plate": 0, "sheet": 0,
    ...                   "outline": [[0.1, 0.1], [1.0, 0.1], [1.0, 0.9], [0.1, 0.9]]}]}
    >>> sheet_document(doc, [0])["parts"][0]["tone_index"]
    0
    """
    if hasattr(sheets, "layout") and callable(sheets.layout):
        sheets = sheets.layout()
    if not isinstance(sheets, dict):
        raise OptionError(
            f"sheets must be a workshop plan or its layout (sheets.json), got "
            f"{type(sheets).__name__}"
        )
    missing = [k for k in ("sheets", "parts") if not isinstance(sheets.get(k), list)]
    if missing:
        raise OptionError(
            f"sheets: the nesting document has no {' and no '.join(missing)} list (is it the "
            "sheets.json that ccu fabricate writes?)"
        )
    name = sheets.get("design")
    if design is not None and name is not None and name != design:
        raise OptionError(f"sheets: the nesting is of design {name!r}, not of {design!r}")
    count = len(sheets["sheets"])
    model = sheets.get("model_plate_ids")
    if plate_ids is not None:
        plate_ids = [int(v) for v in plate_ids]
        if model is not None and sorted(int(v) for v in model) != sorted(plate_ids):
            raise OptionError(
                f"sheets: the nesting is of {len(model)} plates {sorted(model)}, the model has "
                f"{len(plate_ids)} plates {sorted(plate_ids)}"
            )
    index = {pid: i for i, pid in enumerate(plate_ids or [])}
    parts = []
    for part in sheets["parts"]:
        k = part.get("sheet")
        if not isinstance(k, int) or not 0 <= k < count:
            raise OptionError(
                f"sheets: part {part.get('name')!r} is on sheet {k!r}, but there are {count} sheets"
            )
        outline = np.asarray(part.get("outline", []), dtype=float)
        if outline.ndim != 2 or outline.shape[0] < 3 or outline.shape[1] != 2:
            raise OptionError(
                f"sheets: part {part.get('name')!r} has no outline of at least 3 points (x, y)"
            )
        plate = int(part.get("plate", 0))
        if model is not None and plate_ids is not None:
            if not 0 <= plate < len(model):
                raise OptionError(
                    f"sheets: part {part.get('name')!r} is of plate {plate}, but the nesting "
                    f"has {len(model)} plates"
                )
            tone = index[int(model[plate])]
        else:
            tone = plate
        parts.append({**part, "tone_index": tone})
    return {**sheets, "parts": parts}


def _strip_triangles(m: int) -> np.ndarray:
    """(t, 3) triangles of a part outline of ``m`` points.

    An even outline is a strip of quads between rulings (its near row ``0 .. k``, then its far
    row back, ``m = 2k + 2``), as the parts of the workshop are: two triangles per quad, so the
    crescents of a vault fill correctly. Any other outline is filled as a fan from its first
    point (right for convex outlines).
    """
    if m >= 4 and m % 2 == 0:
        j = np.arange(m // 2 - 1)
        a = np.stack([j, j + 1, m - 2 - j], axis=1)
        b = np.stack([j, m - 2 - j, m - 1 - j], axis=1)
        return np.concatenate([a, b])
    j = np.arange(1, m - 1)
    return np.stack([np.zeros_like(j), j, j + 1], axis=1)


def _sheet_traces(doc: dict, corners: np.ndarray, z: float, kinds: list, tones: list) -> list:
    """The traces of the nested sheets (legend group ``cut``), in the plane ``z``.

    Parts first (their fill: the first ``cut`` trace), then the boards, the sheet edges, the
    part outlines, the creases by kind, the score lines, the splice marks and the labels.
    Coordinates are float64: every part lies exactly at its nested place plus its sheet's
    corner.
    """
    import plotly.graph_objects as go

    def at(points, sheet, dz=0.0) -> np.ndarray:
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        out = np.empty((len(pts), 3))
        out[:, :2] = pts + corners[sheet]
        out[:, 2] = z + dz
        return out

    parts = doc["parts"]
    dz = 1e-3 * max(1.0, float(np.ptp(corners, axis=0).max()) if len(corners) else 1.0)
    verts, tri, colors, text = [], [], [], []
    base = 0
    for part in parts:
        pts = at(part["outline"], part["sheet"], -dz)
        t = _strip_triangles(len(pts))
        verts.append(pts)
        tri.append(t + base)
        base += len(pts)
        colors += [tones[part["tone_index"] % len(tones)]] * len(t)
        text += [f"{part.get('name', '')} · sheet {part['sheet'] + 1}"] * len(pts)
    verts = np.concatenate(verts) if verts else np.zeros((0, 3))
    tri = np.concatenate(tri) if tri else np.zeros((0, 3), dtype=int)
    sheets = doc["sheets"]
    traces = [
        _cut_mesh(
            _xyz64(verts),
            tri,
            f"cut patterns: {len(sheets)} sheets, {len(parts)} parts",
            text,
            facecolor=colors,
        )
    ]
    rects, boards, board_text = [], [], []
    for k, sheet in enumerate(sheets):
        length, width = (float(v) for v in sheet["size"])
        corner = [[0.0, 0.0], [length, 0.0], [length, width], [0.0, width]]
        rects.append(at(corner + corner[:1], k))
        boards.append(at(corner, k, -2.0 * dz))
        u = float(sheet.get("utilisation", 0.0))
        t = float(sheet.get("thickness") or 0.0)
        thick = f" × {t * 1000:g}" if t > 0.0 else ""
        board_text += [
            f"sheet {k + 1}: {length * 1000:g} × {width * 1000:g}{thick} mm, utilisation "
            f"{100 * u:.1f} %"
        ] * 4
    quads = np.arange(len(sheets))[:, None] * 4
    board_tri = np.concatenate([quads + [0, 1, 2], quads + [0, 2, 3]]) if len(sheets) else []
    board_tri = np.asarray(board_tri, dtype=np.int32).reshape(-1, 3)
    traces.append(
        _cut_mesh(
            _xyz64(np.concatenate(boards) if boards else np.zeros((0, 3))),
            board_tri,
            "sheets",
            board_text,
            legend=False,
            color=_BOARD,
        )
    )
    traces.append(_line_trace64(_polylines(rects), "sheet edges", _BOARD_EDGE, 3))
    outlines = [at(np.r_[o, o[:1]], p["sheet"]) for p in parts for o in [np.asarray(p["outline"])]]
    traces.append(_line_trace64(_polylines(outlines), "part outlines", EDGE_COLOR, 2))
    for kind in kinds:
        lines = [
            at(c["points"], p["sheet"])
            for p in parts
            for c in p.get("creases", [])
            if c.get("kind") == kind
        ]
        if lines:
            traces.append(
                _line_trace64(
                    _polylines(lines), f"sheets: {kind}", KIND_COLORS.get(kind, EDGE_COLOR), 5
                )
            )
    score = [at(line, p["sheet"]) for p in parts for line in p.get("score", [])]
    if score:
        traces.append(_line_trace64(_polylines(score), "score lines", RULING_COLOR, 1.5))
    marks = [
        at(np.r_[m, m[:1]], p["sheet"])
        for p in parts
        for m in (np.asarray(r, dtype=float) for r in p.get("marks", []))
    ]
    if marks:
        traces.append(_line_trace64(_polylines(marks), "splice marks", _MARK_COLOR, 1.5))
    centres = [at(np.asarray(p["outline"], dtype=float).mean(axis=0), p["sheet"]) for p in parts]
    traces.append(
        go.Scatter3d(
            **_xyz64(np.concatenate(centres) if centres else np.zeros((0, 3))),
            mode="text",
            text=[str(p.get("name", "")) for p in parts],
            textfont={"size": 10, "color": _FONT},
            name="part names",
            legendgroup="cut",
            showlegend=False,
            hoverinfo="skip",
        )
    )
    # at the front-left corner of every sheet (the nearest to the default camera, so that the
    # sheet behind the text on the screen does not hide it), lifted over the parts' lines
    labels = [at([0.0, 0.0], k, 10.0 * dz)[0] for k in range(len(sheets))]
    traces.append(
        go.Scatter3d(
            **_xyz64(np.asarray(labels).reshape(-1, 3)),
            mode="text",
            text=[
                f"sheet {k + 1} · {100 * float(sheet.get('utilisation', 0.0)):.0f} %"
                for k, sheet in enumerate(sheets)
            ],
            textposition="top right",
            textfont={"size": 11, "color": _BOARD_EDGE},
            name="sheet numbers",
            legendgroup="cut",
            showlegend=False,
            hoverinfo="skip",
        )
    )
    return traces


_DEFAULT_CAMERA = {
    "eye": {"x": 0.7, "y": -1.05, "z": 0.5},
    "center": {"x": 0.0, "y": 0.0, "z": -0.08},
    "up": {"x": 0.0, "y": 0.0, "z": 1.0},
    "projection": {"type": "perspective"},
}
_READOUT_NAME = "ccu-readout"


def _readout_annotation(text: str) -> dict:
    """The state read-out above the slider (α, span, rise, plate length)."""
    return {
        "name": _READOUT_NAME,
        "text": text,
        "xref": "paper",
        "yref": "paper",
        "x": 0.0,
        "y": 0.0,
        "xanchor": "left",
        "yanchor": "bottom",
        "yshift": 4,
        "showarrow": False,
        "font": {"size": 15, "color": _FONT},
        "bgcolor": "rgba(255,255,255,0.85)",
    }


def _readouts(structures) -> list:
    """One line per state: α, then span, rise and plate length (the state's key figures)."""
    return [f"α = {s.alpha:.4g}° · {readout(state_figures(s))}" for s in structures]


def _eye(view) -> dict:
    """A plotly scene camera for a view name or ``"azimuth,elevation"`` (see render.camera)."""
    cam = camera(view)
    az, el = math.radians(cam.azimuth), math.radians(cam.elevation)
    r = 1.9
    eye = {
        "x": r * math.cos(el) * math.cos(az),
        "y": r * math.cos(el) * math.sin(az),
        "z": r * math.sin(el),
    }
    up = {"x": 0.0, "y": 0.0, "z": 1.0}
    if abs(cam.elevation) > 89.0:  # from above: y up the screen
        up = {"x": 0.0, "y": 1.0, "z": 0.0}
    kind = "perspective" if cam.distance is not None else "orthographic"
    return {
        "eye": eye,
        "up": up,
        "center": {"x": 0.0, "y": 0.0, "z": 0.0},
        "projection": {"type": kind},
    }


def _range(lo: np.ndarray, hi: np.ndarray):
    """Padded axis ranges and the matching manual aspect ratio of a box (lo, hi : (3,))."""
    ext = np.maximum(hi - lo, EXACT_RELATIVE)
    pad = _PAD * float(ext.max())
    lo, hi = lo - pad, hi + pad
    ext = hi - lo
    ratio = ext / ext.max()
    ranges = [[float(a), float(b)] for a, b in zip(lo, hi)]
    return ranges, {"x": float(ratio[0]), "y": float(ratio[1]), "z": float(ratio[2])}


def _scene_layout(ranges, ratio) -> dict:
    """Relayout keys that set the 3D box (fixed ranges, manual aspect)."""
    out = {"scene.aspectmode": "manual", "scene.aspectratio": ratio}
    for name, r in zip("xyz", ranges):
        out[f"scene.{name}axis.range"] = r
    return out


# -- the figure ------------------------------------------------------------------------------
def _check_arguments(model, steps, alpha) -> float:
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
        raise OptionError(f"steps must be an integer >= 1, got {steps!r}")
    if alpha is None:
        return float(model.alpha_design)
    try:
        value = float(alpha)
    except (TypeError, ValueError):
        raise OptionError(f"alpha must be a number of degrees > 0, got {alpha!r}") from None
    if not math.isfinite(value) or value <= 0.0:
        raise OptionError(f"alpha must be a finite angle > 0 degrees, got {alpha!r}")
    return value


def _label(alpha: float) -> str:
    return f"{alpha:.4g}°"


def _edge_index(structure, n: int) -> np.ndarray:
    """(m,) gather index of the plate edges that no crease line draws, ``-1`` for a gap.

    Free boundaries (a near or far boundary that is not a crease) and the two end rulings of
    every plate, as polylines into the ``(p v, 3)`` stacked vertices.
    """
    p = len(structure.plate_ids)
    rulings = plate_rulings(n)
    v = rulings.size  # vertices of one plate
    index = {pid: i for i, pid in enumerate(structure.plate_ids)}
    near, far = rulings.T
    creased = set()
    for c in structure.creases:
        for plate, verts in zip(c["plates"], c["vertices"]):
            creased.add((index[plate], "near" if int(verts[0]) == 0 else "far"))
    parts = []
    for i in range(p):
        lines = [rulings[0], rulings[-1]]  # the two end rulings
        lines += [b for name, b in (("near", near), ("far", far)) if (i, name) not in creased]
        parts += [np.r_[i * v + line, -1] for line in lines]
    return np.concatenate(parts)


def _gather(points: np.ndarray, index: np.ndarray) -> np.ndarray:
    """(m, 3) rows ``points[index]``, NaN where ``index < 0``."""
    out = points[np.maximum(index, 0)].astype(float)
    out[index < 0] = np.nan
    return out


def _state_data(scene, edges: np.ndarray, rulings_at: np.ndarray, kinds: list) -> dict:
    """Coordinates of the state-dependent traces of one grounded scene.

    Parameters
    ----------
    scene : compas_ccu.viz.scene.Scene
    edges : (m,) int
        :func:`_edge_index` of the structure.
    rulings_at : (r,) int
        Rulings drawn per plate.
    kinds : list of str
        Crease kinds, one trace each.

    Returns
    -------
    dict
        ``plates`` (p v, 3), ``edges`` (m, 3), ``rulings`` (3 p r, 3) and one ``(.., 3)`` array
        per crease kind (NaN rows separate polylines).
    """
    p, v, _ = scene.vertices.shape
    stacked = scene.vertices.reshape(p * v, 3)
    out = {
        "plates": stacked,
        "edges": _gather(stacked, edges),
        "rulings": _polylines(scene.rulings[:, rulings_at].reshape(-1, 2, 3)),
    }
    for kind in kinds:
        out[kind] = _polylines([c["points"] for c in scene.creases if c["kind"] == kind])
    return out


def _line_trace(points, name: str, group: str, color: str, width: float, *, legend=True):
    """A plotly line trace (NaN rows break the line) in a legend group, without hover."""
    import plotly.graph_objects as go

    return go.Scatter3d(
        **_xyz(points),
        mode="lines",
        name=name,
        legendgroup=group,
        showlegend=legend,
        line={"color": color, "width": width},
        hoverinfo="skip",
    )


def _xyz64(points: np.ndarray) -> dict:
    """Coordinates kept as float64 (the sheets: every part exactly at its nested place)."""
    pts = np.ascontiguousarray(points, dtype=float)
    return {"x": pts[:, 0], "y": pts[:, 1], "z": pts[:, 2]}


def _line_trace64(points, name: str, color: str, width: float):
    """A line trace of the sheets (legend group ``cut``, float64, not in the legend)."""
    import plotly.graph_objects as go

    return go.Scatter3d(
        **_xyz64(points),
        mode="lines",
        name=name,
        legendgroup="cut",
        showlegend=False,
        line={"color": color, "width": width},
        hoverinfo="skip",
    )


def _xyz(points: np.ndarray) -> dict:
    pts = _f32(points)
    return {"x": pts[:, 0], "y": pts[:, 1], "z": pts[:, 2]}


def _title(model, kinds: list, counts: dict, alphas: np.ndarray) -> dict:
    name = getattr(model.design, "name", None) or "design"
    ncreases = sum(counts.values())
    by_kind = ", ".join(f"{counts[k]} {k}" for k in kinds)
    plates = len(model.plate_ids)
    sub = (
        f"{plates} plates · {ncreases} creases ({by_kind}) · design α = "
        f"{model.alpha_design:.4g}° · deployment limit α = {model.alpha_limit:.4g}° · "
        f"path α = 0° → {alphas[-1]:.4g}° in {len(alphas) - 1} steps"
    )
    return {
        "text": f"<b>{name}</b> — curved-crease unfolding",
        "subtitle": {"text": sub, "font": {"size": 13, "color": "#555555"}},
        "x": 0.01,
        "xanchor": "left",
        "y": 0.985,
        "yanchor": "top",
        "font": {"size": 20, "color": _FONT},
    }


#: Lighting of the cut patterns and the sheets: flat, as on a drawing.
_FLAT_LIGHT = {"ambient": 0.95, "diffuse": 0.05, "specular": 0.0}


def _cut_mesh(coordinates: dict, triangles, name: str, text, *, legend: bool = True, **colour):
    """A flat-lit Mesh3d of the ``"cut"`` group: ``coordinates`` (x, y, z), ``triangles``
    (t, 3) int, hover ``text`` per vertex, ``colour`` (``facecolor=`` or ``color=``)."""
    import plotly.graph_objects as go

    tri = np.asarray(triangles).reshape(-1, 3).astype(np.int32)
    return go.Mesh3d(
        **coordinates,
        i=tri[:, 0],
        j=tri[:, 1],
        k=tri[:, 2],
        flatshading=True,
        lighting=_FLAT_LIGHT,
        name=name,
        legendgroup="cut",
        showlegend=legend,
        text=text,
        hovertemplate="%{text}<extra></extra>",
        **colour,
    )


def viewer_figure(
    model,
    *,
    steps: int = 24,
    alpha: float | None = None,
    title: str | None = None,
    view=None,
    pattern_offsets=None,
    sheets=None,
) -> go.Figure:
    """Interactive 3D figure of a model along its deployment path, with slider and toggles.

    The states are ``numpy.linspace(0, alpha, steps + 1)``: from the flat-folded stack to the
    target; the figure opens on the last one. Every state is grounded (lowest point on
    ``z = 0``) and the axis ranges are fixed over all states, so the view does not jump. The cut
    patterns (hidden at first) lie on the ground behind the structure (+y, so that the
    structure stands in front of them, large), in the compact columns of
    :func:`cut_pattern_layout` (or at ``pattern_offsets``), none overlapping another; or, with
    ``sheets``, the fabrication's sheets with every part at its nested place, beside and behind
    the structure. Showing them widens the box to include them. A read-out under the scene
    gives α, span, rise and plate length of the state shown
    (:func:`compas_ccu.key_figures.state_figures`).

    Traces, in order: plates (Mesh3d, two triangles per quad, alternating plate tones), plate
    edges (free boundaries and plate ends, thin dark lines), one crease trace per kind present
    (wide, coloured and labelled by kind), rulings (at most 32 per plate), then the cut patterns
    (fill, outlines, creases by kind, rulings, plate ids; with ``sheets``: the parts' fill,
    boards, sheet edges, part outlines, creases by kind, score lines and splice marks if any,
    part names, sheet numbers). Every trace carries ``legendgroup``
    ``"plates"``, ``"creases"``, ``"rulings"`` or ``"cut"``; the animation frames update the
    coordinates of the structure's traces only. *Play* runs the whole path from α = 0.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    steps : int
        Number of steps of the path (``steps + 1`` states, ``steps >= 1``).
    alpha : float, optional
        Target reference reflection angle, degrees (``> 0``); default the design angle.
    title : str, optional
        Replaces the headline (the design name); the key figures stay below it.
    view : str, optional
        The opening camera: a view name of :func:`compas_ccu.viz.render.camera` (``iso``,
        ``front``, ``side``, ``top``, ...) or ``"azimuth,elevation"``; default a perspective
        from the front right.
    pattern_offsets : (p, 2) float, optional
        Where the cut patterns lie (translations of the flat-folded stack's plates); default
        :func:`cut_pattern_layout`.
    sheets : WorkshopPlan or dict, optional
        The fabrication's nesting: a ``compas_ccu.fabrication.workshop.WorkshopPlan`` or its
        ``layout()`` (the ``sheets.json`` of a ``ccu fabricate`` folder:
        :func:`compas_ccu.viz.record.read_sheets`). The cut patterns are then the sheets: every
        sheet (its board and edge, "sheet k · utilisation") in a grid around the structure
        (:func:`sheet_grid_layout`), every part at exactly its nested place (float64, the
        placement of the sheet DXFs), filled in its plate's tone, with its crease edges by
        kind, its score lines and splice marks if any, and its name.

    Returns
    -------
    plotly.graph_objects.Figure
        With ``steps + 1`` frames named ``"0" .. str(steps)``, one slider, Play / Pause buttons
        and one toggle menu per group.

    Raises
    ------
    compas_ccu.errors.OptionError
        ``steps`` is not an integer >= 1 or ``alpha`` is not a finite angle > 0 (the message
        names the value); ``sheets`` is no nesting, or one of another design or other plates
        (:func:`sheet_document`), or is given with ``pattern_offsets``.
    compas_ccu.errors.DeploymentLimitError, compas_ccu.errors.SelfIntersectionError
        ``alpha`` is beyond the deployment limit, or a crease overlaps itself on the way.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> fig = viewer_figure(model, steps=4)
    >>> len(fig.frames), fig.layout.sliders[0].active, fig.layout.sliders[0].steps[-1].label
    (5, 4, '40°')
    """
    import plotly.graph_objects as go

    target = _check_arguments(model, steps, alpha)
    doc = None
    if sheets is not None:  # checked before the path is computed
        if pattern_offsets is not None:
            raise OptionError("give sheets or pattern_offsets, not both")
        name = getattr(model.design, "name", None)
        doc = sheet_document(sheets, model.plate_ids, design=name)
    alphas = np.linspace(0.0, target, int(steps) + 1)
    structures = model.path(alphas)
    scenes = [scene_from_structure(s, ground=True) for s in structures]
    flat = scene_from_structure(structures[-1], state="flat")
    last = scenes[-1]
    p, v, _ = last.vertices.shape
    n = last.segments
    counts = structures[-1].crease_kind_counts()
    kinds = [k for k in _KIND_ORDER if k in counts] + sorted(
        k for k in counts if k not in _KIND_ORDER
    )
    rulings_at = _ruling_index(n)
    edges = _edge_index(structures[-1], n)
    data = [_state_data(s, edges, rulings_at, kinds) for s in scenes]

    # fixed box over all states; a wider one that includes the cut patterns
    allv = np.stack([s.vertices for s in scenes]).reshape(-1, 3)
    lo, hi = allv.min(axis=0), allv.max(axis=0)
    size = float(np.linalg.norm(hi - lo))
    fv = flat.vertices
    tones = [plate_tone(i) for i in range(p)]
    if doc is None:
        if pattern_offsets is None:
            beside = (float(hi[0] - lo[0]), float(hi[1] - lo[1]))
            pattern_offsets = cut_pattern_layout(fv, n, gap=0.02 * size, beside=beside)
        pattern_offsets = np.asarray(pattern_offsets, dtype=float)
        if pattern_offsets.shape != (p, 2):
            raise OptionError(
                f"pattern_offsets must have shape {(p, 2)} (one translation per plate), got "
                f"{pattern_offsets.shape}"
            )
        pattern = fv.copy()
        pattern[..., :2] += pattern_offsets[:, None, :]
        centre = 0.5 * (pattern[..., 0].min() + pattern[..., 0].max())
        shift = np.array(
            [0.5 * (lo[0] + hi[0]) - centre, hi[1] + 0.04 * size - pattern[..., 1].min(), 0.0]
        )
        pattern = pattern + shift
        pattern[..., 2] = 0.0
        extent = pattern.reshape(-1, 3)
    else:
        sizes = np.array([s["size"] for s in doc["sheets"]], dtype=float).reshape(-1, 2)
        corners = sheet_grid_layout(sizes, gap=0.04 * size, structure=(lo[0], lo[1], hi[0], hi[1]))
        sheet_kinds = {c.get("kind") for part in doc["parts"] for c in part.get("creases", [])}
        cut_kinds = kinds + sorted(k for k in sheet_kinds if k and k not in kinds)
        cut = _sheet_traces(doc, corners, 0.0, cut_kinds, tones)
        ends = np.concatenate([corners, corners + sizes]) if len(sizes) else np.zeros((0, 2))
        extent = np.c_[ends, np.zeros(len(ends))]
    struct_ranges, struct_ratio = _range(lo, hi)
    plo = np.minimum(lo, extent.min(axis=0)) if len(extent) else lo
    phi = np.maximum(hi, extent.max(axis=0)) if len(extent) else hi
    all_ranges, all_ratio = _range(plo, phi)

    tri = _triangles(last.faces, v)
    facecolor = np.repeat(tones, 2 * n)
    plate_text = np.repeat([f"plate {pid}" for pid in last.plate_ids], v)
    # mostly ambient, with a light from the front right: the arches shade from left to right
    lighting = {
        "ambient": 0.5,
        "diffuse": 0.5,
        "specular": 0.08,
        "roughness": 0.85,
        "fresnel": 0.05,
        "facenormalsepsilon": 0.0,
    }
    light = {"x": 1e4, "y": -5e3, "z": 5e3}

    def state_traces(d: dict) -> list:
        traces = [
            go.Mesh3d(
                **_xyz(d["plates"]),
                name="plates",
                legendgroup="plates",
                showlegend=True,
                flatshading=True,
                lighting=lighting,
                lightposition=light,
                text=plate_text,
                hovertemplate="%{text}<extra></extra>",
            ),
            _line_trace(d["edges"], "plate edges", "plates", EDGE_COLOR, 2, legend=False),
        ]
        for kind in kinds:
            traces.append(
                _line_trace(
                    d[kind],
                    KIND_LABELS.get(kind, kind),
                    "creases",
                    KIND_COLORS.get(kind, EDGE_COLOR),
                    7,
                )
            )
        traces.append(_line_trace(d["rulings"], "rulings", "rulings", RULING_COLOR, 1.5))
        return traces

    first = state_traces(data[-1])
    first[0].update(i=tri[:, 0].astype(np.int32), j=tri[:, 1].astype(np.int32))
    first[0].update(k=tri[:, 2].astype(np.int32), facecolor=facecolor)
    moving = list(range(len(first)))

    # cut patterns (static, hidden at first): the compact layout, or the sheets built above
    if doc is None:
        cut = [
            _cut_mesh(
                _xyz(pattern.reshape(-1, 3) - np.array([0.0, 0.0, 1e-3 * size])),
                tri,
                "cut patterns",
                np.char.add(plate_text, f" ({_PATTERN_TAG})"),
                facecolor=facecolor,
            ),
            _line_trace(
                _polylines(pattern[:, _outline_index(n)]),
                "cut outlines",
                "cut",
                EDGE_COLOR,
                2,
                legend=False,
            ),
        ]
        index = {pid: i for i, pid in enumerate(structures[-1].plate_ids)}
        for kind in kinds:
            lines = []
            for c in structures[-1].creases:
                if c["kind"] == kind:
                    for plate, verts in zip(c["plates"], c["vertices"]):
                        lines.append(pattern[index[plate], np.asarray(verts, dtype=int)])
            cut.append(
                _line_trace(
                    _polylines(lines),
                    f"cut: {kind}",
                    "cut",
                    KIND_COLORS.get(kind, EDGE_COLOR),
                    5,
                    legend=False,
                )
            )
        ends = plate_rulings(n)
        prul = pattern[:, ends[rulings_at]]
        mid = 0.5 * (pattern[:, ends[n // 2, 0]] + pattern[:, ends[n // 2, 1]])
        cut += [
            _line_trace(
                _polylines(prul.reshape(-1, 2, 3)),
                "cut rulings",
                "cut",
                RULING_COLOR,
                1.5,
                legend=False,
            ),
            go.Scatter3d(
                **_xyz(mid),
                mode="text",
                text=[str(pid) for pid in last.plate_ids],
                textfont={"size": 12, "color": _FONT},
                name="plate ids",
                legendgroup="cut",
                showlegend=False,
                hoverinfo="skip",
            ),
        ]
    for trace in cut:
        trace.visible = False

    traces = first + cut
    groups = [t.legendgroup for t in traces]
    index_of = {g: [i for i, x in enumerate(groups) if x == g] for g in _GROUPS}

    # frames carry coordinates only: styling, text and triangles stay those of the traces
    keys = ["plates", "edges", *kinds, "rulings"]
    kinds_of = [go.Mesh3d] + [go.Scatter3d] * (len(keys) - 1)
    readouts = _readouts(structures)
    frames = [
        go.Frame(
            name=str(k),
            data=[cls(**_xyz(d[key])) for cls, key in zip(kinds_of, keys)],
            traces=moving,
            layout={"annotations": [_readout_annotation(readouts[k])]},
        )
        for k, d in enumerate(data)
    ]
    every = max(1, math.ceil((len(alphas) - 1) / _SLIDER_LABELS))
    labels = [
        _label(a) if k % every == 0 or k == len(alphas) - 1 else "" for k, a in enumerate(alphas)
    ]
    if len(alphas) > 1 and (len(alphas) - 1) % every and (len(alphas) - 1) % every < every / 2:
        labels[(len(alphas) - 1) // every * every] = ""  # too close to the last label
    animate = {"mode": "immediate", "transition": {"duration": 0}}
    slider = {
        "active": len(alphas) - 1,
        "x": 0.0,
        "len": 1.0,
        "xanchor": "left",
        "y": 0.0,
        "yanchor": "top",
        "pad": {"t": 8, "b": 8, "l": 0, "r": 10},
        "currentvalue": {"visible": False},  # the read-out annotation shows the state
        "font": {"size": 11, "color": _FONT},
        "bgcolor": "#efe9dc",
        "activebgcolor": "#d5bd93",
        "bordercolor": "#9a8c74",
        "tickcolor": "#9a8c74",
        "transition": {"duration": 0},
        "steps": [
            {
                "label": label,
                "method": "animate",
                "args": [[str(k)], {**animate, "frame": {"duration": 0, "redraw": True}}],
            }
            for k, label in enumerate(labels)
        ],
    }
    button_style = {
        "type": "buttons",
        "showactive": True,
        "bgcolor": "#f7f4ee",
        "bordercolor": "#9a8c74",
        "borderwidth": 1,
        "font": {"size": 13, "color": _FONT},
        "pad": {"r": 12, "t": 0, "l": 0, "b": 0},
        "xanchor": "right",
        "yanchor": "top",
        "x": 0.0,
    }
    play = {
        **button_style,
        "direction": "left",
        "showactive": False,
        "y": -0.005,
        "pad": {"r": 12, "t": 28},
        "buttons": [
            {
                "label": "▶ Play",
                "method": "animate",
                "args": [
                    None,
                    {
                        **animate,
                        "fromcurrent": False,
                        "frame": {"duration": 140, "redraw": True},
                    },
                ],
            },
            {
                "label": "❚❚ Pause",
                "method": "animate",
                "args": [[None], {**animate, "frame": {"duration": 0, "redraw": False}}],
            },
        ],
    }
    toggles = []
    for row, (group, label) in enumerate(_TOGGLES):
        ids = index_of[group]
        # a one-button menu per group: the button is "active" while the group is shown, and a
        # click on the active button runs args2 (hide); its label shows the state (☑ / ☐)
        key = f"updatemenus[{1 + row}].buttons[0].label"
        # hidden groups stay in the legend (greyed, a click there shows them again), except the
        # cut patterns: they need the wider box that only this button sets
        off = False if group == "cut" else "legendonly"
        show = [{"visible": True}, {key: f"{_ON} {label}"}, ids]
        hide = [{"visible": off}, {key: f"{_OFF} {label}"}, ids]
        if group == "cut":
            show[1].update(_scene_layout(all_ranges, all_ratio))
            hide[1].update(_scene_layout(struct_ranges, struct_ratio))
        shown = group != "cut"
        toggles.append(
            {
                **button_style,
                "name": f"toggle {group}",
                "active": 0 if shown else -1,
                "y": 1.0 - 0.085 * row,
                "buttons": [
                    {
                        "label": f"{_ON if shown else _OFF} {label}",
                        "method": "update",
                        "args": show,
                        "args2": hide,
                    }
                ],
            }
        )

    axis = {
        "showbackground": True,
        "backgroundcolor": _PANE,
        "gridcolor": _GRID,
        "zerolinecolor": "#c9c3b6",
        "color": "#666666",
        "tickfont": {"size": 13},
        "nticks": 6,
        "ticksuffix": " m",
    }
    layout = {
        "template": "none",
        "title": _title(model, kinds, counts, alphas),
        "paper_bgcolor": _PAPER,
        "font": {"family": "Helvetica, Arial, sans-serif", "color": _FONT},
        "margin": {"l": 140, "r": 10, "t": 88, "b": 110},
        "showlegend": True,
        "legend": {
            "x": 1.0,
            "xanchor": "right",
            "y": 1.0,
            "yanchor": "top",
            "bgcolor": "rgba(255,255,255,0.85)",
            "bordercolor": "#d9d3c6",
            "borderwidth": 1,
            "font": {"size": 12},
            "groupclick": "togglegroup",
            "itemsizing": "constant",
        },
        "scene": {
            "xaxis": {**axis, "title": {"text": "x", "font": {"size": 16}}},
            "yaxis": {**axis, "title": {"text": "y", "font": {"size": 16}}},
            "zaxis": {**axis, "title": {"text": "z", "font": {"size": 16}}},
            "camera": _DEFAULT_CAMERA if view is None else _eye(view),
            "dragmode": "turntable",
        },
        "sliders": [slider],
        "annotations": [_readout_annotation(readouts[-1])],
        "updatemenus": [play, *toggles],
        "uirevision": "ccu-viewer",
        "hoverlabel": {"bgcolor": "#ffffff", "font": {"size": 12}},
    }
    fig = go.Figure(data=traces, layout=layout, frames=frames)
    fig.update_layout(_scene_layout(struct_ranges, struct_ratio))
    if title is not None:
        fig.layout.title.text = title
    return fig


def write_viewer(
    model,
    path,
    *,
    steps: int = 24,
    alpha: float | None = None,
    title: str | None = None,
    view=None,
    pattern_offsets=None,
    sheets=None,
) -> Path:
    """Write the viewer of :func:`viewer_figure` as one self-contained, offline HTML page.

    plotly.js is bundled in the page (no CDN, no MathJax) and the page loads nothing from the
    network. Coordinates are stored as float32 binary arrays (≲ 1e-6 m at metre scale), so the
    page is plotly.js (4.8 MB) plus ~63 kB per state for the 10-plate, 64-segment vault: 5.9 MB
    at ``steps=12`` and 6.7 MB at the default ``steps=24`` (the 2-plate cone: 5.2 MB at 24).
    The plot ``<div>`` has the id :data:`VIEWER_DIV_ID` (``"ccu-viewer"``).

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    path : str or pathlib.Path
        The ``.html`` file to write (its folder is created).
    steps, alpha, title, view, pattern_offsets, sheets
        As in :func:`viewer_figure`.

    Returns
    -------
    pathlib.Path
        The written file.

    Examples
    --------
    >>> import tempfile
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/vault.toml")
    >>> out = write_viewer(model, tempfile.mkdtemp() + "/vault.html", steps=6)
    >>> out.stat().st_size > 4_000_000, "cdn.plot.ly/plotly" in out.read_text(encoding="utf-8")
    (True, False)
    """
    fig = viewer_figure(
        model,
        steps=steps,
        alpha=alpha,
        title=title,
        view=view,
        pattern_offsets=pattern_offsets,
        sheets=sheets,
    )
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    html = fig.to_html(
        include_plotlyjs=True,
        include_mathjax=False,
        full_html=True,
        auto_play=False,
        div_id=VIEWER_DIV_ID,
        default_width="100%",
        default_height="max(680px, 100vh)",  # the whole window, with room for the menus
        config={"displaylogo": False, "responsive": True},
    )
    # a tab title, and no page margin: the plot fills the window without scroll bars
    name = title if title is not None else getattr(model.design, "name", None) or "design"
    name = html_escape(f"{name} — CCU viewer")
    head = f"<title>{name}</title>\n<style>body {{margin: 0;}}</style>\n</head>"
    html = html.replace("</head>", head, 1)
    path.write_text(html, encoding="utf-8")
    return path
