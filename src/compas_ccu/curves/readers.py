"""Curves from files: CSV / TXT points, DXF, SVG paths and Rhino 3dm curves, in metres.

:func:`read_curve` reads one curve of a file as a dense polyline of 3D points in metres;
:func:`plane_coordinates` turns it into the 2D coordinates of its plane (a crease profile).

Formats (chosen by the file suffix):

``.csv``, ``.txt``
    One point a line, ``x, y`` or ``x, y, z``, separated by commas, semicolons, tabs or spaces;
    ``#`` starts a comment and a first line that is not numbers is a header. No units in the
    file: metres unless ``units`` is given. NumPy only.
``.dxf``
    LWPOLYLINE (with bulges), POLYLINE (2D and 3D), SPLINE, ARC and chains of LINE entities
    of the model space (``ezdxf``, the ``fab`` extra). SPLINE is evaluated with ezdxf's
    B-spline construction tool, the others through ``ezdxf.path``; units from ``$INSUNITS``
    (a unitless file needs ``units``).
``.svg``
    Every ``<path>``, ``<polyline>``, ``<polygon>`` and ``<line>``, with the transforms and
    viewBox applied by ``svgelements`` (``pip install svgelements``). SVG user units are CSS
    pixels (96 per inch), so a file whose ``width`` / ``height`` carry a unit (``mm``) is read
    in that unit. SVG's y axis points down: the y coordinate is negated so that a drawing
    reads upright.
``.3dm``
    Every curve object (line, polyline, arc, NURBS, polycurve) of a Rhino file
    (``rhino3dm``, the ``fab`` extra), evaluated with ``Curve.PointAt``; units from the
    file's model unit system.

Curves are sampled until every chord lies within ``tolerance`` (relative to the curve's
bounding-box diagonal, default 1e-8) of the curve at its midpoint, so the polyline read back
is the source curve to that tolerance (docs/import.md gives the measured distances).

A file with several curves needs ``layer`` (a DXF or 3dm layer, an SVG group id or Inkscape
label), ``name`` (a DXF handle, a 3dm object name, an SVG element id) or ``index`` (among the
curves left) to choose one; the error lists the candidates.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from compas_ccu import limits
from compas_ccu.curves.dxf_input import (
    check_dxf_points,
    check_finite,
    dxf_units,
    extent,
    one_line,
    spline_sampler,
    straight_polyline_points,
)
from compas_ccu.errors import ProfileError, require
from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = [
    "dxf_sampler",
    "dxf_line_chains",
    "UNITS",
    "CURVE_SUFFIXES",
    "CurveRead",
    "read_curve",
    "plane_coordinates",
]

#: Length units a file may be read in, metres per unit (``px``: SVG user units, 96 per inch).
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "ft": 0.3048, "px": 0.0254 / 96.0}

#: File suffixes :func:`read_curve` reads.
CURVE_SUFFIXES = (".csv", ".txt", ".dxf", ".svg", ".3dm")

#: Default chord tolerance of the sampling, relative to the curve's bounding-box diagonal.
TOLERANCE = 1e-8


@dataclass(frozen=True)
class CurveRead:
    """One curve read from a file.

    Attributes
    ----------
    points : (n, 3) float
        The curve, m, as a polyline within the sampling tolerance of the source.
    source : str
        ``"path: ENTITY"``, naming the entity read (type, handle or name, layer).
    units : str
        The units of the file's numbers (a key of :data:`UNITS`).
    """

    points: np.ndarray
    source: str
    units: str


@dataclass
class _Candidate:
    label: str  # e.g. "LWPOLYLINE #1F on layer CREASE"
    layer: str | None
    name: str | None
    sample: object  # (tolerance in file units) -> (n, 3) points in file units
    layers: tuple = ()  # SVG: the ids and labels of every enclosing group, lower case


def read_curve(
    path,
    *,
    layer: str | None = None,
    name: str | None = None,
    index: int | None = None,
    units: str | None = None,
    scale: float = 1.0,
    tolerance: float = TOLERANCE,
) -> CurveRead:
    """Read one curve of a CSV / TXT, DXF, SVG or 3dm file as 3D points in metres.

    Parameters
    ----------
    path : str or Path
        The file; its suffix chooses the reader.
    layer, name : str, optional
        Keep only the curves on this layer (DXF, 3dm; SVG: a group's id or Inkscape label) or
        of this name (DXF handle, 3dm object name, SVG element id). Case-insensitive.
    index : int, optional
        Which of the curves left (0-based, in file order); needed if more than one is left.
    units : str, optional
        Units of the file's numbers (``m``, ``cm``, ``mm``, ``in``, ``ft``): overrides the
        file's own. CSV / TXT: default ``m``.
    scale : float
        Factor applied after the unit conversion (default 1).
    tolerance : float
        Chord tolerance of the sampling, relative to the curve's size.

    Returns
    -------
    CurveRead

    Raises
    ------
    ProfileError
        The file is missing or unreadable; no curve, or several and no choice (the message
        lists them); a unit that is unknown or missing (unitless DXF); fewer than 2 points.
    MissingExtraError
        ezdxf (DXF), rhino3dm (3dm) or svgelements (SVG) is not installed.

    Examples
    --------
    >>> import tempfile, os
    >>> folder = tempfile.mkdtemp()
    >>> path = os.path.join(folder, "crease.csv")
    >>> _ = open(path, "w").write("x,y\\n0,0\\n500,250\\n1000,0\\n")
    >>> curve = read_curve(path, units="mm")
    >>> curve.points.tolist()
    [[0.0, 0.0, 0.0], [0.5, 0.25, 0.0], [1.0, 0.0, 0.0]]
    """
    path = Path(path)
    if units is not None and units not in UNITS:
        raise ProfileError(f"units must be one of {', '.join(UNITS)}, got {units!r}")
    if not (isinstance(scale, (int, float)) and math.isfinite(scale) and scale > 0):
        raise ProfileError(f"scale must be a number > 0, got {scale!r}")
    suffix = path.suffix.lower()
    if suffix not in CURVE_SUFFIXES:
        raise ProfileError(
            f"{str(path)!r}: cannot read curves from {suffix or 'a file without suffix'!r} "
            f"files; readable: {', '.join(CURVE_SUFFIXES)}"
        )
    if not path.is_file():
        raise ProfileError(f"curve file {str(path)!r} does not exist")
    reader = {
        ".csv": _csv,
        ".txt": _csv,
        ".dxf": _dxf,
        ".svg": _svg,
        ".3dm": _rhino,
    }[suffix]
    if suffix == ".dxf":  # the file's $INSUNITS matters only without units
        candidates, file_units, file_factor = _dxf(path, units)
    else:
        candidates, file_units, file_factor = reader(path)
    chosen = _choose(path, candidates, layer=layer, name=name, index=index)
    used = units or file_units
    if used is None:
        raise ProfileError(
            f"{str(path)!r} has no units we read (unitless, or a unit other than "
            f"{', '.join(UNITS)}): give units = one of {', '.join(UNITS)}"
        )
    factor = UNITS[used] if units is not None or file_factor is None else file_factor
    rough = check_finite(chosen.sample(None), f"{str(path)!r}: {chosen.label}").reshape(-1, 3)
    size = extent(rough, f"{str(path)!r}: {chosen.label}")
    points = check_finite(chosen.sample(tolerance * size), f"{str(path)!r}: {chosen.label}")
    limits.check("points", len(points), what=f"points of {chosen.label} in {path.name}")
    if len(points) > 1:  # drop repeated points (joints of segments)
        keep = np.r_[True, np.linalg.norm(np.diff(points, axis=0), axis=1) > 1e-12 * size]
        points = points[keep]
    if len(points) < 2:
        raise ProfileError(f"{str(path)!r}: {chosen.label} has fewer than 2 distinct points")
    scaled = points * (factor * scale)
    if not np.isfinite(scaled).all():
        raise ProfileError(
            f"{str(path)!r}: {chosen.label} times scale {scale:g} ({used}) is not finite"
        )
    return CurveRead(scaled, f"{path}: {chosen.label}", used)


def plane_coordinates(points, *, source: str = "curve", planarity: float = 1e-6):
    """The 2D coordinates of a planar 3D polyline in its plane, and the plane.

    A curve in a plane ``z = const`` keeps its x, y coordinates. Any other planar curve is
    expressed in the frame of its chord: origin at the chord's midpoint, x from the first to the
    last point, y in the curve's plane towards the side the curve bulges to (an arch rises to
    +y), as the analytic profiles are.

    Parameters
    ----------
    points : (n, 3) float
        The curve, m.
    source : str
        What to name in an error (file and entity).
    planarity : float
        Largest distance from the best-fit plane allowed, relative to the curve's size.

    Returns
    -------
    points2 : (n, 2) float
        Plane coordinates, m.
    frame : dict
        ``origin``, ``xaxis``, ``yaxis`` (3 floats each) of the plane in the file's coordinates
        (m), as the ``[plane]`` section of a design takes them.
    deviation : float
        The largest distance of a point from the plane, m.

    Raises
    ------
    ProfileError
        The curve is not planar (the message gives its deviation) or is straight.

    Examples
    --------
    >>> pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [2.0, 0.0, 0.0]]
    >>> p2, frame, dev = plane_coordinates(pts)
    >>> (p2.round(12) + 0.0).tolist(), [v + 0.0 for v in frame["yaxis"]], dev
    ([[-1.0, 0.0], [0.0, 1.0], [1.0, 0.0]], [0.0, 0.0, 1.0], 0.0)
    """
    p = np.asarray(points, dtype=float)
    size = float(np.linalg.norm(np.ptp(p, axis=0)))
    if size == 0.0:
        raise ProfileError(f"{source}: all points coincide")
    if float(np.ptp(p[:, 2])) <= planarity * size:
        z = float(np.mean(p[:, 2]))
        frame = {"origin": [0.0, 0.0, z], "xaxis": [1.0, 0.0, 0.0], "yaxis": [0.0, 1.0, 0.0]}
        return p[:, :2].copy(), frame, float(np.max(np.abs(p[:, 2] - z)))
    centre = p.mean(axis=0)
    _, sv, vt = np.linalg.svd(p - centre)
    normal = vt[2]
    deviation = float(np.max(np.abs((p - centre) @ normal)))
    if deviation > planarity * size:
        raise ProfileError(
            f"{source}: the curve is not planar: its points lie up to {deviation:.6g} m from "
            f"their best-fit plane ({deviation / size:.3g} of its size; allowed "
            f"{planarity:g}); a crease profile is a plane curve"
        )
    chord = p[-1] - p[0]
    chord -= (chord @ normal) * normal
    if np.linalg.norm(chord) <= 1e-9 * size:  # a closed curve: the first principal direction
        chord = vt[0]
    xaxis = chord / np.linalg.norm(chord)
    yaxis = np.cross(normal, xaxis)
    origin = 0.5 * (p[0] + p[-1])
    q = p - origin
    local = np.c_[q @ xaxis, q @ yaxis]
    if local[:, 1].mean() < 0.0:  # the curve bulges to +y
        yaxis = -yaxis
        local[:, 1] *= -1.0
    frame = {"origin": origin.tolist(), "xaxis": xaxis.tolist(), "yaxis": yaxis.tolist()}
    return local, frame, deviation


# -- choosing a curve -------------------------------------------------------------------------


def _choose(path: Path, candidates: list, *, layer, name, index) -> _Candidate:
    left = candidates
    if layer is not None:
        left = [
            c
            for c in left
            if (c.layer is not None and c.layer.lower() == layer.lower())
            or layer.lower() in c.layers
        ]
    if name is not None:
        left = [c for c in left if c.name is not None and c.name.lower() == name.lower()]
    listing = "; ".join(f"[{k}] {c.label}" for k, c in enumerate(candidates[:20]))
    if len(candidates) > 20:
        listing += f"; ... ({len(candidates)} curves)"
    if not candidates:
        raise ProfileError(f"{str(path)!r} holds no curve")
    if not left:
        asked = ", ".join(
            f"{k} = {v!r}" for k, v in (("layer", layer), ("name", name)) if v is not None
        )
        raise ProfileError(f"{str(path)!r}: no curve with {asked}; the file holds: {listing}")
    if index is not None:
        if not 0 <= index < len(left):
            raise ProfileError(
                f"{str(path)!r}: index {index} out of range 0 ... {len(left) - 1} of the curves "
                f"{'left' if left is not candidates else 'in the file'}: "
                + "; ".join(f"[{k}] {c.label}" for k, c in enumerate(left[:20]))
            )
        return left[index]
    if len(left) > 1:
        raise ProfileError(
            f"{str(path)!r} holds {len(left)} candidate curves; choose one with layer, name or "
            "index: " + "; ".join(f"[{k}] {c.label}" for k, c in enumerate(left[:20]))
        )
    return left[0]


def _adaptive(evaluate, t0: float, t1: float, tolerance, *, start: int = 16, breaks=()):
    """Sample a parametric curve until every chord's midpoint lies within ``tolerance`` of the
    curve's midpoint; ``evaluate`` maps an (m,) array of parameters to (m, 3) points."""
    ts = np.unique(np.r_[np.linspace(t0, t1, start + 1), [b for b in breaks if t0 < b < t1]])
    if tolerance is None:
        return evaluate(ts)
    pts = evaluate(ts)
    for _ in range(40):
        mids = 0.5 * (ts[:-1] + ts[1:])
        pm = evaluate(mids)
        error = np.linalg.norm(pm - 0.5 * (pts[:-1] + pts[1:]), axis=1)
        bad = error > tolerance
        if not bad.any():
            return pts
        if len(ts) + int(bad.sum()) > limits.LIMITS.points:
            limits.check("points", len(ts) + int(bad.sum()), what="points (the curve's sampling)")
        ts = np.sort(np.r_[ts, mids[bad]])
        pts = evaluate(ts)
    return pts  # pragma: no cover - 2^40 refinements


