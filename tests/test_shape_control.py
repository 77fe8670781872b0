"""Shape control (issue 4): plane layouts, planarity along the path, relaxation, inverse design,
the rule catalog and its measured global curvature classes."""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import numpy as np
import pytest

from compas_ccu.analysis import global_curvature
from compas_ccu.analysis.planarity import planarity_along_path
from compas_ccu.catalog import (
    CATALOG_DIR,
    catalog_design,
    catalog_entries,
    catalog_entry,
    catalog_metrics,
    catalog_path,
)
from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.design.inverse import design_from_crease
from compas_ccu.errors import DesignError, GeometryError, OptionError
from compas_ccu.model import CCUModel, flat_design, load_model, round_trip
from conftest import EXAMPLES

VAULT = {
    "crease": {"profile": "arc", "span": 2.5, "rise": 1.0, "segments": 48},
    "rulings": {"type": "orthogonal"},
    "deployment": {"alpha": 30.0},
}


def vault(layout, **sections):
    doc = copy.deepcopy(VAULT)
    doc["layout"] = layout
    doc.update(copy.deepcopy(sections))
    return CCUModel(Design(doc))


def path_planarity(model, steps=24):
    return planarity_along_path(model, steps=steps).max


# -- layouts and planarity along the path -----------------------------------------------------


@pytest.mark.parametrize(
    "layout, rulings",
    [
        ({"type": "parallel", "plates": 8, "spacing": 0.12}, {"type": "orthogonal"}),
        ({"type": "parallel", "plates": 8, "spacing": [0.1, 0.14] * 4}, {"type": "orthogonal"}),
        (
            {"type": "parallel", "plates": 6, "spacing": 0.1},
            {"type": "angle", "gamma": [[0, 75], [1, 100]]},
        ),
        (
            {"type": "inclined", "plates": 8, "spacing": 0.12, "spacing_start": 0.08},
            {"type": "cylindrical", "direction": [0.0, -1.0]},
        ),
    ],
)
def test_layouts_the_theory_calls_planar_stay_planar_along_the_whole_path(layout, rulings):
    model = vault(layout, rulings=rulings)
    report = planarity_along_path(model, steps=24)
    assert report.exact and report.max < 1e-13 * model.size
    states = model.path(np.linspace(1.0, model.alpha_design, 6))
    for s in states:  # docs/geometry.md §3 invariants at every state
        assert s.max_invariant_error < 1e-12 * model.size


def test_inclined_planes_with_conical_strips_leave_their_plane_but_not_at_the_design_state():
    """Paper Fig. 6b claims planarity for inclination about the actuation axis; measured, it
    holds for cylindrical rulings (above) but not for the conical strips of an arc crease."""
    model = vault({"type": "inclined", "plates": 8, "spacing": 0.12, "spacing_start": 0.08})
    report = planarity_along_path(model, steps=24)
    assert 1e-4 < report.max < 2e-3  # metres, at 2.5 m span
    assert model.deploy().metrics["crease_planarity_max"] < 1e-14
    assert not report.exact
    fixed = [i for i, c in enumerate(model.mechanism.creases) if c.fixed]
    assert [report.creases[i]["exact"] for i in fixed] == [True]  # the leading crease


def test_inclined_layout_places_planes_at_the_given_distances():
    model = vault(
        {
            "type": "inclined",
            "plates": 4,
            "leading": 0,
            "spacing": 0.14,
            "spacing_start": 0.08,
            "spacing_end": 0.16,
        }
    )
    planes = model.planes
    local = model.geometry.profile_points * [1.0, model.flip]
    controls = local[[0, model.reference, -1]]
    for k in range(1, 5):
        heights = planes.height(k, controls) - planes.height(k - 1, controls)
        np.testing.assert_allclose(heights, [0.08, 0.14, 0.16], atol=1e-14)
    inc = planes.inclinations()
    # about the actuation axis: 0.02 m more at the apex (1 m up) than on the chord
    np.testing.assert_allclose(np.abs(inc[:, 0]), math.degrees(math.atan(0.02 / 1.0)), atol=1e-9)
    # perpendicular: the planes turn about y by atan(0.08 / 2.5) per plate in height terms
    assert abs(abs(inc[0, 1]) - math.degrees(math.atan(0.08 / 2.5))) < 1e-9
    assert abs(abs(inc[:, 1].sum()) - math.degrees(math.atan(4 * 0.08 / 2.5))) < 1e-9


