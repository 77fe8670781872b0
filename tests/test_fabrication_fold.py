"""FOLD 1.2 writer (compas_ccu.fabrication.fold)."""

from __future__ import annotations

import json
from collections import Counter
from dataclasses import replace

import numpy as np
import pytest

from compas_ccu.catalog import catalog_path  # noqa: E402
from compas_ccu.fabrication import fabrication_data
from compas_ccu.fabrication.fold import crease_fold_angles, fold_document, read_fold, write_fold
from compas_ccu.fabrication.meshes import crease_line
from compas_ccu.model import load_model
from conftest import EXAMPLES

TOL = 1e-5  # 0.01 mm


@pytest.fixture(scope="module")
def data(vault_fab_data):
    return vault_fab_data


@pytest.fixture(scope="module")
def doc(data, tmp_path_factory):
    path = write_fold(data, tmp_path_factory.mktemp("fold") / "vault.fold")
    json.loads(path.read_text())  # plain JSON
    return read_fold(path)


def frames(doc):
    return [doc, *doc["file_frames"]]


def directed_edges(faces):
    out = Counter()
    for f in faces:
        for k in range(len(f)):
            out[(f[k], f[(k + 1) % len(f)])] += 1
    return out


def test_required_keys_and_metadata(doc, data):
    # edges_faces uses null for the missing right face of a boundary edge: FOLD 1.2
    assert doc["file_spec"] == 1.2
    assert any(None in ef for ef in doc["edges_faces"])
    assert doc["file_creator"] == "compas_ccu"
    assert doc["file_classes"] == ["singleModel"]
    assert len(doc["file_frames"]) == 2
    classes = [f["frame_classes"] for f in frames(doc)]
    assert classes == [["foldedForm"], ["creasePattern"], ["foldedForm"]]
    dims = [f["frame_attributes"][0] for f in frames(doc)]
    assert dims == ["3D", "2D", "3D"]
    for f in frames(doc):
        assert f["frame_unit"] == "m"
        assert f["frame_title"]
        for key in (
            "vertices_coords",
            "faces_vertices",
            "edges_vertices",
            "edges_assignment",
            "edges_foldAngle",
            "faces_ccu:plate",
            "edges_ccu:crease",
        ):
            assert key in f, key
        assert "manifold" in f["frame_attributes"] and "orientable" in f["frame_attributes"]
    assert doc["ccu:thickness"] == data.thickness
    assert doc["ccu:alpha"] == data.alpha


def test_counts_assignments_and_euler(doc, data):
    p, n = len(data.plate_ids), data.segments
    crease_segments = sum(len(c["vertices"][0]) - 1 for c in data.creases)
    crease_vertices = sum(len(c["vertices"][0]) for c in data.creases)
    assert crease_segments == 9 * 64
    for f in frames(doc):
        assert len(f["faces_vertices"]) == p * n
        assert all(len(q) == 4 and len(set(q)) == 4 for q in f["faces_vertices"])
        assert set(f["edges_assignment"]) <= {"B", "M", "V", "F", "U"}
        assert len(f["edges_assignment"]) == len(f["edges_vertices"]) == len(f["edges_foldAngle"])
        assert Counter(f["edges_ccu:kind"])["ruling"] == p * (n - 1)
        assert f["faces_ccu:plate"] == [pid for pid in data.plate_ids for _ in range(n)]
        edges = {tuple(sorted(e)) for e in f["edges_vertices"]}
        assert len(edges) == len(f["edges_vertices"])  # no duplicate edges
        # every face side is an edge, and edges_faces lists the faces using it
        sides = directed_edges(f["faces_vertices"])
        assert {tuple(sorted(k)) for k in sides} == edges
        for (u, v), (fl, fr) in zip(f["edges_vertices"], f["edges_faces"]):
            assert u in f["faces_vertices"][fl] and v in f["faces_vertices"][fl]
            assert (fr is None) == ((v, u) not in sides)

    for f in (doc, doc["file_frames"][1]):  # the two 3D frames: one sheet
        a = Counter(f["edges_assignment"])
        creases = np.array(f["edges_ccu:crease"])
        kinds = np.array(f["edges_ccu:kind"])
        assert (kinds == "crease").sum() == crease_segments == (creases >= 0).sum()
        # every crease and every (bent) ruling is folded
        assert a["M"] + a["V"] == crease_segments + p * (n - 1)
        assert a["U"] == a["F"] == 0
        # hinge vertices merged: one vertex per crease vertex pair
        V, E, F = (len(f[k]) for k in ("vertices_coords", "edges_vertices", "faces_vertices"))
        assert f["ccu:unmergedCreases"] == []
        assert V == p * (2 * n + 2) - crease_vertices == 715
        assert a["B"] == p * (2 * n + 2) - 2 * crease_segments == 148
        # the corrugated sheet is one disk: chi = 1
        assert V - E + F == 1
    # thick plates: the mid-surfaces do not meet, every crease was snapped onto its hinge
    for f, dist in ((doc, (0.5, 1.0)), (doc["file_frames"][1], (1.0 - 1e-9, 1.0 + 1e-9))):
        snapped = f["ccu:snappedCreases"]
        assert sorted(s["crease"] for s in snapped) == sorted(c["id"] for c in data.creases)
        for s in snapped:
            assert dist[0] * data.thickness < s["maxDistance"] <= dist[1] * data.thickness
            assert s["maxMove"] == pytest.approx(0.5 * data.thickness, rel=1e-3)
    # cut patterns: p separate disks, no crease edges
    cp = doc["file_frames"][0]
    V, E, F = (len(cp[k]) for k in ("vertices_coords", "edges_vertices", "faces_vertices"))
    assert V == p * (2 * n + 2) and V - E + F == p
    assert Counter(cp["edges_assignment"]) == {"B": p * (2 * n + 2), "F": p * (n - 1)}
    assert set(cp["edges_foldAngle"]) == {0.0}
    assert (np.array(cp["edges_ccu:crease"]) >= 0).sum() == 2 * crease_segments


