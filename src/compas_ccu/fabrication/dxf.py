"""The plate cut files: one DXF per plate in millimetres, written and read back.

Plate files (:func:`write_plate_dxf`) have four layers:

``CUT``
    the closed outline (LWPOLYLINE, double precision);
``CREASE``
    the plate's crease polylines (open LWPOLYLINE; XDATA ``COMPAS_CCU``: crease id and the
    other plate id), on the outline: the edges the hinge strips are glued along;
``RULING_SCORE``
    every interior ruling as a LINE (score lines); with ``score_rulings=False`` (the
    ``[fabrication]`` default, plywood that must bend) the same lines are on ``RULING``, a
    reference layer that is not machined;
``LABEL``
    TEXT: plate id, stack position, crease ids with their neighbouring plates, and a face-up
    mark ("UP" and a small triangle pointing up the text), inside the plate.

:func:`read_plate_dxf` reads such a file back in metres. The hinge file (``HINGE_CUT``,
``HINGE_CREASE``, ``LABEL``) is :mod:`compas_ccu.fabrication.hinge_dxf`'s; where the label
goes, :mod:`compas_ccu.fabrication.label_placement`'s; the document, its extents ("zoom extents"
works in every CAD tool) and its fixed bytes, :mod:`compas_ccu.fabrication.dxf_document`'s.
Their public names are importable from here too. ezdxf is imported inside the functions
(``pip install ezdxf``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from compas_ccu.fabrication.dxf_document import APPID, MM, new_document, save_document, xy_list
from compas_ccu.fabrication.hinge_dxf import HINGE_LAYERS, strip_layout, write_hinge_dxf
from compas_ccu.fabrication.label_placement import label_frame, upright
from compas_ccu.kinematics.plates import plate_rulings

__all__ = [
    "write_plate_dxf",
    "write_hinge_dxf",
    "read_plate_dxf",
    "label_frame",
    "strip_layout",
    "PLATE_LAYERS",
    "HINGE_LAYERS",
]

#: Plate file layers and their ACI colours.
PLATE_LAYERS = {"CUT": 1, "CREASE": 5, "RULING_SCORE": 3, "LABEL": 7}
#: The reference layer of the rulings when they are not scored.
RULING_REFERENCE = "RULING"


def _label_lines(data, i: int) -> list:
    """(text, relative height) lines of the label block of plate ``i``."""
    pid = data.plate_ids[i]
    p = len(data.plate_ids)
    k = int(data.stack_position[i])
    lines = [(f"PLATE {pid}", 1.5), (f"stack {k + 1} of {p} (bottom = 1)", 1.0)]
    for cid, other, _ in data.plate_creases(i):
        lines.append((f"crease {cid} to plate {other}", 1.0))
    lines.append((f"{data.name} | {data.material} {data.thickness * 1000:g} mm", 0.8))
    lines.append(("UP", 1.0))
    return lines


def _draw_creases(msp, data, i: int, flat, poly, h: float) -> None:
    """The crease polylines of plate ``i`` (``flat``: its pattern, mm) and a tag beside each,
    inside the plate ``poly``, ``0.7 h`` high."""
    from ezdxf.enums import TextEntityAlignment
    from shapely import Point

    for c, (cid, other, idx) in enumerate(data.plate_creases(i)):
        pts = flat[idx]
        e = msp.add_lwpolyline(
            xy_list(pts), format="xy", close=False, dxfattribs={"layer": "CREASE"}
        )
        e.set_xdata(APPID, [(1000, "crease"), (1071, int(cid)), (1071, int(other))])
        # a small tag along the crease, inside the plate, at 1/4 (3/4, 1/4, ...) of its vertices
        # (clear of the label block near the centre)
        m = int(round((0.25 + 0.5 * (c % 2)) * (len(pts) - 1)))
        t = upright(pts[min(m + 1, len(pts) - 1)] - pts[max(m - 1, 0)])
        nrm = np.array([-t[1], t[0]])
        hs = 0.7 * h
        if not poly.contains(Point(pts[m] + 1.5 * hs * nrm)):
            nrm = -nrm
        e = msp.add_text(
            f"crease {cid} (plate {other})",
            height=hs,
            rotation=math.degrees(math.atan2(t[1], t[0])),
            dxfattribs={"layer": "LABEL"},
        )
        e.set_placement(tuple(pts[m] + 1.5 * hs * nrm), align=TextEntityAlignment.MIDDLE_CENTER)


def _draw_label(msp, lines: list, anchor, u, h: float) -> None:
    """The label block (:func:`_label_lines`) centred on ``anchor``, reading along ``u``, line
    height ``h``; "UP" with a small triangle pointing up the text."""
    from ezdxf.enums import TextEntityAlignment

    v = np.array([-u[1], u[0]])
    rotation = math.degrees(math.atan2(u[1], u[0]))

    def text(s, where, height, layer="LABEL"):
        e = msp.add_text(s, height=height, rotation=rotation, dxfattribs={"layer": layer})
        e.set_placement(tuple(where), align=TextEntityAlignment.MIDDLE_CENTER)
        return e

    pitch = [1.6 * r * h for _, r in lines]
    top = 0.5 * sum(pitch)
    y = top
    for (s, r), dy in zip(lines, pitch):
        centre = anchor + (y - 0.5 * dy) * v
        y -= dy
        if s == "UP":
            text(s, centre + 0.6 * h * u, r * h)
            tri = np.array([[-2.0, -0.6], [-0.8, -0.6], [-1.4, 0.6]]) * h
            msp.add_lwpolyline(
                xy_list(centre + tri[:, :1] * u + tri[:, 1:] * v),
                format="xy",
                close=True,
                dxfattribs={"layer": "LABEL"},
            )
        else:
            text(s, centre, r * h)


def write_plate_dxf(data, i: int, path, *, score_rulings: bool = True) -> Path:
    """Write the cut file of plate ``i`` (array index) in millimetres.

    Parameters
    ----------
    data : compas_ccu.fabrication.data.FabricationData
    i : int
        Array index of the plate (``data.plate_ids[i]`` is its id).
    path : str or Path
        Output ``.dxf`` file.
    score_rulings : bool
        Rulings on ``RULING_SCORE`` (scored); False: on the reference layer ``RULING``.

    Returns
    -------
    Path
        ``path``.

    Notes
    -----
    DXF R2010, ``$INSUNITS`` = 4 (mm). Coordinates are ``data.flat[i] * 1000``: the cut pattern
    seen from the top of the flat-folded stack; cut it with this side up.
    """
    from shapely import Polygon

    if not 0 <= int(i) < len(data.plate_ids):
        raise IndexError(f"plate index {i} out of range for {len(data.plate_ids)} plates")
    i = int(i)
    path = Path(path)
    ruling_layer = "RULING_SCORE" if score_rulings else RULING_REFERENCE
    layers = dict(PLATE_LAYERS)
    if not score_rulings:
        layers = {(RULING_REFERENCE if k == "RULING_SCORE" else k): v for k, v in layers.items()}
    doc = new_document(layers)
    doc.header["$PROJECTNAME"] = str(data.name)
    msp = doc.modelspace()
    flat = np.asarray(data.flat[i], dtype=float) * MM
    outline = np.asarray(data.outline(i), dtype=float) * MM

    cut = msp.add_lwpolyline(xy_list(outline), format="xy", close=True, dxfattribs={"layer": "CUT"})
    cut.set_xdata(APPID, [(1000, "plate"), (1071, int(data.plate_ids[i]))])
    lines = _label_lines(data, i)
    anchor, u, h = label_frame(
        outline, lines=int(math.ceil(sum(r for _, r in lines))), chars=max(len(t) for t, _ in lines)
    )
    _draw_creases(msp, data, i, flat, Polygon(outline), h)
    for a, b in plate_rulings(data.segments)[1:-1]:
        msp.add_line(tuple(flat[a]), tuple(flat[b]), dxfattribs={"layer": ruling_layer})
    _draw_label(msp, lines, anchor, u, h)
    save_document(doc, path)
    return path


def read_plate_dxf(path) -> dict:
    """Read a plate cut file written by :func:`write_plate_dxf` back, in metres.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    dict
        ``outline`` : (m, 2) float, the ``CUT`` polyline (first vertex not repeated);
        ``creases`` : list of dict with ``id`` and ``other`` (crease id, other plate id, from
        XDATA; None if absent) and ``points`` (k, 2) float; ``rulings`` : list of (2, 2) float,
        ``RULING_SCORE`` (or ``RULING``) lines (start, end); ``labels`` : list of str, the
        ``LABEL`` texts;
        ``units`` : int, ``$INSUNITS``. Coordinates are converted to metres from ``$INSUNITS``
        (millimetres if unset).
    """
    import ezdxf

    doc = ezdxf.readfile(str(path))
    units = int(doc.units or ezdxf.units.MM)
    k = ezdxf.units.conversion_factor(units, ezdxf.units.M)
    msp = doc.modelspace()

    def points(e):
        return np.array([p[:2] for p in e.get_points("xy")], dtype=float) * k

    outline = None
    creases, rulings, labels = [], [], []
    for e in msp:
        layer = e.dxf.layer.upper()
        kind = e.dxftype()
        if layer == "CUT" and kind == "LWPOLYLINE" and outline is None:
            outline = points(e)
        elif layer == "CREASE" and kind == "LWPOLYLINE":
            cid = other = None
            if e.has_xdata(APPID):
                ints = [v for code, v in e.get_xdata(APPID) if code in (1070, 1071)]
                cid, other = (ints + [None, None])[:2]
            creases.append({"id": cid, "other": other, "points": points(e)})
        elif layer in ("RULING_SCORE", RULING_REFERENCE) and kind == "LINE":
            rulings.append(
                np.array([tuple(e.dxf.start)[:2], tuple(e.dxf.end)[:2]], dtype=float) * k
            )
        elif layer == "LABEL" and kind == "TEXT":
            labels.append(e.dxf.text)
        elif layer == "LABEL" and kind == "MTEXT":
            labels.append(e.plain_text())
    return {
        "outline": np.zeros((0, 2)) if outline is None else outline,
        "creases": creases,
        "rulings": rulings,
        "labels": labels,
        "units": units,
    }
