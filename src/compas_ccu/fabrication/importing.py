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
the ruling ends are the rulings' far end points. :func:`import_design` turns one crease and its
two plates into a ``state = "flat"`` design with ``explicit`` rulings, the design
:func:`compas_ccu.model.flat_design` writes. That is what a design file can say about a cut
pattern: one crease, its leading plate and the leading plate's mirror partner. So the partner
must be the leading plate's mirror image (same crease, same rulings), and a multi-crease
structure is imported into a design file one crease pair at a time (docs/import.md says why);
:func:`import_structure` joins every plate of the folder into one mechanism that deploys the
whole structure.

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

from compas_ccu.curves.readers import dxf_line_chains, dxf_sampler
from compas_ccu.design import Design
from compas_ccu.design.build import build
from compas_ccu.errors import DesignError, MissingExtraError
from compas_ccu.geometry import rigid_align
from compas_ccu.kinematics.mechanism import CreaseLink, Mechanism, PlateLink
from compas_ccu.model import CCUModel
from compas_ccu.strips.intrinsics import strip_intrinsics

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
    "structure_round_trip_error",
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
    try:
        import ezdxf
    except ImportError:
        raise MissingExtraError("ccu import needs ezdxf (pip install 'compas_ccu[fab]')") from None
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
    try:
        doc = ezdxf.readfile(str(path))
    except (OSError, ezdxf.DXFError) as exc:
        raise DesignError(f"cannot read plate file {str(path)!r}: {exc}") from exc
    if units is not None:
        k = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "ft": 0.3048}[units]
    else:
        insunits = int(doc.header.get("$INSUNITS", 0) or 0) or ezdxf.units.MM
        k = ezdxf.units.conversion_factor(insunits, ezdxf.units.M)
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
    rough = np.asarray(sample(None))[:, :2]
    size = float(np.linalg.norm(np.ptp(rough, axis=0)))
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
        pts = _dedupe(np.asarray(sampler(SAMPLING * size))[:, :2] * k, SNAP * size * k)
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
    length2 = np.maximum((ab * ab).sum(axis=1), 1e-300)
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
        lim = tol / max(float(np.linalg.norm(r[i])), 1e-300)
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
        tol = PARTNER_TOLERANCE * max(crease.length, 1e-300)
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
            float(np.abs(ea - eb).max()) / max(float(ea.max()), 1e-300),
            float(np.abs(la - lb).max()) / max(float(la.max()), 1e-300),
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


def _select(folder: Path, *, crease, units):
    """Read a folder; the crease pair chosen (its stack-upper plate first) and every pattern."""
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
    # the plate higher in the flat-folded stack leads: the drawings show the plates from the
    # stack's top, so it rises towards the viewer as the leading plate does (+z); without
    # fabrication.json, the first file leads and the structure may come out mirrored
    stack = manifest.get("stack_order")
    if stack and pair.a.plate_id in stack and pair.b.plate_id in stack:
        if stack.index(pair.a.plate_id) < stack.index(pair.b.plate_id):
            pair = CreasePair(pair.key, pair.b, pair.crease_b, pair.a, pair.crease_a)
            patterns[pair.key] = patterns[pair.key][::-1]
    return manifest, plates, pairs, pair, patterns


def import_design(
    folder,
    *,
    crease=None,
    alpha: float | None = None,
    reference: float = 0.5,
    name: str | None = None,
    units: str | None = None,
):
    """A flat design (TOML document) from a folder of plate DXFs.

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

    Returns
    -------
    document : dict
        The design (``crease.state = "flat"``, ``polyline`` crease, ``explicit`` rulings).
    report : dict
        ``plates`` (files), ``crease``, ``segments``, ``partner_error`` (largest relative
        difference between the partner and the leading plate's mirror image), ``pairs``.

    Raises
    ------
    DesignError
        Inconsistent drawings (file and entity named), several creases and no choice, no alpha.

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
    partner_error, _ = _check_partner(pair, a_pattern, b_pattern)
    if alpha is None:
        alpha = manifest.get("alpha")
    if alpha is None:
        raise DesignError(
            f"{folder}: no fabrication.json with the design angle: give the design reflection "
            "angle (--alpha DEG)"
        )
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


def round_trip_error(model, folder, *, crease=None) -> dict:
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
    document, report = import_design(folder, crease=crease)
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


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, (list, tuple)):
        if value and isinstance(value[0], (list, tuple)):
            return "[\n" + "".join(f"    {_toml_value(v)},\n" for v in value) + "]"
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise TypeError(f"no TOML for {type(value).__name__}")  # pragma: no cover


def design_toml(document: dict, *, header: str = "") -> str:
    """TOML text of a design document of tables of numbers, strings and lists (floats
    written with ``repr``: they read back exactly).

    Examples
    --------
    >>> print(design_toml({"crease": {"points": [[0.0, 1.5]], "state": "flat"}}))
    [crease]
    points = [
        [0.0, 1.5],
    ]
    state = "flat"
    <BLANKLINE>
    """
    lines = [f"# {line}" for line in header.splitlines()]
    for section, values in document.items():
        if lines:
            lines.append("")
        lines.append(f"[{section}]")
        lines += [f"{key} = {_toml_value(value)}" for key, value in values.items()]
    return "\n".join(lines) + "\n"


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
        The leading crease pair's design (alpha, reference vertex, plate section).
    report : dict
        :func:`import_design`'s report, with ``attached`` (plate files joined to the pair).
    """

    mechanism: Mechanism
    plate_ids: list
    design: Design
    report: dict


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