def test_radial_layout_turns_every_plane_about_the_axis():
    model = CCUModel(catalog_design("fig12b-dome"))
    normals = model.planes.normals
    turn = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", normals[:-1], normals[1:]), -1, 1)))
    np.testing.assert_allclose(turn, 8.0, atol=1e-9)
    # every plane contains the axis (x = 0, z = 0, any y)
    for k in range(len(normals)):
        for y in (0.0, 1.0):
            assert abs(normals[k] @ [0.0, y, 0.0] - model.planes.offsets[k]) < 1e-14


@pytest.mark.parametrize(
    "layout, message",
    [
        (
            {"type": "inclined", "plates": 4, "spacing": 0.12, "spacing_start": 0.0},
            r"layout\.spacing_start: crease planes \d and \d cross at crease vertex 0",
        ),
        (
            {"type": "inclined", "plates": 4, "spacing": 0.12, "spacing_start": [0.1] * 3},
            r"layout\.spacing_start: needs one value per plate \(4\), got 3",
        ),
        (
            {"type": "radial", "plates": 4, "angle": 5.0, "axis": 0.0},
            r"layout\.axis: the axis x = 0 m must lie beside the crease",
        ),
        (
            {"type": "radial", "plates": 4, "angle": 100.0, "axis": 3.0},
            r"layout\.angle: the planes turn by 400 deg in total",
        ),
        ({"type": "radial", "plates": 4, "angle": 5.0}, r"layout\.axis: required"),
        ({"type": "inclined", "plates": 4}, r"layout\.spacing: required"),
    ],
)
def test_impossible_layouts_are_refused_with_the_key_and_the_value(layout, message):
    with pytest.raises(DesignError, match=message):
        vault(layout)


def test_planes_too_far_apart_for_the_crease_curvature_are_refused():
    with pytest.raises(GeometryError, match=r"the rulings of plate \d+ cross between crease"):
        vault({"type": "parallel", "plates": 10, "spacing": 2.0})
    with pytest.raises(DesignError, match=r"layout: the rulings of plate \d do not reach crease"):
        vault(
            {"type": "radial", "plates": 2, "leading": 0, "angle": 120.0, "axis": 3.0},
            crease={"profile": "arc", "span": 2.5, "rise": 1.0, "segments": 16},
        )


# -- relaxation fallback ----------------------------------------------------------------------


def test_relaxation_reports_bounded_residuals_where_the_kinematics_is_not_exact():
    model = CCUModel(catalog_design("fig12a-asymmetric"))
    kinematic = model.deploy(15.0)
    relaxed, result = model.relax(15.0)
    assert result.converged
    assert kinematic.metrics["isometry"] > 1e-4  # the mirror construction is not exact here
    assert relaxed.metrics["isometry"] < 0.3 * kinematic.metrics["isometry"]
    assert 1e-6 < result.max_strain < 3e-4  # relative length error left
    assert result.quad_planarity < 3e-4  # m
    assert result.displacement < 5e-3  # m, at 2.5 m span
    assert relaxed.metrics["hinge_gap"] == 0.0
    rel = relaxed.metrics["relaxation"]
    assert len(rel["max_strain_per_plate"]) == 10 and rel["max_strain_per_plate"][5] < 1e-13
    # where the kinematics is exact, the relaxation changes nothing
    exact, exact_result = model.relax(model.alpha_design)
    assert exact_result.displacement < 1e-12 and exact_result.max_strain < 1e-12


