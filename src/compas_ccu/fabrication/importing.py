"""The reverse of fabrication: plate DXFs back to a design that deploys (``ccu import``).

A folder of plate cut files, as :func:`compas_ccu.fabrication.dxf.write_plate_dxf` writes them
or drawn by hand to the same convention (docs/import.md), is read back:

``CUT``
    the closed outline of the plate (LWPOLYLINE or POLYLINE, bulges allowed);
``CREASE``
    every crease of the plate, on the outline: LWPOLYLINE, POLYLINE, ARC, SPLINE or a chain of
    LINEs. XDATA ``COMPAS_CCU`` (crease id, other plate id) pairs the plates; without it the
    plates are paired by their creases' lengths;
``RULING_SCORE``
    every interior ruling as a LINE from the crease to the other side of the plate (or on the
    reference layer ``RULING``, where ``ccu fabricate`` puts them when they are not scored).
    The two end rulings are the outline's edges at the crease's ends.

The crease vertices are the crease's end points and the rulings' feet on it, in order along it;
the ruling ends are the rulings' far end points. :func:`import_structure` joins every plate of
the folder into one mechanism that deploys the whole structure, and writes it as a design
document (``ccu import``): the leading plate as a ``state = "flat"`` design with ``explicit``
rulings, every other plate as a ``[[layout.patterns]]`` table (its cut pattern, its parent and
the parent's boundary it hangs from; :mod:`compas_ccu.design.patterns`).
:func:`import_design` turns one crease and its two plates into a single-crease design, the one
:func:`compas_ccu.model.flat_design` writes (``ccu import --leading-pair-only``); there the
partner must be the leading plate's mirror image (same crease, same rulings).

Inconsistent drawings are refused before anything is written, the error naming the plate file
and the entity (DXF handle): a missing layer, a ruling that does not start on the crease or
crosses another one, partner creases of different length, a partner that is not the mirror
image of the leading plate.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from compas_ccu.curves.dxf_input import (
    check_dxf_points,
    check_finite,
    dxf_units,
    extent,
    one_line,
)
from compas_ccu.curves.readers import UNITS, dxf_line_chains, dxf_sampler
from compas_ccu.design import Design
from compas_ccu.design.build import build
from compas_ccu.design.writer import design_toml
from compas_ccu.errors import DesignError, GeometryError, ProfileError, require
from compas_ccu.geometry import fit_planes, rigid_align, unit
from compas_ccu.kinematics.mechanism import CreaseLink, Mechanism, PlateLink
from compas_ccu.kinematics.plates import hinge_and_rulings
from compas_ccu.model import CCUModel
from compas_ccu.strips.intrinsics import strip_intrinsics
from compas_ccu.thickness.axis_shift import crease_sides, place_thick, vertex_offsets
from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE

__all__ = [
    "PlateDrawing",
    "CreaseDrawing",
    "CreasePair",
    "read_plate_drawing",
    "read_plate_folder",
    "crease_pattern",
    "pair_creases",
    "import_design",
    "design_toml",
    "round_trip_error",
    "ImportedStructure",
    "import_structure",
    "structure_document",
    "thickness_shifts",
    "structure_round_trip_error",
    "structure_error",
]

REQUIRED_LAYERS = ("CUT", "CREASE", "RULING_SCORE")
APPID = "COMPAS_CCU"
#: Points closer than this (relative to the plate's size) are the same point of the drawing.
SNAP = 1e-7
#: Relative tolerance of the partner checks: crease lengths, ruling lengths and angles.
PARTNER_TOLERANCE = 1e-6
#: Sampling tolerance of curved outlines and creases, relative to the plate's size.
SAMPLING = 1e-9


@dataclass
class CreaseDrawing:
    """One ``CREASE`` entity (or chain of LINEs) of a plate file, m."""

    handle: str
    points: np.ndarray  # (k, 2) polyline along the crease (dense for curves)
    crease_id: int | None = None
    other: int | None = None

    @property
    def length(self) -> float:
        """Length of the crease curve, m."""
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())


@dataclass
class PlateDrawing:
    """One plate cut file read back, m."""

    path: Path
    plate_id: int | None
    outline: np.ndarray  # (m, 2) closed outline, first vertex not repeated
    outline_handle: str
    creases: list = field(default_factory=list)
    rulings: list = field(default_factory=list)  # [(handle, (2, 2) float)]

    @property
    def size(self) -> float:
        """Diagonal of the outline's bounding box, m."""
        return float(np.linalg.norm(np.ptp(self.outline, axis=0)))

    @property
    def label(self) -> str:
        return self.path.name


@dataclass
class CreasePair:
    """A crease and its two plates (``a`` the leading one)."""

    key: str
    a: PlateDrawing
    crease_a: CreaseDrawing
    b: PlateDrawing
    crease_b: CreaseDrawing


def _ezdxf():
    require("ezdxf", "fab", what="'ccu import'")
    import ezdxf

    return ezdxf


def _xdata_ints(e) -> list:
    if not e.has_xdata(APPID):
        return []
    return [v for code, v in e.get_xdata(APPID) if code in (1070, 1071)]


def read_plate_drawing(path, *, units: str | None = None) -> PlateDrawing:
    """Read one plate cut file (layers CUT, CREASE, RULING_SCORE) in metres.

    Parameters
    ----------
    path : str or Path
    units : str, optional
        ``mm``, ``cm``, ``m``, ``in`` or ``ft``: overrides the file's ``$INSUNITS``; a unitless
        file is read in millimetres (the unit ``ccu fabricate`` writes).

    Raises
    ------
    DesignError
        The file cannot be read, a layer is missing or empty, CUT is not one closed polyline,
        an entity has a type its layer does not take (file, layer and handle named).
    """
    ezdxf = _ezdxf()
    path = Path(path)
    check_dxf_points(path)
    try:
        doc = ezdxf.readfile(str(path))
    except (OSError, ezdxf.DXFError, StopIteration, ValueError) as exc:  # ValueError: decoding
        raise DesignError(f"cannot read plate file {str(path)!r}: {one_line(exc)}") from None
    if units is None:
        try:
            units = dxf_units(doc, path.name) or "mm"  # unitless: as ccu fabricate writes
        except ProfileError as exc:
            raise DesignError(str(exc)) from None
    k = UNITS[units]
    try:
        return _plate_drawing(path, doc, k)
    except ProfileError as exc:  # a SPLINE no curve is built of, a non-finite coordinate
        raise DesignError(f"{path.name} {exc}") from None