def test_faces_are_consistently_oriented_in_3d(doc):
    for f in (doc, doc["file_frames"][1]):
        use = directed_edges(f["faces_vertices"])
        assert max(use.values()) == 1  # no edge run twice the same way
        # and every interior edge is run once each way
        interior = [
            tuple(e) for e, a in zip(f["edges_vertices"], f["edges_assignment"]) if a != "B"
        ]
        assert all(use[(u, v)] == 1 and use[(v, u)] == 1 for u, v in interior)
    # the mean normal points up (module rule)
    x = np.array(doc["vertices_coords"])
    q = x[np.array(doc["faces_vertices"])]
    normal = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]).sum(axis=0)
    assert normal[2] > 0


def test_vertices_and_faces_equal_the_model(doc, data):
    n = data.segments
    for frame, coords, state in (
        (doc, data.deployed_mid, "deployed"),
        (doc["file_frames"][1], np.asarray(data.stack_solids).mean(axis=1), "stack"),
    ):
        # expected position of every plate vertex: its mid-surface point, or the hinge line
        expected = np.array(coords, dtype=float)
        solids = data.solids if state == "deployed" else data.stack_solids
        for c in data.creases:
            line, gap, where = crease_line(data, c, state=state)
            assert gap <= 1e-9 and where != "mid-mid"  # the facing faces meet exactly
            fa = ("lower", "upper").index(where.split("-")[0])
            ia = c["vertices"][0]
            np.testing.assert_allclose(line, solids[data.index(c["plates"][0]), fa][ia], atol=1e-12)
            for pid, idx in zip(c["plates"], c["vertices"]):
                expected[data.index(pid), idx] = line
        x = np.array(frame["vertices_coords"])
        worst = 0.0
        for v, pairs in enumerate(frame["vertices_ccu:plateVertices"]):
            for pid, k in pairs:
                worst = max(worst, np.abs(x[v] - expected[data.index(pid), k]).max())
        fv = np.array(frame["faces_vertices"]).reshape(len(data.plate_ids), n, 4)
        for i in range(len(data.plate_ids)):
            quads = data.faces[i][:, ::-1] if frame["faces_ccu:flipped"][i * n] else data.faces[i]
            worst = max(worst, np.abs(x[fv[i]] - expected[i][quads]).max())
        assert worst <= TOL
        # only the hinge vertices moved, by half a thickness
        moved = np.linalg.norm(expected - coords, axis=-1)
        assert moved.max() == pytest.approx(0.5 * data.thickness, rel=1e-3)
        assert (moved > 0).sum() == sum(2 * len(c["vertices"][0]) for c in data.creases)
    cp = doc["file_frames"][0]
    x = np.array(cp["vertices_coords"])
    off = np.array(cp["ccu:offsets"])
    fv = np.array(cp["faces_vertices"]).reshape(len(data.plate_ids), n, 4)
    for i in range(len(data.plate_ids)):
        np.testing.assert_allclose(x[fv[i]] - off[i], data.flat[i][data.faces[i]], atol=TOL, rtol=0)
        # counter-clockwise as cut
        q = x[fv[i]]
        area = 0.5 * np.sum(
            q[..., 0] * np.roll(q[..., 1], -1, 1) - np.roll(q[..., 0], -1, 1) * q[..., 1], 1
        )
        assert (area > 0).all()


