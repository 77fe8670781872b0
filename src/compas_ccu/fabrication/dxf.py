"""DXF cut files in millimetres: one per plate, and one with every textile hinge strip.

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

The hinge file (:func:`write_hinge_dxf`) has ``HINGE_CUT``, ``HINGE_CREASE`` and ``LABEL``.

Every file's header extents ``$EXTMIN`` / ``$EXTMAX`` (and the model space's extents and initial
view) are set to the bounding box of its entities (``ezdxf.bbox.extents`` in its fast mode: exact
for the polylines and lines, text estimated from its height and length), so "zoom extents" works
in every CAD tool; ezdxf leaves them at the +-1e20 placeholders otherwise.
ezdxf is imported inside the functions (``pip install ezdxf``).
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from compas_ccu.kinematics.plates import plate_rulings
from compas_ccu.tolerances import ZERO_LENGTH

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
#: Hinge file layers and their ACI colours.
HINGE_LAYERS = {"HINGE_CUT": 1, "HINGE_CREASE": 5, "LABEL": 7}
APPID = "COMPAS_CCU"
MM = 1000.0  # DXF units per metre


@contextmanager
def _fixed_metadata():
    """ezdxf's fixed metadata for the block (creation and update dates 2000-01-01, zero GUIDs,
    its marker without the clock), so a file depends on its drawing only."""
    import ezdxf

    fixed = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = fixed


def new_document(layers: dict):
    """A new R2010 ezdxf document in millimetres with ``layers`` (name -> ACI colour) and
    ezdxf's fixed metadata (the same bytes every run)."""
    import ezdxf

    with _fixed_metadata():  # the marker of its creation: no clock either
        doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM  # $INSUNITS = 4
    doc.header["$MEASUREMENT"] = 1  # metric
    doc.header["$LUNITS"] = 2  # decimal
    for name, color in layers.items():
        doc.layers.add(name, color=color)
    doc.appids.add(APPID)
    return doc


def save_document(doc, path: Path) -> None:
    """Set the header / model space extents and the initial view from the entities, and save.

    The file depends on the drawing only: ezdxf's fixed metadata (creation and update dates
    2000-01-01, zero GUIDs, no clock in its marker) instead of the time of writing, so the same
    design and options write the same bytes (docs/robustness.md).
    """
    from ezdxf import bbox, zoom

    msp = doc.modelspace()
    box = bbox.extents(msp, fast=True)
    if box.has_data:
        lo, hi = box.extmin, box.extmax
        doc.header["$EXTMIN"] = (lo.x, lo.y, lo.z)
        doc.header["$EXTMAX"] = (hi.x, hi.y, hi.z)
        msp.reset_extents((lo.x, lo.y, lo.z), (hi.x, hi.y, hi.z))
        zoom.center(msp, box.center, box.size)
    _fixed_class_order(doc)
    with _fixed_metadata():
        doc.saveas(path)


def _fixed_class_order(doc) -> None:
    """The CLASSES section in a fixed order: ezdxf adds a CLASS for every entity type in use
    from a set, whose order follows Python's string hashing and so changes from one process to
    the next (the same drawing wrote other bytes in every run). Its required classes first, in
    its order, then the others by name; saving adds nothing more (ezdxf keeps a class once)."""
    from ezdxf.sections.classes import REQUIRED_CLASSES

    doc.commit_pending_changes()
    doc.classes.add_required_classes(doc.dxfversion)
    required = {n: k for k, n in enumerate(REQUIRED_CLASSES.get(doc.dxfversion, ()))}
    keys = sorted(doc.classes.classes, key=lambda key: (required.get(key[0], len(required)), key))
    doc.classes.classes = {key: doc.classes.classes[key] for key in keys}


def xy_list(points) -> list:
    """(m, 2) points as the list of tuples ezdxf's polylines take."""
    return [tuple(p) for p in np.asarray(points, dtype=float).tolist()]


def _upright(u: np.ndarray) -> np.ndarray:
    """Unit direction ``u`` flipped so text along it reads left to right (angle in (-90, 90])."""
    u = np.asarray(u, dtype=float)
    u = u / np.linalg.norm(u)
    if u[0] < -ZERO_LENGTH or (abs(u[0]) <= ZERO_LENGTH and u[1] < 0):
        u = -u
    return u