def _plate_drawing(path: Path, doc, k: float) -> PlateDrawing:
    by_layer: dict = {}
    for e in doc.modelspace():
        by_layer.setdefault(e.dxf.layer.upper(), []).append(e)
    if not by_layer.get("RULING_SCORE") and by_layer.get("RULING"):
        by_layer["RULING_SCORE"] = by_layer["RULING"]  # rulings drawn but not scored
    for layer in REQUIRED_LAYERS:
        if not by_layer.get(layer):
            raise DesignError(
                f"{path.name}: no entity on layer {layer} (a plate file has the layers "
                f"{', '.join(REQUIRED_LAYERS)}; docs/import.md)"
            )
    cuts = by_layer["CUT"]
    if len(cuts) != 1 or cuts[0].dxftype() not in ("LWPOLYLINE", "POLYLINE"):
        handles = ", ".join(f"{e.dxftype()} #{e.dxf.handle}" for e in cuts)
        raise DesignError(
            f"{path.name}: layer CUT must hold one closed polyline (the outline), holds {handles}"
        )
    cut = cuts[0]
    closed = cut.closed if cut.dxftype() == "LWPOLYLINE" else cut.is_closed
    sample = dxf_sampler(cut)
    rough = check_finite(sample(None), f"CUT #{cut.dxf.handle}")[:, :2]
    size = extent(rough, f"CUT #{cut.dxf.handle}")
    outline = _dedupe(np.asarray(sample(SAMPLING * size))[:, :2] * k, SNAP * size * k)
    if np.linalg.norm(outline[0] - outline[-1]) <= SNAP * size * k:
        outline, closed = outline[:-1], True
    if not closed:
        raise DesignError(f"{path.name} CUT #{cut.dxf.handle}: the outline is not closed")
    ints = _xdata_ints(cut)
    plate = PlateDrawing(path, ints[0] if ints else None, outline, cut.dxf.handle)

    lines = []
    for e in by_layer["CREASE"]:
        if e.dxftype() == "LINE":
            lines.append(e)
            continue
        sampler = dxf_sampler(e)
        if sampler is None:
            raise DesignError(
                f"{path.name} CREASE #{e.dxf.handle}: a {e.dxftype()} is no crease curve "
                "(LWPOLYLINE, POLYLINE, ARC, SPLINE or LINEs)"
            )
        pts = check_finite(sampler(SAMPLING * size), f"CREASE #{e.dxf.handle}")
        pts = _dedupe(pts[:, :2] * k, SNAP * size * k)
        cid, other = (_xdata_ints(e) + [None, None])[:2]
        plate.creases.append(CreaseDrawing(e.dxf.handle, pts, cid, other))
    for _, handles, pts in dxf_line_chains(lines):
        plate.creases.append(CreaseDrawing(handles[0], pts[:, :2] * k))
    for e in by_layer["RULING_SCORE"]:
        if e.dxftype() != "LINE":
            raise DesignError(
                f"{path.name} RULING_SCORE #{e.dxf.handle}: a {e.dxftype()}; rulings are LINEs"
            )
        line = np.array([tuple(e.dxf.start)[:2], tuple(e.dxf.end)[:2]], dtype=float) * k
        plate.rulings.append((e.dxf.handle, line))
    return plate


def _dedupe(points, tol):
    """Drop points that repeat their predecessor (the joints of line and arc pieces)."""
    if len(points) < 2:
        return points
    keep = np.r_[True, np.linalg.norm(np.diff(points, axis=0), axis=1) > tol]
    return points[keep]