# -- CSV / TXT --------------------------------------------------------------------------------

_SPLIT = re.compile(r"[,;\s]+")


_COMMENT = re.compile(r"#[^\n]*")
_TO_SPACE = str.maketrans({",": " ", ";": " ", "\t": " ", "\r": "\n", "\f": " ", "\v": " "})


def _csv(path: Path):
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise ProfileError(f"cannot read {str(path)!r}: {exc}") from exc
    limits.check("points", text.count("\n"), what=f"lines of {path.name}")
    points = _csv_fast(text)
    if points is None:  # ragged, malformed or non-finite: the line-by-line reading names it
        points = _csv_lines(path, text)
    candidate = _Candidate(f"{len(points)} points", None, None, lambda tol: points)
    return [candidate], "m", None


def _csv_fast(text: str):
    """The points of a CSV / TXT text whose rows all have 2 or all 3 finite numbers (after an
    optional header line), parsed by NumPy; None for anything else."""
    if "#" in text:
        text = _COMMENT.sub("", text)
    clean = text.translate(_TO_SPACE)
    clean = clean.lstrip()  # leading blank lines
    end = clean.find("\n")
    first = clean if end < 0 else clean[:end]
    try:
        [float(f) for f in first.split()]
    except ValueError:  # a header line
        clean = "" if end < 0 else clean[end + 1 :]
    data = clean.split()
    try:
        values = np.array(data, dtype=float)
    except ValueError:
        return None
    if not len(values) or not np.isfinite(values).all():
        return None
    # the fields of every non-empty line: a field starts where a blank is followed by a non-blank
    b = np.frombuffer(clean.encode("utf-8"), dtype=np.uint8)
    blank = (b == 32) | (b == 10)
    starts = np.flatnonzero(~blank & np.r_[True, blank[:-1]])
    line = np.searchsorted(np.flatnonzero(b == 10), starts)  # ascending line numbers
    counts = np.diff(np.r_[0, np.flatnonzero(np.diff(line)) + 1, len(line)])
    width = int(counts[0])
    if width not in (2, 3) or (counts != width).any():
        return None
    points = values.reshape(-1, width)
    return np.c_[points, np.zeros(len(points))] if width == 2 else points