def label_frame(outline, *, lines: int = 5, chars: int = 30):
    """Where and how large a block of text fits inside a plate, near its centroid of area.

    Parameters
    ----------
    outline : (m, 2) float
        Closed plate outline (first vertex not repeated).
    lines : int
        Lines of text in the block.
    chars : int
        Characters of the longest line.

    Returns
    -------
    anchor : (2,) float
        Centre of the block: the centroid of area if the block fits around it, else the nearest
        point to it at which the block (height ``1.6 * lines * height``) stays inside.
    direction : (2,) float
        Unit reading direction of the text: x, or the direction of the nearest outline edge if
        the centroid lies outside (crescent plates), turned to read left to right.
    height : float
        Text height of one line, outline units: 3.5 % of the plate's bounding-box diagonal,
        reduced until the block fits the plate's inscribed circle and its length.
    """
    from shapely import Point, Polygon
    from shapely.ops import nearest_points, polylabel

    outline = np.asarray(outline, dtype=float)
    poly = Polygon(outline)
    if not poly.is_valid:
        poly = poly.buffer(0)
    size = float(np.linalg.norm(np.ptp(outline, axis=0)))
    pole = polylabel(poly, tolerance=1e-3 * size)
    r_in = float(poly.exterior.distance(pole))
    height = min(0.035 * size, 1.6 * r_in / (1.6 * lines))
    centroid = poly.centroid
    direction = np.array([1.0, 0.0])
    anchor = np.array([centroid.x, centroid.y])
    for _ in range(2):  # the second pass re-checks the block length along the new direction
        half_block = 0.8 * lines * height
        inset = poly.buffer(-min(half_block, 0.95 * r_in))
        if inset.is_empty:
            inset = pole
        if inset.contains(centroid):
            anchor, direction = np.array([centroid.x, centroid.y]), np.array([1.0, 0.0])
        else:
            q = nearest_points(inset, centroid)[0]
            anchor = np.array([q.x, q.y])
            ring = poly.exterior
            s = ring.project(Point(anchor))
            eps = 1e-3 * size
            p0, p1 = ring.interpolate(s - eps), ring.interpolate(s + eps)
            edge = np.array([p1.x - p0.x, p1.y - p0.y])
            if np.linalg.norm(edge) > 0:
                direction = _upright(edge)
        # the block must also fit the plate's extent along the reading direction
        along = outline @ direction
        height = min(height, 0.8 * float(np.ptp(along)) / (0.65 * max(chars, 1)))
    return anchor, direction, height


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
    from ezdxf.enums import TextEntityAlignment
    from shapely import Point, Polygon

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
    n = data.segments
    outline = np.asarray(data.outline(i), dtype=float) * MM

    poly = Polygon(outline)
    cut = msp.add_lwpolyline(xy_list(outline), format="xy", close=True, dxfattribs={"layer": "CUT"})
    cut.set_xdata(APPID, [(1000, "plate"), (1071, int(data.plate_ids[i]))])

    lines = _label_lines(data, i)
    anchor, u, h = label_frame(
        outline, lines=int(math.ceil(sum(r for _, r in lines))), chars=max(len(t) for t, _ in lines)
    )
    v = np.array([-u[1], u[0]])
    rotation = math.degrees(math.atan2(u[1], u[0]))

    def text(s, where, height, layer="LABEL"):
        e = msp.add_text(s, height=height, rotation=rotation, dxfattribs={"layer": layer})
        e.set_placement(tuple(where), align=TextEntityAlignment.MIDDLE_CENTER)
        return e

    for c, (cid, other, idx) in enumerate(data.plate_creases(i)):
        pts = flat[idx]
        e = msp.add_lwpolyline(
            xy_list(pts), format="xy", close=False, dxfattribs={"layer": "CREASE"}
        )
        e.set_xdata(APPID, [(1000, "crease"), (1071, int(cid)), (1071, int(other))])
        # a small tag along the crease, inside the plate, at 1/4 (3/4, 1/4, ...) of its vertices
        # (clear of the label block near the centre)
        m = int(round((0.25 + 0.5 * (c % 2)) * (len(pts) - 1)))
        t = _upright(pts[min(m + 1, len(pts) - 1)] - pts[max(m - 1, 0)])
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

    for a, b in plate_rulings(n)[1:-1]:
        msp.add_line(tuple(flat[a]), tuple(flat[b]), dxfattribs={"layer": ruling_layer})

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
    save_document(doc, path)
    return path


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


def write_hinge_dxf(strips, path, *, name: str = "hinges", gap: float | None = None) -> dict:
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
    dict
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
        t = _upright(centre[min(m + 1, len(centre) - 1)] - centre[max(m - 1, 0)])
        hs = 0.22 * s.width * MM
        label = msp.add_text(
            f"crease {s.crease_id}: plates {a} - {b}",
            height=hs,
            rotation=math.degrees(math.atan2(t[1], t[0])),
            dxfattribs={"layer": "LABEL"},
        )
        where = centre[m] + 0.25 * s.width * MM * np.array([-t[1], t[0]])
        label.set_placement(tuple(where), align=TextEntityAlignment.MIDDLE_CENTER)
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