def read_plate_folder(folder, *, units: str | None = None) -> list:
    """Every plate file of a folder: ``plates/plate_*.dxf`` (as ``ccu fabricate`` writes them),
    else ``plate_*.dxf``, else every ``*.dxf`` but ``hinges.dxf``; in name order.

    Raises
    ------
    DesignError
        The folder does not exist or holds no plate file; a plate file is refused
        (:func:`read_plate_drawing`).
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise DesignError(f"plate folder {str(folder)!r} does not exist")
    for pattern in ("plates/plate_*.dxf", "plate_*.dxf", "*.dxf"):
        paths = sorted(p for p in folder.glob(pattern) if p.name.lower() != "hinges.dxf")
        if paths:
            break
    if not paths:
        raise DesignError(f"{str(folder)!r} holds no plate DXF file (plates/plate_<id>.dxf)")
    return [read_plate_drawing(p, units=units) for p in paths]


def _distance_to_polyline(points, polyline):
    """Distance of every point to a polyline, and the arc length of its nearest point."""
    a, b = polyline[:-1], polyline[1:]
    ab = b - a
    length2 = np.maximum((ab * ab).sum(axis=1), DIVISION_FLOOR)
    s_edges = np.r_[0.0, np.cumsum(np.sqrt(length2))]
    out_d, out_s = [], []
    for p in np.atleast_2d(points):
        t = np.clip(((p - a) * ab).sum(axis=1) / length2, 0.0, 1.0)
        q = a + t[:, None] * ab
        d = np.linalg.norm(q - p, axis=1)
        k = int(np.argmin(d))
        out_d.append(d[k])
        out_s.append(s_edges[k] + t[k] * math.sqrt(length2[k]))
    return np.array(out_d), np.array(out_s)


def _end_ruling(plate: PlateDrawing, crease: CreaseDrawing, end: np.ndarray, tol: float):
    """Far end of the end ruling at a crease end point: the outline's edge that leaves the
    crease there (followed while straight)."""
    outline = plate.outline
    d = np.linalg.norm(outline - end, axis=1)
    i = int(np.argmin(d))
    if d[i] > tol:
        raise DesignError(
            f"{plate.label} CREASE #{crease.handle}: its end point {np.round(end, 6).tolist()} "
            f"is not a vertex of the CUT outline #{plate.outline_handle} (nearest "
            f"{d[i]:.3g} m away): a crease lies on the outline"
        )
    m = len(outline)
    for step in (1, -1):
        j = (i + step) % m
        off, _ = _distance_to_polyline(outline[j], crease.points)
        if off[0] > tol:
            direction = outline[j] - outline[i]
            direction /= np.linalg.norm(direction)
            # follow collinear vertices along the straight end edge
            while True:
                nxt = (j + step) % m
                v = outline[nxt] - outline[i]
                if (
                    np.linalg.norm(v) > 0
                    and abs(direction[0] * v[1] - direction[1] * v[0]) <= (tol)
                    and v @ direction > np.linalg.norm(outline[j] - outline[i])
                ):
                    j = nxt
                else:
                    break
            return outline[j]
    raise DesignError(  # pragma: no cover - a CUT outline equal to its crease
        f"{plate.label} CREASE #{crease.handle}: no outline edge leaves the crease end "
        f"{np.round(end, 6).tolist()}"
    )


def crease_pattern(plate: PlateDrawing, crease: CreaseDrawing):
    """The crease vertices and ruling ends of a plate at one of its creases.

    Returns
    -------
    near : (n + 1, 2) float
        Crease vertices: the crease's end points and the interior rulings' feet, in order.
    far : (n + 1, 2) float
        The other end of every ruling (the end rulings: the outline's edges at the ends).
    handles : list of str
        The ruling of every vertex (the outline's handle for the end rulings).

    Raises
    ------
    DesignError
        A ruling that touches the crease with neither end, two rulings from one crease point,
        rulings that cross (file and both handles named), a crease end off the outline.
    """
    tol = SNAP * plate.size
    line = crease.points
    feet, fars, handles, params = [], [], [], []
    for handle, seg in plate.rulings:
        d, s = _distance_to_polyline(seg, line)
        if min(d) > tol:
            if (
                any(
                    min(_distance_to_polyline(seg, c.points)[0]) <= tol
                    for c in plate.creases
                    if c is not crease
                )
                and len(plate.creases) > 1
            ):
                continue  # a ruling of another crease of this plate that ends elsewhere
            raise DesignError(
                f"{plate.label} RULING_SCORE #{handle}: the ruling does not start on the "
                f"crease #{crease.handle} (its ends are {min(d):.3g} m from it)"
            )
        k = int(np.argmin(d))
        feet.append(seg[k])
        fars.append(seg[1 - k])
        params.append(s[k])
        handles.append(handle)
    order = np.argsort(params)
    params = np.asarray(params)[order]
    total = crease.length
    if len(params) and (params[0] <= tol or params[-1] >= total - tol):
        k = 0 if params[0] <= tol else len(params) - 1
        raise DesignError(
            f"{plate.label} RULING_SCORE #{handles[order[k]]}: an interior ruling starts at an "
            f"end of the crease #{crease.handle} (the end rulings are the outline's edges)"
        )
    same = np.flatnonzero(np.diff(params) <= tol)
    if same.size:
        a, b = handles[order[same[0]]], handles[order[same[0] + 1]]
        raise DesignError(
            f"{plate.label} RULING_SCORE #{a} and #{b}: two rulings start at the same crease point"
        )
    start, end = line[0], line[-1]
    near = np.array([start, *[feet[k] for k in order], end])
    far = np.array(
        [
            _end_ruling(plate, crease, start, tol),
            *[fars[k] for k in order],
            _end_ruling(plate, crease, end, tol),
        ]
    )
    names = [f"{plate.outline_handle} (end ruling)"] + [handles[k] for k in order]
    names.append(f"{plate.outline_handle} (end ruling)")
    _check_crossings(plate, near, far, names, tol)
    return near, far, names


def _check_crossings(plate, near, far, names, tol) -> None:
    """Refuse rulings that cross inside the plate (a pattern that folds over itself)."""
    p, r = near, far - near
    n = len(p)
    for i in range(n - 1):
        q, s = p[i + 1 :], r[i + 1 :]
        denom = r[i, 0] * s[:, 1] - r[i, 1] * s[:, 0]
        qp = q - p[i]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (qp[:, 0] * s[:, 1] - qp[:, 1] * s[:, 0]) / denom
            u = (qp[:, 0] * r[i, 1] - qp[:, 1] * r[i, 0]) / denom
        lim = tol / max(float(np.linalg.norm(r[i])), DIVISION_FLOOR)
        hit = np.flatnonzero(
            (np.abs(denom) > 0) & (t > lim) & (t < 1 - lim) & (u > lim) & (u < 1 - lim)
        )
        if hit.size:
            j = i + 1 + int(hit[0])
            raise DesignError(
                f"{plate.label} RULING_SCORE #{names[i]} and #{names[j]}: the rulings cross "
                f"inside the plate (at crease vertices {i} and {j}); rulings of a developable "
                "plate never cross"
            )


def pair_creases(plates: list) -> list:
    """The creases of a folder of plates and their two plates.

    Creases with XDATA are paired by crease id; the others by length (a crease and the one
    crease of another plate with the same length).

    Raises
    ------
    DesignError
        Partner creases of different length (both plates, handles and lengths named), a crease
        id on more or fewer than two plates, a crease without a partner.
    """
    pairs, loose = [], []
    by_id: dict = {}
    for plate in plates:
        for crease in plate.creases:
            if crease.crease_id is not None:
                by_id.setdefault(crease.crease_id, []).append((plate, crease))
            else:
                loose.append((plate, crease))
    for cid, members in sorted(by_id.items()):
        if len(members) != 2:
            where = ", ".join(f"{p.label} #{c.handle}" for p, c in members)
            raise DesignError(f"crease {cid} is on {len(members)} plates ({where}), not 2")
        pairs.append(CreasePair(f"crease {cid}", members[0][0], members[0][1], *members[1]))
    while loose:
        plate, crease = loose.pop(0)
        others = [(p, c) for p, c in loose if p is not plate]
        if not others:
            raise DesignError(
                f"{plate.label} CREASE #{crease.handle}: no partner crease on another plate"
            )
        tol = PARTNER_TOLERANCE * max(crease.length, DIVISION_FLOOR)
        match = [(p, c) for p, c in others if abs(c.length - crease.length) <= tol]
        if not match:
            p, c = min(others, key=lambda pc: abs(pc[1].length - crease.length))
            raise DesignError(
                f"partner creases of different length: {plate.label} CREASE #{crease.handle} "
                f"is {crease.length:.9g} m long, {p.label} CREASE #{c.handle} "
                f"{c.length:.9g} m (difference {abs(c.length - crease.length):.3g} m); the two "
                "plates of a crease share it"
            )
        loose.remove(match[0])
        pairs.append(CreasePair(f"crease {plate.label} #{crease.handle}", plate, crease, *match[0]))
    for pair in pairs:
        la, lb = pair.crease_a.length, pair.crease_b.length
        if abs(la - lb) > PARTNER_TOLERANCE * la:
            raise DesignError(
                f"partner creases of different length ({pair.key}): {pair.a.label} CREASE "
                f"#{pair.crease_a.handle} is {la:.9g} m long, {pair.b.label} CREASE "
                f"#{pair.crease_b.handle} {lb:.9g} m (difference {abs(la - lb):.3g} m)"
            )
    return pairs


def _intrinsic(near, far):
    """Crease edge lengths, ruling lengths and the (unsigned) angles between them."""
    edges = np.linalg.norm(np.diff(near, axis=0), axis=1)
    r = far - near
    lengths = np.linalg.norm(r, axis=1)
    t = np.gradient(near, axis=0)
    cos = (t * r).sum(axis=1) / (np.linalg.norm(t, axis=1) * lengths)
    return edges, lengths, np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def _check_partner(pair: CreasePair, a_pattern, b_pattern):
    """The partner must be the leading plate's mirror image (or the same pattern)."""
    near_a, far_a, _ = a_pattern
    near_b, far_b, names_b = b_pattern
    if len(near_a) != len(near_b):
        raise DesignError(
            f"{pair.b.label}: {len(near_b) - 2} interior rulings on CREASE "
            f"#{pair.crease_b.handle}, its partner in {pair.a.label} has {len(near_a) - 2}: the "
            "two plates of a crease have their rulings at the same crease points"
        )
    ea, la, ga = _intrinsic(near_a, far_a)
    best = None
    for flip in (False, True):
        nb, fb, nm = (
            (near_b[::-1], far_b[::-1], names_b[::-1]) if flip else (near_b, far_b, names_b)
        )
        eb, lb, gb = _intrinsic(nb, fb)
        if flip:
            gb = 180.0 - gb
        err = max(
            float(np.abs(ea - eb).max()) / max(float(ea.max()), DIVISION_FLOOR),
            float(np.abs(la - lb).max()) / max(float(la.max()), DIVISION_FLOOR),
        )
        if best is None or err < best[0]:
            best = (err, la, lb, ea, eb, nm, flip)
    err, la, lb, ea, eb, nm, flip = best
    if err > PARTNER_TOLERANCE:
        j = int(np.argmax(np.abs(la - lb)))
        if abs(la[j] - lb[j]) > PARTNER_TOLERANCE * la.max():
            raise DesignError(
                f"{pair.b.label} RULING_SCORE #{nm[j]}: the ruling at crease vertex {j} is "
                f"{lb[j]:.9g} m long, its partner in {pair.a.label} {la[j]:.9g} m: a design "
                "file holds one crease and a mirror partner of the same rulings, so this pair "
                "cannot be imported (docs/import.md)"
            )
        j = int(np.argmax(np.abs(ea - eb)))
        raise DesignError(
            f"{pair.b.label} CREASE #{pair.crease_b.handle}: its segment {j} is {eb[j]:.9g} m, "
            f"the partner's in {pair.a.label} {ea[j]:.9g} m: the rulings do not meet the two "
            "creases at the same points"
        )
    return err, flip


def _select(folder: Path, *, crease, units, whole: bool = False):
    """Read a folder; the crease pair chosen (its stack-upper plate first) and every pattern.

    ``whole``: without ``crease``, the crease of the shallowest attachment tree leads (a
    mechanism grows from the middle of its layout) instead of a refusal."""
    folder = Path(folder)
    manifest = {}
    for place in (folder / "fabrication.json", folder.parent / "fabrication.json"):
        if place.is_file():
            manifest = json.loads(place.read_text(encoding="utf-8"))
            break
    plates = read_plate_folder(folder, units=units)
    pairs = pair_creases(plates)
    patterns = {}
    for pair in pairs:
        patterns[pair.key] = (
            crease_pattern(pair.a, pair.crease_a),
            crease_pattern(pair.b, pair.crease_b),
        )
    listing = "; ".join(f"{p.key}: {p.a.label} - {p.b.label}" for p in pairs)
    if whole and crease is None and len(pairs) > 1:
        lead = manifest.get("leading_crease")  # ccu fabricate records the design's
        if lead is not None and any(p.crease_a.crease_id == lead for p in pairs):
            crease = lead
        else:
            return manifest, plates, pairs, _middle(pairs, patterns, manifest), patterns
    if crease is None and len(pairs) != 1:
        raise DesignError(
            f"{folder}: {len(pairs)} creases ({listing}); a design file holds one crease pair: "
            "choose one (--crease ID or the leading plate's file name; docs/import.md)"
        )
    if crease is None:
        pair = pairs[0]
    else:
        chosen = [
            p
            for p in pairs
            if str(crease) in (str(p.crease_a.crease_id), p.a.label, p.b.label, p.key)
        ]
        if not chosen:
            raise DesignError(f"{folder}: no crease {crease!r}; the creases: {listing}")
        pair = chosen[0]
    return manifest, plates, pairs, _stack_upper_leads(pair, patterns, manifest), patterns


def _middle(pairs: list, patterns: dict, manifest: dict) -> CreasePair:
    """The crease pair whose attachment tree is the shallowest (the first of equals), its
    stack-upper plate first (``patterns`` reordered with it)."""
    best = None
    for pair in pairs:
        trial = dict(patterns)
        upper = _stack_upper_leads(pair, trial, manifest)
        depth = _depth(_structure_tree(upper, pairs, *trial[upper.key])[0])
        if best is None or depth < best[0]:
            best = (depth, pair)
    return _stack_upper_leads(best[1], patterns, manifest)


def _stack_upper_leads(pair: CreasePair, patterns: dict, manifest: dict) -> CreasePair:
    """The pair with the plate higher in the flat-folded stack as plate ``a`` (``patterns``
    reordered with it): the drawings show the plates from the stack's top, so it rises towards
    the viewer as the leading plate does (+z); without fabrication.json, the first file leads
    and the structure may come out mirrored."""
    stack = manifest.get("stack_order")
    if stack and pair.a.plate_id in stack and pair.b.plate_id in stack:
        if stack.index(pair.a.plate_id) < stack.index(pair.b.plate_id):
            pair = CreasePair(pair.key, pair.b, pair.crease_b, pair.a, pair.crease_a)
            patterns[pair.key] = patterns[pair.key][::-1]
    return pair


def import_design(
    folder,
    *,
    crease=None,
    alpha: float | None = None,
    reference: float = 0.5,
    name: str | None = None,
    units: str | None = None,
    as_drawn: bool = False,
):
    """A flat design (TOML document) from a folder of plate DXFs.

    ``ccu fabricate``'s cut patterns carry the thickness correction of the axis-shift hinges
    (paper §5.3; :meth:`compas_ccu.thickness.ThickModel.cut_patterns`): every crease vertex is
    moved along its ruling into the plate so that the thick plates meet along planar hinges.
    When the folder has a ``fabrication.json`` with the plate thickness, the correction is
    undone: the design is the zero-thickness pattern whose corrected pattern is the one read
    (the whole folder's structure is needed for it: every crease's correction depends on the
    plates before it). Hand-drawn folders (no ``fabrication.json``) and ``as_drawn`` are
    imported as drawn.

    Parameters
    ----------
    folder : str or Path
        ``ccu fabricate``'s output folder (or its ``plates`` folder), or hand-drawn files.
    crease : int or str, optional
        Which crease to import when the folder holds several: a crease id (XDATA), or a plate
        file name (its first crease). Of its two plates the one higher in the flat-folded
        stack (``fabrication.json``) leads; without the stack order, the first file.
    alpha : float, optional
        Design reflection angle, degrees; default: ``fabrication.json``'s (required without it).
    reference : float
        Arc-length fraction of the reference vertex (default 0.5, the designs' default).
    name : str, optional
        Design name (default: ``fabrication.json``'s design name, else the folder's name).
    units : str, optional
        Units of the DXF files, overriding ``$INSUNITS`` (unitless files: mm).
    as_drawn : bool
        Take the patterns as drawn: do not undo ``fabrication.json``'s thickness correction.

    Returns
    -------
    document : dict
        The design (``crease.state = "flat"``, ``polyline`` crease, ``explicit`` rulings).
    report : dict
        ``plates`` (files), ``crease``, ``segments``, ``partner_error`` (largest relative
        difference between the partner and the leading plate's mirror image), ``pairs``,
        ``thickness_correction`` (None if taken as drawn; else ``thickness``, ``iterations``,
        ``largest`` shift undone and the last ``change``, m).

    Raises
    ------
    DesignError
        Inconsistent drawings (file and entity named), several creases and no choice, no alpha,
        a thickness correction that cannot be undone (no convergence: the folder named).

    Examples
    --------
    >>> import tempfile
    >>> from compas_ccu.model import load_model
    >>> from compas_ccu.fabrication.fabricate import fabricate
    >>> out = tempfile.mkdtemp()
    >>> _ = fabricate(load_model("examples/cone.toml"), out)
    >>> document, report = import_design(out)
    >>> document["crease"]["state"], document["rulings"]["type"], report["segments"]
    ('flat', 'explicit', 48)
    """
    folder = Path(folder)
    manifest, plates, pairs, pair, patterns = _select(folder, crease=crease, units=units)
    a_pattern, b_pattern = patterns[pair.key]
    if alpha is None:
        alpha = manifest.get("alpha")
    if alpha is None:
        _check_partner(pair, a_pattern, b_pattern)
        raise DesignError(
            f"{folder}: no fabrication.json with the design angle: give the design reflection "
            "angle (--alpha DEG)"
        )
    info = None
    if _thickness(folder, manifest, as_drawn) is not None:
        members, _, undone, info = _zero_thickness(
            folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
            as_drawn=as_drawn,
        )  # fmt: skip
        near_b, far_b = undone[1]
        if members[1].flipped:
            near_b, far_b = near_b[::-1], far_b[::-1]
        a_pattern = (*undone[0], a_pattern[2])
        b_pattern = (near_b, far_b, b_pattern[2])
    partner_error, _ = _check_partner(pair, a_pattern, b_pattern)
    near, far, _ = a_pattern
    n = len(near) - 1
    document = {
        "design": {
            "name": name or manifest.get("design") or folder.name,
            "description": f"imported from the plate files of {folder.name} ({pair.key}: "
            f"{pair.a.label}, partner {pair.b.label})",
        },
        "crease": {
            "profile": "polyline",
            "points": near.tolist(),
            "segments": n,
            "reference": float(reference),
            "state": "flat",
        },
        "rulings": {"type": "explicit", "points": far.tolist()},
        "deployment": {"alpha": float(alpha)},
        "layout": {"type": "single"},
    }
    plates_section = {k: manifest[k] for k in ("thickness", "material") if k in manifest}
    if plates_section:
        document["plates"] = plates_section
    report = {
        "plates": [p.label for p in plates],
        "crease": pair.key,
        "leading": pair.a.label,
        "partner": pair.b.label,
        "segments": n,
        "partner_error": partner_error,
        "pairs": [p.key for p in pairs],
        "crease_id": pair.crease_a.crease_id,
        "plate_ids": [pair.a.plate_id, pair.b.plate_id],
        "thickness_correction": info,
    }
    return document, report


def _model_ids(folder) -> tuple:
    """Workshop id -> model id of the plates and creases (``fabrication.json``'s
    ``model_ids``; the identity without it)."""
    folder = Path(folder)
    for place in (folder / "fabrication.json", folder.parent / "fabrication.json"):
        if place.is_file():
            ids = json.loads(place.read_text(encoding="utf-8")).get("model_ids") or {}
            plates, creases = ids.get("plates"), ids.get("creases")
            return (
                (lambda k: k) if plates is None else (lambda k, m=plates: m[int(k)]),
                (lambda k: k) if creases is None else (lambda k, m=creases: m[int(k)]),
            )
    return (lambda k: k), (lambda k: k)


def round_trip_error(model, folder, *, crease=None, as_drawn: bool = False) -> dict:
    """Fabricate -> import -> deploy: the imported crease pair against the model's two plates.

    ``folder`` holds the plate files ``ccu fabricate`` wrote for ``model``. The imported design
    is deployed to the model's design angle and its two plates are compared, vertex by vertex
    (the crease records give the correspondence), with the model's plates of that crease after
    a best rigid alignment.

    Returns
    -------
    dict
        ``max`` (m) and ``max_relative`` (to the diagonal of the compared plates' bounding box)
        vertex distance, ``crease_id``, ``plate_ids`` (leading, partner), ``report`` (of
        :func:`import_design`).
    """
    document, report = import_design(folder, crease=crease, as_drawn=as_drawn)
    alpha = model.alpha_design
    new = CCUModel(Design(document)).deploy(alpha)
    old = model.deploy(alpha)
    plate_id, crease_id = _model_ids(folder)  # the files' ids follow the stack
    cid = crease_id(report["crease_id"])
    record = next((c for c in old.creases if c["id"] == cid), None)
    if record is None:
        raise DesignError(f"the model has no crease {cid!r} (the plate files' XDATA)")
    n = model.segments
    old_xyz = np.asarray(old.deployed)
    new_xyz = np.asarray(new.deployed)
    a_id, b_id = (plate_id(k) for k in report["plate_ids"])
    side = {pid: k for k, pid in enumerate(record["plates"])}
    rows_old, rows_new = [], []
    for k_new, pid in ((0, a_id), (1, b_id)):
        idx = np.asarray(record["vertices"][side[pid]])  # along the crease, as in the DXF
        far = np.where(idx <= n, idx + n + 1, idx - n - 1)
        plate = old_xyz[old.plate_ids.index(pid)]
        rows_old += [plate[idx], plate[far]]
        mine = new_xyz[new.plate_ids.index(k_new)]
        rows_new += [mine[: n + 1], mine[n + 1 :]]
    a = np.concatenate(rows_new)
    b = np.concatenate(rows_old)
    moved = rigid_align(a, b)
    distance = float(np.linalg.norm(moved - b, axis=1).max())
    size = float(np.linalg.norm(np.ptp(b, axis=0)))
    return {
        "max": distance,
        "max_relative": distance / size,
        "crease_id": cid,
        "plate_ids": [a_id, b_id],
        "report": report,
    }


@dataclass
class ImportedStructure:
    """Every plate of a folder of plate files, joined into one mechanism.

    Attributes
    ----------
    mechanism : Mechanism
        The leading crease pair's mechanism (:func:`import_design`, built) with every other
        plate attached where the drawings join it: it deploys the whole structure.
    plate_ids : list
        The plate id (XDATA; else the file name) of every mechanism plate.
    design : Design
        The whole structure's design (``document``): alpha, reference vertex, plate section.
    report : dict
        :func:`import_design`'s report, with ``attached`` (plate files joined to the pair),
        ``ids_written`` (whether the document keeps the plate ids).
    document : dict
        The design document of the whole structure (``layout.type = "patterns"``): what
        ``ccu import`` writes; its mechanism is ``mechanism``.
    """

    mechanism: Mechanism
    plate_ids: list
    design: Design
    report: dict
    document: dict = field(default_factory=dict)


def _row_order(plate, crease, near, reference, where: str):
    """``near`` (the plate's crease vertices) in the order of ``reference`` (the same crease's
    vertices on the other plate): reversed or not, by the segment lengths; refused if they
    differ."""
    if len(near) != len(reference):
        raise DesignError(
            f"{plate.label} CREASE #{crease.handle}: {len(near) - 2} interior rulings, "
            f"{len(reference) - 2} on its partner {where}: the two plates of a crease have "
            "their rulings at the same crease points"
        )
    ref = np.linalg.norm(np.diff(reference, axis=0), axis=1)
    errors = []
    for flip in (False, True):
        mine = np.linalg.norm(np.diff(near[::-1] if flip else near, axis=0), axis=1)
        errors.append(float(np.abs(mine - ref).max()))
    flip = errors[1] < errors[0]
    if min(errors) > PARTNER_TOLERANCE * float(ref.sum()):
        j = int(np.argmax(np.abs(ref - np.linalg.norm(np.diff(near, axis=0), axis=1))))
        raise DesignError(
            f"{plate.label} CREASE #{crease.handle}: its segments differ from its partner's "
            f"{where} by {min(errors):.3g} m (segment {j}): the rulings do not meet the two "
            "creases at the same points"
        )
    return flip


@dataclass
class _Member:
    """A plate of the imported structure in mechanism order, its pattern as read (m).

    ``near`` is the plate's row on the crease with its parent (the leading crease for the
    leading pair), in the parent's order; ``far`` the other ends of its rulings.
    """

    plate: PlateDrawing
    crease: CreaseDrawing
    near: np.ndarray
    far: np.ndarray
    parent: int | None = None
    boundary: str = "near"
    flipped: bool = False


def _structure_tree(pair: CreasePair, pairs: list, a_pattern, b_pattern):
    """The plates of a folder in mechanism order from the crease ``pair`` (its plate ``a``
    leads), and the creases between them: (plate_a, boundary_a, plate_b) member indices."""
    near_a, far_a, _ = a_pattern
    near_b, far_b, _ = b_pattern
    flip = _row_order(pair.b, pair.crease_b, near_b, near_a, f"in {pair.a.label}")
    if flip:
        near_b, far_b = near_b[::-1], far_b[::-1]
    members = [
        _Member(pair.a, pair.crease_a, near_a, far_a),
        _Member(pair.b, pair.crease_b, near_b, far_b, 0, "near", flip),
    ]
    links = [(0, "near", 1)]
    done = {id(pair.a), id(pair.b)}
    by_plate: dict = {}
    for p in pairs:
        by_plate.setdefault(id(p.a), []).append((p.crease_a, p.b, p.crease_b))
        by_plate.setdefault(id(p.b), []).append((p.crease_b, p.a, p.crease_a))
    k = 0
    while k < len(members):
        member = members[k]
        plate = member.plate
        others = [item for item in by_plate.get(id(plate), []) if item[0] is not member.crease]
        if len(others) > 1:
            raise DesignError(
                f"{plate.label}: {len(others) + 1} creases; a CCU plate joins two creases "
                "(its near and far boundary)"
            )
        for own, child, child_crease in others:
            if id(child) in done:
                continue  # a loop closes here: the mechanism places every plate once
            d, _ = _distance_to_polyline(member.far, own.points)
            if d.max() > SNAP * plate.size:
                raise DesignError(
                    f"{plate.label} CREASE #{own.handle}: the rulings of the plate do not end on "
                    f"it ({d.max():.3g} m off)"
                )
            near_c, far_c, _ = crease_pattern(child, child_crease)
            flip = _row_order(child, child_crease, near_c, member.far, f"in {plate.label}")
            if flip:
                near_c, far_c = near_c[::-1], far_c[::-1]
            links.append((k, "far", len(members)))
            members.append(_Member(child, child_crease, near_c, far_c, k, "far", flip))
            done.add(id(child))
        k += 1
    return members, links


def _leading_document(near, far, *, alpha, reference, name) -> dict:
    """The flat design of a leading plate: polyline crease, explicit rulings, single layout."""
    return {
        "design": {"name": name},
        "crease": {
            "profile": "polyline",
            "points": np.asarray(near).tolist(),
            "segments": len(near) - 1,
            "reference": float(reference),
            "state": "flat",
        },
        "rulings": {"type": "explicit", "points": np.asarray(far).tolist()},
        "deployment": {"alpha": float(alpha)},
        "layout": {"type": "single"},
    }


def structure_document(members, patterns, ids, *, alpha, reference, name) -> dict:
    """The design document of a whole structure: the leading plate's flat design and every
    other plate as a ``[[layout.patterns]]`` table (:mod:`compas_ccu.design.patterns`).

    ``members`` in mechanism order, ``patterns`` their (near, far) rows (m), ``ids`` their
    plate ids: written (``layout.leading`` and ``id``) when they are the integers 0 ... p - 1.
    """
    document = _leading_document(*patterns[0], alpha=alpha, reference=reference, name=name)
    keep = sorted(str(i) for i in ids) == sorted(str(i) for i in range(len(ids))) and all(
        isinstance(i, int) for i in ids
    )
    layout: dict = {"type": "patterns"}
    if keep:
        layout["leading"] = int(ids[0])
    tables = []
    for member, (near, far), pid in zip(members[1:], patterns[1:], ids[1:]):
        table = {"parent": int(member.parent), "boundary": member.boundary}
        if keep:
            table["id"] = int(pid)
        table["near"] = np.asarray(near, dtype=float).tolist()
        table["far"] = np.asarray(far, dtype=float).tolist()
        tables.append(table)
    layout["patterns"] = tables
    document["layout"] = layout
    return document


def _assemble(members, links, patterns, *, alpha, reference, name):
    """The design of the leading plate and the mechanism of every member, from ``patterns``
    ((near, far) per member, in the members' order)."""
    design = Design(_leading_document(*patterns[0], alpha=alpha, reference=reference, name=name))
    geometry = build(design)
    plates = [geometry.mechanism.plates[0]]
    for k, (member, (near, far)) in enumerate(zip(members[1:], patterns[1:]), start=1):
        plates.append(
            PlateLink(strip_intrinsics(near, far), member.parent, member.boundary, "ccu", k - 1)
        )
    creases = [
        CreaseLink(a, boundary, b, "ccu", k == 0, (0.0, 0.0, 1.0))
        for k, (a, boundary, b) in enumerate(links)
    ]
    return design, Mechanism(geometry.mechanism.leading, plates, creases)


def thickness_shifts(mechanism: Mechanism, thickness: float, alpha: float):
    """The thickness correction of cut patterns: how far every crease vertex of every plate
    moves along its ruling into the plate (paper §5.3), as ``ccu fabricate`` applies it.

    The axis-shift hinges of :class:`compas_ccu.thickness.ThickModel` at the design state: the
    thick plates are placed at the reference angle ``alpha``, and every crease's correction
    (:class:`compas_ccu.thickness.axis_shift.HingePlanes`) moves the crease rows of both its
    plates.

    Parameters
    ----------
    mechanism : Mechanism
        The zero-thickness mechanism.
    thickness : float
        Plate thickness, m.
    alpha : float
        Design reflection angle, degrees.

    Returns
    -------
    near, far : (p, n + 1) float
        Shifts of the near and the far row of every mechanism plate, m (0 on free boundaries).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")  # rulings orthogonal to the crease
    >>> near, far = thickness_shifts(model.mechanism, 0.008, model.alpha_design)
    >>> near.shape, bool(np.abs(near).max() < 1e-15)  # planar offset creases: no correction
    ((2, 49), True)
    """
    s0 = np.atleast_1d(mechanism.leading.s0_for_alpha(math.radians(alpha)))
    sides = crease_sides(mechanism, mechanism.place(s0))
    corrections = place_thick(mechanism, s0, thickness, sides).corrections[0]
    p, m = len(mechanism.plates), mechanism.segments + 1
    near, far = np.zeros((p, m)), np.zeros((p, m))
    for ci, link in enumerate(mechanism.creases):
        (near if link.boundary_a == "near" else far)[link.plate_a] = corrections[ci]
        near[link.plate_b] = corrections[ci]
    return near, far


#: Undoing the thickness correction: the shifts are iterated until they change by less than
#: this (m) or :data:`UNDO_RELATIVE` times the largest plate's size (rounding: the 22-plate
#: dome's planar steps stop at changes of 3e-12 to 6e-12 m, plates 2.3 m across) ...
UNDO_TOLERANCE = 1e-13
UNDO_RELATIVE = 1e-11
#: ... within this many iterations.
UNDO_ITERATIONS = 20
#: A leading crease whose shifts still change by more than this (m) after the attachment
#: tree's depth + 3 iterations is not the one the correction was computed from: the next is
#: tried (the design angle is the reflection angle of the design's leading crease).
PATIENCE_CHANGE = 1e-6


def _shift_update(mechanism: Mechanism, near_shift, far_shift, thickness: float, alpha: float):
    """One step of undoing the thickness correction: the shifts that take the zero-thickness
    crease rows (planar) to the corrected rows read, measured on the current mechanism.

    ``ccu fabricate``'s corrected crease points ``M`` (the rows read: the current rows moved
    along their rulings by the current shifts) lie on the rulings, and their facing-face points
    ``M + σ t/2 ν`` lie in the hinge plane P (:class:`~compas_ccu.thickness.axis_shift.
    HingePlanes`): P is the plane through them. The zero-thickness crease lies in the plane Q,
    P moved back by the mean offset ``mean(σ t/2 ν · n)``; it is where the rulings cross Q.
    Only the placed ruling lines of the current patterns are used, not their crease rows: the
    step fixes where a row lies along its rulings, which the forward correction
    (:func:`thickness_shifts`) hardly sees (:func:`_undo_correction`).
    """
    s0 = np.atleast_1d(mechanism.leading.s0_for_alpha(math.radians(alpha)))
    placed = mechanism.place(s0)
    sides = crease_sides(mechanism, placed)
    near, far = placed.near[0], placed.far[0]
    half = 0.5 * float(thickness)
    new_near, new_far = np.zeros_like(near_shift), np.zeros_like(far_shift)
    for ci, link in enumerate(mechanism.creases):
        a = link.plate_a
        row, away = hinge_and_rulings(near[a], far[a], link.boundary_a)
        shift = (near_shift if link.boundary_a == "near" else far_shift)[a]
        offset = sides[ci, 0] * half * vertex_offsets(near[a], far[a])
        hinge = row + shift[:, None] * away + offset
        origin, normal, _ = fit_planes(hinge[None], np.asarray(link.design_normal))
        origin, normal = origin[0], normal[0]
        origin = origin - float((offset @ normal).mean()) * normal  # P back to Q
        slope = away @ normal
        with np.errstate(divide="ignore", invalid="ignore"):
            along = -((row - origin) @ normal) / slope
        new = np.where(np.abs(slope) > EXACT_RELATIVE, shift - along, 0.0)
        (new_near if link.boundary_a == "near" else new_far)[a] = new
        new_near[link.plate_b] = new
    return new_near, new_far


def _undo_correction(folder, members, links, thickness, *, alpha, reference, name, patience=None):
    """The zero-thickness patterns whose thickness-corrected patterns are those read.

    ``ccu fabricate`` moves every crease vertex along its ruling into the plate by the
    correction ``F(P0)`` of the zero-thickness patterns ``P0`` (:func:`thickness_shifts`); the
    rulings keep their lines, so ``P0 = P_read - s u`` with ``u`` the rulings' directions read
    and ``s`` the solution of ``s = F(P_read - s u)``. Iterating ``F`` alone does not find it:
    ``F`` hardly changes when a crease row slides along its rulings (the corrected crease is
    where the rulings cross the hinge plane, wherever the row was), so that iteration stops
    anywhere along such a slide (fig11a: 1.7e-5 m from the original). The planar step
    :func:`_shift_update` fixes exactly those slides (a CCU crease is planar) but is nearly
    blind to others (fig12b: it stops 1.2e-7 m off); each step alternates the two, which
    converges to the common solution (one plate of the attachment tree per step).

    Returns
    -------
    patterns : list of (near, far)
    info : dict
        ``thickness``, ``iterations``, ``largest`` (largest shift, m), ``change`` (the last
        iteration's, m): the forward correction of the patterns returned differs from the
        shifts undone by at most ``change``.

    Raises
    ------
    DesignError
        No convergence within :data:`UNDO_ITERATIONS` (folder, thickness and last change named).
    """
    read = [(m.near, m.far) for m in members]
    ruling = [unit(far - near) for near, far in read]
    p, m = len(members), len(members[0].near)
    shifts = (np.zeros((p, m)), np.zeros((p, m)))

    def undone(near_shift, far_shift):
        return [
            (near - sn[:, None] * u, far + sf[:, None] * u)
            for (near, far), u, sn, sf in zip(read, ruling, near_shift, far_shift)
        ]

    def mechanism(near_shift, far_shift):
        patterns = undone(near_shift, far_shift)
        return _assemble(members, links, patterns, alpha=alpha, reference=reference, name=name)[1]

    change = math.inf
    tolerance = max(UNDO_TOLERANCE, UNDO_RELATIVE * max(m.plate.size for m in members))
    for iteration in range(1, UNDO_ITERATIONS + 1):
        planar = _shift_update(mechanism(*shifts), *shifts, thickness, alpha)
        forward = thickness_shifts(mechanism(*planar), thickness, alpha)
        change = float(
            max(
                np.abs(np.subtract(planar, shifts)).max(),
                np.abs(np.subtract(forward, planar)).max(),
            )
        )
        shifts = forward
        if patience is not None and iteration >= patience and change > PATIENCE_CHANGE:
            break  # this leading crease is not the one the correction was made with
        if change <= tolerance:
            info = {
                "thickness": float(thickness),
                "iterations": iteration,
                "largest": float(np.abs(shifts).max()),
                "change": change,
            }
            return undone(*shifts), info
    raise DesignError(
        f"{folder}: undoing the thickness correction of the cut patterns ({thickness:g} m "
        f"plates, fabrication.json) did not converge in {iteration} iterations (the "
        f"shifts still change by {change:.3g} m > {tolerance:.3g} m); import the patterns "
        "as drawn (as_drawn=True, ccu import --as-drawn)"
    )


def _thickness(folder, manifest: dict, as_drawn: bool):
    """The plate thickness whose correction the patterns carry: ``fabrication.json``'s, None
    for hand-drawn folders (no ``fabrication.json``) and ``as_drawn``."""
    if as_drawn:
        return None
    t = manifest.get("thickness")
    if t is None:
        return None
    if isinstance(t, bool) or not isinstance(t, (int, float)) or not (math.isfinite(t) and t > 0):
        raise DesignError(
            f"{folder}: fabrication.json's thickness must be a length > 0 m, got {t!r} (as_drawn / "
            "--as-drawn imports the patterns as drawn)"
        )
    return float(t)


def _depth(members) -> int:
    """Depth of the attachment tree (the leading plate: 0)."""
    depth = [0] * len(members)
    for k, member in enumerate(members[1:], start=1):
        depth[k] = depth[member.parent] + 1
    return max(depth)


def _rows_as(member: _Member, other: _Member, undone) -> tuple:
    """``undone`` (the zero-thickness rows of ``other``, the same plate in another attachment
    tree) in the rows of ``member``: the same rows, swapped (the tree reaches the plate from
    its other crease) and / or reversed, matched on the points read."""
    best = None
    for near_o, far_o, near_u, far_u in (
        (other.near, other.far, *undone),
        (other.far, other.near, undone[1], undone[0]),
    ):
        for step in (1, -1):
            d = max(
                np.abs(member.near - near_o[::step]).max(),
                np.abs(member.far - far_o[::step]).max(),
            )
            if best is None or d < best[0]:
                best = (d, near_u[::step], far_u[::step])
    if best[0] > SNAP * member.plate.size:  # pragma: no cover - the same drawing read twice
        raise DesignError(f"{member.plate.label}: its rows differ between two crease trees")
    return best[1], best[2]


def _chain(first: list, rest):
    """The items of ``first``, then those of ``rest()`` (called only when they are needed)."""
    yield from first
    yield from rest()


def _zero_thickness(folder, manifest, pairs, pair, patterns, *, alpha, reference, as_drawn):
    """The members of the structure led by ``pair``, their zero-thickness patterns and the
    undoing report (``None`` when the patterns are taken as drawn).

    The correction is undone on the attachment tree of the design's leading crease, whose
    reflection angle ``alpha`` is: ``pair``'s first, then every other crease's (the first that
    converges; a folder records no leading crease). ``info["leading"]`` names it.
    """
    a_pattern, b_pattern = patterns[pair.key]
    members, links = _structure_tree(pair, pairs, a_pattern, b_pattern)
    thickness = _thickness(folder, manifest, as_drawn)
    name = manifest.get("design") or Path(folder).name
    if thickness is None:
        return members, links, [(m.near, m.far) for m in members], None

    def others():
        # the other creases from the shallowest tree (a mechanism grows from the middle of
        # its layout)
        roots = []
        for other in pairs:
            if other.key != pair.key:  # (``pair`` may be a reordered copy)
                other = _stack_upper_leads(other, patterns, manifest)
                roots.append((other, *_structure_tree(other, pairs, *patterns[other.key])))
        return sorted(roots, key=lambda root: _depth(root[1]))

    first = None
    for root, tree, tree_links in _chain([(pair, members, links)], others):
        try:
            undone, info = _undo_correction(
                folder, tree, tree_links, thickness, alpha=alpha, reference=reference,
                name=name, patience=_depth(tree) + 3,
            )  # fmt: skip
        except DesignError as exc:
            first = first or exc
            continue
        except GeometryError as exc:  # diverged until a pattern degenerated: not this crease
            first = first or DesignError(
                f"{folder}: undoing the thickness correction with {root.key} as the leading "
                f"crease diverged ({exc}); import the patterns as drawn (as_drawn=True, ccu "
                "import --as-drawn)"
            )
            continue
        info["leading"] = root.key
        if tree is members:
            return members, links, undone, info
        where = {id(m.plate): k for k, m in enumerate(tree)}
        mapped = [
            _rows_as(m, tree[where[id(m.plate)]], undone[where[id(m.plate)]]) for m in members
        ]
        return members, links, mapped, info
    raise DesignError(
        f"{first} (tried every crease of the folder as the design's leading crease)"
    ) from first


def import_structure(
    folder,
    *,
    crease=None,
    alpha=None,
    reference=0.5,
    name: str | None = None,
    units=None,
    as_drawn: bool = False,
):
    """The whole structure of a folder of plate files: one mechanism and its design document.

    The leading crease pair is imported as by :func:`import_design` (its design fixes the
    leading strip, the design angle and the reference vertex); every other plate is attached
    to the plate it shares a crease with, as the mechanism attaches plates (the mirror image of
    the parent's rulings across the crease's plane, with the plate's own ruling lengths). The
    document (:func:`structure_document`, ``layout.type = "patterns"``) holds every plate's
    cut pattern; ``ccu import`` writes it.

    With ``fabrication.json``'s thickness (``ccu fabricate``'s folders), the thickness
    correction of the cut patterns is undone first (:func:`import_design`).

    Parameters
    ----------
    folder, alpha, reference, name, units, as_drawn
        As :func:`import_design`.
    crease : int or str, optional
        The leading crease. Default: with one crease, it; with several, ``fabrication.json``'s
        ``leading_crease`` (the design's, as ``ccu fabricate`` records it), else the crease
        with which the thickness correction of the patterns was made (found by undoing it),
        else (hand-drawn, ``as_drawn``) the crease of the shallowest attachment tree (the
        middle of the layout; the design angle is then that crease's).

    Returns
    -------
    ImportedStructure

    Raises
    ------
    DesignError
        As :func:`import_design` (except that the partner need not be the leading plate's
        mirror image), and a plate with more than two creases.

    Examples
    --------
    >>> import tempfile
    >>> from compas_ccu.model import load_model
    >>> from compas_ccu.fabrication.fabricate import fabricate
    >>> out = tempfile.mkdtemp()
    >>> _ = fabricate(load_model("examples/cone.toml"), out)
    >>> structure = import_structure(out)
    >>> undone = structure.report["thickness_correction"]
    >>> structure.plate_ids, undone["thickness"], undone["iterations"], undone["leading"]
    ([1, 0], 0.005, 1, 'crease 0')
    >>> layout = structure.document["layout"]
    >>> layout["type"], layout["leading"], [(t["parent"], t["boundary"], t["id"])
    ...                                     for t in layout["patterns"]]
    ('patterns', 1, [(0, 'near', 0)])
    """
    folder = Path(folder)
    manifest, plates, pairs, pair, patterns = _select(
        folder, crease=crease, units=units, whole=True
    )
    read = dict(patterns)  # as read: the undoing may reorder pairs' patterns
    if alpha is None:
        alpha = manifest.get("alpha")
    if alpha is None:
        raise DesignError(
            f"{folder}: no fabrication.json with the design angle: give the design reflection "
            "angle (alpha, --alpha DEG)"
        )
    members, links, undone, info = _zero_thickness(
        folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
        as_drawn=as_drawn,
    )  # fmt: skip
    if crease is None and info is not None and info["leading"] != pair.key:
        # the correction was made with another crease leading: the design's leading crease
        patterns = dict(read)
        found = next(p for p in pairs if p.key == info["leading"])
        pair = _stack_upper_leads(found, patterns, manifest)
        members, links, undone, info = _zero_thickness(
            folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
            as_drawn=as_drawn,
        )  # fmt: skip
    name = name or manifest.get("design") or folder.name
    _, mechanism = _assemble(members, links, undone, alpha=alpha, reference=reference, name=name)
    ids = [m.plate.plate_id if m.plate.plate_id is not None else m.plate.label for m in members]
    document = structure_document(members, undone, ids, alpha=alpha, reference=reference, name=name)
    document["design"]["description"] = (
        f"imported from the plate files of {folder.name}: {len(members)} plates, leading "
        f"{pair.key} ({pair.a.label}, partner {pair.b.label})"
    )
    plates_section = {k: manifest[k] for k in ("thickness", "material") if k in manifest}
    if plates_section:
        document["plates"] = plates_section
    report = {
        "crease": pair.key,
        "leading": pair.a.label,
        "partner": pair.b.label,
        "attached": [m.plate.label for m in members],
        "plates": [p.label for p in plates],
        "pairs": [p.key for p in pairs],
        "segments": len(members[0].near) - 1,
        "ids_written": "leading" in document["layout"],
        "thickness_correction": info,
    }
    return ImportedStructure(mechanism, ids, Design(document), report, document)


def structure_round_trip_error(model, folder, *, crease=None, as_drawn: bool = False) -> dict:
    """Fabricate -> import -> deploy for the whole structure (:func:`import_structure`).

    Both mechanisms are deployed to the model's design angle; every vertex of every plate is
    compared with the model's (plates matched by id) after a best rigid alignment.

    Returns
    -------
    dict
        ``max`` (m), ``max_relative`` (to the structure's bounding-box diagonal), ``plates``.
    """
    imported = import_structure(folder, crease=crease, as_drawn=as_drawn)
    out = structure_error(model, folder, imported.mechanism, imported.plate_ids)
    out["report"] = imported.report
    return out


def structure_error(model, folder, mechanism: Mechanism, plate_ids) -> dict:
    """An imported mechanism against the model whose plate files ``folder`` holds.

    Both are deployed to the model's design angle; every vertex of every plate is compared
    with the model's after a best rigid alignment, plates matched by id: ``plate_ids`` (of
    the mechanism's plates) are the plate files' ids, mapped to the model's by
    ``fabrication.json``. The model of a design file ``ccu import`` wrote compares with
    ``loaded.mechanism, loaded.geometry.plate_ids``.

    Returns
    -------
    dict
        ``max`` (m), ``max_relative`` (to the structure's bounding-box diagonal), ``plates``.
    """
    alpha = math.radians(model.alpha_design)
    new = mechanism.deploy(alpha)
    old = model.mechanism.deploy(alpha)
    old_ids = list(model.geometry.plate_ids)
    plate_id, _ = _model_ids(folder)
    a, b = [], []
    for i, pid in enumerate(plate_ids):
        j = old_ids.index(plate_id(pid))
        a += [new.near[0, i], new.far[0, i]]
        b += [old.near[0, j], old.far[0, j]]
    a, b = np.concatenate(a), np.concatenate(b)
    moved = rigid_align(a, b)
    distance = float(np.linalg.norm(moved - b, axis=1).max())
    size = float(np.linalg.norm(np.ptp(b, axis=0)))
    return {"max": distance, "max_relative": distance / size, "plates": len(plate_ids)}
