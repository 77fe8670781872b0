"""Fit to geometry (docs/fit.md): reading targets and scans, the exact point-to-plates
distance, the as-built registration and the design fit, and their refusals."""

from __future__ import annotations

import json

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.errors import CCUError, DesignError, FitError, GeometryError, OptionError
from compas_ccu.fit import (
    PlateSurface,
    PointSet,
    closest_on_triangles,
    fit_design,
    parse_free,
    plate_triangles,
    read_points,
    register,
    sample_triangles,
)
from compas_ccu.fit.rigid import apply, matrix, rotation
from compas_ccu.model import CCUModel, load_model

VAULT = "examples/vault.toml"


@pytest.fixture(scope="module")
def vault():
    return load_model(VAULT)


def plate_points(model, alpha, count, *, seed=1, shift=None):
    """Points on the plates at alpha; ``shift = (row, metres)`` moves one plate along its
    mean normal first."""
    v = model.vertices([alpha])[0].copy()
    if shift is not None:
        row, dist = shift
        tri, plate = plate_triangles(v, model.faces)
        t = tri[plate == row]
        n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]).sum(0)
        v[row] += dist * n / np.linalg.norm(n)
    tri, _ = plate_triangles(v, model.faces)
    flat = np.arange(len(tri) * 3).reshape(-1, 3)
    return sample_triangles(tri.reshape(-1, 3), flat, count, seed=seed)


