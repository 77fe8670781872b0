"""The plotly traces of the viewer: the structure of one state, the cut patterns, the sheets.

Every trace carries a legend group (``plates``, ``creases``, ``rulings`` or ``cut``) that the
viewer's toggles show and hide (:mod:`compas_ccu.viz.viewer_controls`). The structure's
coordinates are float32 (≲ 1e-6 m at metre scale); the sheets' are float64, every part exactly
at its nested place. Plotly is imported when a trace is built.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.kinematics.plates import plate_rulings
from compas_ccu.viz.colors import EDGE_COLOR, KIND_COLORS, KIND_LABELS, RULING_COLOR
from compas_ccu.viz.viewer_data import ViewerData, polylines
from compas_ccu.viz.viewer_ground import outline_index

__all__ = [
    "structure_traces",
    "cut_pattern_traces",
    "sheet_traces",
    "frame_traces",
    "line_trace",
    "xyz",
    "FONT_COLOR",
]

#: The colour of the viewer's text (titles, labels, read-out).
FONT_COLOR = "#2b2b2b"
_PATTERN_TAG = "cut pattern"
_BOARD = "#dfe3e6"  # the sheets (stock boards) under the nested parts
_BOARD_EDGE = "#5d6468"
_MARK_COLOR = "#7a6a52"  # where the splice plates go (engraved)
#: Lighting of the cut patterns and the sheets: flat, as on a drawing.
_FLAT_LIGHT = {"ambient": 0.95, "diffuse": 0.05, "specular": 0.0}
# the plates: mostly ambient, with a light from the front right (the arches shade from left to
# right)
_PLATE_LIGHTING = {
    "ambient": 0.5,
    "diffuse": 0.5,
    "specular": 0.08,
    "roughness": 0.85,
    "fresnel": 0.05,
    "facenormalsepsilon": 0.0,
}
_PLATE_LIGHT = {"x": 1e4, "y": -5e3, "z": 5e3}


# -- coordinates and plain traces ------------------------------------------------------------
def _f32(a) -> np.ndarray:
    """Coordinates for display: float32 (≲ 1e-6 m for structures up to ~10 m), NaN gaps."""
    return np.ascontiguousarray(a, dtype=np.float32)


def xyz(points: np.ndarray) -> dict:
    """``x``, ``y``, ``z`` keyword arguments of a trace: (m, 3) points as float32 columns."""
    pts = _f32(points)
    return {"x": pts[:, 0], "y": pts[:, 1], "z": pts[:, 2]}


def _xyz64(points: np.ndarray) -> dict:
    """Coordinates kept as float64 (the sheets: every part exactly at its nested place)."""
    pts = np.ascontiguousarray(points, dtype=float)
    return {"x": pts[:, 0], "y": pts[:, 1], "z": pts[:, 2]}


def line_trace(points, name: str, group: str, color: str, width: float, *, legend=True):
    """A plotly line trace (NaN rows break the line) in a legend group, without hover."""
    import plotly.graph_objects as go

    return go.Scatter3d(
        **xyz(points),
        mode="lines",
        name=name,
        legendgroup=group,
        showlegend=legend,
        line={"color": color, "width": width},
        hoverinfo="skip",
    )


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


def _text_trace(coordinates: dict, text, name: str, size: float, color: str, **style):
    """Labels of the ``"cut"`` group (not in the legend, no hover)."""
    import plotly.graph_objects as go

    return go.Scatter3d(
        **coordinates,
        mode="text",
        text=text,
        **style,
        textfont={"size": size, "color": color},
        name=name,
        legendgroup="cut",
        showlegend=False,
        hoverinfo="skip",
    )


# -- the structure ---------------------------------------------------------------------------
def structure_traces(data: ViewerData, state: int = -1) -> list:
    """The traces of one state of the structure, the ones the animation frames move.

    Plates (Mesh3d, two triangles per quad in the plate tones, hover "plate <id>"), plate
    edges, one crease trace per kind (wide, coloured and labelled by kind), rulings.

    Parameters
    ----------
    data : ViewerData
    state : int
        The state shown (default the last).

    Returns
    -------
    list of plotly trace
    """
    import plotly.graph_objects as go

    d = data.states[state]
    plates = go.Mesh3d(
        **xyz(d["plates"]),
        name="plates",
        legendgroup="plates",
        showlegend=True,
        flatshading=True,
        lighting=_PLATE_LIGHTING,
        lightposition=_PLATE_LIGHT,
        text=data.plate_text,
        hovertemplate="%{text}<extra></extra>",
    )
    traces = [plates, line_trace(d["edges"], "plate edges", "plates", EDGE_COLOR, 2, legend=False)]
    for kind in data.kinds:
        label, color = KIND_LABELS.get(kind, kind), KIND_COLORS.get(kind, EDGE_COLOR)
        traces.append(line_trace(d[kind], label, "creases", color, 7))
    traces.append(line_trace(d["rulings"], "rulings", "rulings", RULING_COLOR, 1.5))
    tri = data.triangles
    plates.update(i=tri[:, 0].astype(np.int32), j=tri[:, 1].astype(np.int32))
    plates.update(k=tri[:, 2].astype(np.int32), facecolor=data.facecolor)
    return traces


def frame_traces(data: ViewerData, state: int) -> list:
    """The coordinates of :func:`structure_traces` at one state, for an animation frame
    (styling, text and triangles stay those of the traces)."""
    import plotly.graph_objects as go

    d = data.states[state]
    keys = ["plates", "edges", *data.kinds, "rulings"]
    kinds_of = [go.Mesh3d] + [go.Scatter3d] * (len(keys) - 1)
    return [cls(**xyz(d[key])) for cls, key in zip(kinds_of, keys)]


# -- the cut patterns ------------------------------------------------------------------------
def cut_pattern_traces(data: ViewerData, pattern: np.ndarray) -> list:
    """The traces of the cut patterns laid out on the ground (legend group ``cut``).

    Fill (the plate tones, just under the ground), outlines, creases by kind, rulings, plate
    ids.

    Parameters
    ----------
    data : ViewerData
    pattern : (p, v, 3) float
        :func:`compas_ccu.viz.viewer_data.cut_pattern_places`.
    """
    n, size = data.segments, data.size
    cut = [
        _cut_mesh(
            xyz(pattern.reshape(-1, 3) - np.array([0.0, 0.0, 1e-3 * size])),
            data.triangles,
            "cut patterns",
            np.char.add(data.plate_text, f" ({_PATTERN_TAG})"),
            facecolor=data.facecolor,
        ),
        line_trace(
            polylines(pattern[:, outline_index(n)]),
            "cut outlines",
            "cut",
            EDGE_COLOR,
            2,
            legend=False,
        ),
    ]
    cut += _pattern_crease_traces(data, pattern)
    ends = plate_rulings(n)
    prul = pattern[:, ends[data.rulings_at]]
    mid = 0.5 * (pattern[:, ends[n // 2, 0]] + pattern[:, ends[n // 2, 1]])
    cut += [
        line_trace(
            polylines(prul.reshape(-1, 2, 3)),
            "cut rulings",
            "cut",
            RULING_COLOR,
            1.5,
            legend=False,
        ),
        _text_trace(xyz(mid), [str(pid) for pid in data.plate_ids], "plate ids", 12, FONT_COLOR),
    ]
    return cut


def _pattern_crease_traces(data: ViewerData, pattern: np.ndarray) -> list:
    """One trace per crease kind: both sides of every crease on the cut patterns."""
    structure = data.structures[-1]
    index = {pid: i for i, pid in enumerate(structure.plate_ids)}
    traces = []
    for kind in data.kinds:
        lines = []
        for c in structure.creases:
            if c["kind"] == kind:
                for plate, verts in zip(c["plates"], c["vertices"]):
                    lines.append(pattern[index[plate], np.asarray(verts, dtype=int)])
        color = KIND_COLORS.get(kind, EDGE_COLOR)
        traces.append(line_trace(polylines(lines), f"cut: {kind}", "cut", color, 5, legend=False))
    return traces


# -- the sheets ------------------------------------------------------------------------------
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


def _placer(corners: np.ndarray, z: float):
    """``at(points, sheet, dz=0)``: (k, 2) sheet points as (k, 3) points in the plane
    ``z + dz`` at the sheet's corner."""

    def at(points, sheet, dz=0.0) -> np.ndarray:
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        out = np.empty((len(pts), 3))
        out[:, :2] = pts + corners[sheet]
        out[:, 2] = z + dz
        return out

    return at


