"""Reading plate cut files back in metres (the first step of ``ccu import``).

A plate file has the layers ``CUT`` (the closed outline), ``CREASE`` (its creases, with XDATA
``COMPAS_CCU`` pairing the plates) and ``RULING_SCORE`` (or ``RULING``: the interior rulings);
:mod:`compas_ccu.fabrication.importing` joins them into a design (docs/import.md).
"""

from __future__ import annotations

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
from compas_ccu.errors import DesignError, ProfileError, require
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "REQUIRED_LAYERS",
    "APPID",
    "SNAP",
    "SAMPLING",
    "CreaseDrawing",
    "PlateDrawing",
    "read_plate_drawing",
    "read_plate_folder",
]

REQUIRED_LAYERS = ("CUT", "CREASE", "RULING_SCORE")


APPID = "COMPAS_CCU"


#: Points closer than this (relative to the plate's size) are the same point of the drawing.
SNAP = 1e-7


#: Sampling tolerance of curved outlines and creases, relative to the plate's size.
SAMPLING = EXACT_RELATIVE


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
