"""Crease profiles and target curves read from curve files named in a design file."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.design import Design, load_design
from compas_ccu.errors import DesignError
from compas_ccu.model import CCUModel
from conftest import circumradius_error

ezdxf = pytest.importorskip("ezdxf")

R, ALPHA = 2.0, 40.0
CONE = """
[crease]
profile = "polyline"
points = {points}
segments = 48
state = "flat"

[rulings]
type = "orthogonal"

[deployment]
alpha = 40.0

[layout]
width = 0.4
"""


def arc_file(folder, name="crease.dxf"):
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    doc.modelspace().add_arc((0, 0), R * 1000.0, 45, 135, dxfattribs={"layer": "CREASE"})
    doc.modelspace().add_line((0, 0), (100, 0), dxfattribs={"layer": "OTHER"})
    doc.saveas(folder / name)
    return folder / name


def test_cone_from_a_dxf_arc_relative_to_the_design_file(tmp_path, monkeypatch):
    """The crease file is read from the design file's folder, not the current one; the flat
    crease is a 48-gon within 1e-8 of the arc, so the deployed crease is the cone's circle
    r3D = R cos(alpha) to that tolerance."""
    folder = tmp_path / "design"
    folder.mkdir()
    arc_file(folder)
    path = folder / "cone.toml"
    path.write_text(CONE.format(points='{ file = "crease.dxf", layer = "CREASE" }'))
    monkeypatch.chdir(tmp_path)
    design = load_design(path)
    crease = np.asarray(design.crease.points)
    structure = CCUModel(design).deploy(ALPHA)
    deployed = np.asarray(structure.deployed)[0, :49]
    assert circumradius_error(deployed, R * math.cos(math.radians(ALPHA))) < 1e-7
    assert circumradius_error(np.c_[crease, np.zeros(len(crease))], R) < 1e-14


def test_missing_file_and_several_curves_name_the_key_and_the_path(tmp_path):
    path = tmp_path / "cone.toml"
    path.write_text(CONE.format(points='"nowhere.dxf"'))
    with pytest.raises(DesignError, match=r"crease.points: curve file '.*nowhere.dxf' does not"):
        load_design(path)
    arc_file(tmp_path)
    path.write_text(CONE.format(points='"crease.dxf"'))
    with pytest.raises(DesignError, match=r"crease.points: .*2 candidate curves.*layer CREASE"):
        load_design(path)
    path.write_text(CONE.format(points='{ file = "crease.dxf", colour = 1 }'))
    with pytest.raises(DesignError, match=r"crease.points.colour: unknown key.*file, layer"):
        load_design(path)
    path.write_text(CONE.format(points='{ file = "crease.dxf", units = "yd" }'))
    with pytest.raises(DesignError, match=r"crease.points.units: must be one of m, cm"):
        load_design(path)


def test_target_curve_from_a_csv(tmp_path):
    (tmp_path / "apex.csv").write_text("d, y\n0, 1\n1, 1.1\n2, 1.3\n")
    values = {
        "crease": {"profile": "arc", "span": 4.0, "rise": 1.0},
        "rulings": {"type": "orthogonal"},
        "deployment": {"alpha": 30.0},
        "layout": {"type": "parallel", "plates": 4, "spacing": 0.3},
        "target": {"apex": "apex.csv"},
    }
    design = Design(values, base=tmp_path)
    assert design.target.apex == [[0.0, 1.0], [1.0, 1.1], [2.0, 1.3]]
    assert design.document["target"]["apex"] == "apex.csv"  # the document keeps the reference
    again = Design.__from_data__(design.__data__)
    assert again.target.apex == design.target.apex


def test_target_curve_off_a_plane_z_const_and_non_planar_crease_are_refused(tmp_path):
    (tmp_path / "apex.csv").write_text("0 1 0\n1 1.1 0.2\n2 1.3 0\n")
    values = {
        "crease": {"profile": "arc", "span": 4.0, "rise": 1.0},
        "rulings": {"type": "orthogonal"},
        "deployment": {"alpha": 30.0},
        "layout": {"type": "parallel", "plates": 4, "spacing": 0.3},
        "target": {"apex": {"file": "apex.csv"}},
    }
    with pytest.raises(DesignError, match=r"target.apex: .*apex.csv: 3 points: a target curve "):
        Design(values, base=tmp_path)
    (tmp_path / "crease.csv").write_text("0 0 0\n1 1 0\n2 1 0.5\n3 0 0\n")
    path = tmp_path / "c.toml"
    path.write_text(CONE.format(points='"crease.csv"'))
    with pytest.raises(DesignError, match=r"crease.points: .*crease.csv: 4 points: the curve is"):
        load_design(path)


def test_a_crease_drawn_in_a_tilted_plane_stands_where_it_was_drawn(tmp_path):
    """A 3D arc (R = 2 m, 90 deg) in the plane through (1, 2, 3) spanned by (0, 1, 0) and
    (0.6, 0, 0.8), as a CSV of 3D points; no [plane] in the design: the plane comes from the
    file and the deployed crease (state = "deployed": the profile is the 3D crease) lies on the
    drawn arc."""
    t = np.linspace(math.radians(45.0), math.radians(135.0), 2001)
    u, v = np.array([0.0, 1.0, 0.0]), np.array([0.6, 0.0, 0.8])
    origin = np.array([1.0, 2.0, 3.0])
    arc = origin + np.outer(R * np.cos(t), u) + np.outer(R * np.sin(t), v)
    np.savetxt(tmp_path / "arc.csv", arc, delimiter=",", fmt="%.17g")
    document = {
        "crease": {"profile": "polyline", "points": "arc.csv", "segments": 32},
        "rulings": {"type": "orthogonal"},
        "deployment": {"alpha": 30.0},
        "layout": {"width": 0.3},
    }
    design = Design(document, base=tmp_path)
    assert design.plane.yaxis == pytest.approx(v.tolist(), abs=1e-12)
    crease = np.asarray(CCUModel(design).deploy().deployed)[0, :33]
    # on the circle of radius R about the arc's centre, in the drawn plane
    normal = np.cross(u, v)
    assert np.abs((crease - origin) @ normal).max() < 1e-12
    radius = np.linalg.norm(
        (crease - origin) - np.outer((crease - origin) @ normal, normal), axis=1
    )
    assert np.abs(radius - R).max() < 1.6e-7  # sagitta of the file polyline: 1.5e-7
    with_plane = Design({**document, "plane": {"yaxis": [0.0, 0.0, 1.0]}}, base=tmp_path)
    assert with_plane.plane.yaxis == [0.0, 0.0, 1.0]  # a given plane wins


def test_a_csv_crease_in_a_millimetre_design_is_read_in_millimetres(tmp_path):
    """A CSV file has no units: it is read in the design's units, a DXF keeps its own."""
    (tmp_path / "c.csv").write_text("-1000 0\n0 500\n1000 0\n")
    doc = {
        "design": {"units": "mm"},
        "crease": {"profile": "polyline", "points": "c.csv"},
        "rulings": {"type": "orthogonal"},
        "deployment": {"alpha": 30.0},
        "layout": {"width": 300},
    }
    d = Design(doc, base=tmp_path)
    assert d.values["crease"]["points"] == [[-1.0, 0.0], [0.0, 0.5], [1.0, 0.0]]
    assert d.layout.width == 0.3