def _csv_lines(path: Path, text: str):
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f for f in _SPLIT.split(line) if f]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            if not rows:  # a header
                continue
            raise ProfileError(f"{str(path)!r} line {number}: not numbers: {line[:60]!r}") from None
        if len(values) not in (2, 3) or not all(map(math.isfinite, values)):
            raise ProfileError(
                f"{str(path)!r} line {number}: a point is 2 or 3 finite numbers, got {line[:60]!r}"
            )
        rows.append(values + [0.0] * (3 - len(values)))
    return np.array(rows, dtype=float).reshape(-1, 3)


# -- DXF --------------------------------------------------------------------------------------


def _need(module: str, extra: str, what: str):
    import importlib

    require(module, extra, what=f"reading {what}")
    return importlib.import_module(module)


def _dxf(path: Path, units=None):
    ezdxf = _need("ezdxf", "fab", "DXF files")
    check_dxf_points(path)
    try:
        doc = ezdxf.readfile(str(path))
    except (OSError, ezdxf.DXFError, StopIteration, ValueError) as exc:  # ValueError: decoding
        raise ProfileError(f"cannot read DXF file {str(path)!r}: {one_line(exc)}") from None
    file_units = units if units is not None else dxf_units(doc, path)  # None: unitless
    candidates = []
    lines = []
    for e in doc.modelspace():
        if e.dxftype() == "LINE":
            lines.append(e)
            continue
        sample = dxf_sampler(e)
        if sample is not None:
            label = f"{e.dxftype()} #{e.dxf.handle} on layer {e.dxf.layer}"
            candidates.append(_Candidate(label, e.dxf.layer, e.dxf.handle, sample))
    for layer, handles, pts in dxf_line_chains(lines):
        label = (
            f"LINE #{handles[0]} on layer {layer}"
            if len(handles) == 1
            else f"chain of {len(handles)} LINEs #{handles[0]}... on layer {layer}"
        )
        candidates.append(_Candidate(label, layer, handles[0], lambda tol, pts=pts: pts))
    return candidates, file_units, None


