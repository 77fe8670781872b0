"""DXF cut files: plates and hinge strips read back with ezdxf, in millimetres, to 0.01 mm."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

ezdxf = pytest.importorskip("ezdxf")

from shapely import LineString, Point, Polygon  # noqa: E402

from compas_ccu.errors import GeometryError  # noqa: E402
from compas_ccu.fabrication import FabricationData  # noqa: E402
from compas_ccu.fabrication.dxf import (  # noqa: E402
    APPID,
    HINGE_LAYERS,
    PLATE_LAYERS,
    read_plate_dxf,
    write_hinge_dxf,
    write_plate_dxf,
)
from compas_ccu.fabrication.hinges import hinge_strips, offset_strip  # noqa: E402

TOL = 0.01  # mm


@pytest.fixture(scope="module")
def data(vault_fab_data):
    return vault_fab_data


@pytest.fixture(scope="module")
def plate_files(data, tmp_path_factory):
    out = tmp_path_factory.mktemp("plates")
    return [write_plate_dxf(data, i, out / f"plate_{i}.dxf") for i in range(len(data.plate_ids))]


@pytest.fixture(scope="module")
def hinge_file(data, tmp_path_factory):
    path = tmp_path_factory.mktemp("hinges") / "hinges.dxf"
    strips = hinge_strips(data)
    moves = write_hinge_dxf(strips, path, name=data.name)
    return path, strips, moves


def _entities(doc, layer, kind):
    return [e for e in doc.modelspace() if e.dxf.layer == layer and e.dxftype() == kind]


def _xy(e) -> np.ndarray:
    return np.array([p[:2] for p in e.get_points("xy")], dtype=float)


def _xdata_ints(e) -> list:
    return [v for code, v in e.get_xdata(APPID) if code in (1070, 1071)]


# ---------------------------------------------------------------------------------------- plates


def test_plate_files_units_layers_version(data, plate_files):
    assert len(plate_files) == len(data.plate_ids) == 10
    for path in plate_files:
        doc = ezdxf.readfile(path)
        assert doc.units == ezdxf.units.MM == 4
        assert doc.header["$INSUNITS"] == 4
        assert doc.dxfversion >= "AC1024"  # R2010
        names = {layer.dxf.name for layer in doc.layers}
        assert set(PLATE_LAYERS) <= names
        colors = [doc.layers.get(name).color for name in PLATE_LAYERS]
        assert len(set(colors)) == len(colors)


def _geometry_box(doc):
    """Bounding box of every polyline / line vertex and text insertion point, mm."""
    pts = []
    for e in doc.modelspace():
        kind = e.dxftype()
        if kind == "LWPOLYLINE":
            pts += [tuple(p[:2]) for p in e.get_points("xy")]
        elif kind == "LINE":
            pts += [tuple(e.dxf.start)[:2], tuple(e.dxf.end)[:2]]
        elif kind == "TEXT":
            pts.append(tuple(e.dxf.align_point)[:2])
    pts = np.array(pts, dtype=float)
    return pts.min(axis=0), pts.max(axis=0)


def test_header_extents_are_the_entities(data, plate_files, hinge_file):
    """$EXTMIN / $EXTMAX bound the drawing (not ezdxf's +-1e20 placeholders)."""
    docs = [ezdxf.readfile(path) for path in plate_files]  # each file read once
    for path, doc in zip([*plate_files, hinge_file[0]], [*docs, ezdxf.readfile(hinge_file[0])]):
        lo = np.array(doc.header["$EXTMIN"][:2], dtype=float)
        hi = np.array(doc.header["$EXTMAX"][:2], dtype=float)
        glo, ghi = _geometry_box(doc)
        assert (lo <= glo + 1e-9).all() and (hi >= ghi - 1e-9).all(), path
        size = np.linalg.norm(ghi - glo)
        # tight: only text may stick out, by less than 5 % of the drawing
        assert np.linalg.norm(lo - glo) < 0.05 * size and np.linalg.norm(hi - ghi) < 0.05 * size
        assert doc.header["$EXTMIN"][2] == doc.header["$EXTMAX"][2] == 0.0
    for i, doc in enumerate(docs):  # plates: the labels are inside, the box is the cut
        outline = data.outline(i) * 1000.0
        np.testing.assert_allclose(doc.header["$EXTMIN"][:2], outline.min(axis=0), atol=1e-9)
        np.testing.assert_allclose(doc.header["$EXTMAX"][:2], outline.max(axis=0), atol=1e-9)


def test_cut_outline_in_mm(data, plate_files):
    worst = 0.0
    for i, path in enumerate(plate_files):
        doc = ezdxf.readfile(path)
        cuts = _entities(doc, "CUT", "LWPOLYLINE")
        assert len(cuts) == 1 and cuts[0].closed
        got = _xy(cuts[0])
        want = data.outline(i) * 1000.0
        assert got.shape == want.shape == (2 * data.segments + 2, 2)
        err = float(np.abs(got - want).max())
        worst = max(worst, err)
        assert err < TOL, (i, err)
        # a plate is metres wide: the file really is in mm
        assert np.ptp(got, axis=0).max() > 1000.0
    assert worst < 1e-6  # doubles: far below the 0.01 mm tolerance


def test_crease_polylines(data, plate_files):
    for i, path in enumerate(plate_files):
        doc = ezdxf.readfile(path)
        polylines = _entities(doc, "CREASE", "LWPOLYLINE")
        expected = data.plate_creases(i)
        assert len(polylines) == len(expected) >= 1
        by_id = {_xdata_ints(e)[0]: e for e in polylines}
        for cid, other, idx in expected:
            e = by_id[cid]
            assert not e.closed
            assert _xdata_ints(e)[1] == other
            want = data.flat[i][idx] * 1000.0
            got = _xy(e)
            assert got.shape == want.shape
            assert np.abs(got - want).max() < TOL


def test_ruling_score_lines(data, plate_files):
    n = data.segments
    for i, path in enumerate(plate_files):
        doc = ezdxf.readfile(path)
        lines = _entities(doc, "RULING_SCORE", "LINE")
        assert len(lines) == n - 1
        got = np.array([[tuple(e.dxf.start)[:2], tuple(e.dxf.end)[:2]] for e in lines])
        j = np.arange(1, n)
        want = np.stack([data.flat[i][j], data.flat[i][n + 1 + j]], axis=1) * 1000.0
        # order-free matching, either direction
        d = np.abs(got[:, None] - want[None]).max(axis=(2, 3))
        d_rev = np.abs(got[:, None, ::-1] - want[None]).max(axis=(2, 3))
        best = np.minimum(d, d_rev)
        match = best.argmin(axis=1)
        assert sorted(match.tolist()) == list(range(n - 1))
        assert best.min(axis=1).max() < TOL


def test_labels(data, plate_files):
    p = len(data.plate_ids)
    for i, path in enumerate(plate_files):
        doc = ezdxf.readfile(path)
        texts = _entities(doc, "LABEL", "TEXT")
        labels = [e.dxf.text for e in texts]
        joined = "\n".join(labels)
        pid = data.plate_ids[i]
        k = data.stack_position[i]
        assert re.search(rf"\bPLATE {pid}\b", joined)
        assert f"stack {k + 1} of {p} (bottom = 1)" in joined
        for cid, other, _ in data.plate_creases(i):
            assert re.search(rf"\bcrease {cid} to plate {other}\b", joined)
        assert "UP" in labels
        # the face-up triangle and every label sit inside the plate
        plate = Polygon(data.outline(i) * 1000.0)
        marks = _entities(doc, "LABEL", "LWPOLYLINE")
        assert len(marks) == 1 and marks[0].closed and len(_xy(marks[0])) == 3
        for e in texts:
            assert plate.contains(Point(tuple(e.dxf.align_point)[:2])), e.dxf.text
        assert plate.contains(Polygon(_xy(marks[0])))


def test_read_plate_dxf_round_trip(data, plate_files):
    i = 3
    r = read_plate_dxf(plate_files[i])
    assert r["units"] == 4
    assert np.abs(r["outline"] - data.outline(i)).max() < 1e-8  # metres
    assert [(c["id"], c["other"]) for c in r["creases"]] == [
        (cid, other) for cid, other, _ in data.plate_creases(i)
    ]
    assert len(r["rulings"]) == data.segments - 1
    assert np.abs(r["rulings"][0] - data.flat[i][[1, data.segments + 2]]).max() < 1e-8
    assert any(f"PLATE {data.plate_ids[i]}" == s for s in r["labels"])


def test_plate_index_out_of_range(data, tmp_path):
    with pytest.raises(IndexError, match="10"):
        write_plate_dxf(data, 10, tmp_path / "x.dxf")


# ---------------------------------------------------------------------------------------- hinges


def _hinge_entities(path):
    doc = ezdxf.readfile(path)
    cut = {_xdata_ints(e)[0]: e for e in _entities(doc, "HINGE_CUT", "LWPOLYLINE")}
    centre = {_xdata_ints(e)[0]: e for e in _entities(doc, "HINGE_CREASE", "LWPOLYLINE")}
    return doc, cut, centre


def test_hinge_file_units_layers(data, hinge_file):
    path, strips, moves = hinge_file
    doc, cut, centre = _hinge_entities(path)
    assert doc.units == 4 and doc.header["$INSUNITS"] == 4
    assert set(HINGE_LAYERS) <= {layer.dxf.name for layer in doc.layers}
    ids = [c["id"] for c in data.creases]
    assert sorted(cut) == sorted(centre) == sorted(moves) == sorted(ids)
    assert all(cut[c].closed and not centre[c].closed for c in ids)


def test_hinge_strip_width(data, hinge_file):
    path, strips, moves = hinge_file
    _, cut, centre = _hinge_entities(path)
    half = 0.5 * data.hinge_width * 1000.0
    for s in strips:
        line = LineString(_xy(centre[s.crease_id]))
        ring = _xy(cut[s.crease_id])
        assert len(ring) == 2 * len(s.centre)
        d = np.array([line.distance(Point(q)) for q in ring])
        assert np.abs(d - half).max() < TOL, (s.crease_id, d.min(), d.max())
        poly = Polygon(ring)
        assert poly.is_valid
        # a strip of constant width: area = width x length (to 0.1 %)
        assert poly.area == pytest.approx(2.0 * half * line.length, rel=1e-3)


def test_hinge_centre_is_the_crease(data, hinge_file):
    path, strips, moves = hinge_file
    _, _, centre = _hinge_entities(path)
    for c in data.creases:
        a = c["plates"][0]
        want = data.flat[data.index(a)][c["vertices"][0]] * 1000.0
        dx, dy = moves[c["id"]]
        got = _xy(centre[c["id"]]) - 1000.0 * np.array([dx, dy])
        assert got.shape == want.shape
        assert np.abs(got - want).max() < TOL
        # the XDATA records the same translation, mm
        floats = [v for code, v in centre[c["id"]].get_xdata(APPID) if code == 1040]
        assert floats[:2] == pytest.approx([1000.0 * dx, 1000.0 * dy], abs=1e-9)


def test_hinge_strips_do_not_overlap(hinge_file):
    path, strips, moves = hinge_file
    _, cut, _ = _hinge_entities(path)
    polys = [Polygon(_xy(e)) for e in cut.values()]
    assert len(polys) == 9
    for k in range(len(polys)):
        for m in range(k + 1, len(polys)):
            assert not polys[k].intersects(polys[m]), (k, m)
    # and the layout is compact: well below stacking every bounding box
    boxes = sum(p.bounds[3] - p.bounds[1] for p in polys)
    total = max(p.bounds[3] for p in polys) - min(p.bounds[1] for p in polys)
    assert total < boxes


def test_hinge_labels(data, hinge_file):
    path, strips, _ = hinge_file
    doc = ezdxf.readfile(path)
    joined = "\n".join(e.dxf.text for e in _entities(doc, "LABEL", "TEXT"))
    for c in data.creases:
        a, b = c["plates"]
        assert f"crease {c['id']}: plates {a} - {b}" in joined


def test_hinge_strips_model(data):
    strips = hinge_strips(data, width=0.03)
    assert [s.crease_id for s in strips] == [c["id"] for c in data.creases]
    for s, c in zip(strips, data.creases):
        assert s.plates == tuple(c["plates"]) and s.width == 0.03
        assert s.outline.shape == (2 * len(s.centre), 2)
        # the two sides lie at +-width / 2 along the crease normals, ends included
        assert np.linalg.norm(s.outline[0] - s.centre[0]) == pytest.approx(0.015, abs=1e-12)


# ---------------------------------------------------------------------------------------- errors


@pytest.mark.parametrize("width", [0.0, -0.01, float("nan"), float("inf"), "wide"])
def test_bad_width(data, width):
    with pytest.raises(GeometryError, match=re.escape(repr(width))):
        hinge_strips(data, width=width)
    with pytest.raises(GeometryError, match=re.escape(repr(width))):
        hinge_strips(dataclasses.replace(data, hinge_width=width))


def test_too_wide_for_the_vault(data):
    with pytest.raises(GeometryError) as err:
        hinge_strips(data, width=3.5)
    msg = str(err.value)
    assert "crease 0" in msg and "3.5" in msg and "radius of curvature" in msg


def _tight_arc(radius: float = 0.1, n: int = 24) -> FabricationData:
    """Two plates either side of a quarter-circle crease of ``radius``."""
    t = np.linspace(0.0, 0.5 * np.pi, n + 1)
    arc = np.c_[np.cos(t), np.sin(t)]
    crease = radius * arc
    inner = 0.5 * radius * arc
    outer = 1.6 * radius * arc
    flat = np.stack([np.r_[crease, inner], np.r_[crease, outer]])
    j = np.arange(n)
    faces = np.stack([j, j + 1, n + 2 + j, n + 1 + j], axis=1)
    zeros = np.zeros((2, 2 * n + 2, 3))
    return FabricationData(
        name="tight",
        alpha=30.0,
        thickness=0.004,
        material="plywood",
        plate_ids=[0, 1],
        faces=np.stack([faces, faces]),
        flat=flat,
        deployed_mid=zeros,
        solids=np.stack([zeros, zeros], axis=1),
        stack_solids=np.stack([zeros, zeros], axis=1),
        creases=[
            {
                "id": 7,
                "plates": [0, 1],
                "vertices": [list(range(n + 1)), list(range(n + 1))],
                "kind": "synclastic",
                "fold_angle": 60.0,
            }
        ],
        stack_position=[0, 1],
        hinge_width=0.05,
    )


def test_tight_arc(tmp_path):
    tight = _tight_arc(radius=0.1)
    (s,) = hinge_strips(tight, width=0.12)  # half-width 0.06 < radius 0.1: fine
    r = np.linalg.norm(s.outline, axis=1)
    assert r.max() == pytest.approx(0.16, rel=1e-2) and r.min() == pytest.approx(0.04, rel=2e-2)
    # coarse polyline (3.75 deg turns): still every outline vertex at exactly width / 2
    line = LineString(s.centre)
    d = np.array([line.distance(Point(q)) for q in s.outline])
    assert np.abs(d - 0.06).max() < 1e-12
    assert Polygon(s.outline).is_valid
    moves = write_hinge_dxf([s], tmp_path / "tight.dxf", name="tight")
    assert set(moves) == {7}
    with pytest.raises(GeometryError) as err:
        hinge_strips(tight, width=0.25)  # half-width 0.125 > radius 0.1
    msg = str(err.value)
    assert "crease 7" in msg and "0.25" in msg
    radius = float(re.search(r"radius of curvature is ([0-9.]+)", msg).group(1))
    assert radius == pytest.approx(0.1, rel=1e-2)


def test_offset_strip_straight_and_degenerate():
    line = np.c_[np.linspace(0.0, 1.0, 5), np.zeros(5)]
    ring = offset_strip(line, 10.0)  # no curvature: no limit
    assert np.abs(np.abs(ring[:, 1]) - 5.0).max() < 1e-12
    with pytest.raises(GeometryError, match="zero length"):
        offset_strip(np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0]]), 0.1)
    with pytest.raises(GeometryError, match="turns back"):
        offset_strip(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]]), 0.1)


