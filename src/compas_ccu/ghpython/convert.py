"""Rhino / Grasshopper geometry in and out, without importing Rhino where it is not there.

In: a Rhino curve (``Rhino.Geometry.Curve``, or anything with ``DivideByCount`` and
``PointAt``), a polyline (anything iterable of points, or with ``points``), and points with
``X``, ``Y``, ``Z`` (``Point3d``) or as sequences. Out: COMPAS meshes / polylines / lines, turned
into Rhino geometry by ``compas_rhino.conversions`` where it imports (inside Rhino 8) and left
as COMPAS geometry elsewhere (CPython, tests); ruled NURBS surfaces through the plate vertices
by RhinoCommon (``Rhino.Geometry.NurbsSurface.CreateThroughPoints``) where it imports.
"""

from __future__ import annotations

import importlib

import numpy as np
from compas.datastructures import Mesh
from compas.geometry import Line, Polyline

from compas_ccu.errors import GeometryError, OptionError
from compas_ccu.tolerances import EXACT_RELATIVE, MACHINE, ZERO_LENGTH

__all__ = [
    "point_xyz",
    "curve_points",
    "crease_plane",
    "host_module",
    "to_host",
    "to_host_surface",
    "document_unit_scale",
    "PLANARITY_TOLERANCE",
]

#: Largest distance of a crease curve's points from their best-fit plane, relative to the
#: curve's size: a crease of a CCU structure is planar.
PLANARITY_TOLERANCE = 1e-6

_MISSING = object()
_HOSTS: dict = {}


def host_module(name: str):
    """The module ``name`` (``"compas_rhino.conversions"``, ``"Rhino"``) or None if it does
    not import here (CPython outside Rhino). Looked up once per name."""
    module = _HOSTS.get(name, _MISSING)
    if module is _MISSING:
        try:
            module = importlib.import_module(name)
        except ImportError:
            module = None
        _HOSTS[name] = module
    return module


def point_xyz(point) -> tuple:
    """``(x, y, z)`` of a ``Point3d`` (``X``, ``Y``, ``Z``), a COMPAS point or a sequence
    of two or three numbers (z = 0)."""
    if hasattr(point, "X"):
        return (float(point.X), float(point.Y), float(point.Z))
    values = [float(v) for v in point]
    if len(values) not in (2, 3):
        raise GeometryError(f"a point has 2 or 3 coordinates, got {point!r}")
    return tuple(values + [0.0] * (3 - len(values)))


def curve_points(curve, *, count: int = 64) -> np.ndarray:
    """(m, 3) points along a curve.

    Parameters
    ----------
    curve
        A Rhino curve (``DivideByCount(count, True)`` and ``PointAt(t)``: ``count + 1``
        points, equal arc length apart), or a polyline: an object with ``points`` (COMPAS)
        or an iterable of points (``Rhino.Geometry.Polyline``, a list).
    count : int
        Segments to divide a curve into (polylines keep their vertices).

    Raises
    ------
    GeometryError
        Fewer than 3 points, or a curve that cannot be divided.

    Examples
    --------
    >>> curve_points(Polyline([[0, 0, 0], [1, 0, 1], [2, 0, 0]])).shape
    (3, 3)
    """
    if isinstance(count, bool) or not isinstance(count, int) or count < 2:
        raise OptionError(f"count must be an integer >= 2, got {count!r}")
    if hasattr(curve, "DivideByCount") and hasattr(curve, "PointAt"):
        params = curve.DivideByCount(count, True)
        if params is None:
            raise GeometryError(f"the curve could not be divided into {count} segments")
        points = [point_xyz(curve.PointAt(t)) for t in params]
    else:
        source = curve.points if hasattr(curve, "points") else curve
        try:
            points = [point_xyz(p) for p in source]
        except TypeError:
            raise GeometryError(
                f"expected a curve, a polyline or a list of points, got {type(curve).__name__}"
            ) from None
    if len(points) < 3:
        raise GeometryError(f"a crease needs at least 3 points, got {len(points)}")
    return np.asarray(points, dtype=float)