def dxf_sampler(e):
    """A function ``tolerance -> (n, 3) points`` (file units) for a DXF curve entity, or None.

    SPLINE: ezdxf's B-spline construction tool; ARC and the arcs of bulged LWPOLYLINE and 2D
    POLYLINE segments: exact points of the circle; 3D POLYLINE: its vertices. ``tolerance``
    None gives a rough sample (for the curve's size). Any other entity: None.

    Examples
    --------
    >>> import ezdxf
    >>> arc = ezdxf.new().modelspace().add_arc((0, 0), 2.0, 0, 90)
    >>> points = dxf_sampler(arc)(1e-6)
    >>> bool(abs(np.linalg.norm(points, axis=1) - 2.0).max() < 1e-15), len(points) > 100
    (True, True)
    """
    kind = e.dxftype()
    if kind == "SPLINE":
        return spline_sampler(e)
    if kind == "ARC":
        return _dxf_arc_sampler(e)
    if kind == "LWPOLYLINE" or (kind == "POLYLINE" and e.is_2d_polyline):
        return _dxf_polyline_sampler(e)
    if kind == "POLYLINE" and e.is_3d_polyline:
        pts = np.array([tuple(v.dxf.location) for v in e.vertices], dtype=float)
        if e.is_closed:
            pts = np.r_[pts, pts[:1]]
        return lambda tol: pts
    return None


