"""FE validation of the deployment: meshes, the cone pair against the exact cone, the engines'
agreement, non-convergence, the structural checks and ``ccu validate`` / ``ccu info``."""

from __future__ import annotations

import ast
import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.design import load_design
from compas_ccu.fea.comparison import compare
from compas_ccu.fea.mesh import mesh_model
from compas_ccu.fea.problem import ConvergenceError, FEError
from compas_ccu.fea.record import agreement
from compas_ccu.fea.stresses import principal
from compas_ccu.fea.validation import FESettings, validate
from compas_ccu.model import CCUModel
from compas_ccu.thickness import ThickModel

CONE = "tests/data/cone8.toml"  # 8 mm, no [loads]: the figures below were measured on it
FAST = {"element_size": 0.1, "steps": 4}


@pytest.fixture(scope="module")
def cone():
    return CCUModel(load_design(CONE))


@pytest.fixture(scope="module")
def cone_runs(cone):
    """The cone pair deployed to 40 deg by both engines (no checks)."""
    return {e: validate(cone, engine=e, checks=False, **FAST) for e in ("kratos", "opensees")}


def circumcentre(a, b, c):
    """Centre of the circle through three points in space."""
    u, w = b - a, c - a
    n = np.cross(u, w)
    return a + (np.dot(u, u) * np.cross(w, n) + np.dot(w, w) * np.cross(n, u)) / (2 * n @ n)


# -- meshes -------------------------------------------------------------------------------------
def test_mesh_reproduces_the_plates_exactly_at_every_state(cone):
    mesh = mesh_model(cone, element_size=0.05)
    n = cone.segments
    assert mesh.along == 2 and list(mesh.across) == [8, 8]
    assert mesh.elements.shape == (2 * n * 2 * 8, 4)
    # the geometry-only path gives exactly the structures' vertices
    many = cone.vertices([0.0, 17.0, 40.0])
    for k, alpha in enumerate((0.0, 17.0, 40.0)):
        s = cone.deploy(alpha)
        assert np.array_equal(many[k], s.deployed)
        x = mesh.kinematic(s.deployed)
        # nodes on the model's vertices sit exactly on them; hinge nodes coincide
        corners = (mesh.node_uv[:, 0] == 0) & np.isin(mesh.node_uv[:, 1], (0.0, 1.0))
        p, j = mesh.node_plate[corners], mesh.node_quad[corners]
        far = mesh.node_uv[corners, 1] == 1.0
        v = s.deployed[p, np.where(far, n + 1 + j, j)]
        assert np.abs(x[corners] - v).max() <= 1e-15 * cone.size
        gap = np.linalg.norm(x[mesh.ties[:, 0]] - x[mesh.ties[:, 1]], axis=1)
        assert gap.max() <= 1e-12 * cone.size
    # elements are isometric to the reference (the flat stack): edge lengths kept
    x = mesh.kinematic(cone.deploy(40.0).deployed)
    q0, q1 = mesh.nodes[mesh.elements], x[mesh.elements]
    e0 = np.linalg.norm(q0 - np.roll(q0, 1, axis=1), axis=2)
    e1 = np.linalg.norm(q1 - np.roll(q1, 1, axis=1), axis=2)
    assert np.abs(e1 - e0).max() <= 1e-12
    assert np.allclose(np.linalg.norm(mesh.directions, axis=1), 1.0)
    assert len(mesh.supports) == 2 * 2 * (8 + 1)


def test_mesh_refuses_a_bad_element_size(cone):
    for bad in (0.0, -0.1, "a"):
        with pytest.raises(FEError, match="element_size"):
            mesh_model(cone, element_size=bad)
    with pytest.raises(FEError, match="2 million nodes"):
        mesh_model(cone, element_size=1e-4)