# -- global curvature class -------------------------------------------------------------------


@pytest.fixture(scope="module")
def catalog_rows():
    rows = {}
    for entry in catalog_entries():
        model = CCUModel(catalog_design(entry.name))
        rows[entry.name] = catalog_metrics(model, steps=6, relax=False)
    return rows


@pytest.mark.slow  # every catalog design built and measured (~4 s)
def test_every_catalog_design_is_built_measured_and_exact_at_its_design_state(catalog_rows):
    assert len(catalog_rows) == len(catalog_entries()) == 15
    figures = {catalog_entry(n).figure for n in catalog_rows}
    assert {
        "9a",
        "9b",
        "9c",
        "9d",
        "9e",
        "10a",
        "10b",
        "10c",
        "11a",
        "12a",
        "12b",
        "12c",
    } <= figures
    for name, row in catalog_rows.items():
        assert row["invariant_max_relative"] < 1e-12, name
        assert row["global_curvature"] in ("monoclastic", "synclastic", "anticlastic"), name
        alpha = row["alpha_design"]
        assert row["alpha_limit"] > alpha and row["overlap_alpha"] > alpha, name
        assert row["crease_span"] > 0 and row["crease_rise"] > 0 and row["stack_x"] > 0


@pytest.mark.slow  # every catalog design built and measured (~4 s)
def test_measured_global_curvature_matches_the_paper_rule(catalog_rows):
    for entry in catalog_entries():
        if entry.expected is not None:
            assert catalog_rows[entry.name]["global_curvature"] == entry.expected, entry
    # monoclastic: the smaller principal curvature vanishes to rounding, not to a fit error
    assert catalog_rows["fig10a-monoclastic"]["curvature_ratio"] < 1e-12
    assert catalog_rows["fig10b-synclastic"]["curvature_ratio"] > 0.1
    assert catalog_rows["fig12c-funnel"]["gaussian_curvature"] < -0.1


def test_global_curvature_of_analytic_surfaces():
    u, v = np.meshgrid(np.linspace(-0.5, 0.5, 9), np.linspace(-0.8, 0.8, 33), indexing="ij")
    cylinder = np.stack([u, np.sin(v), np.cos(v)], axis=-1)  # radius 1
    g = global_curvature(cylinder)
    assert g.kind == "monoclastic" and abs(g.gaussian) < 1e-12
    assert abs(abs(g.principal[0]) - 1.0) < 0.02
    saddle = np.stack([u, v, 0.3 * (u**2 - v**2)], axis=-1)
    assert global_curvature(saddle).kind == "anticlastic"
    with pytest.raises(ValueError, match="at least 5 plane curves"):
        global_curvature(cylinder[:4])


def test_freeform_crease_changes_kind_along_it_per_vertex():
    s = CCUModel(catalog_design("fig09e-freeform")).deploy()
    crease = s.creases[0]
    assert crease["kind"] == "mixed"
    kinds = [k for k in crease["vertex_kinds"] if k in ("synclastic", "anticlastic")]
    changes = sum(a != b for a, b in zip(kinds, kinds[1:]))
    assert changes == 4  # the spline has four inflection points
    sums = np.asarray(crease["sum_beta"])
    vk = crease["vertex_kinds"][1:-1]
    assert all((b < 360.0) == (k == "synclastic") for b, k in zip(sums, vk) if k != "straight")


def test_impossible_freeform_is_refused_before_deployment():
    doc = catalog_entry("fig09e-freeform").document
    doc["crease"]["points"] = [
        [-1.25, 0],
        [-1.1, 0.7],
        [-0.5, 0.9],
        [0.2, 0.7],
        [0.8, 1.1],
        [1.25, 0],
    ]
    doc["rulings"]["side"] = "right"
    with pytest.raises(
        GeometryError, match=r"the rulings of plate 0 cross between crease vertices"
    ):
        CCUModel(Design(doc))