def _dxf_arc_sampler(e):
    """Exact points of a DXF ARC (counter-clockwise in its OCS) as a function of tolerance."""
    ocs = e.ocs()
    centre = np.array(tuple(e.dxf.center), dtype=float)
    radius = float(e.dxf.radius)
    start = math.radians(e.dxf.start_angle)
    sweep = math.radians((e.dxf.end_angle - e.dxf.start_angle) % 360.0) or 2.0 * math.pi

    def evaluate(ts):
        local = np.c_[
            centre[0] + radius * np.cos(start + ts * sweep),
            centre[1] + radius * np.sin(start + ts * sweep),
            np.full(len(ts), centre[2]),
        ]
        return np.array([tuple(ocs.to_wcs(tuple(p))) for p in local], dtype=float)

    return lambda tol: _adaptive(evaluate, 0.0, 1.0, tol)


def _dxf_polyline_sampler(e):
    """A 2D polyline with bulges as exact line and arc pieces (ezdxf's virtual entities); an
    LWPOLYLINE without bulges as its vertices (vectorised)."""
    count = len(e) if e.dxftype() == "LWPOLYLINE" else len(e.vertices)
    limits.check("points", count, what=f"vertices of {e.dxftype()} #{e.dxf.handle}")
    if e.dxftype() == "LWPOLYLINE":
        straight = straight_polyline_points(e)
        if straight is not None:
            return lambda tol: straight
    pieces = list(e.virtual_entities())

    def sample(tol):
        out = []
        for piece in pieces:
            if piece.dxftype() == "ARC":
                pts = _dxf_arc_sampler(piece)(tol)
            else:
                pts = np.array([tuple(piece.dxf.start), tuple(piece.dxf.end)], dtype=float)
            if out and np.linalg.norm(pts[-1] - out[-1][-1]) < np.linalg.norm(pts[0] - out[-1][-1]):
                pts = pts[::-1]  # ARC pieces run counter-clockwise, whatever the bulge's sign
            if len(out) == 1 and np.linalg.norm(out[0][0] - pts[0]) < np.linalg.norm(
                out[0][-1] - pts[0]
            ):
                out[0] = out[0][::-1]  # the first piece was reversed
            out.append(pts)
        return np.concatenate(out) if out else np.zeros((0, 3))

    return sample