def sheet_traces(doc: dict, corners: np.ndarray, z: float, kinds: list, tones: list) -> list:
    """The traces of the nested sheets (legend group ``cut``), in the plane ``z``.

    Parts first (their fill: the first ``cut`` trace), then the boards, the sheet edges, the
    part outlines, the creases by kind, the score lines, the splice marks and the labels.
    Coordinates are float64: every part lies exactly at its nested place plus its sheet's
    corner.

    Parameters
    ----------
    doc : dict
        :func:`compas_ccu.viz.viewer_ground.sheet_document`.
    corners : (s, 2) float
        Where each sheet's corner lies.
    z : float
        The plane of the sheets.
    kinds : list of str
        The crease kinds, one trace each (those present on the parts).
    tones : list of str
        The plates' colours (a part's ``tone_index`` picks its own).
    """
    at = _placer(corners, z)
    dz = 1e-3 * max(1.0, float(np.ptp(corners, axis=0).max()) if len(corners) else 1.0)
    traces = [_parts_mesh(doc, at, dz, tones), *_board_traces(doc["sheets"], at, dz)]
    traces += _part_line_traces(doc["parts"], at, kinds)
    traces += _sheet_label_traces(doc, at, dz)
    return traces


def _parts_mesh(doc: dict, at, dz: float, tones: list):
    """The parts' fill, just under the sheets' plane, in their plates' tones."""
    parts = doc["parts"]
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
    name = f"cut patterns: {len(doc['sheets'])} sheets, {len(parts)} parts"
    return _cut_mesh(_xyz64(verts), tri, name, text, facecolor=colors)