def test_flat_pattern_beyond_its_limit_is_refused_at_build():
    from compas_ccu.errors import DeploymentLimitError

    pattern = flat_design(load_design(EXAMPLES / "cone.toml"))
    doc = copy.deepcopy(pattern.document)
    doc["deployment"]["alpha"] = 89.9
    with pytest.raises(DeploymentLimitError, match=r"the design alpha 89.9 deg cannot be reached"):
        CCUModel(Design(doc))


def test_funicular_crease_from_a_design_file_has_a_vertex_at_every_load():
    design = catalog_design("fig09d-funicular")
    model = CCUModel(design)
    crease = model.geometry.profile_points
    assert np.min(np.abs(crease[:, 0] - 0.5)) < 1e-12  # the point load's kink is a vertex
    assert abs(crease[:, 1].max() - 1.0) < 1e-3
    bad = copy.deepcopy(design.document)
    bad["crease"]["point_loads"] = [[0.5]]
    with pytest.raises(DesignError, match=r"crease\.point_loads: must be a non-empty list of rows"):
        Design(bad)
    bad["crease"]["point_loads"] = [[3.0, 1.0]]
    with pytest.raises(DesignError, match=r"\[crease\]"):
        CCUModel(Design(bad))


# -- inverse design ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "crease, rulings",
    [
        ({"profile": "arc", "span": 2.5, "rise": 1.0, "segments": 48}, {"type": "orthogonal"}),
        ({"profile": "catenary", "span": 2.0, "rise": 0.7, "segments": 64}, {"type": "orthogonal"}),
        (
            {"profile": "elastica", "span": 2.0, "rise": 0.8, "segments": 64},
            {"type": "angle", "gamma": [[0, 80], [1, 100]]},
        ),
        (
            {"profile": "catenary", "span": 2.0, "rise": 0.7, "segments": 40},
            {"type": "conical", "apex": [0.3, -0.5]},
        ),
    ],
)
def test_inverse_pattern_round_trips_to_the_target(crease, rulings):
    design = Design(
        {
            "crease": crease,
            "rulings": rulings,
            "deployment": {"alpha": 35.0},
            "layout": {"type": "single", "width": 0.25},
        }
    )
    err = round_trip(design)
    assert err.max_relative <= 1e-9
    assert err.crease_max <= 1e-9 * err.span
    assert err.alpha_error < 1e-9


def test_design_from_a_3d_target_polyline_and_its_errors():
    t = np.linspace(0.2, np.pi - 0.4, 41)
    tilt = np.array([[1.0, 0.0, 0.0], [0.0, 0.8, 0.6], [0.0, -0.6, 0.8]])  # a tilted plane
    target = np.c_[1.5 * np.cos(t), np.zeros_like(t), 0.9 * np.sin(t)] @ tilt.T + [3, 1, 0.5]
    design = design_from_crease(target, alpha=25.0, width=0.3)
    structure = CCUModel(design).deploy()
    crease = np.asarray(structure.deployed)[0, :41]
    assert np.abs(crease - target).max() < 1e-12  # the crease IS the target, in place
    assert round_trip(design).max_relative < 1e-9
    bent = target.copy()
    bent[20] += tilt[:, 1] * 0.01
    with pytest.raises(DesignError, match=r"a CCU crease must be planar .* target point 20"):
        design_from_crease(bent, alpha=25.0, width=0.3)
    with pytest.raises(DesignError, match=r"\(n >= 3, 3\) points"):
        design_from_crease(target[:, :2], alpha=25.0, width=0.3)