# -- the cone pair --------------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("engine", ["kratos", "opensees"])
def test_cone_pair_deploys_within_0_3_percent_of_span_of_the_exact_cone(cone_runs, engine):
    v = cone_runs[engine]
    s = v.summary()
    assert s["converged"] and s["alpha"] == 40.0
    # the kinematic model of this design is the exact cone: crease radius R cos(alpha)
    crease = v.kinematic[-1][v.mesh.ties[:, 0]]
    centre = circumcentre(crease[0], crease[len(crease) // 2], crease[-1])
    radius = np.linalg.norm(crease - centre, axis=1)
    np.testing.assert_allclose(radius, 2.0 * np.cos(np.radians(40.0)), rtol=1e-12)
    assert 0.0 < s["deviation"]["max_percent"] <= 0.3
    assert s["deviation"]["alignment"] == "none"  # the supports hold both in the same frame
    assert s["deviation"]["mean_percent"] < 0.1
    # the FE crease radius follows the cone to 0.3 % of the span
    fe = v.positions[-1][v.mesh.ties[:, 0]]
    fe_centre = circumcentre(fe[0], fe[len(fe) // 2], fe[-1])
    fe_radius = np.linalg.norm(fe - fe_centre, axis=1)
    assert np.abs(fe_radius - radius).max() <= 0.003 * s["span"]
    # active bending: about 20 MPa for 8 mm plywood at this opening, membrane much smaller
    assert 15.0 < s["stresses"]["max_bending_MPa"] < 25.0
    assert s["stresses"]["max_membrane_MPa"] < 0.2 * s["stresses"]["max_bending_MPa"]
    # deployment stores energy: the work of the supports grows with alpha
    work = np.asarray(s["load_path"]["work_J"])
    assert work[0] == 0.0 and np.all(np.diff(work) > 0.0)


@pytest.mark.slow
def test_the_kinematic_bending_stress_is_never_below_the_fe(cone_runs):
    """Plate stress Q11 kappa t/2 of the kinematic check against the FE's peak bending stress of
    the deployed state (no loads): at or above it, within 10 % (docs/thickness.md; measured
    cone +2.7 %, vault +8.9 % at 0.2 m); the beam formula E kappa t/2 was below it."""
    vault = CCUModel(load_design("examples/overbent.toml"))  # the vault in 8 mm
    runs = {
        "cone": (cone_runs["kratos"], CCUModel(load_design(CONE))),
        "vault": (validate(vault, engine="kratos", checks=False, element_size=0.2, steps=2), vault),
    }
    for name, (run, model) in runs.items():
        fe = run.summary()["stresses"]["max_bending_MPa"]
        thick = ThickModel(model)
        kappa = np.abs(thick.bending([model.alpha_design]).curvature).max()
        plate = kappa * float(thick.material.plate_modulus(0.0)) * thick.thickness / 2e6
        beam = kappa * thick.material.E1 * thick.thickness / 2e6
        assert fe <= plate <= 1.10 * fe, (name, fe, plate)
        assert beam < fe, (name, fe, beam)


@pytest.mark.slow
def test_engines_agree_on_the_cone_pair_to_three_digits(cone_runs):
    a = agreement(cone_runs["kratos"], cone_runs["opensees"])
    assert a.engines == ["kratos", "opensees"]
    assert a.position_max_percent <= 1e-2  # 1e-4 of the span (measured 2.5e-5)
    assert a.moment_max_relative <= 1e-3  # 3 digits (measured 3e-4)
    assert list(a.to_dict()) == [
        "engines", "position_max_m", "position_max_percent", "deviation_max_percent",
        "deviation_max_relative", "moment_max_Nm_per_m", "moment_max_relative", "wall_time_s",
    ]  # fmt: skip
    ka, ko = (cone_runs[e] for e in ("kratos", "opensees"))
    ma = np.abs(principal(ka.result.forces[-1][:, 3:])).max(axis=1)
    mo = np.abs(principal(ko.result.forces[-1][:, 3:])).max(axis=1)
    # element by element: the elements touching the prescribed end rulings (a singular
    # boundary layer) differ by up to 12 %; elsewhere within 2 % of the peak (median 6e-4)
    mesh = ka.mesh
    away = ~np.isin(mesh.elements, mesh.supports).any(axis=1)
    assert np.abs(ma - mo)[away].max() <= 0.025 * ma.max()
    assert np.median(np.abs(ma - mo)) <= 1e-3 * ma.max()


@pytest.mark.slow
def test_hinges_of_the_cone_pair_carry_a_line_force_and_balance(cone_runs):
    v = cone_runs["kratos"]
    hinges = v.hinge_forces()
    assert len(hinges) == 1 and hinges[0]["max_N_per_m"] > 0.0
    # the resultant through the hinge agrees between the engines within 10 % (measured 7 %):
    # the crease-end nodes are prescribed in both plates, and how much of the concentrated
    # force there the next tie takes depends on the element formulation
    ko = cone_runs["opensees"].hinge_forces()[0]["resultant_N"]
    np.testing.assert_allclose(hinges[0]["resultant_N"], ko, rtol=0.1, atol=1e-2)


# -- failures -------------------------------------------------------------------------------------
@pytest.mark.slow
def test_non_convergence_is_reported_with_step_and_residual(cone):
    with pytest.raises(ConvergenceError) as info:
        validate(cone, engine="kratos", max_iterations=1, max_cuts=0, checks=False, **FAST)
    err = info.value
    assert err.step == 1 and np.isfinite(err.residual) and err.residual > 0.0
    assert "step 1" in str(err) and "alpha = 10 deg" in str(err)
    assert err.result is not None and err.result.steps == 0 and not err.result.converged


def test_bad_options_are_refused_with_the_value(cone):
    with pytest.raises(FEError, match="unknown FE option.*'elemnt_size'"):
        validate(cone, elemnt_size=0.1)
    with pytest.raises(FEError, match="mode must be one of"):
        FESettings(mode="push")
    with pytest.raises(FEError, match="control must be one of"):
        FESettings(control="all")
    with pytest.raises(FEError, match="thickness must be > 0"):
        FESettings(thickness=-0.008)
    with pytest.raises(ValueError, match="unknown material 'oak'"):
        FESettings(material="oak")
    with pytest.raises(FEError, match="unknown FE engine 'abaqus'"):
        validate(cone, engine="abaqus", **FAST)
    with pytest.raises(ValueError, match="self-intersection at alpha = 89 deg"):
        validate(cone, alpha=89.0, **FAST)


def test_comparison_names_its_alignment_and_the_rigid_one_removes_a_rigid_motion():
    rng = np.random.default_rng(1)
    kinematic = rng.normal(size=(2, 30, 3))
    c, s = np.cos(0.3), np.sin(0.3)
    turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    moved = kinematic @ turn.T + [0.5, -0.2, 0.1]
    history = SimpleNamespace(positions=moved, kinematic=kinematic, spans=np.array([2.0, 2.0]))
    plain, rigid = compare(history), compare(history, alignment="rigid")
    assert plain.alignment == "none" and rigid.alignment == "rigid"
    assert plain.deviation.min() > 0.1 and rigid.deviation.max() < 1e-12
    np.testing.assert_allclose(plain.deviation_percent(), 50.0 * plain.deviation)
    with pytest.raises(FEError, match="alignment must be one of"):
        compare(history, alignment="affine")


def test_actuation_refuses_a_prebend_beyond_the_target(cone):
    with pytest.raises(FEError, match="prebend must lie between 0 and the target 40 deg"):
        validate(cone, mode="actuation", prebend=45.0, **FAST)


def test_fea_modules_form_layers_and_only_output_draws():
    """No import of compas_ccu inside a function, none of a private name; only output draws."""
    root = Path(__file__).resolve().parents[1] / "src" / "compas_ccu" / "fea"
    for path in sorted(root.rglob("*.py")):
        tree = ast.parse(path.read_text())
        top = {id(node) for node in tree.body}
        for node in ast.walk(tree):
            module = getattr(node, "module", None) or ""
            if not isinstance(node, ast.ImportFrom) or not module.startswith("compas_ccu"):
                continue
            assert not any(a.name.startswith("_") for a in node.names), (path.name, module)
            assert id(node) in top, (path.name, module)
            if module.startswith("compas_ccu.viz"):
                assert path.name == "output.py", path.name


# -- checks ---------------------------------------------------------------------------------------
@pytest.mark.slow
def test_structural_checks_on_the_deployed_state(cone):
    v = validate(cone, engine="opensees", element_size=0.2, steps=3, area_load=1500.0)
    c = v.summary()["checks"]
    weight = 600.0 * 9.81 * 0.008
    assert c["load"]["self_weight_N_per_m2"] == pytest.approx(weight)
    # the supports carry the whole load: (self-weight + 1.5 kN/m2) x plate area, vertically
    area = v.mesh.element_areas().sum()
    total = np.asarray(c["reaction_total_N"])
    assert total[2] == pytest.approx((weight + 1500.0) * area, rel=1e-6)
    assert abs(total[0]) < 1e-6 * total[2] and abs(total[1]) < 1e-6 * total[2]
    assert 0.0 < c["deflection_max_m"] and c["deflection_limit_m"] == pytest.approx(
        v.spans[2] / 500.0
    )
    assert c["deflection_ok"] == (c["deflection_max_m"] <= c["deflection_limit_m"])
    # the design strength of the default basis (EC5 SC1 permanent): 0.6 x 30 / 1.2 = 15 MPa
    assert c["strength_MPa"] == pytest.approx(15.0, rel=1e-15)
    assert c["strength_characteristic_MPa"] == 30.0
    assert c["basis"]["basis"] == "EC5 SC1 permanent" and c["basis"]["k_mod"] == 0.6
    # per case: the design strength of its load duration (self-weight permanent, the area
    # load short-term: k_mod 0.9 -> 22.5 MPa), the ULS stress over it
    by = {k["name"]: k for k in c["cases"]}
    assert list(by) == ["self-weight", "area-load"]
    assert by["area-load"]["strength_MPa"] == pytest.approx(22.5, rel=1e-15)
    for k in c["cases"]:
        assert 0.0 < k["utilisation_max_characteristic"] < 2.0
        assert k["utilisation_max"] == pytest.approx(
            30.0 / k["strength_MPa"] * k["utilisation_max_characteristic"], rel=1e-12
        )
    assert c["utilisation_max"] == max(k["utilisation_max"] for k in c["cases"])
    assert c["buckling_factor"] is None and "kratos" in c["buckling_note"]


@pytest.mark.slow
def test_buckling_factor_of_the_loaded_cone_pair_scales_with_the_load(cone):
    """Kratos: the factor falls roughly in proportion when the area load grows fivefold."""
    light = validate(cone, engine="kratos", area_load=1500.0, **FAST).summary()["checks"]
    heavy = validate(cone, engine="kratos", area_load=7500.0, **FAST).summary()["checks"]
    assert 3.0 < light["buckling_factor_mean"] < 20.0  # measured 6.64
    assert 1.0 < heavy["buckling_factor_mean"] < light["buckling_factor_mean"] / 3.0  # 1.46
    # the design factor (EC5 2.4.1, E_mean / gamma_M and creep): the same reduction for both
    # loads (measured 3.08 and 0.68), so the heavier load fails where the mean factor passes
    for c in (light, heavy):
        assert c["buckling_factor"] < c["buckling_factor_mean"] / 1.2
    assert light["buckling_factor"] / light["buckling_factor_mean"] == pytest.approx(
        heavy["buckling_factor"] / heavy["buckling_factor_mean"], rel=1e-12
    )
    assert heavy["buckling_factor"] < 1.0 < light["buckling_factor"]
    # the buckling load itself (factor x total design load, 1.35 G + 1.5 Q) agrees within
    # 15 % (pre-buckling nonlinearity; measured 15.4 and 16.5 kN/m2); near the limit point
    # (15 kN/m2 characteristic, factor 1.06) the linearised factor overshoots by 55 %
    w = 600.0 * 9.81 * 0.008
    first = light["buckling_factor_mean"] * (1.5 * 1500.0 + 1.35 * w)
    second = heavy["buckling_factor_mean"] * (1.5 * 7500.0 + 1.35 * w)
    assert abs(first - second) <= 0.15 * first
    assert heavy["deflection_max_m"] > 4.0 * light["deflection_max_m"]


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["kratos", "opensees"])
def test_actuation_reaches_the_target_with_crease_end_actuators(cone, engine):
    v = validate(cone, engine=engine, mode="actuation", element_size=0.1, steps=8)
    s = v.summary()
    act = s["actuation"]
    assert act["prebend_deg"] == 10.0 and act["feet"] == 4
    # the feet reach their targets; the structure reaches the target angle
    assert act["foot_miss_m"][-1] <= 3e-3
    assert abs(act["reached_alpha"][-1] - 40.0) <= 0.1
    assert np.allclose(act["reached_alpha"][:2], [5.0, 10.0], atol=0.01)  # pre-bending
    # no clamps at the plate ends: the shape relaxes more than under displacement control but
    # stays within 0.5 % of the span of the kinematic cone (measured 0.41 %)
    assert 0.2 < s["deviation"]["max_percent"] <= 0.5
    assert s["deviation"]["alignment"] == "rigid" and v.alignment == "rigid"
    # the actuators push along the crease and pull the plates apart, more as alpha grows
    force = np.asarray(act["force_max_N"])
    assert force[1] == 0.0 and np.all(np.diff(force[2:]) > 0.0)
    assert act["force_perpendicular_max_N"][-1] > act["force_crease_aligned_max_N"][-1] > 0.0
    assert s["checks"] is None  # the checks need the supports: displacement mode only


# -- command line ---------------------------------------------------------------------------------
@pytest.mark.slow
def test_ccu_validate_writes_results_and_info_shows_them(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("CCU_CACHE_DIR", str(tmp_path / "cache"))
    design = tmp_path / "cone.toml"
    design.write_text(open(CONE).read())
    assert main(["info", str(design)]) == 0
    assert "FE validation     none yet" in capsys.readouterr().out
    out = tmp_path / "fe"
    code = main(
        ["validate", str(design), "--out", str(out), "--engine", "opensees"]
        + ["--element-size", "0.2", "--steps", "3", "--allow-exceeded"]
    )
    assert code == 0
    said, told = capsys.readouterr()
    # the 8 mm cone is the one that fails its self-weight ULS check (deployment bending
    # of 8 mm plates, the reason the shipped cone is 5 mm): written, named, allowed
    assert "FE self-weight ULS utilisation" in told
    assert "deviation from the kinematic model at alpha = 40 deg" in said
    for name in ("validation.json", "fe_results.npz", "fe_stress.png", "fe_deviation.png"):
        assert (out / name).stat().st_size > 1000
    summary = json.loads((out / "validation.json").read_text())
    assert summary["format"] == "ccu.validation" and summary["engine"] == "opensees"
    assert summary["deviation"]["max_percent"] < 1.0
    data = np.load(out / "fe_results.npz")
    assert data["positions"].shape[1:] == data["nodes"].shape
    assert main(["info", str(design)]) == 0
    info = capsys.readouterr().out
    assert "FE validation     opensees displacement with 8 mm plywood, alpha 40 deg" in info
    assert f"{summary['deviation']['max_percent']:.3f} %" in info
    # a changed design shows no stale validation
    design.write_text(open(CONE).read().replace("alpha = 40.0", "alpha = 35.0"))
    assert main(["info", str(design)]) == 0
    assert "none yet" in capsys.readouterr().out


def test_ccu_validate_reports_a_bad_option(tmp_path, capsys):
    code = main(["validate", CONE, "--out", str(tmp_path), "--element-size", "-1"])
    assert code == 2
    assert "--element-size must be > 0, got -1.0" in capsys.readouterr().err


@pytest.mark.slow
def test_orthotropic_plywood_runs_on_opensees_and_is_refused_by_kratos(cone):
    """Birch plywood with E1 = 11 GPa along the crease, E2 = 6 GPa across (OpenSees only)."""
    options = dict(element_size=0.2, steps=2, checks=False, material="birch-plywood")
    iso = validate(cone, engine="opensees", **options)
    ortho = validate(cone, engine="opensees", orthotropic=True, **options)
    settings = ortho.summary()["settings"]
    assert settings["orthotropic"] and settings["material"]["E1"] == 11.0e9
    # the cone bends across its rulings, i.e. along the crease: the stiffer E1 carries it, so
    # the typical moment is E1 / E_mean = 11 / 8.5 = 1.29 times the isotropic model's (measured
    # 1.31 on the median element; 1.36 at the peak, near the supports)
    m_iso, m_ortho = (
        np.abs(principal(v.result.forces[-1][:, 3:])).max(axis=1) for v in (iso, ortho)
    )
    assert np.median(m_ortho) / np.median(m_iso) == pytest.approx(11.0 / 8.5, rel=0.03)
    with pytest.raises(FEError, match="orthotropic plates are not available"):
        validate(cone, engine="kratos", orthotropic=True, **options)


@pytest.mark.slow
def test_validate_uses_the_designs_plates_and_says_so(tmp_path, capsys):
    """A 12 mm aluminium design used to be validated as 8 mm plywood without a word."""
    text = Path(CONE).read_text() + '\n[plates]\nthickness = 0.012\nmaterial = "aluminium"\n'
    design = tmp_path / "alu.toml"
    design.write_text(text)
    v = validate(CCUModel(load_design(design)), **FAST)
    assert v.summary()["plates"] == {
        "thickness": 0.012,
        "material": "aluminium",
        "thickness_from": "design [plates]",
        "material_from": "design [plates]",
    }
    plywood = validate(CCUModel(load_design(CONE)), **FAST)
    # stiffer and thicker plates: the same bending curvature needs more stress
    assert (
        v.summary()["stresses"]["max_bending_MPa"]
        > plywood.summary()["stresses"]["max_bending_MPa"]
    )
    args = ["validate", str(design), "--out", str(tmp_path / "fe"), "--no-figures", "--steps", "4"]
    args += ["--allow-exceeded"]  # the aluminium pair's ULS check fails (1.73): not the point here
    assert main(args + ["--element-size", "0.1", "--thickness", "0.01"]) == 0
    out = capsys.readouterr().out
    assert "plates: 10 mm aluminium (thickness from option, material from design [plates])" in out
    saved = json.loads((tmp_path / "fe" / "validation.json").read_text())
    assert saved["plates"]["thickness"] == 0.01
    # aluminium: gamma_M 1.1 (EN 1999-1-1), k_mod 1: the design strength is 130 / 1.1 MPa
    assert (
        "strength of the governing case: 118.2 MPa, EC5 SC1 short-term: f_d = k_mod f_k / "
        "gamma_M, k_mod 1" in out
    )
    assert saved["checks"]["strength_MPa"] == pytest.approx(130.0 / 1.1, rel=1e-12)