def signed_fold_angles(frame):
    """Fold angle of every edge recomputed from the file alone (FOLD sign convention)."""
    x = np.array(frame["vertices_coords"])
    faces = np.array(frame["faces_vertices"])
    q = x[faces]
    normals = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    owner = {}
    for fi, f in enumerate(faces.tolist()):
        for k in range(4):
            owner[(f[k], f[(k + 1) % 4])] = fi
    out = []
    for u, v in frame["edges_vertices"]:
        if (u, v) not in owner or (v, u) not in owner:
            out.append(0.0)
            continue
        nl, nr = normals[owner[(u, v)]], normals[owner[(v, u)]]
        e = (x[v] - x[u]) / np.linalg.norm(x[v] - x[u])
        # valley: the left face's normal turns towards the right face
        out.append(np.degrees(np.arctan2(-np.cross(nl, nr) @ e, nl @ nr)))
    return np.array(out)


def test_mountain_valley_and_fold_angles(doc, data):
    a = np.array(doc["edges_assignment"])
    angle = np.array(doc["edges_foldAngle"])
    crease = np.array(doc["edges_ccu:crease"])
    kind = np.array(doc["edges_ccu:kind"])
    # every edge's angle is the one of the file's own coordinates (creases and rulings)
    np.testing.assert_allclose(angle, signed_fold_angles(doc), rtol=0, atol=1e-9)
    # the sign of edges_foldAngle matches the assignment (FOLD spec)
    assert (angle[a == "V"] > 0).all() and (angle[a == "M"] < 0).all()
    assert (angle[np.isin(a, ["B", "F", "U"])] == 0).all()
    assert set(kind[a == "B"]) == {"outline"}
    # creases: the hinge vertices are snapped by t / 2, which tilts the hinge quads: the file's
    # angle is 116-117 degrees, the plates' own mid-surfaces give 180 - 2 alpha = 120
    creases = kind == "crease"
    assert 116.0 < np.abs(angle[creases]).min() and np.abs(angle[creases]).max() < 117.2
    own = np.array(doc["edges_ccu:plateFoldAngle"])
    # rulings: the smooth bending of the plates, a small discrete angle, on both sides of the file
    rulings = kind == "ruling"
    assert 1.2 < np.abs(angle[rulings]).min() and np.abs(angle[rulings]).max() < 1.3
    assert 1.2 < np.abs(own[rulings]).min() and np.abs(own[rulings]).max() < 1.3
    assert set(a[rulings]) <= {"M", "V"}
    design = crease_fold_angles(data)  # on the plates' own mid-surfaces, no snapping
    for c in data.creases:
        m = crease == c["id"]
        assert m.sum() == len(c["vertices"][0]) - 1
        assert len(set(a[m])) == 1
        np.testing.assert_allclose(np.abs(own[m]), 180.0 - c["fold_angle"], atol=0.05)
        np.testing.assert_allclose(np.abs(design[c["id"]]), 180.0 - c["fold_angle"], atol=0.05)
        np.testing.assert_allclose(np.abs(own[m]), np.abs(design[c["id"]]), atol=1e-9)
        assert np.sign(design[c["id"]]).tolist() == np.sign(angle[m]).tolist()
        assert np.sign(own[m]).tolist() == np.sign(angle[m]).tolist()
        # seen from above a vault, the synclastic (ridge) creases are mountains
        assert a[m][0] == {"synclastic": "M", "anticlastic": "V"}[c["kind"]]
    # the corrugation alternates along the chain of plates
    chain = sorted(data.creases, key=lambda c: min(c["plates"]))
    kinds = [a[crease == c["id"]][0] for c in chain]
    assert all(k1 != k2 for k1, k2 in zip(kinds[:-1], kinds[1:]))
    # the stack keeps every crease's assignment, folded nearly through 180 degrees (the snapped
    # hinge quads tilt by about t / 2 over a ruling), its own plates exactly through 180
    st = doc["file_frames"][1]
    sa, sc = np.array(st["edges_assignment"]), np.array(st["edges_ccu:crease"])
    sang = np.array(st["edges_foldAngle"])
    np.testing.assert_allclose(sang, signed_fold_angles(st), rtol=0, atol=1e-9)
    for c in data.creases:
        assert set(sa[sc == c["id"]]) == set(a[crease == c["id"]])
    assert 176.0 < np.abs(sang[sc >= 0]).min() and np.abs(sang[sc >= 0]).max() < 180.0
    sown = np.array(st["edges_ccu:plateFoldAngle"])
    np.testing.assert_array_equal(np.abs(sown[sc >= 0]), 180.0)
    assert (np.sign(sown[sc >= 0]) == np.sign(sang[sc >= 0])).all()
    # the vault's quads stay planar after the snap
    assert doc["ccu:maxFaceWarp"] < 1e-9 and st["ccu:maxFaceWarp"] < 1e-9


