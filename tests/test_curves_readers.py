"""Curves from files (CSV / TXT, DXF, SVG, 3dm) read back against the exact source curve."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.curves.readers import plane_coordinates, read_curve
from compas_ccu.errors import ProfileError

ezdxf = pytest.importorskip("ezdxf")
rhino3dm = pytest.importorskip("rhino3dm")
pytest.importorskip("svgelements")

R = 2.0  # m: a 90-degree arc of radius 2 m from 45 to 135 degrees, centre at the origin
A0, A1 = math.radians(45.0), math.radians(135.0)
SIZE = 2.0 * R * math.sin(math.radians(45.0))  # the chord: the curve's bounding-box diagonal


def radial_error(points, centre=(0.0, 0.0)):
    """Largest distance of the points (and of the chords' midpoints) from the circle."""
    p = np.asarray(points)[:, :2] - np.asarray(centre)
    mids = 0.5 * (p[1:] + p[:-1])
    return (
        float(np.abs(np.linalg.norm(p, axis=1) - R).max()),
        float(np.abs(np.linalg.norm(mids, axis=1) - R).max()),
    )


def arc_dxf(path, units=ezdxf.units.MM, k=1000.0):
    doc = ezdxf.new("R2010")
    doc.units = units
    msp = doc.modelspace()
    msp.add_arc((0, 0), R * k, 45, 135, dxfattribs={"layer": "ARC"})
    bulge = -math.tan(math.radians(90.0) / 4.0)  # clockwise from 135 to 45 degrees
    start = (R * k * math.cos(A1), R * k * math.sin(A1), bulge)
    msp.add_lwpolyline(
        [start, (R * k * math.cos(A0), R * k * math.sin(A0), 0.0)],
        format="xyb",
        dxfattribs={"layer": "BULGE"},
    )
    doc.saveas(path)
    return path


@pytest.mark.parametrize("layer", ["ARC", "BULGE"])
def test_dxf_arc_and_bulge_polyline_are_the_exact_arc(tmp_path, layer):
    curve = read_curve(arc_dxf(tmp_path / "a.dxf"), layer=layer)
    vertices, chords = radial_error(curve.points)
    assert curve.units == "mm" and layer in curve.source
    assert vertices < 1e-15 * 10  # exact evaluation, rounding only
    assert chords <= 1e-8 * SIZE  # the sampling tolerance
    assert np.linalg.norm(curve.points[[0, -1], :2], axis=1) == pytest.approx([R, R], abs=1e-14)


def test_object_coordinates_to_world_are_ezdxfs_to_the_bit():
    """ocs_to_wcs (all points at once) against ezdxf's OCS.to_wcs point by point: a mirrored
    arc's extrusion (0, 0, -1), the world's, and random tilted ones, to the last bit."""
    from ezdxf.math import OCS

    from compas_ccu.curves.dxf_input import ocs_to_wcs

    rng = np.random.default_rng(7)
    extrusions = [(0.0, 0.0, -1.0), (0.0, 0.0, 1.0), (0.01, 0.0, 1.0)]
    extrusions += [tuple(rng.normal(size=3)) for _ in range(20)]
    for extrusion in extrusions:
        ocs = OCS(extrusion)
        local = rng.normal(size=(40, 3)) * 10.0 ** rng.uniform(-3, 3)
        want = np.array([tuple(ocs.to_wcs(tuple(p))) for p in local], dtype=float)
        assert ocs_to_wcs(ocs, local).tobytes() == want.tobytes(), extrusion


def test_a_mirrored_dxf_arc_is_read_where_it_is_drawn(tmp_path):
    """An ARC with extrusion (0, 0, -1), as a CAD mirror writes it: its points in the world."""
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    doc.modelspace().add_arc((0, 0), R * 1000.0, 45, 135, dxfattribs={"extrusion": (0, 0, -1)})
    doc.saveas(tmp_path / "m.dxf")
    points = read_curve(tmp_path / "m.dxf").points
    vertices, chords = radial_error(points)
    assert vertices < 1e-15 * 10 and chords <= 1e-8 * SIZE
    assert (points[:, 1] > 0.0).all()  # the mirror image of an arc above the x axis is above it
    assert np.allclose(sorted(points[[0, -1], 0]), [-R * math.cos(A0), R * math.cos(A0)])


def test_dxf_several_curves_need_a_choice_and_the_error_lists_them(tmp_path):
    path = arc_dxf(tmp_path / "a.dxf")
    with pytest.raises(ProfileError, match=r"2 candidate curves.*\[0\] ARC #\w+ on layer ARC"):
        read_curve(path)
    with pytest.raises(ProfileError, match="no curve with layer = 'CREASE'.*BULGE"):
        read_curve(path, layer="CREASE")
    assert "LWPOLYLINE" in read_curve(path, index=1).source
    with pytest.raises(ProfileError, match="index 5 out of range 0 ... 1"):
        read_curve(path, index=5)


def test_dxf_unitless_needs_units_and_units_override(tmp_path):
    path = arc_dxf(tmp_path / "a.dxf", units=0, k=1.0)
    with pytest.raises(ProfileError, match="no units.*give units"):
        read_curve(path, layer="ARC")
    curve = read_curve(path, layer="ARC", units="m", scale=2.0)
    assert np.linalg.norm(curve.points[0, :2]) == pytest.approx(2.0 * R, rel=1e-15)


def test_dxf_line_chain_in_any_order_and_spline(tmp_path):
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.M
    msp = doc.modelspace()
    pts = [(0.0, 0.0), (1.0, 0.5), (2.0, 0.7), (3.0, 0.5), (4.0, 0.0)]
    for a, b in [(2, 3), (0, 1), (4, 3), (1, 2)]:  # shuffled and one reversed
        msp.add_line(pts[a], pts[b], dxfattribs={"layer": "CHAIN"})
    spline = msp.add_spline([(0, 0), (1, 1), (3, 1), (4, 0)], dxfattribs={"layer": "SPLINE"})
    path = tmp_path / "b.dxf"
    doc.saveas(path)
    chain = read_curve(path, layer="CHAIN").points[:, :2]
    assert chain.tolist() in ([list(p) for p in pts], [list(p) for p in pts[::-1]])
    curve = read_curve(path, layer="spline")  # layer names are case-insensitive
    tool = spline.construction_tool()
    exact = np.array([tuple(v) for v in tool.points(np.linspace(0.0, tool.max_t, 20001))])
    # every point read lies on the spline: nearest of 20001 exact points within their spacing
    probe = curve.points[:: max(1, len(curve.points) // 200)]
    d = np.linalg.norm(probe[:, None, :] - exact[None, :, :], axis=2).min(axis=1)
    assert d.max() < 2.5e-4
    assert np.abs(curve.points[[0, -1]] - [[0, 0, 0], [4, 0, 0]]).max() < 1e-15


def test_svg_arc_in_millimetres_is_exact(tmp_path):
    """svgelements converts mm to pixels with 3.7795296 px/mm (5e-7 too large); the reader
    divides it out, so the arc comes back to rounding."""
    c = 2000.0 * math.cos(A0)
    path = tmp_path / "a.svg"
    path.write_text(
        '<svg xmlns="http://www.w3.org/2000/svg" width="4000mm" height="2000mm" '
        'viewBox="0 0 4000 2000"><g id="CREASE"><path id="arc" '
        f'd="M {2000 - c!r} {2000 - c!r} A 2000 2000 0 0 1 {2000 + c!r} {2000 - c!r}"/></g>'
        '<path id="other" d="M 0 0 L 10 10"/></svg>'
    )
    curve = read_curve(path, layer="CREASE")
    vertices, chords = radial_error(curve.points, centre=(2.0, -2.0))  # y is negated
    assert vertices < 1e-14 and chords <= 1e-8 * SIZE
    assert curve.points[:, 1].max() == pytest.approx(-2.0 + R, abs=1e-14)  # the arc points up
    assert read_curve(path, name="other").points[-1, :2].tolist() == pytest.approx([0.01, -0.01])


def test_rhino_arc_and_nurbs_in_millimetres(tmp_path):
    model = rhino3dm.File3dm()
    model.Settings.ModelUnitSystem = rhino3dm.UnitSystem.Millimeters
    arc = rhino3dm.Arc(rhino3dm.Point3d(0, 0, 0), R * 1000.0, math.radians(90.0))
    attributes = rhino3dm.ObjectAttributes()
    attributes.Name = "crease"
    model.Objects.AddArc(arc, attributes)
    model.Objects.AddPolyline([rhino3dm.Point3d(0, 0, 0), rhino3dm.Point3d(1, 1, 0)])
    path = tmp_path / "a.3dm"
    model.Write(str(path), 8)
    curve = read_curve(path, name="crease")
    assert curve.units == "mm"
    # the arc starts on the x axis: 0 ... 90 degrees
    vertices, chords = radial_error(curve.points)
    assert vertices < 1e-14 and chords <= 1.0e-8 * SIZE
    with pytest.raises(ProfileError, match="2 candidate curves"):
        read_curve(path)


def test_csv_header_comments_separators_and_errors(tmp_path):
    path = tmp_path / "c.txt"
    path.write_text("# a comment\nx;y\n0;0 # start\n\n1\t0.5\n2, 0\n")
    assert read_curve(path).points[:, :2].tolist() == [[0, 0], [1, 0.5], [2, 0]]
    path.write_text("0 0\n1 nan\n")
    with pytest.raises(ProfileError, match="line 2: a point is 2 or 3 finite numbers"):
        read_curve(path)
    with pytest.raises(ProfileError, match="does not exist"):
        read_curve(tmp_path / "missing.csv")
    with pytest.raises(ProfileError, match="cannot read curves from '.obj'"):
        read_curve(tmp_path / "x.obj")


def test_plane_coordinates_of_a_tilted_arc_and_non_planar_refused():
    t = np.linspace(A0, A1, 33)
    flat = np.c_[R * np.cos(t), R * np.sin(t)]
    # the arc in the plane through (1, 2, 3) spanned by (0, 1, 0) and (0.6, 0, 0.8)
    u, v = np.array([0.0, 1.0, 0.0]), np.array([0.6, 0.0, 0.8])
    points = np.array([1.0, 2.0, 3.0]) + flat[:, :1] * u + flat[:, 1:] * v
    p2, frame, deviation = plane_coordinates(points)
    assert deviation < 1e-15
    # chord frame: ends at (-/+ chord / 2, 0), the arc rising to +y, lengths kept
    assert p2[0] == pytest.approx([SIZE / 2.0, 0.0], abs=1e-15) or p2[0] == pytest.approx(
        [-SIZE / 2.0, 0.0], abs=1e-15
    )
    assert p2[16, 1] == pytest.approx(R - R * math.cos(math.radians(45.0)), abs=1e-14)
    assert frame["yaxis"] == pytest.approx(v, abs=1e-15)
    bent = points.copy()
    bent[16] += 0.01 * np.cross(u, v)
    with pytest.raises(ProfileError, match=r"not planar: its points lie up to 0\.00\d+ m"):
        plane_coordinates(bent, source="c.dxf: ARC")