def _board_traces(sheets: list, at, dz: float) -> list:
    """The boards (under the parts, hover: size and utilisation) and the sheet edges."""
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
    board = _cut_mesh(
        _xyz64(np.concatenate(boards) if boards else np.zeros((0, 3))),
        board_tri,
        "sheets",
        board_text,
        legend=False,
        color=_BOARD,
    )
    return [board, _line_trace64(polylines(rects), "sheet edges", _BOARD_EDGE, 3)]


def _part_line_traces(parts: list, at, kinds: list) -> list:
    """The part outlines, the creases by kind, the score lines and the splice marks."""
    outlines = [at(np.r_[o, o[:1]], p["sheet"]) for p in parts for o in [np.asarray(p["outline"])]]
    traces = [_line_trace64(polylines(outlines), "part outlines", EDGE_COLOR, 2)]
    for kind in kinds:
        lines = [
            at(c["points"], p["sheet"])
            for p in parts
            for c in p.get("creases", [])
            if c.get("kind") == kind
        ]
        if lines:
            color = KIND_COLORS.get(kind, EDGE_COLOR)
            traces.append(_line_trace64(polylines(lines), f"sheets: {kind}", color, 5))
    score = [at(line, p["sheet"]) for p in parts for line in p.get("score", [])]
    if score:
        traces.append(_line_trace64(polylines(score), "score lines", RULING_COLOR, 1.5))
    marks = [
        at(np.r_[m, m[:1]], p["sheet"])
        for p in parts
        for m in (np.asarray(r, dtype=float) for r in p.get("marks", []))
    ]
    if marks:
        traces.append(_line_trace64(polylines(marks), "splice marks", _MARK_COLOR, 1.5))
    return traces


def _sheet_label_traces(doc: dict, at, dz: float) -> list:
    """The part names (at their centres) and the sheet numbers with their utilisation."""
    parts, sheets = doc["parts"], doc["sheets"]
    centres = [at(np.asarray(p["outline"], dtype=float).mean(axis=0), p["sheet"]) for p in parts]
    names = _text_trace(
        _xyz64(np.concatenate(centres) if centres else np.zeros((0, 3))),
        [str(p.get("name", "")) for p in parts],
        "part names",
        10,
        FONT_COLOR,
    )
    # at the front-left corner of every sheet (the nearest to the default camera, so that the
    # sheet behind the text on the screen does not hide it), lifted over the parts' lines
    labels = [at([0.0, 0.0], k, 10.0 * dz)[0] for k in range(len(sheets))]
    numbers = _text_trace(
        _xyz64(np.asarray(labels).reshape(-1, 3)),
        [
            f"sheet {k + 1} · {100 * float(sheet.get('utilisation', 0.0)):.0f} %"
            for k, sheet in enumerate(sheets)
        ],
        "sheet numbers",
        11,
        _BOARD_EDGE,
        textposition="top right",
    )
    return [names, numbers]
