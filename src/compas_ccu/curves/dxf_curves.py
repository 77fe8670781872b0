"""The curves of a DXF file (``ezdxf``, the ``fab`` extra), as candidate curves in file units.

LWPOLYLINE (with bulges), POLYLINE (2D and 3D), SPLINE, ARC and chains of LINE entities of the
model space. SPLINE is evaluated with ezdxf's B-spline construction tool
(:func:`compas_ccu.curves.dxf_input.spline_sampler`), ARC and the arcs of bulged polylines as
exact points of their circles; units from ``$INSUNITS`` (a unitless file needs ``units``).
:func:`dxf_sampler` and :func:`dxf_line_chains` serve the plate importer too.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from compas_ccu import limits
from compas_ccu.curves.candidates import Candidate, adaptive, need_module
from compas_ccu.curves.dxf_input import (
    check_dxf_points,
    dxf_units,
    ocs_to_wcs,
    one_line,
    spline_sampler,
    straight_polyline_points,
)
from compas_ccu.errors import ProfileError
from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE

__all__ = ["dxf_candidates", "dxf_sampler", "dxf_line_chains"]


def dxf_candidates(path: Path, units=None):
    """The curves of a DXF file's model space, its units and no unit factor.

    Parameters
    ----------
    path : Path
    units : str, optional
        The units given by the caller: ``$INSUNITS`` is read (and checked) only without them.

    Returns
    -------
    candidates : list of Candidate
        LWPOLYLINE, POLYLINE, SPLINE and ARC entities in file order, then the chains of LINE
        entities of every layer.
    units : str or None
        ``units``, else the unit of ``$INSUNITS`` (None: unitless).
    factor : None

    Raises
    ------
    ProfileError
        The file is unreadable, above the point limit, or its ``$INSUNITS`` is not understood.
    MissingExtraError
        ezdxf is not installed.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import ezdxf
    >>> doc = ezdxf.new()
    >>> doc.header["$INSUNITS"] = 4  # mm
    >>> _ = doc.modelspace().add_lwpolyline([(0, 0), (1000, 500), (2000, 0)])
    >>> path = Path(tempfile.mkdtemp()) / "crease.dxf"
    >>> doc.saveas(path)
    >>> candidates, units, factor = dxf_candidates(path)
    >>> len(candidates), units, factor
    (1, 'mm', None)
    >>> candidates[0].sample(None)[:, :2].tolist()
    [[0.0, 0.0], [1000.0, 500.0], [2000.0, 0.0]]
    """
    ezdxf = need_module("ezdxf", "fab", "DXF files")
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
            candidates.append(Candidate(label, e.dxf.layer, e.dxf.handle, sample))
    for layer, handles, pts in dxf_line_chains(lines):
        label = (
            f"LINE #{handles[0]} on layer {layer}"
            if len(handles) == 1
            else f"chain of {len(handles)} LINEs #{handles[0]}... on layer {layer}"
        )
        candidates.append(Candidate(label, layer, handles[0], lambda tol, pts=pts: pts))
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
        return ocs_to_wcs(ocs, local)

    return lambda tol: adaptive(evaluate, 0.0, 1.0, tol)


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

    Examples
    --------
    Two LINEs meeting at (1, 0), the second drawn backwards, make one chain:

    >>> import ezdxf
    >>> msp = ezdxf.new().modelspace()
    >>> lines = [msp.add_line((0, 0), (1, 0)), msp.add_line((2, 1), (1, 0))]
    >>> [(layer, len(handles), pts.tolist()) for layer, handles, pts in dxf_line_chains(lines)]
    [('0', 2, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 1.0, 0.0]])]
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
        close = EXACT_RELATIVE * size
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
