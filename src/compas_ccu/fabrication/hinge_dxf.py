"""The hinge file: every textile hinge strip as a cut pattern in one DXF, in millimetres.

:func:`write_hinge_dxf` lays the strips out without overlaps (:func:`strip_layout`: top to
bottom, curved strips nested) on three layers:

``HINGE_CUT``
    the closed outline of every strip (LWPOLYLINE; XDATA ``COMPAS_CCU``: crease id, its two
    plate ids, the strip's translation and width in mm);
``HINGE_CREASE``
    the strip's centre line, the crease it is glued along (open LWPOLYLINE, the same XDATA);
``LABEL``
    TEXT: the crease and its plates on every strip, and a title above the strips.

Extents and fixed bytes: :mod:`compas_ccu.fabrication.dxf_document`. ezdxf and shapely are
imported inside the functions.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from compas_ccu.fabrication.dxf_document import APPID, MM, new_document, save_document, xy_list
from compas_ccu.fabrication.label_placement import upright

__all__ = ["HINGE_LAYERS", "strip_layout", "write_hinge_dxf"]

#: Hinge file layers and their ACI colours.
HINGE_LAYERS = {"HINGE_CUT": 1, "HINGE_CREASE": 5, "LABEL": 7}


def strip_layout(outlines, *, gap: float) -> np.ndarray:
    """Translations that stack closed outlines top to bottom, ``gap`` apart, nesting curved ones.

    Every outline is centred in x on the first one's bounding-box centre; each one after the
    first starts wholly below those placed, then moves up (bisection) as far as it can while
    staying at least ``gap`` away from all of them. Finally everything is shifted so the
    layout's bounding box starts at x = 0 and ends at y = 0.

    Parameters
    ----------
    outlines : sequence of (m, 2) float
        Closed outlines (first vertex not repeated).
    gap : float
        Least distance between any two outlines, > 0.

    Returns
    -------
    (s, 2) float
        Translation of every outline.
    """
    from shapely import Polygon
    from shapely.affinity import translate

    shifts = np.zeros((len(outlines), 2))
    placed = None
    for k, outline in enumerate(outlines):
        outline = np.asarray(outline, dtype=float)
        poly = Polygon(outline)
        lo, hi = outline.min(axis=0), outline.max(axis=0)
        dx = -0.5 * float(lo[0] + hi[0])
        if placed is None:
            dy = -float(hi[1])
        else:
            # dy: the outline wholly below everything placed (feasible); bisect upwards, towards
            # its top level with the first one's, keeping dy feasible
            dy = float(placed.bounds[1]) - gap - float(hi[1])
            bad = float(placed.bounds[3]) - float(hi[1])
            for _ in range(60):
                mid = 0.5 * (dy + bad)
                if translate(poly, dx, mid).distance(placed) >= gap:
                    dy = mid
                else:
                    bad = mid
                if abs(bad - dy) < 1e-6 * (1.0 + abs(dy)):
                    break
        moved = translate(poly, dx, dy)
        placed = moved if placed is None else placed.union(moved)
        shifts[k] = dx, dy
    if placed is not None:
        shifts -= np.array([placed.bounds[0], placed.bounds[3]])
    return shifts


def _draw_strip(msp, s, dx: float, dy: float) -> None:
    """Strip ``s`` translated by ``(dx, dy)`` (m): its outline, centre line and label."""
    from ezdxf.enums import TextEntityAlignment

    shift = np.array([dx, dy])
    a, b = s.plates
    xdata = [
        (1000, "hinge"),
        (1071, int(s.crease_id)),
        (1071, int(a)),
        (1071, int(b)),
        (1040, dx * MM),
        (1040, dy * MM),
        (1040, float(s.width) * MM),
    ]
    e = msp.add_lwpolyline(
        xy_list((s.outline + shift) * MM),
        format="xy",
        close=True,
        dxfattribs={"layer": "HINGE_CUT"},
    )
    e.set_xdata(APPID, xdata)
    centre = (np.asarray(s.centre, dtype=float) + shift) * MM
    e = msp.add_lwpolyline(
        xy_list(centre), format="xy", close=False, dxfattribs={"layer": "HINGE_CREASE"}
    )
    e.set_xdata(APPID, xdata)
    # label on the strip, beside the centre line, at half its length
    seg = np.linalg.norm(np.diff(centre, axis=0), axis=1)
    arc = np.r_[0.0, np.cumsum(seg)]
    m = int(np.searchsorted(arc, 0.5 * arc[-1]))
    m = min(max(m, 1), len(centre) - 2) if len(centre) > 2 else 0
    t = upright(centre[min(m + 1, len(centre) - 1)] - centre[max(m - 1, 0)])
    hs = 0.22 * s.width * MM
    label = msp.add_text(
        f"crease {s.crease_id}: plates {a} - {b}",
        height=hs,
        rotation=math.degrees(math.atan2(t[1], t[0])),
        dxfattribs={"layer": "LABEL"},
    )
    where = centre[m] + 0.25 * s.width * MM * np.array([-t[1], t[0]])
    label.set_placement(tuple(where), align=TextEntityAlignment.MIDDLE_CENTER)


def write_hinge_dxf(
    strips, path, *, name: str = "hinges", gap: float | None = None
) -> dict[int, tuple[float, float]]:
    """Write every hinge strip into one DXF in millimetres, laid out without overlaps.

    Each strip keeps its orientation and is only translated (:func:`strip_layout`): top to
    bottom, each one as high as it can be while ``gap`` clear of those above (curved strips
    nest), the layout starting at x = 0 and ending at y = 0 (the title sits above).

    Parameters
    ----------
    strips : sequence of compas_ccu.fabrication.hinges.HingeStrip
    path : str or Path
        Output ``.dxf`` file.
    name : str
        Design name, written as a title above the strips.
    gap : float, optional
        Clearance between strips, m (default: half the largest strip width).

    Returns
    -------
    dict of int to tuple of float
        ``{crease_id: (dx, dy)}``, the translation of every strip in metres: its DXF
        coordinates are ``1000 * (centre + (dx, dy))``. The same translation (in mm) is in the
        XDATA ``COMPAS_CCU`` of its ``HINGE_CUT`` and ``HINGE_CREASE`` polylines.
    """
    from ezdxf.enums import TextEntityAlignment

    strips = list(strips)
    path = Path(path)
    doc = new_document(HINGE_LAYERS)
    doc.header["$PROJECTNAME"] = str(name)
    msp = doc.modelspace()
    if gap is None:
        gap = 0.5 * max((s.width for s in strips), default=0.05)
    gap = float(gap)
    shifts = strip_layout([st.outline for st in strips], gap=gap)
    moves = {}
    for s, (dx, dy) in zip(strips, shifts.tolist()):
        moves[int(s.crease_id)] = (dx, dy)
        _draw_strip(msp, s, dx, dy)
    if strips:
        width = max(s.width for s in strips)
        title = msp.add_text(
            f"{name}: hinge strips, width {width * MM:g} mm",
            height=0.4 * width * MM,
            dxfattribs={"layer": "LABEL"},
        )
        title.set_placement((0.0, 0.6 * width * MM), align=TextEntityAlignment.BOTTOM_LEFT)
    save_document(doc, path)
    return moves
