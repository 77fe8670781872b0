"""Rhino geometry in and out with host doubles that only carry data."""

from __future__ import annotations

import types

import numpy as np
import pytest
from compas.datastructures import Mesh
from compas.geometry import Frame, Line, Polyline

from compas_ccu.errors import GeometryError, OptionError
from compas_ccu.ghpython import convert
from compas_ccu.ghpython.convert import (
    crease_plane,
    curve_points,
    document_unit_scale,
    to_host,
    to_host_surface,
)


class Point3d:
    """RhinoCommon's Point3d, as data."""

    def __init__(self, x, y, z):
        self.X, self.Y, self.Z = x, y, z


class ArcCurve:
    """A Rhino curve double: a half circle of radius 1 in the world XZ plane (domain 0..pi)."""

    def DivideByCount(self, count, include_ends):
        assert include_ends is True
        return [np.pi * k / count for k in range(count + 1)]

    def PointAt(self, t):
        return Point3d(1.0 - np.cos(t), 2.0, np.sin(t))


def test_a_rhino_curve_is_divided_by_arc_length_parameters():
    pts = curve_points(ArcCurve(), count=8)
    assert pts.shape == (9, 3)
    assert np.allclose(np.linalg.norm(pts - [1.0, 2.0, 0.0], axis=1), 1.0)
    assert pts[4].tolist() == pytest.approx([1.0, 2.0, 1.0])


def test_polylines_and_point_lists_keep_their_vertices():
    rows = [[0, 0, 0], [1, 0, 1], [2, 0, 0]]
    assert curve_points(Polyline(rows)).tolist() == rows
    assert curve_points([Point3d(*r) for r in rows]).tolist() == rows
    assert curve_points([[0, 0], [1, 1], [2, 0]])[:, 2].tolist() == [0.0, 0.0, 0.0]


@pytest.mark.parametrize(
    ("curve", "error", "message"),
    [
        ([[0, 0, 0], [1, 0, 1]], GeometryError, "at least 3 points, got 2"),
        ([[0, 0, 0, 0]] * 3, GeometryError, "2 or 3 coordinates"),
        (42, GeometryError, "expected a curve, a polyline or a list of points, got int"),
    ],
)
def test_what_is_not_a_crease_curve_is_refused(curve, error, message):
    with pytest.raises(error, match=message):
        curve_points(curve)


def test_a_curve_count_below_two_is_refused():
    with pytest.raises(OptionError, match="count must be an integer >= 2, got 1"):
        curve_points(ArcCurve(), count=1)


def test_the_crease_plane_keeps_an_arch_an_arch():
    origin, x, y, profile = crease_plane(curve_points(ArcCurve(), count=16))
    assert origin.tolist() == [0.0, 2.0, 0.0]
    assert x.tolist() == pytest.approx([1.0, 0.0, 0.0], abs=1e-15)
    assert y.tolist() == pytest.approx([0.0, 0.0, 1.0], abs=1e-15)
    assert profile[:, 1].max() == pytest.approx(1.0)  # the apex, 1 m above the chord
    assert np.allclose(profile[[0, -1]], [[0.0, 0.0], [2.0, 0.0]], rtol=0.0, atol=1e-15)


def test_an_upside_down_curve_gets_a_flipped_plane():
    pts = curve_points(ArcCurve(), count=16) * [1.0, 1.0, -1.0]
    _, _, y, profile = crease_plane(pts)
    assert y.tolist() == pytest.approx([0.0, 0.0, -1.0])
    assert profile[:, 1].min() >= 0.0


@pytest.mark.parametrize(
    ("points", "message"),
    [
        ([[0, 0, 0], [1, 0, 1], [2, 0, 0.0001], [0, 0, 0]], "closed"),
        ([[0, 0, 0], [1, 0, 0], [2, 0, 0]], "straight"),
        ([[0, 0, 0], [1, 0, 1], [2, 0.01, 0], [3, 0, 1]], "not planar: a point lies 0.0025 m off"),
    ],
)
def test_impossible_crease_curves_are_refused(points, message):
    with pytest.raises(GeometryError, match=message):
        crease_plane(points)


def test_outside_rhino_geometry_stays_compas(monkeypatch):
    monkeypatch.setattr(convert, "_HOSTS", {"compas_rhino.conversions": None, "Rhino": None})
    mesh = Mesh.from_polyhedron(4)
    assert to_host(mesh) is mesh
    assert to_host_surface([[0, 0, 0], [1, 0, 0]], [[0, 1, 0], [1, 1, 0]]) is None
    assert document_unit_scale() == 1.0


def test_inside_rhino_the_conversions_are_compas_rhino_and_rhinocommon(monkeypatch):
    calls = []
    conversions = types.SimpleNamespace(
        vertices_and_faces_to_rhino=lambda v, f, color=None: calls.append("mesh") or ("M", v, f),
        polyline_to_rhino_curve=lambda p: calls.append("polyline") or ("P", p),
        line_to_rhino_curve=lambda line: calls.append("line") or ("L", line),
    )
    surface = types.SimpleNamespace(CreateThroughPoints=lambda *args: ("S", args))
    rhino = types.SimpleNamespace(
        Geometry=types.SimpleNamespace(Point3d=Point3d, NurbsSurface=surface),
        RhinoDoc=types.SimpleNamespace(ActiveDoc=types.SimpleNamespace(ModelUnitSystem="mm")),
        UnitSystem=types.SimpleNamespace(Meters="m"),
        RhinoMath=types.SimpleNamespace(UnitScale=lambda a, b: {("mm", "m"): 0.001}[(a, b)]),
    )
    monkeypatch.setattr(
        convert, "_HOSTS", {"compas_rhino.conversions": conversions, "Rhino": rhino}
    )
    kind, vertices, faces = to_host(Mesh.from_polyhedron(4))
    assert (kind, len(vertices), len(faces)) == ("M", 4, 4)
    assert to_host(Polyline([[0, 0, 0], [1, 0, 0]]))[0] == "P"
    assert to_host(Line([0, 0, 0], [1, 0, 0]))[0] == "L"
    assert calls == ["mesh", "polyline", "line"]
    kind, (points, u, v, du, dv, uc, vc) = to_host_surface(
        [[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 0], [1, 1, 0], [2, 1, 0]]
    )
    assert (u, v, du, dv, uc, vc) == (2, 3, 1, 2, False, False)
    assert [(p.X, p.Y) for p in points] == [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]
    assert document_unit_scale() == 0.001
    with pytest.raises(OptionError, match="no Rhino conversion for a Frame"):
        to_host(Frame.worldXY())
