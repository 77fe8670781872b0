"""Closed plate solids and the OBJ / glTF writers (compas_ccu.fabrication.meshes)."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.fabrication.meshes import (
    layout_offsets,
    plate_solids,
    signed_volume,
    solid_mesh,
    write_gltf,
    write_obj,
)

trimesh = pytest.importorskip("trimesh")

THICKNESS = 0.008


@pytest.fixture(scope="module")
def data(vault_fab_data):
    return vault_fab_data


def plate_area(data, i):
    """Mid-surface area of plate i (array index) from its quads, m²."""
    q = data.deployed_mid[i][data.faces[i]]
    return 0.5 * np.linalg.norm(np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]), axis=1).sum()


def edge_use(triangles):
    """Directed edge -> count."""
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    keys, counts = np.unique(e, axis=0, return_counts=True)
    return {tuple(k): c for k, c in zip(keys.tolist(), counts.tolist())}


@pytest.mark.parametrize("state", ["deployed", "stack"])
def test_every_plate_solid_is_closed_outward_and_has_the_right_volume(data, state):
    n = data.segments
    solids = plate_solids(data, state=state)
    assert [name for name, _, _ in solids] == [f"plate_{pid}" for pid in data.plate_ids]
    for i, (_, vertices, triangles) in enumerate(solids):
        assert vertices.shape == (4 * n + 4, 3)
        assert triangles.shape == (8 * n + 4, 3)
        mesh = trimesh.Trimesh(vertices, triangles, process=False)
        assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume
        # independent check: every directed edge once, its reverse once
        use = edge_use(triangles)
        assert all(c == 1 and use.get((b, a)) == 1 for (a, b), c in use.items())
        area = plate_area(data, i)
        assert mesh.volume > 0.0
        assert mesh.volume == pytest.approx(area * THICKNESS, rel=0.01)
        assert signed_volume(vertices, triangles) == pytest.approx(mesh.volume, rel=1e-12)


def test_solid_mesh_orientation_does_not_depend_on_the_side_of_upper(data):
    lower, upper = data.solids[3]
    v1, t1 = solid_mesh(lower, upper)
    v2, t2 = solid_mesh(upper, lower)  # "upper" now on the other side of "lower"
    vol1, vol2 = signed_volume(v1, t1), signed_volume(v2, t2)
    assert vol1 > 0 and vol2 > 0
    assert vol1 == pytest.approx(vol2, rel=1e-12)
    # the two call orders give reversed windings of the same combinatorial mesh
    assert not np.array_equal(t1, t2)
    # a unit box: exact volume and outward normals
    box = np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0], [1, 2, 0]], float)
    for dz in (0.5, -0.5):
        v, t = solid_mesh(box, box + [0, 0, dz])
        assert signed_volume(v, t) == pytest.approx(1.0, abs=1e-15)
        m = trimesh.Trimesh(v, t, process=False)
        centre = v.mean(axis=0)
        out = np.einsum("ij,ij->i", m.face_normals, m.triangles_center - centre)
        assert (out > 0).all()
    with pytest.raises(ValueError):
        solid_mesh(box, box)
    with pytest.raises(ValueError):
        solid_mesh(box[:3], box[:3])


def parse_obj(path):
    """{object name: (vertices (v, 3), triangles (t, 3) local 0-based)} parsed by hand."""
    objects, order, allv = {}, [], []
    current = None
    for line in path.read_text().splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "o":
            current = parts[1]
            order.append(current)
            objects[current] = {"v": [], "f": []}
        elif parts[0] == "v":
            allv.append([float(x) for x in parts[1:4]])
            objects[current]["v"].append(len(allv) - 1)
        elif parts[0] == "f":
            objects[current]["f"].append([int(x) - 1 for x in parts[1:4]])
    allv = np.array(allv)
    out = {}
    for name in order:
        idx = np.array(objects[name]["v"])
        f = np.array(objects[name]["f"]) - idx[0]
        out[name] = (allv[idx], f)
    return order, out


@pytest.mark.parametrize("state", ["deployed", "stack"])
def test_obj_round_trip_one_object_per_plate_exact_coordinates(data, tmp_path, state):
    path = write_obj(data, tmp_path / f"vault_{state}.obj", state=state)
    order, objects = parse_obj(path)
    names = [f"plate_{pid}" for pid in data.plate_ids]
    assert order == names
    solids = data.solids if state == "deployed" else data.stack_solids
    worst = 0.0
    for i, name in enumerate(names):
        vertices, triangles = objects[name]
        expected = np.concatenate([solids[i, 0], solids[i, 1]])
        assert vertices.shape == expected.shape
        worst = max(worst, np.abs(vertices - expected).max())
        _, _, ref = plate_solids(data, state=state)[i]
        np.testing.assert_array_equal(triangles, ref)
    assert worst <= 1e-8  # %.17g: in fact exact
    # trimesh reads the same objects, closed
    scene = trimesh.load_scene(path, split_objects=True, group_material=False, process=False)
    assert sorted(scene.geometry) == sorted(names)
    for i, name in enumerate(names):
        g = scene.geometry[name]
        assert g.is_watertight and g.is_winding_consistent
        assert g.volume == pytest.approx(plate_area(data, i) * THICKNESS, rel=0.01)
        np.testing.assert_allclose(g.vertices, objects[name][0], rtol=0, atol=1e-8)


def test_glb_round_trip_nodes_and_float32_coordinates(data, tmp_path):
    path = write_gltf(data, tmp_path / "vault.glb")
    assert path.read_bytes()[:4] == b"glTF"
    scene = trimesh.load_scene(path, process=False)
    names = [f"plate_{pid}" for pid in data.plate_ids]
    p = len(names)
    assert len(scene.geometry) == p
    assert sorted(scene.graph.nodes_geometry) == sorted(names)
    size = np.abs(data.solids).max()
    for i, name in enumerate(names):
        transform, geometry = scene.graph.get(name)
        np.testing.assert_allclose(transform, np.eye(4), atol=0)
        g = scene.geometry[geometry]
        expected = np.concatenate([data.solids[i, 0], data.solids[i, 1]])
        # glTF is Y up: (x, y, z) = world (x, z, -y)
        world = g.vertices[:, [0, 2, 1]] * [1.0, -1.0, 1.0]
        err = np.abs(world - expected).max()
        assert err <= 1e-5 * size
        assert g.is_watertight and g.is_winding_consistent
        assert g.volume > 0  # still outward-oriented after the rotation
    # the vault stands upright in a Y-up viewer: its rise is along +y, its span along x
    points = np.concatenate([g.vertices for g in scene.geometry.values()])
    world = np.concatenate([data.solids.reshape(-1, 3)])
    assert np.ptp(points[:, 1]) == pytest.approx(np.ptp(world[:, 2]), rel=1e-6)
    assert np.ptp(points[:, 0]) == pytest.approx(np.ptp(world[:, 0]), rel=1e-6)
    assert points[:, 1].max() == pytest.approx(world[:, 2].max(), rel=1e-6)


def test_layout_offsets_do_not_overlap(data):
    gap = 0.1
    off = layout_offsets(data, gap=gap)
    boxes = [(data.flat[i] + off[i]) for i in range(len(data.plate_ids))]
    lo = np.array([b.min(axis=0) for b in boxes])
    hi = np.array([b.max(axis=0) for b in boxes])
    np.testing.assert_allclose(lo[:, 1], 0.0, atol=1e-15)
    np.testing.assert_allclose(lo[0, 0], 0.0, atol=1e-15)
    np.testing.assert_allclose(lo[1:, 0] - hi[:-1, 0], gap, atol=1e-12)