def import_structure(folder, *, crease=None, alpha=None, reference=0.5, units=None):
    """The whole structure of a folder of plate files as one mechanism.

    The leading crease pair is imported as by :func:`import_design` (its design fixes the
    leading strip, the design angle and the reference vertex); every other plate is attached
    to the plate it shares a crease with, as the mechanism attaches plates (the mirror image of
    the parent's rulings across the crease's plane, with the plate's own ruling lengths). A
    design file cannot hold this (docs/import.md); the mechanism deploys it.

    Parameters
    ----------
    folder, crease, alpha, reference, units
        As :func:`import_design`; ``crease`` names the leading crease.

    Returns
    -------
    ImportedStructure

    Raises
    ------
    DesignError
        As :func:`import_design` (except that the partner need not be the leading plate's
        mirror image), and a plate with more than two creases.
    """
    folder = Path(folder)
    manifest, plates, pairs, pair, patterns = _select(folder, crease=crease, units=units)
    a_pattern, b_pattern = patterns[pair.key]
    if alpha is None:
        alpha = manifest.get("alpha")
    if alpha is None:
        raise DesignError(
            f"{folder}: no fabrication.json with the design angle: give the design reflection "
            "angle (alpha)"
        )
    near_a, far_a, _ = a_pattern
    document = {
        "design": {"name": manifest.get("design") or folder.name},
        "crease": {
            "profile": "polyline",
            "points": near_a.tolist(),
            "segments": len(near_a) - 1,
            "reference": float(reference),
            "state": "flat",
        },
        "rulings": {"type": "explicit", "points": far_a.tolist()},
        "deployment": {"alpha": float(alpha)},
        "layout": {"type": "single"},
    }
    design = Design(document)
    geometry = build(design)
    leading = geometry.mechanism.leading
    # the partner with its own ruling lengths, in the order of the leading crease
    near_b, far_b, _ = b_pattern
    if _row_order(pair.b, pair.crease_b, near_b, near_a, f"in {pair.a.label}"):
        near_b, far_b = near_b[::-1], far_b[::-1]
    links = [
        geometry.mechanism.plates[0],
        PlateLink(strip_intrinsics(near_b, far_b), 0, "near", "ccu", 0),
    ]
    creases = [CreaseLink(0, "near", 1, "ccu", True, (0.0, 0.0, 1.0))]
    members = [(pair.a, pair.crease_a, far_a), (pair.b, pair.crease_b, far_b)]
    done = {id(pair.a), id(pair.b)}
    by_plate: dict = {}
    for p in pairs:
        by_plate.setdefault(id(p.a), []).append((p.crease_a, p.b, p.crease_b))
        by_plate.setdefault(id(p.b), []).append((p.crease_b, p.a, p.crease_a))
    k = 0
    while k < len(members):
        plate, near_crease, far_row = members[k]
        others = [item for item in by_plate.get(id(plate), []) if item[0] is not near_crease]
        if len(others) > 1:
            raise DesignError(
                f"{plate.label}: {len(others) + 1} creases; a CCU plate joins two creases "
                "(its near and far boundary)"
            )
        for own, child, child_crease in others:
            if id(child) in done:
                continue  # a loop closes here: the mechanism places every plate once
            d, _ = _distance_to_polyline(far_row, own.points)
            if d.max() > SNAP * plate.size:
                raise DesignError(
                    f"{plate.label} CREASE #{own.handle}: the rulings of the plate do not end on "
                    f"it ({d.max():.3g} m off)"
                )
            near_c, far_c, _ = crease_pattern(child, child_crease)
            if _row_order(child, child_crease, near_c, far_row, f"in {plate.label}"):
                near_c, far_c = near_c[::-1], far_c[::-1]
            creases.append(CreaseLink(k, "far", len(links), "ccu", False, (0.0, 0.0, 1.0)))
            links.append(
                PlateLink(strip_intrinsics(near_c, far_c), k, "far", "ccu", len(creases) - 1)
            )
            members.append((child, child_crease, far_c))
            done.add(id(child))
        k += 1
    mechanism = Mechanism(leading, links, creases)
    ids = [m[0].plate_id if m[0].plate_id is not None else m[0].label for m in members]
    report = {
        "crease": pair.key,
        "leading": pair.a.label,
        "partner": pair.b.label,
        "attached": [m[0].label for m in members],
        "plates": [p.label for p in plates],
    }
    return ImportedStructure(mechanism, ids, design, report)


def structure_round_trip_error(model, folder, *, crease=None) -> dict:
    """Fabricate -> import -> deploy for the whole structure (:func:`import_structure`).

    Both mechanisms are deployed to the model's design angle; every vertex of every plate is
    compared with the model's (plates matched by id) after a best rigid alignment.

    Returns
    -------
    dict
        ``max`` (m), ``max_relative`` (to the structure's bounding-box diagonal), ``plates``.
    """
    imported = import_structure(folder, crease=crease)
    alpha = math.radians(model.alpha_design)
    new = imported.mechanism.deploy(alpha)
    old = model.mechanism.deploy(alpha)
    old_ids = list(model.geometry.plate_ids)
    plate_id, _ = _model_ids(folder)
    a, b = [], []
    for i, pid in enumerate(imported.plate_ids):
        j = old_ids.index(plate_id(pid))
        a += [new.near[0, i], new.far[0, i]]
        b += [old.near[0, j], old.far[0, j]]
    a, b = np.concatenate(a), np.concatenate(b)
    moved = rigid_align(a, b)
    distance = float(np.linalg.norm(moved - b, axis=1).max())
    size = float(np.linalg.norm(np.ptp(b, axis=0)))
    return {
        "max": distance,
        "max_relative": distance / size,
        "plates": len(imported.plate_ids),
        "report": imported.report,
    }
