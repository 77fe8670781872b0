"""One variant's evaluation: metrics against the analytic cone, and failures recorded by stage."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from compas_ccu.catalog import catalog_path
from compas_ccu.design import load_design
from compas_ccu.explore import METRICS, evaluate_variant, metric_names
from compas_ccu.explore.evaluate import STAGES, row_template
from compas_ccu.explore.metrics import collision_metrics, metrics_markdown
from compas_ccu.model import load_model
from compas_ccu.thickness import ThickModel
from conftest import EXAMPLES

CONE = load_design(EXAMPLES / "cone.toml").document


@pytest.fixture(scope="module")
def cone_row():
    return evaluate_variant(copy.deepcopy(CONE), path_states=9)


def test_cone_shape_against_the_analytic_cone(cone_row):
    """Flat crease: a regular 48-gon of radius R = 2 m over 90 deg, radial rulings. Deployed, it
    stays a regular polygon of radius r3D = R cos(alpha) whose turning angle d3 obeys the
    discrete cone relation sin(d3 / 2) = sin(d / 2) / cos(alpha) (smooth limit: k3D = k2D /
    cos(alpha)), so span and rise are exact to rounding."""
    r = cone_row
    assert r["status"] == "ok" and r["error"] is None
    alpha, n = math.radians(40.0), 48
    d = math.radians(90.0) / n
    d3 = 2.0 * math.asin(math.sin(d / 2.0) / math.cos(alpha))
    radius = 2.0 * math.cos(alpha)
    half = n * d3 / 2.0
    assert r["span"] == pytest.approx(2.0 * radius * math.sin(half), abs=1e-12)
    assert r["rise"] == pytest.approx(radius * (1.0 - math.cos(half)), abs=1e-12)
    assert r["rise_to_span"] == pytest.approx(r["rise"] / r["span"], rel=1e-15)
    assert r["alpha_design"] == 40.0
    assert r["alpha_max"] == pytest.approx(40.0, abs=1e-9)  # the cone: constant alpha
    assert (r["plates"], r["creases"]) == (2, 1)
    assert r["limit_margin"] == pytest.approx(min(r["alpha_limit"], r["overlap_alpha"]) - 40.0)
    assert r["invariant_error"] < 1e-13
    assert r["crease_planarity"] < 1e-12  # orthogonal rulings: exactly planar along the path
    assert r["global_curvature"] is None  # a single crease has no global surface


def test_cone_pattern_area_stack_and_mass_are_exact(cone_row):
    """Two annular sectors of chords: n * (R^2 - r^2) * sin(dtheta) / 2 each, t = 5 mm."""
    n, dtheta = 48, math.radians(90.0) / 48
    area = 2 * n * 0.5 * (2.0**2 - 1.6**2) * math.sin(dtheta)
    assert cone_row["plate_area"] == pytest.approx(area, rel=1e-13)
    assert cone_row["thickness"] == 0.005 and cone_row["material"] == "plywood"
    assert cone_row["stack_height"] == pytest.approx(2 * 0.005, abs=1e-15)
    assert cone_row["mass"] == pytest.approx(area * 0.005 * 600.0, rel=1e-13)


def test_cone_bending_is_the_thick_model_check_over_the_path(cone_row):
    model = load_model(EXAMPLES / "cone.toml")
    bend = ThickModel(model).bending(np.linspace(0.0, 40.0, 9))
    assert cone_row["bending_utilisation"] == bend.max
    assert cone_row["bending_curvature"] == float(np.abs(bend.curvature).max())
    assert cone_row["bending_utilisation_characteristic"] == bend.max_characteristic
    assert 0.0 < cone_row["bending_utilisation_characteristic"] < 1.0
    # the default basis (EC5, SC1, permanent): f_d = 0.6 f_k / 1.2, the utilisation doubles
    assert cone_row["bending_utilisation"] == pytest.approx(
        2.0 * cone_row["bending_utilisation_characteristic"], rel=1e-12
    )
    assert (cone_row["bending_basis"], cone_row["k_mod"], cone_row["gamma_M"]) == (
        "EC5 SC1 permanent",
        0.6,
        1.2,
    )


def test_row_has_exactly_the_declared_columns(cone_row):
    assert list(cone_row) == list(row_template())
    names = metric_names()
    assert set(names) <= set(cone_row)
    assert "collision_free" not in cone_row and "fe_bending_MPa" not in cone_row
    assert cone_row["t_collisions"] is None and cone_row["t_fe"] is None
    assert cone_row["seconds"] >= sum(cone_row[f"t_{s}"] or 0.0 for s in STAGES) > 0.0
    assert cone_row["worker"].endswith(f":{__import__('os').getpid()}")


def test_collision_metrics_of_the_vault():
    doc = load_design(EXAMPLES / "vault.toml").document
    doc["layout"]["plates"] = 4
    row = evaluate_variant(doc, path_states=5, collisions=True)
    assert row["status"] == "ok"
    assert row["collision_free"] is True and row["collision_alpha"] is None
    assert row["max_penetration"] <= 1e-15  # round-off of the 6 mm offsets, not a penetration
    # plates 0 and 2 lie 6 mm apart in the flat stack with plate 1 between them
    assert row["min_clearance"] == pytest.approx(0.006, abs=1e-12)


def test_a_collision_is_reported_with_its_angle():
    """The Fig. 12c funnel closes on itself beyond 70 deg (docs/thickness.md)."""
    model = load_model(catalog_path("fig12c-funnel"))
    m = collision_metrics(ThickModel(model), np.linspace(70.0, 77.0, 8))
    assert m["collision_free"] is False
    assert 70.0 <= m["collision_alpha"] <= 77.0 and m["max_penetration"] > 0.0


@pytest.mark.parametrize(
    "change, stage, error_type, match",
    [
        (lambda d: d["crease"].update(rise=-1.0), "model", "DesignError", "crease.rise"),
        (lambda d: d["crease"].update(radius=-1.0), "model", "DesignError", "crease.radius"),
        (lambda d: d["deployment"].update(alpha=89.5), "model", "DeploymentLimitError", "89.0625"),
        (lambda d: d["deployment"].update(alpha=80.0), "model", "SelfIntersectionError", "75.51"),
        (
            lambda d: d.update(plates={"thickness": 0.15}),
            "model",
            "DesignError",
            "plates.thickness",
        ),
        (
            lambda d: d.update(
                plates={"thickness": 0.09}, layout={"type": "single", "width": 0.15}
            ),
            "thickness",
            "GeometryError",
            "half the narrowest",
        ),
    ],
)
def test_a_failing_variant_is_a_row_with_its_stage_and_error(change, stage, error_type, match):
    doc = copy.deepcopy(CONE)
    change(doc)
    row = evaluate_variant(doc, path_states=5)
    assert (row["status"], row["stage"], row["error_type"]) == ("failed", stage, error_type)
    assert match in row["error"]
    assert row["bending_utilisation"] is None and row["seconds"] > 0.0
    if stage == "thickness":  # the kinematic metrics before the failing stage are kept
        assert row["span"] > 0.0 and row["t_model"] > 0.0 and row["t_thickness"] is None


def test_a_bug_is_recorded_too_not_raised():
    row = evaluate_variant({"crease": None})
    assert row["status"] == "failed" and row["stage"] == "model" and row["error"]


@pytest.mark.slow
def test_fe_metrics_of_the_cone():
    fe = {"engine": "kratos", "element_size": 0.25, "steps": 4, "checks": True}
    row = evaluate_variant(copy.deepcopy(CONE), path_states=5, fe=fe)
    assert row["status"] == "ok", row["error"]
    assert 0.0 < row["fe_deviation_percent"] < 1.0  # the FE plates follow the kinematics
    # below the characteristic 30 MPa; the utilisation is against the design strength of the
    # default basis (EC5 SC1 permanent: 0.6 x 30 / 1.2 = 15 MPa), hence up to 2
    assert 0.0 < row["fe_bending_MPa"] < 30.0 and 0.0 < row["fe_utilisation"] < 2.0
    assert row["fe_buckling_factor"] > 1.0 and row["fe_elements"] > 0 and row["t_fe"] > 0.0


def test_metric_catalogue_is_unique_and_documented():
    names = [m.name for m in METRICS]
    assert len(names) == len(set(names))
    assert {m.dtype for m in METRICS} <= {"float", "int", "bool", "str"}
    table = metrics_markdown()
    assert all(f"`{n}`" in table for n in names)
    assert metric_names(collisions=True, fe=True) == names


def test_docs_list_every_metric():
    text = (EXAMPLES.parent / "docs" / "explore.md").read_text(encoding="utf-8")
    table = text.split("<!-- metrics:begin")[1].split("-->", 1)[1].split("<!-- metrics:end -->")[0]
    assert table.strip() == metrics_markdown().strip()  # regenerate: see the comment in the docs