def dxf_line_chains(lines) -> list:
    """LINE entities of one layer joined end to end into open chains (in file order).

    Returns
    -------
    list of (layer, handles, (k, 3) float points)
    """
    out = []
    by_layer: dict = {}
    for e in lines:
        by_layer.setdefault(e.dxf.layer, []).append(e)
    for layer, group in by_layer.items():
        segs = [
            (np.array(tuple(e.dxf.start), dtype=float), np.array(tuple(e.dxf.end), dtype=float), e)
            for e in group
        ]
        size = max(
            float(np.linalg.norm(np.ptp([p for s in segs for p in s[:2]], axis=0))), DIVISION_FLOOR
        )
        close = 1e-9 * size
        unused = list(range(len(segs)))
        while unused:
            first = unused.pop(0)
            chain = [segs[first][0], segs[first][1]]
            handles = [segs[first][2].dxf.handle]
            grown = True
            while grown:
                grown = False
                for k in list(unused):
                    a, b, e = segs[k]
                    for end in (-1, 0):
                        for p, q in ((a, b), (b, a)):
                            if np.linalg.norm(chain[end] - p) <= close:
                                if end == -1:
                                    chain.append(q)
                                else:
                                    chain.insert(0, q)
                                handles.append(e.dxf.handle)
                                unused.remove(k)
                                grown = True
                                break
                        if grown:
                            break
                    if grown:
                        break
            out.append((layer, handles, np.array(chain)))
    return out


# -- SVG --------------------------------------------------------------------------------------


_INKSCAPE_LABEL = "{http://www.inkscape.org/namespaces/inkscape}label"


def _svg(path: Path):
    svgelements = _need("svgelements", "fab", "SVG files")
    try:
        svg = svgelements.SVG.parse(str(path), reify=True, ppi=96.0)
    except Exception as exc:  # XML or SVG syntax errors of any kind
        raise ProfileError(f"cannot read SVG file {str(path)!r}: {exc}") from exc
    candidates = []

    def walk(group, layers):
        for element in group:
            if isinstance(element, svgelements.Group):
                names = [element.id, element.values.get(_INKSCAPE_LABEL)]
                walk(element, layers + [n for n in names if n])
            elif isinstance(element, (svgelements.Path, svgelements.SimpleLine)) or (
                type(element).__name__ in ("Polyline", "Polygon")
            ):
                candidate = _svg_candidate(svgelements, element, layers)
                if candidate is not None:
                    candidates.append(candidate)

    walk(svg, [])
    return candidates, "px", _svg_metres_per_px(svgelements, svg.values.get("width"))


def _svg_candidate(svgelements, element, layers):
    """The first subpath of an SVG shape as a candidate curve (y negated: upright)."""
    segments, moves = [], 0
    for seg in svgelements.Path(element).segments():
        if isinstance(seg, svgelements.Move):
            moves += 1
            if moves > 1:
                break
        elif not isinstance(seg, svgelements.Close):
            segments.append(seg)
    if not segments:
        return None
    tag = type(element).__name__.lower()
    label = f"<{tag}> id={element.id!r}" + (f" in group {'/'.join(layers)!r}" if layers else "")

    def sample(tol):
        pieces = []
        for seg in segments:
            if isinstance(seg, svgelements.Line):
                pieces.append(np.array([[seg.start.x, seg.start.y], [seg.end.x, seg.end.y]]))
            else:
                pieces.append(_adaptive(_pad(seg.npoint), 0.0, 1.0, tol)[:, :2])
        pts = np.concatenate(pieces)
        return np.c_[pts[:, 0], -pts[:, 1], np.zeros(len(pts))]

    return _Candidate(
        label, layers[-1] if layers else None, element.id, sample, tuple(n.lower() for n in layers)
    )