_WRITE_ONE = """
import sys
from compas_ccu.fabrication.dxf import new_document, save_document
doc = new_document({"CUT": 1, "LABEL": 3})
msp = doc.modelspace()
msp.add_lwpolyline([(0, 0), (10, 0), (10, 5)], dxfattribs={"layer": "CUT"})
msp.add_line((0, 0), (5, 5))
msp.add_text("P0", dxfattribs={"layer": "LABEL"})
msp.add_mtext("plate 0")
msp.add_circle((1, 1), 0.5)
msp.add_arc((2, 2), 1.0, 0, 90)
msp.add_point((3, 3))
msp.add_spline([(0, 0), (1, 2), (3, 1), (4, 4)])
msp.add_ellipse((5, 5), major_axis=(2, 0), ratio=0.5)
msp.add_hatch().paths.add_polyline_path([(0, 0), (1, 0), (1, 1)])
save_document(doc, sys.argv[1])
"""


@pytest.mark.slow  # three processes (~1.8 s)
def test_a_drawing_writes_the_same_bytes_in_every_process(tmp_path):
    """ezdxf lists the CLASS of every entity type in use in a set's order, which follows the
    process's string hashing: save_document fixes the order (the same file in every run)."""
    import os
    import subprocess
    import sys

    files = []
    for seed in range(4):
        path = tmp_path / f"seed{seed}.dxf"
        env = {**os.environ, "PYTHONHASHSEED": str(seed)}
        subprocess.run([sys.executable, "-c", _WRITE_ONE, str(path)], env=env, check=True)
        files.append(path.read_bytes())
    assert b"CLASSES" in files[0] and all(f == files[0] for f in files[1:])
