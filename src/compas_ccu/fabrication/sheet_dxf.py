"""One sheet's DXF: kerf-compensated toolpaths, score lines, engraved labels, the parts' true
outlines and the sheet for reference (millimetres).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from compas_ccu.fabrication.dxf_document import APPID, MM, new_document, save_document, xy_list
from compas_ccu.fabrication.label_placement import label_frame
from compas_ccu.fabrication.plan import WorkshopPlan, outline_ring

__all__ = [
    "SHEET_LAYERS",
    "write_sheet_dxf",
]

#: Sheet file layers and their ACI colours: the toolpaths (cutter centre lines), the score
#: lines, the engraved labels, and for reference only the parts' true outlines and the sheet.
SHEET_LAYERS = {
    "OUTER_CUT": 1,
    "INNER_CUT": 6,
    "SCORE": 3,
    "LABEL": 7,
    "PART_OUTLINE": 8,
    "SHEET": 9,
}


def write_sheet_dxf(plan: WorkshopPlan, s: int, path, *, name: str = "design") -> Path:
    """Write sheet ``s`` of ``plan`` in millimetres.

    Layers: ``OUTER_CUT`` (every part's toolpath: its outline offset by kerf / 2 outwards,
    round corners), ``INNER_CUT`` (holes; none yet), ``SCORE`` (interior rulings when
    ``score_rulings``), ``LABEL`` (engraved part names and splice positions), and for
    reference ``PART_OUTLINE`` (true outlines) and ``SHEET`` (the sheet's edge). Every toolpath
    carries XDATA ``COMPAS_CCU``: "part", its name, rotation (deg) and translation (mm).
    """
    from ezdxf.enums import TextEntityAlignment
    from shapely import Polygon

    o = plan.options
    sheet = plan.sheets[s]
    doc = new_document(SHEET_LAYERS)
    doc.header["$PROJECTNAME"] = str(name)
    msp = doc.modelspace()
    length, width = (v * MM for v in sheet["size"])
    msp.add_lwpolyline(
        [(0.0, 0.0), (length, 0.0), (length, width), (0.0, width)],
        format="xy",
        close=True,
        dxfattribs={"layer": "SHEET"},
    )
    for p in plan.parts:
        if p.sheet != s:
            continue
        outline = p.placed(p.outline) * MM
        poly = Polygon(outline)
        path_poly = poly.buffer(0.5 * o.cut * MM, join_style="round", quad_segs=8)
        e = msp.add_lwpolyline(
            xy_list(outline_ring(path_poly)),
            format="xy",
            close=True,
            dxfattribs={"layer": "OUTER_CUT"},
        )
        e.set_xdata(
            APPID,
            [
                (1000, "part"),
                (1000, p.name),
                (1040, p.rotation),
                (1040, p.translation[0] * MM),
                (1040, p.translation[1] * MM),
            ],
        )
        msp.add_lwpolyline(
            xy_list(outline), format="xy", close=True, dxfattribs={"layer": "PART_OUTLINE"}
        )
        if o.score_rulings:
            for line in p.score:
                a, b = p.placed(line) * MM
                msp.add_line(tuple(a), tuple(b), dxfattribs={"layer": "SCORE"})
        for rect in p.marks:  # the splice plate's place, clipped to the part
            mark = Polygon(p.placed(rect) * MM).intersection(poly)
            if mark.geom_type == "Polygon" and not mark.is_empty:
                msp.add_lwpolyline(
                    xy_list(outline_ring(mark)),
                    format="xy",
                    close=True,
                    dxfattribs={"layer": "LABEL"},
                )
        anchor, u, h = label_frame(
            outline, lines=len(p.label) + 1, chars=max(len(t) for t in p.label)
        )
        v = np.array([-u[1], u[0]])
        rotation = math.degrees(math.atan2(u[1], u[0]))
        top = 0.5 * 1.6 * h * (len(p.label) - 1)
        for k, text in enumerate(p.label):
            t = msp.add_text(
                text,
                height=h * (1.4 if k == 0 else 1.0),
                rotation=rotation,
                dxfattribs={"layer": "LABEL"},
            )
            t.set_placement(
                tuple(anchor + (top - 1.6 * h * k) * v), align=TextEntityAlignment.MIDDLE_CENTER
            )
    title = msp.add_text(
        f"{name}: sheet {s + 1} of {len(plan.sheets)}, {length:g} x {width:g} x "
        f"{sheet.get('thickness', 0.0) * MM:g} mm, kerf "
        f"{o.cut * MM:g} mm, utilisation {100 * sheet['utilisation']:.1f} %",
        height=0.012 * width,
        dxfattribs={"layer": "LABEL"},
    )
    title.set_placement((0.0, width + 0.01 * width), align=TextEntityAlignment.BOTTOM_LEFT)
    save_document(doc, Path(path))
    return Path(path)