def _svg_metres_per_px(svgelements, width) -> float:
    """Metres per user unit as svgelements scaled them: it converts a root ``width`` in mm or cm
    to pixels with a rounded factor (3.7795296 px/mm instead of 96 / 25.4, 5e-7 too large), so
    the exact factor is the unit's length over svgelements' pixels per unit."""
    unit = re.sub(r"^[-+0-9.eE]+", "", str(width or "")).strip().lower()
    exact = {"mm": 0.001, "cm": 0.01, "in": 0.0254, "pt": 0.0254 / 72.0, "pc": 0.0254 / 6.0}
    if unit not in exact:
        return UNITS["px"]
    return exact[unit] / svgelements.Length(f"1{unit}").value(ppi=96.0)


def _pad(evaluate):
    """An evaluator of (m, 2) points as one of (m, 3) points with z = 0."""

    def padded(ts):
        pts = np.asarray(evaluate(ts), dtype=float)
        return np.c_[pts[:, :2], np.zeros(len(pts))]

    return padded


# -- Rhino 3dm --------------------------------------------------------------------------------

_RHINO_UNITS = {
    "Meters": "m",
    "Millimeters": "mm",
    "Centimeters": "cm",
    "Inches": "in",
    "Feet": "ft",
}


def _rhino(path: Path):
    rhino3dm = _need("rhino3dm", "fab", "3dm files")
    model = rhino3dm.File3dm.Read(str(path))
    if model is None:
        raise ProfileError(f"cannot read 3dm file {str(path)!r}")
    unit_name = str(model.Settings.ModelUnitSystem).split(".")[-1]
    file_units = _RHINO_UNITS.get(unit_name)
    if file_units is None and unit_name not in ("None", "Unset"):
        raise ProfileError(
            f"{str(path)!r}: model units {unit_name} are not supported; give units = one of "
            f"{', '.join(UNITS)}"
        )
    layers = {k: model.Layers[k] for k in range(len(model.Layers))}
    candidates = []
    for obj in model.Objects:
        geometry = obj.Geometry
        if not isinstance(geometry, rhino3dm.Curve):
            continue
        attrs = obj.Attributes
        layer = layers.get(attrs.LayerIndex)
        layer_name = layer.Name if layer is not None else None
        kind = type(geometry).__name__
        name = attrs.Name or None
        label = f"{kind} {name or str(attrs.Id)[:8]!r} on layer {layer_name}"
        candidates.append(_Candidate(label, layer_name, name, _rhino_sampler(rhino3dm, geometry)))
    return candidates, file_units, None


def _rhino_sampler(rhino3dm, curve):
    if isinstance(curve, rhino3dm.PolylineCurve):
        pts = np.array([[p.X, p.Y, p.Z] for p in (curve.Point(k) for k in range(curve.PointCount))])
        return lambda tol: pts
    if isinstance(curve, rhino3dm.LineCurve):
        a, b = curve.PointAtStart, curve.PointAtEnd
        pts = np.array([[a.X, a.Y, a.Z], [b.X, b.Y, b.Z]])
        return lambda tol: pts
    domain = curve.Domain
    breaks = ()
    nurbs = curve.ToNurbsCurve()
    if nurbs is not None:  # knots of multiplicity >= degree: possible kinks, sampled exactly
        knots = [nurbs.Knots[k] for k in range(len(nurbs.Knots))]
        breaks = tuple(sorted(set(knots)))

    def evaluate(ts):
        out = []
        for t in ts:
            p = curve.PointAt(float(t))
            out.append((p.X, p.Y, p.Z))
        return np.array(out, dtype=float)

    return lambda tol: _adaptive(evaluate, domain.T0, domain.T1, tol, breaks=breaks)