def test_flat_design_is_a_cut_pattern_with_explicit_rulings(tmp_path):
    pattern = flat_design(load_design(EXAMPLES / "cone.toml"))
    assert pattern.values["crease"]["state"] == "flat"
    assert pattern.values["rulings"]["type"] == "explicit"
    from compas_ccu.design.inverse import write_design

    write_design(pattern, tmp_path / "p.toml")
    again = load_model(tmp_path / "p.toml").deploy()
    first = CCUModel(pattern).deploy()
    assert np.abs(np.asarray(again.deployed) - np.asarray(first.deployed)).max() < 1e-15
    doc = copy.deepcopy(pattern.document)
    doc["crease"]["state"] = "deployed"
    with pytest.raises(DesignError, match=r"rulings\.points: explicit rulings describe a cut"):
        CCUModel(Design(doc))
    doc = copy.deepcopy(pattern.document)
    doc["rulings"]["points"] = doc["rulings"]["points"][:-1]
    with pytest.raises(DesignError, match=r"rulings\.points: needs one point per crease vertex"):
        CCUModel(Design(doc))
    with pytest.raises(DesignError, match=r"layout\.type: flat_design needs a single-crease"):
        flat_design(load_design(EXAMPLES / "vault.toml"))


def _ridge_targets(model):
    """Apex (d, profile y) and support (d, profile x) of every plane of the leading parity."""
    b = model.geometry
    states = model.mechanism.deploy(np.radians([model.alpha_design]))
    curves = model.plane_curves(states)[0]  # world
    rel = curves - model.origin
    x, y, d = rel @ model.axes[0], rel @ model.axes[1], rel @ model.axes[2]
    k0 = b.planes.leading
    qs = [q for q in range(b.planes.plates + 1) if (q - k0) % 2 == 0]
    ref = b.reference
    apex = [[d[q, ref], y[q, ref]] for q in qs]
    start = [[d[q, 0], x[q, 0]] for q in qs]
    end = [[d[q, -1], x[q, -1]] for q in qs]
    return apex, start, end


def test_target_curves_round_trip_to_the_layout_that_made_them():
    layout = {
        "type": "inclined",
        "plates": 8,
        "spacing": [0.12, 0.13, 0.11, 0.12, 0.12, 0.13, 0.12, 0.11],
        "spacing_start": [0.10, 0.12, 0.09, 0.11, 0.12, 0.12, 0.11, 0.13],
        "spacing_end": [0.11, 0.12, 0.10, 0.12, 0.13, 0.12, 0.12, 0.14],
    }
    original = vault(layout)
    apex, start, end = _ridge_targets(original)
    guess = copy.deepcopy(layout)
    for key in ("spacing", "spacing_start", "spacing_end"):
        for k in (0, 2, 5, 7):  # plates that reach a solved plane: their distances are unused
            guess[key][k] = 0.2
    fitted = vault(guess, target={"apex": apex, "support": start, "support_end": end})
    fit = fitted.geometry.target_fit
    assert fit.planes == [0, 2, 6, 8]
    assert fit.max_residual == 0.0
    span = 2.5
    err = np.abs(fitted.geometry.design_far - original.geometry.design_far).max()
    assert err <= 1e-9 * span
    np.testing.assert_allclose(
        fit.distances,
        np.c_[layout["spacing_start"], layout["spacing"], layout["spacing_end"]],
        atol=1e-12,
    )


def test_target_curves_that_the_rulings_cannot_reach_report_the_remaining_error():
    model = vault(
        {"type": "parallel", "plates": 6, "spacing": 0.12},
        target={"apex": [[-1.0, 1.0], [0.2, 1.0]]},  # ends before plane 5 (d = 0.24)
    )
    fit = model.geometry.target_fit
    assert fit.planes == [1, 5]
    assert fit.residuals[1][1] == 0.0
    assert 1e-4 < fit.residuals[5][1] < 0.05 and fit.max_residual == fit.residuals[5][1]


