"""Rhino 3DM writer (compas_ccu.fabrication.rhino), read back with rhino3dm."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.fabrication.meshes import solid_mesh
from compas_ccu.fabrication.rhino import LAYERS, read_3dm_summary, write_3dm

rhino3dm = pytest.importorskip("rhino3dm")

TOL = 1e-5  # 0.01 mm


@pytest.fixture(scope="module")
def data(vault_fab_data):
    return vault_fab_data


@pytest.fixture(scope="module")
def written(data, tmp_path_factory):
    path = write_3dm(data, tmp_path_factory.mktemp("rhino") / "vault.3dm")
    return path, rhino3dm.File3dm.Read(str(path))


def objects_on(model, layer_name):
    index = [lay.Index for lay in model.Layers if lay.Name == layer_name]
    assert len(index) == 1, layer_name
    return [o for o in model.Objects if o.Attributes.LayerIndex == index[0]]


def mesh_vertices(mesh):
    return np.array(
        [[q.X, q.Y, q.Z] for q in map(mesh.Vertices.Point3dAt, range(len(mesh.Vertices)))]
    )


def curve_points(curve):
    if isinstance(curve, rhino3dm.LineCurve):
        return np.array([[q.X, q.Y, q.Z] for q in (curve.PointAtStart, curve.PointAtEnd)])
    return np.array([[q.X, q.Y, q.Z] for q in map(curve.Point, range(curve.PointCount))])


def test_units_layers_counts_and_user_text(data, written):
    path, model = written
    p, n = len(data.plate_ids), data.segments
    assert model.Settings.ModelUnitSystem == rhino3dm.UnitSystem.Meters
    names = [lay.Name for lay in model.Layers]
    assert names == ["plates", "creases", "rulings", "solids", "cut patterns", "stack"]
    assert len({lay.Color for lay in model.Layers}) == 6
    summary = read_3dm_summary(path)
    assert summary["units"] == "Meters"
    counts = {k: v["count"] for k, v in summary["layers"].items()}
    assert counts == {
        "plates": p,
        "creases": len(data.creases),
        "rulings": (n - 1) * p,
        "solids": p,
        "cut patterns": p,
        "stack": p,
    }
    assert summary["layers"]["plates"]["names"] == [f"plate {pid}" for pid in data.plate_ids]
    assert sorted(summary["layers"]["creases"]["names"]) == sorted(
        f"crease {c['id']}" for c in data.creases
    )
    assert set(summary["layers"]["rulings"]["types"]) == {"LineCurve"}
    assert set(summary["layers"]["cut patterns"]["types"]) == {"PolylineCurve"}
    assert {k: v["color"] for k, v in summary["layers"].items()} == LAYERS
    text = summary["user_text"]
    assert text["design"] == data.name == "vault"
    assert float(text["alpha"]) == data.alpha == 30.0
    assert float(text["thickness"]) == data.thickness == 0.008
    assert text["material"] == "plywood"


def test_plate_meshes_equal_the_deployed_mid_surface(data, written):
    _, model = written
    worst = 0.0
    for obj in objects_on(model, "plates"):
        mesh = obj.Geometry
        i = data.index(int(obj.Attributes.Name.split()[1]))
        v = mesh_vertices(mesh)
        assert v.shape == data.deployed_mid[i].shape
        worst = max(worst, np.abs(v - data.deployed_mid[i]).max())
        assert len(mesh.Faces) == data.segments
        faces = np.array([mesh.Faces[k][:4] for k in range(len(mesh.Faces))])
        np.testing.assert_array_equal(faces, data.faces[i])
    assert worst <= TOL
    assert worst == 0.0  # double-precision vertices: no float32 rounding


def test_solids_and_stack_are_closed_and_exact(data, written):
    _, model = written
    for layer, solids in (("solids", data.solids), ("stack", data.stack_solids)):
        objs = objects_on(model, layer)
        assert len(objs) == len(data.plate_ids)
        for obj in objs:
            i = data.index(int(obj.Attributes.Name.split()[1]))
            mesh = obj.Geometry
            assert mesh.IsClosed
            v, t = solid_mesh(solids[i, 0], solids[i, 1])
            assert len(mesh.Faces) == len(t)
            np.testing.assert_allclose(mesh_vertices(mesh), v, rtol=0, atol=TOL)


def test_creases_and_rulings_equal_the_model(data, written):
    _, model = written
    n = data.segments
    creases = {c["id"]: c for c in data.creases}
    worst = 0.0
    for obj in objects_on(model, "creases"):
        c = creases[int(obj.Attributes.Name.split()[1])]
        pts = curve_points(obj.Geometry)
        # the hinge: where the facing faces of the two thick plates meet (both of them)
        where = obj.Attributes.GetUserString("hinge")
        assert float(obj.Attributes.GetUserString("hinge_gap")) <= 1e-9
        faces = [("lower", "upper").index(w) for w in where.split("-")]
        for pid, idx, face in zip(c["plates"], c["vertices"], faces):
            i = data.index(pid)
            worst = max(worst, np.abs(pts - data.solids[i, face][idx]).max())
            # half a thickness off each plate's mid-surface crease row
            off = np.linalg.norm(pts - data.deployed_mid[i][idx], axis=1)
            np.testing.assert_allclose(off, 0.5 * data.thickness, rtol=1e-3)
    assert worst <= TOL
    rulings = objects_on(model, "rulings")
    for obj in rulings:
        pid, j = obj.Attributes.Name.split()[1].split(".")
        i, j = data.index(int(pid)), int(j)
        assert 1 <= j <= n - 1
        np.testing.assert_allclose(
            curve_points(obj.Geometry), data.deployed_mid[i][[j, n + 1 + j]], rtol=0, atol=TOL
        )


def test_cut_patterns_are_the_outlines_side_by_side(data, written):
    _, model = written
    objs = objects_on(model, "cut patterns")
    boxes = []
    for obj in objs:
        i = data.index(int(obj.Attributes.Name.split()[1]))
        curve = obj.Geometry
        assert curve.IsClosed
        pts = curve_points(curve)
        np.testing.assert_array_equal(pts[:, 2], 0.0)
        off = np.array([float(obj.Attributes.GetUserString(k)) for k in ("offset_x", "offset_y")])
        outline = data.outline(i)
        assert len(pts) == len(outline) + 1
        np.testing.assert_allclose(pts[:-1, :2] - off, outline, rtol=0, atol=TOL)
        np.testing.assert_allclose(pts[-1], pts[0], atol=0)
        boxes.append((pts[:, 0].min(), pts[:, 0].max()))
    boxes.sort()
    for (_, hi), (lo, _) in zip(boxes[:-1], boxes[1:]):
        assert lo > hi + 0.05  # side by side, no overlap


def test_two_writes_give_the_same_objects_and_bytes_but_the_time_stamp(data, tmp_path):
    """Fixed ids (no random UUIDs): two writes of the vault to one path read back with the
    same ids, and their bytes differ at most in the revision history at the file's start
    (the minute written, which rhino3dm stamps)."""
    path = tmp_path / "vault.3dm"
    first = write_3dm(data, path).read_bytes()
    ids = [str(o.Attributes.Id) for o in rhino3dm.File3dm.Read(str(path)).Objects]
    second = write_3dm(data, path).read_bytes()
    model = rhino3dm.File3dm.Read(str(path))
    assert [str(o.Attributes.Id) for o in model.Objects] == ids
    assert len(set(ids)) == len(ids) > 100  # one id per object
    assert len({str(lay.Id) for lay in model.Layers}) == len(LAYERS)
    assert len(first) == len(second)
    differ = np.flatnonzero(np.frombuffer(first, np.uint8) != np.frombuffer(second, np.uint8))
    assert differ.size == 0 or differ.max() < 1024, differ[:10]