def scan_of(model, alpha, *, count, shift=None, seed=1):
    """A scan: plate points, 40 % missing (one end), 2 mm noise, 10 % outliers, moved."""
    rng = np.random.default_rng(seed)
    pts, _, _ = plate_points(model, alpha, int(count / 0.6), seed=seed, shift=shift)
    pts = pts[pts[:, 0] < np.quantile(pts[:, 0], 0.6)]
    pts = pts + rng.normal(scale=0.002, size=pts.shape)
    lo, hi = pts.min(0), pts.max(0)
    out = rng.uniform(lo - 0.1, hi + 0.1, (len(pts) // 9, 3))
    pose = matrix(rotation([0.3, -0.5, 1.2]), [5.0, -2.0, 1.5])
    return apply(pose, np.concatenate([pts, out])), pose


# -- reading ---------------------------------------------------------------------------------


def test_text_point_clouds_read_with_header_comments_and_units(tmp_path):
    path = tmp_path / "scan.csv"
    path.write_text("x,y,z,intensity\n# a comment\n1,2,3,9\n4;5;6;9\n")
    p = read_points(path, units="mm")
    assert p.kind == "points" and p.points.dtype == np.float64
    assert np.allclose(p.points, [[0.001, 0.002, 0.003], [0.004, 0.005, 0.006]])


def test_meshes_are_sampled_evenly_and_reproducibly(tmp_path):
    path = tmp_path / "square.obj"
    path.write_text("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n")
    a = read_points(path, count=2000, seed=4)
    b = read_points(path, count=2000, seed=4)
    assert a.kind == "mesh" and a.area == pytest.approx(2.0)
    assert np.array_equal(a.points, b.points) and a.points.shape == (2000, 3)
    assert abs(a.points[:, 0].mean() - 1.0) < 0.05 and np.allclose(np.abs(a.normals[:, 2]), 1.0)


def test_a_3dm_mesh_is_read_in_its_model_units(tmp_path):
    rhino3dm = pytest.importorskip("rhino3dm")
    mesh = rhino3dm.Mesh()
    for p in [(0, 0, 0), (2000, 0, 0), (2000, 1000, 0), (0, 1000, 0)]:
        mesh.Vertices.Add(*p)
    mesh.Faces.AddFace(0, 1, 2, 3)
    model = rhino3dm.File3dm()
    model.Settings.ModelUnitSystem = rhino3dm.UnitSystem.Millimeters
    model.Objects.AddMesh(mesh)
    model.Write(str(tmp_path / "square.3dm"), 7)
    p = read_points(tmp_path / "square.3dm", count=500)
    assert p.kind == "mesh" and p.area == pytest.approx(2.0)
    assert p.points.max(axis=0)[:2] == pytest.approx([2.0, 1.0], abs=0.02)


@pytest.mark.parametrize(
    ("name", "text", "words"),
    [
        ("scan.foo", "1 2 3\n", "unknown format '.foo'"),
        ("scan.xyz", "", "no points"),
        ("scan.xyz", "# only a comment\n", "no points"),
        ("scan.xyz", "1 2 3\n4 nan 6\n", "non-finite coordinate (first: point 1"),
        ("scan.xyz", "1 2\n", "not x y z rows"),
        ("missing.ply", None, "no such file"),
    ],
)
def test_bad_files_are_refused_in_one_line(tmp_path, name, text, words):
    path = tmp_path / name
    if text is not None:
        path.write_text(text)
    with pytest.raises(GeometryError) as info:
        read_points(path)
    assert words in str(info.value) and "\n" not in str(info.value)


# -- distance --------------------------------------------------------------------------------


def test_plate_distance_is_exact_against_brute_force(vault):
    v = vault.vertices([27.0])[0]
    surf = PlateSurface.from_vertices(v, vault.faces, spacing=vault.size / 80)
    rng = np.random.default_rng(2)
    lo, hi = v.reshape(-1, 3).min(0), v.reshape(-1, 3).max(0)
    p = rng.uniform(lo - 0.05, hi + 0.05, (400, 3))
    d = surf.query(p)
    brute = np.linalg.norm(
        closest_on_triangles(p[:, None], surf.triangles[None]) - p[:, None], axis=-1
    )
    err = np.abs(d.distance - brute.min(axis=1))
    assert err[d.exact].max() < 1e-12 and err.max() <= surf.cover
    assert d.exact[d.distance < 0.2].all()  # exact near the plates (docs/fit.md)
    assert np.allclose(np.abs(d.signed), d.distance)
    assert np.allclose(brute[np.arange(len(p)), d.triangle][d.exact], d.distance[d.exact])


# -- free keys -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "error", "words"),
    [
        ("crease.height=0.5:1.5", DesignError, "crease.height: not a design key"),
        ("crease.rise", OptionError, "needs bounds"),
        ("crease.rise=0.5", OptionError, "needs bounds"),
        ("crease.rise=1.5:0.5", OptionError, "lower < upper"),
        ("layout.plates=2:12", DesignError, "must be a real number"),
        ("crease.rise=0.5:1.5,crease.rise=0.6:1.2", OptionError, "given twice"),
    ],
)
def test_bad_free_keys_are_refused(text, error, words):
    with pytest.raises(error) as info:
        parse_free(text)
    assert words in str(info.value)


def test_a_target_far_larger_than_any_design_is_refused():
    base = load_design(VAULT)
    pts, normals, _ = plate_points(CCUModel(base), 30.0, 500)
    target = PointSet(pts * 20.0, normals, "big", "mesh")
    with pytest.raises(FitError, match="far larger than any design of vault"):
        fit_design(base, target, parse_free("crease.rise=0.5:1.5"))


def test_a_base_value_outside_its_bounds_is_refused():
    base = load_design(VAULT)
    pts, normals, _ = plate_points(CCUModel(base), 30.0, 500)
    with pytest.raises(OptionError, match="base value 1 lies outside the bounds 1.2:1.5"):
        fit_design(base, PointSet(pts, normals, "t", "mesh"), parse_free("crease.rise=1.2:1.5"))


def test_the_cli_refuses_a_free_key_without_bounds_and_writes_nothing(tmp_path, capsys):
    target = tmp_path / "target.xyz"
    np.savetxt(target, plate_points(load_model(VAULT), 30.0, 300)[0])
    out = tmp_path / "out"
    code = main(["fit", str(target), "--base", VAULT, "--out", str(out), "--free", "crease.rise"])
    assert code == 2 and not out.exists()
    assert "crease.rise: a free key needs bounds" in capsys.readouterr().err


def test_a_fit_that_does_not_converge_is_an_error():
    base = load_design(VAULT)
    doc = base.metric_document()
    doc["crease"]["rise"] = 1.1
    pts, normals, _ = plate_points(CCUModel(Design(doc)), 30.0, 800)
    with pytest.raises(FitError, match="did not converge within 2 evaluations"):
        fit_design(
            base,
            PointSet(pts, normals, "t", "mesh"),
            parse_free("crease.rise=0.5:1.5"),
            points=300,
            max_evaluations=2,
        )


# -- recovery (slow) -------------------------------------------------------------------------


@pytest.mark.slow
def test_a_scan_is_registered_and_a_slipped_plate_found(vault):
    scan, pose = scan_of(vault, 27.0, count=6000, shift=(4, 0.02))
    r = register(vault, scan, per_plate=True)
    assert abs(r.alpha - 27.0) < 0.2
    # the vault is symmetric under a half turn about the vertical axis through its crown
    # (plate i <-> plate 9 - i): the slipped plate is 4, or 5 in the turned pose
    assert r.slipped in ([4], [5])
    slipped = next(p for p in r.plates if p.id == r.slipped[0])
    assert 0.015 < slipped.slip < 0.025
    # the plates away from the slipped one and its neighbours: at the noise level
    assert all(p.rms < 0.0032 for p in r.plates if p.id not in (3, 4, 5, 6))
    assert 0.5 < r.coverage < 0.7 and r.coverage_ok
    assert 0.0015 < r.noise < 0.0025


@pytest.mark.slow
def test_the_asbuilt_command_writes_its_record_and_exits_3_on_little_coverage(tmp_path, vault):
    scan, _ = scan_of(vault, 27.0, count=4000)
    path = tmp_path / "scan.xyz"
    np.savetxt(path, scan)
    out = tmp_path / "out"
    assert main(["asbuilt", str(path), "--design", VAULT, "--out", str(out), "--quiet"]) == 0
    record = json.loads((out / "asbuilt.json").read_text())
    assert record["format"] == "ccu.asbuilt" and record["version"] == 1
    assert abs(record["alpha"] - 27.0) < 0.2 and record["rms"] < 0.003
    assert len(record["plates"]) == 10 and np.array(record["pose"]).shape == (4, 4)
    assert set(record["key_figures"]) == {"as_built", "design"}
    assert (out / "asbuilt.png").exists()
    pts, _, _ = plate_points(vault, 27.0, 3000)
    few = pts[pts[:, 0] < np.quantile(pts[:, 0], 0.12)]
    np.savetxt(path, few)
    assert (
        main(["asbuilt", str(path), "--design", VAULT, "--out", str(tmp_path / "b"), "--quiet"])
        == 3
    )


@pytest.mark.slow
def test_a_scan_of_something_else_fits_no_state(vault):
    rng = np.random.default_rng(5)
    with pytest.raises(FitError, match="fits no state of vault"):
        register(vault, rng.uniform(-5, 5, (600, 3)), sample=300, alpha_grid=3)


@pytest.mark.slow
def test_the_fit_recovers_the_rise(tmp_path):
    base = load_design(VAULT)
    doc = base.metric_document()
    doc["crease"]["rise"] = 1.1
    pts, _, _ = plate_points(CCUModel(Design(doc)), 30.0, 5000, seed=3)
    target = tmp_path / "target.xyz"
    np.savetxt(target, pts)
    out = tmp_path / "out"
    args = ["fit", str(target), "--base", VAULT, "--out", str(out), "--quiet"]
    assert main([*args, "--free", "crease.rise=0.5:1.5", "--points", "1500"]) == 0
    record = json.loads((out / "fit.json").read_text())
    assert record["parameters"]["crease.rise"] == pytest.approx(1.1, rel=0.01)
    assert record["rms"] < 0.003 and record["hausdorff"] < 0.1
    fitted = load_design(out / "vault-fit.toml")
    assert fitted.crease.rise == pytest.approx(record["parameters"]["crease.rise"])
    assert (out / "fit.png").exists()


def test_errors_are_ccu_errors():
    assert issubclass(FitError, CCUError)


def barrel_vault(count, *, span=2.5, rise=1.0, length=1.2, seed=0):
    """The analytic barrel vault of benchmarks/fit_targets.py: the circular cylinder through a
    ``span`` chord with ``rise``, axis along y, ``count`` points evenly over its area."""
    radius = (span**2 / 4.0 + rise**2) / (2.0 * rise)
    half = np.arcsin(span / 2.0 / radius)
    rng = np.random.default_rng(seed)
    theta = rng.uniform(-half, half, count)
    y = rng.uniform(-length / 2.0, length / 2.0, count)
    normals = np.column_stack([np.sin(theta), np.zeros(count), np.cos(theta)])
    points = np.column_stack([radius * np.sin(theta), y, rise - radius + radius * np.cos(theta)])
    return PointSet(points, normals, "barrel vault", "mesh")


@pytest.mark.slow
def test_more_plates_come_closer_to_a_barrel_vault():
    """No CCU design matches a smooth cylinder; at the vault's corrugation (alpha held at 30
    deg) the fit converges and 8 plates come closer than 4 (measured: RMS 110 mm with 4, 46 mm
    with 8 on these 5,000 points; docs/fit.md has the table for 4 ... 14 plates)."""
    target = barrel_vault(5000)
    rms = []
    for plates in (4, 8):
        doc = load_design(VAULT).metric_document()
        spacing = 1.2 / plates
        doc["layout"].update(plates=plates, spacing=spacing)
        free = {
            "crease.span": [2.0, 3.0],
            "crease.rise": [0.7, 1.3],
            "layout.spacing": [0.6 * spacing, 1.4 * spacing],
            "deployment.alpha": [29.995, 30.005],
        }
        r = fit_design(Design(doc), target, free, points=1500, max_evaluations=200)
        assert r.status > 0  # converged (FitError otherwise)
        assert np.isfinite([r.rms, r.max, r.hausdorff]).all()
        assert r.rms <= r.max <= r.hausdorff < 0.5
        rms.append(r.rms)
    assert rms[1] < 0.6 * rms[0]