@pytest.mark.parametrize(
    "layout, target, message",
    [
        (
            {"type": "radial", "plates": 4, "angle": 5.0, "axis": 3.0},
            {"apex": [[0, 1], [1, 1]]},
            r"\[target\]: target curves need layout type 'parallel' or 'inclined'",
        ),
        (
            {"type": "parallel", "plates": 4, "spacing": 0.1},
            {"apex": [[1, 1], [0, 1]]},
            r"target\.apex: the distances d \(first column\) must increase",
        ),
        (
            {"type": "parallel", "plates": 4, "spacing": 0.1},
            {"support_end": [[0, 1], [1, 1]]},
            r"target\.support_end: needs target\.support",
        ),
        (
            {"type": "parallel", "plates": 4, "spacing": 0.1},
            {"apex": [[0, 1]]},
            r"target\.apex: needs at least 2 points",
        ),
    ],
)
def test_bad_targets_are_refused(layout, target, message):
    with pytest.raises(DesignError, match=message):
        vault(layout, target=target)


# -- catalog files and commands ---------------------------------------------------------------


def test_catalog_designs_are_package_data_naming_their_paper_figure():
    import compas_ccu

    assert CATALOG_DIR.parent.parent == Path(compas_ccu.__file__).resolve().parent
    entries = catalog_entries()
    assert [e.path.name for e in entries] == sorted(p.name for p in CATALOG_DIR.glob("*.toml"))
    for entry in entries:
        design = entry.design()
        assert design.name == entry.name == entry.path.stem
        assert design.values["design"]["description"] == f"Fig. {entry.figure}: {entry.title}"
    assert catalog_entry("fig10b-synclastic").expected == "synclastic"
    assert catalog_entry("fig11a-constant-apex").expected is None
    with pytest.raises(OptionError, match=r"no catalog design 'nope'; the catalog has: fig09a"):
        catalog_entry("nope")


def test_catalog_files_are_in_the_package_data():
    pyproject = (EXAMPLES.parent / "pyproject.toml").read_text(encoding="utf-8")
    assert '"data/catalog/*.toml"' in pyproject


def test_ccu_catalog_writes_every_file_and_the_table(tmp_path, capsys):
    names = ["fig10a-monoclastic", "fig10b-synclastic", "fig12a-asymmetric"]
    assert main(["catalog", "--out", str(tmp_path), "--only", *names, "--steps", "4"]) == 0
    out = capsys.readouterr().out
    assert "fig10b-synclastic" in out and "measured synclastic" in out
    rows = json.loads((tmp_path / "catalog.json").read_text())
    assert [r["name"] for r in rows] == names
    assert rows[2]["relaxed_strain"] > 0.0 and not rows[2]["crease_planarity_exact"]
    table = (tmp_path / "catalog.md").read_text()
    assert table.count("\n| fig") == 3 and "global_curvature" in table
    for name in names:
        s = json.loads((tmp_path / name / "structure.json").read_text())
        assert s["format"] == "ccu.structure" and s["metrics"]["catalog"]["name"] == name
        assert load_design(tmp_path / name / "design.toml").name == name
    assert (tmp_path / "fig10.png").stat().st_size > 10_000
    assert main(["catalog", "--out", str(tmp_path), "--only", "nope"]) == 2
    assert "no catalog design 'nope'" in capsys.readouterr().err


def test_ccu_planarity_and_info(tmp_path, capsys):
    design = catalog_path("fig12a-asymmetric")
    assert main(["planarity", str(design), "--out", str(tmp_path), "--steps", "6", "--relax"]) == 0
    out = capsys.readouterr().out
    assert "relaxed at alpha" in out and "converged" in out
    rows = (tmp_path / "planarity.csv").read_text().splitlines()
    assert rows[0] == "alpha_deg,crease,deviation_m" and len(rows) == 1 + 6 * 9
    summary = json.loads((tmp_path / "planarity.json").read_text())
    assert summary["planarity_exact"] is False and len(summary["creases"]) == 9
    assert main(["info", str(catalog_path("fig11d-target-curves"))]) == 0
    out = capsys.readouterr().out
    assert "global shape      anticlastic" in out
    assert "target fit        planes [1, 3, 7, 9] solved, largest miss 0.00e+00 m" in out
    assert main(["planarity", str(design), "--out", str(tmp_path), "--steps", "0"]) == 2