def crease_plane(points) -> tuple:
    """The plane of a planar crease and its 2D profile.

    The profile x axis runs along the chord (first to last point), the y axis towards the
    curve's bulge, so a curve drawn as an arch stays an arch; the origin is the first point.

    Parameters
    ----------
    points : (m, 3) float

    Returns
    -------
    origin, xaxis, yaxis : (3,) float
        The design's ``[plane]`` (world coordinates, m).
    profile : (m, 2) float
        The points in the plane's coordinates.

    Raises
    ------
    GeometryError
        Coincident end points, all points on one line, or points off their best-fit plane
        by more than :data:`PLANARITY_TOLERANCE` times the curve's size.

    Examples
    --------
    >>> o, x, y, p = crease_plane([[0, 5, 0], [1, 5, 1], [2, 5, 0]])
    >>> x.tolist(), y.tolist(), p.tolist()
    ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]])
    """
    pts = np.asarray(points, dtype=float)
    chord = pts[-1] - pts[0]
    size = float(np.linalg.norm(np.ptp(pts, axis=0)))
    if float(np.linalg.norm(chord)) <= ZERO_LENGTH * max(size, 1.0):
        raise GeometryError(
            "the crease curve is closed (its end points coincide): need an open curve"
        )
    xaxis = chord / np.linalg.norm(chord)
    centred = pts - pts.mean(axis=0)
    _, s, vt = np.linalg.svd(centred, full_matrices=False)
    if s[1] <= EXACT_RELATIVE * size:
        raise GeometryError("the crease curve is straight: a CCU crease is curved")
    normal = vt[2] if len(s) > 2 else np.cross(vt[0], vt[1])
    off = float(np.max(np.abs(centred @ normal)))
    if off > PLANARITY_TOLERANCE * size:
        raise GeometryError(
            f"the crease curve is not planar: a point lies {off:.3g} m off its best-fit plane "
            f"(tolerance {PLANARITY_TOLERANCE * size:.3g} m)"
        )
    yaxis = np.cross(normal, xaxis)
    yaxis /= np.linalg.norm(yaxis)
    rel = pts - pts[0]
    profile = np.c_[rel @ xaxis, rel @ yaxis]
    if profile[:, 1].sum() < 0.0:
        yaxis, profile[:, 1] = -yaxis, -profile[:, 1]
    profile[np.abs(profile) < MACHINE] = 0.0
    return pts[0], xaxis, yaxis + 0.0, profile


def to_host(geometry, *, color=None):
    """Rhino geometry of a COMPAS mesh / polyline / line inside Rhino, else ``geometry``.

    Uses ``compas_rhino.conversions`` (``vertices_and_faces_to_rhino``,
    ``polyline_to_rhino_curve``, ``line_to_rhino_curve``).
    """
    conv = host_module("compas_rhino.conversions")
    if conv is None:
        return geometry
    if isinstance(geometry, Mesh):
        vertices, faces = geometry.to_vertices_and_faces()
        return conv.vertices_and_faces_to_rhino(vertices, faces, color=color)
    if isinstance(geometry, Polyline):
        return conv.polyline_to_rhino_curve(geometry)
    if isinstance(geometry, Line):
        return conv.line_to_rhino_curve(geometry)
    raise OptionError(f"no Rhino conversion for a {type(geometry).__name__}")


def to_host_surface(near, far, *, degree: int = 3):
    """A ruled NURBS surface through a plate's two boundaries, inside Rhino.

    ``near``, ``far``: (n + 1, 3) rows of plate vertices (ruling ``j`` joins ``near[j]`` and
    ``far[j]``). The surface interpolates them (degree 1 across the rulings, ``degree`` along
    them). Outside Rhino: None (the plates are exact as meshes of planar quads).
    """
    rhino = host_module("Rhino")
    if rhino is None:
        return None
    geo = rhino.Geometry
    near, far = np.asarray(near, dtype=float), np.asarray(far, dtype=float)
    points = [geo.Point3d(*map(float, p)) for p in np.concatenate([near, far])]
    n1 = len(near)
    return geo.NurbsSurface.CreateThroughPoints(points, 2, n1, 1, min(degree, n1 - 1), False, False)


def document_unit_scale() -> float:
    """Metres per unit of the active Rhino document; 1.0 outside Rhino."""
    rhino = host_module("Rhino")
    if rhino is None:
        return 1.0
    units = rhino.RhinoDoc.ActiveDoc.ModelUnitSystem
    return float(rhino.RhinoMath.UnitScale(units, rhino.UnitSystem.Meters))