def face_warp(frame):
    x = np.array(frame["vertices_coords"])
    q = x[np.array(frame["faces_vertices"])]
    n1 = np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0])
    n2 = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 0])
    sin = np.linalg.norm(np.cross(n1, n2), axis=1)
    return np.degrees(np.arctan2(sin, np.einsum("ij,ij->i", n1, n2)))


@pytest.mark.parametrize("name", ["fig12a-asymmetric", "fig12c-funnel", "cone"])
def test_fold_angles_agree_with_the_coordinates_on_every_layout(name):
    """Inclined and radial layouts: alpha varies along the creases, so no single angle per
    crease describes them (the old per-crease 2 * mean(alpha) was off by up to 20 degrees)."""
    path = EXAMPLES / "cone.toml" if name == "cone" else catalog_path(name)
    data = fabrication_data(load_model(path))
    doc = fold_document(data)
    for frame in (doc, doc["file_frames"][1]):
        angle = np.array(frame["edges_foldAngle"])
        np.testing.assert_allclose(angle, signed_fold_angles(frame), rtol=0, atol=1e-9)
        a = np.array(frame["edges_assignment"])
        assert (angle[a == "V"] > 0).all() and (angle[a == "M"] < 0).all()
        assert (angle[np.isin(a, ["B", "F", "U"])] == 0).all()
        kind = np.array(frame["edges_ccu:kind"])
        assert set(a[kind == "crease"]) <= {"M", "V"}
        assert frame["ccu:maxFaceWarp"] == pytest.approx(face_warp(frame).max(), abs=1e-9)
    json.dumps(doc, allow_nan=False)


def test_strict_merge_keeps_thick_creases_apart(data):
    p, n = len(data.plate_ids), data.segments
    d = fold_document(data, hinges="merge")
    gaps = {u["crease"]: u["maxDistance"] for u in d["ccu:unmergedCreases"]}
    assert sorted(gaps) == sorted(c["id"] for c in data.creases)
    assert all(0.5 * data.thickness < g < data.thickness for g in gaps.values())
    assert d["ccu:snappedCreases"] == []
    assert len(d["vertices_coords"]) == p * (2 * n + 2)
    assert Counter(d["edges_assignment"])["B"] == p * (2 * n + 2)
    assert Counter(d["edges_ccu:kind"]) == {"outline": p * (2 * n + 2), "ruling": p * (n - 1)}
    x = np.array(d["vertices_coords"]).reshape(p, 2 * n + 2, 3)
    np.testing.assert_array_equal(x, data.deployed_mid)
    V, E, F = (len(d[k]) for k in ("vertices_coords", "edges_vertices", "faces_vertices"))
    assert V - E + F == p


def test_coinciding_creases_merge_without_snapping(data):
    mid = data.deployed_mid.copy()
    for c in data.creases:  # a zero-thickness model: b's crease row onto a's
        a, b = (data.index(pid) for pid in c["plates"])
        mid[b, c["vertices"][1]] = mid[a, c["vertices"][0]]
    for hinges in ("merge", "snap"):
        d = fold_document(replace(data, deployed_mid=mid), hinges=hinges)
        assert d["ccu:snappedCreases"] == [] and d["ccu:unmergedCreases"] == []
        assert len(d["vertices_coords"]) == 715
        x = np.array(d["vertices_coords"])
        for v, pairs in enumerate(d["vertices_ccu:plateVertices"]):
            for pid, k in pairs:
                np.testing.assert_array_equal(x[v], mid[data.index(pid), k])
        a = np.array(d["edges_assignment"])[np.array(d["edges_ccu:kind"]) == "crease"]
        assert len(a) == 576 and set(a) <= {"M", "V"}


def test_far_apart_plates_are_not_snapped(data):
    mid = data.deployed_mid.copy()
    mid[0] += [0.0, 0.0, 0.05]  # plate 0 lifted far off its hinge
    d = fold_document(replace(data, deployed_mid=mid))
    (gap,) = d["ccu:unmergedCreases"]
    assert gap["crease"] == next(c["id"] for c in data.creases if data.plate_ids[0] in c["plates"])
    assert gap["maxDistance"] > 2 * data.thickness
    n = data.segments
    assert len(d["vertices_coords"]) == 715 + (n + 1)
    assert Counter(d["edges_assignment"])["B"] == 148 + 2 * n
    # two disks now: the lifted plate and the rest of the sheet
    assert len(d["vertices_coords"]) - len(d["edges_vertices"]) + len(d["faces_vertices"]) == 2
    with pytest.raises(ValueError):
        fold_document(data, hinges="glue")


def test_read_fold_rejects_other_json(tmp_path):
    path = tmp_path / "x.fold"
    path.write_text("[1, 2]")
    with pytest.raises(ValueError):
        read_fold(path)
