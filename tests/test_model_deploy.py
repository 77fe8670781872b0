"""Deployment of whole designs: invariants, planarity tracking, design round trip, errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.design import Design
from compas_ccu.errors import DeploymentLimitError, SelfIntersectionError
from compas_ccu.model import CCUModel
from conftest import make_design

TOL = 1e-9  # docs/geometry.md §3, relative to the structure size


def assert_invariants(structure, tol=TOL):
    m = structure.metrics
    for key in (
        "isometry_relative",
        "quad_planarity_relative",
        "hinge_gap_relative",
        "mirror_error_relative",
        "leading_in_plane_relative",
    ):
        assert m[key] <= tol, (key, m[key])


@pytest.mark.parametrize("alpha", [0.0, 1.0, 12.5, 30.0, 45.0, 60.0, 68.0])
def test_vault_invariants_along_the_path(vault_model, alpha):
    s = vault_model.deploy(alpha)
    assert_invariants(s)
    # parallel planes with conical strips: every crease stays planar to rounding
    assert s.metrics["crease_planarity_max_relative"] < 1e-14
    assert s.alpha == alpha
    np.testing.assert_allclose(s.metrics["alpha_leading"], alpha, atol=1e-12)
    for crease in s.creases:
        np.testing.assert_allclose(crease["alpha"], alpha, atol=1e-11)


def test_vault_alternates_synclastic_and_anticlastic(vault_model):
    s = vault_model.deploy(30.0)
    assert len(s.plate_ids) == 10 and len(s.creases) == 9
    by_plane = sorted(s.creases, key=lambda c: min(c["plates"]))
    kinds = [c["kind"] for c in by_plane]
    assert kinds == ["synclastic", "anticlastic"] * 4 + ["synclastic"]
    for c in by_plane:
        assert sorted(c["plates"])[1] - sorted(c["plates"])[0] == 1


def test_vault_design_state_round_trip(vault_model):
    b = vault_model.geometry
    st = vault_model.mechanism.deploy(b.design_alpha)
    scale = vault_model.size
    assert np.abs(st.near[0] - b.design_near).max() < 1e-13 * scale
    assert np.abs(st.far[0] - b.design_far).max() < 1e-13 * scale
    s = vault_model.deploy(30.0)
    assert s.metrics["span"] == pytest.approx(2.5, abs=1e-12)
    assert s.metrics["rise"] == pytest.approx(1.0, abs=1e-12)
    # the crease planes keep the design spacing 0.12 m at the design state
    normals = np.array([c["plane"]["normal"] for c in s.creases])
    origins = np.array([c["plane"]["origin"] for c in s.creases])
    np.testing.assert_allclose(np.abs(normals @ [0.0, 1.0, 0.0]), 1.0, atol=1e-14)
    offsets = np.sort(origins[:, 1])
    np.testing.assert_allclose(np.diff(offsets), 0.12, atol=1e-12)


def test_flat_folded_stack(vault_model):
    s = vault_model.deploy(0.0)
    # at alpha = 0 every plate lies in the leading plane (world y = 0) ...
    np.testing.assert_allclose(s.deployed[..., 1], 0.0, atol=1e-14)
    # ... and the plates lie exactly on top of each other near each crease
    for crease in s.creases:
        a, b = crease["plates"]
        ia, ib = crease["vertices"]
        np.testing.assert_allclose(s.deployed[a][ia], s.deployed[b][ib], atol=1e-15)
    flat = vault_model.flat()
    np.testing.assert_allclose(flat[..., 2], 0.0, atol=0.0)


def test_cone_example_radius_is_R_cos_alpha(cone_model):
    n = cone_model.segments
    for alpha in (10.0, 40.0, 70.0):
        s = cone_model.deploy(alpha)
        crease = s.deployed[0][: n + 1]
        a, b, c = crease[0], crease[n // 2], crease[-1]
        # circumcentre in the crease plane (world xz)
        ax, bx, cx = a[[0, 2]], b[[0, 2]], c[[0, 2]]
        centre = np.linalg.solve(
            np.array([2 * (bx - ax), 2 * (cx - ax)]), [bx @ bx - ax @ ax, cx @ cx - ax @ ax]
        )
        r3d = np.linalg.norm(crease[:, [0, 2]] - centre, axis=1)
        np.testing.assert_allclose(r3d, 2.0 * math.cos(math.radians(alpha)), rtol=1e-12)
        assert_invariants(s, 1e-13)


def cylindrical_vault(**layout):
    return CCUModel(
        make_design(
            crease={"profile": "catenary", "span": 2.4, "rise": 0.9, "segments": 40},
            rulings={"type": "cylindrical", "direction": [0.0, -1.0], "side": "inside"},
            layout={"type": "parallel", "plates": 6, "spacing": 0.1, **layout},
        )
    )


def test_parallel_planes_with_cylindrical_strips_stay_planar():
    model = cylindrical_vault()
    alphas = np.linspace(0.0, 30.0, 13)
    path = model.path(alphas)
    for s in path:
        assert_invariants(s)
        assert s.metrics["crease_planarity_max_relative"] < 1e-14


def test_parallel_planes_keep_every_crease_planar_for_any_ruling_field():
    """Not only cylinders and cones: by (K1) the height of a ruling point above the leading
    plane is t * sin(beta) * s0 * c_j, proportional to s0, so a crease that is parallel to the
    leading plane at the design state stays parallel in every state (paper §5.1, Fig. 6a)."""
    model = CCUModel(
        make_design(
            crease={"profile": "catenary", "span": 2.0, "rise": 0.7, "segments": 40},
            rulings={"type": "angle", "gamma": [[0.0, 60.0], [1.0, 110.0]]},
            layout={"type": "parallel", "plates": 4, "spacing": 0.1, "leading": 1},
        )
    )
    for s in model.path(np.linspace(0.0, 45.0, 10)):
        assert_invariants(s)
        assert s.metrics["crease_planarity_max_relative"] < 1e-14


def test_leading_plane_anywhere_in_the_layout():
    for leading in (0, 3, 5):
        model = cylindrical_vault(leading=leading)
        s = model.deploy(22.0)
        assert_invariants(s)
        assert sorted(s.plate_ids) == list(range(6))
        kinds = [c["kind"] for c in sorted(s.creases, key=lambda c: min(c["plates"]))]
        assert set(kinds[::2]) != set(kinds[1::2])


def test_path_is_one_vectorised_call_with_the_same_numbers(vault_model):
    alphas = [0.0, 10.0, 20.0, 30.0]
    path = vault_model.path(alphas)
    for alpha, s in zip(alphas, path):
        single = vault_model.deploy(alpha)
        np.testing.assert_allclose(s.deployed, single.deployed, atol=1e-15)


def test_beyond_the_limit_is_an_error_naming_vertex_and_alpha(vault_model):
    limit = vault_model.alpha_limit
    with pytest.raises(DeploymentLimitError) as info:
        vault_model.deploy(limit + 1.0)
    assert info.value.alpha_limit == pytest.approx(limit)
    assert f"crease segment {vault_model.limit_vertex}" in str(info.value)
    with pytest.raises(DeploymentLimitError, match="negative"):
        vault_model.deploy(-5.0)


def test_self_intersection_is_refused(vault_model):
    overlap = vault_model.overlap_alpha
    assert 60.0 < overlap < vault_model.alpha_limit
    vault_model.deploy(overlap - 0.01)
    with pytest.raises(SelfIntersectionError, match="overlaps itself") as info:
        vault_model.deploy(overlap + 0.5)
    assert info.value.alpha == pytest.approx(overlap + 0.5)
    # the 3D crease angle is the 2D angle / cos(alpha): it closes a full turn at the overlap
    flat_angle = 2.0 * math.asin(1.25 / 1.28125) * math.cos(math.radians(30.0))
    closing = math.degrees(math.acos(flat_angle / (2.0 * math.pi)))
    assert overlap == pytest.approx(closing, abs=0.5)


def test_mirror_partner_is_the_mirror_image(cone_model):
    s = cone_model.deploy(40.0)
    a, b = s.deployed
    # the crease plane is world y = const; plate 1 is plate 0 reflected in it
    plane = s.creases[0]["plane"]
    nrm = np.asarray(plane["normal"])
    d = (a - plane["origin"]) @ nrm
    np.testing.assert_allclose(a - 2 * d[:, None] * nrm, b, atol=1e-14)


def test_cone_overlaps_exactly_when_its_3d_angle_closes_a_full_turn(cone_model):
    # smooth: 90 deg of arc in the pattern become 90 / cos(alpha) in space, closing at
    # cos(alpha) = 1/4. Discrete (exact for the planar-quad cone): the chords keep their length
    # and r_3D = R cos(alpha), so sin(d3/2) = sin(d2/2) / cos(alpha) for the central angles of
    # one segment; the 48-gon closes when d3 = 360 / 48.
    n = cone_model.segments
    d2 = math.radians(90.0 / n)
    d3 = math.radians(360.0 / n)
    exact = math.degrees(math.acos(math.sin(d2 / 2) / math.sin(d3 / 2)))
    assert cone_model.overlap_alpha == pytest.approx(exact, abs=1e-6)
    assert abs(exact - math.degrees(math.acos(0.25))) < 0.02


def test_inflected_spline_crease_changes_kind_along_it():
    """A freeform crease with an inflection: Q4 (anticlastic) turns into Q2 (synclastic)."""
    model = CCUModel(
        make_design(
            crease={
                "profile": "spline",
                "segments": 60,
                "points": [[-1.2, 0.0], [-0.6, 0.5], [0.0, 0.3], [0.6, 0.1], [1.2, 0.5]],
            },
            rulings={"type": "orthogonal", "side": "left"},
        )
    )
    s = model.deploy(25.0)
    crease = s.creases[0]
    assert crease["kind"] == "mixed"
    kinds = crease["vertex_kinds"]
    assert kinds[1] == "anticlastic" and kinds[-2] == "synclastic"
    switch = [i for i in range(1, 59) if kinds[i] != kinds[i + 1]]
    assert len(switch) == 1  # one inflection
    assert_invariants(s)


@pytest.mark.parametrize(
    "crease",
    [
        {"profile": "elastica", "span": 2.0, "rise": 0.8, "segments": 60},
        {
            "profile": "polyline",
            "segments": 40,
            "points": [[-1.0, 0.0], [-0.5, 0.4], [0.0, 0.55], [0.5, 0.4], [1.0, 0.0]],
        },
    ],
)
def test_other_profiles_deploy_exactly(crease):
    model = CCUModel(
        make_design(
            crease=crease,
            rulings={"type": "conical", "apex": [0.1, -0.5]},
            layout={"type": "parallel", "plates": 4, "spacing": 0.08},
        )
    )
    for s in model.path([0.0, 10.0, 30.0]):
        assert_invariants(s)
        assert s.metrics["crease_planarity_max_relative"] < 1e-14


def test_profile_errors_are_design_errors_naming_the_section():
    from compas_ccu.errors import DesignError

    with pytest.raises(DesignError, match=r"\[crease\]: unknown key 'span'"):
        CCUModel(
            make_design(
                crease={"profile": "spline", "span": 2.0, "points": [[0, 0], [1, 1], [2, 0]]}
            )
        )


RULINGS = {
    "orthogonal": {"type": "orthogonal"},
    "cylindrical": {"type": "cylindrical", "direction": [0.2, -1.0]},
    "conical": {"type": "conical", "apex": [0.3, -3.0]},
    "angle": {"type": "angle", "gamma": 80.0},
}


@pytest.mark.parametrize("reference", [0.0, 0.03, 0.5, 0.97, 1.0])
@pytest.mark.parametrize("segments", [4, 16])
@pytest.mark.parametrize("rulings", list(RULINGS))
def test_the_design_state_is_reproduced_for_every_reference_vertex(rulings, segments, reference):
    """A reference vertex at an end of the crease (0.03 of 16 segments rounds to vertex 0) used to
    deploy orthogonal rulings 3 mm (16 segments) to 49 mm (4) away from the design while every
    invariant said 1e-16; cylindrical and conical ones reported limits up to 141.6 deg."""
    design = make_design(
        crease={"profile": "arc", "span": 2.5, "rise": 1.0, "segments": segments},
        rulings=RULINGS[rulings],
    )
    design.document["crease"]["reference"] = reference
    model = CCUModel(Design(design.document))
    g = model.geometry
    st = model.mechanism.deploy(g.design_alpha)
    miss = max(np.abs(st.near[0] - g.design_near).max(), np.abs(st.far[0] - g.design_far).max())
    assert miss < 1e-12 * model.size
    assert 0.0 < model.alpha_limit <= 90.0
    near_limit = 0.95 * model.alpha_limit
    alpha = np.asarray(model.deploy(near_limit, check=False).metrics["alpha_leading"])
    assert alpha[model.reference] == pytest.approx(near_limit, abs=1e-9)
    with pytest.raises(DeploymentLimitError, match="beyond the deployment limit"):
        model.deploy(min(model.alpha_limit + 1.0, 95.0))


def test_a_limit_at_90_degrees_names_the_reference_vertex():
    design = make_design(
        crease={"profile": "arc", "span": 2.5, "rise": 1.0, "segments": 16, "reference": 1.0},
        rulings=RULINGS["cylindrical"],
    )
    model = CCUModel(design)
    assert model.alpha_limit == 90.0
    with pytest.raises(DeploymentLimitError, match=r"the surface at reference vertex 16 stands"):
        model.deploy(120.0)


# -- lazy, batched crease records ---------------------------------------------------------------


@pytest.fixture(scope="module")
def multi_models(vault_model, quadrants_model):
    from compas_ccu.catalog import catalog_path
    from compas_ccu.model import load_model

    return {
        "vault": vault_model,
        "quadrants": quadrants_model,  # CCU and CCF creases
        "funnel": load_model(catalog_path("fig12c-funnel")),  # radial, 11 creases
    }


@pytest.mark.parametrize("name", ["vault", "quadrants", "funnel"])
def test_all_relations_equal_the_relations_of_each_crease(multi_models, name):
    """One vectorised call over every crease of every state: the same numbers, bit for bit."""
    model = multi_models[name]
    alphas = np.linspace(0.0, min(model.alpha_design, model.overlap_alpha), 5)
    states = model.mechanism.deploy(np.radians(alphas))
    batch = model.all_relations(states)
    for k in range(len(alphas)):
        for ci in range(len(model.mechanism.creases)):
            one = model.relations(states, k, ci)
            for field in one._fields:
                if field == "kinds":
                    assert batch.kinds[k][ci] == one.kinds
                else:
                    got, want = getattr(batch, field)[k, ci], getattr(one, field)
                    np.testing.assert_array_equal(got, want, err_msg=field)


def test_records_are_computed_when_first_read(vault_model):
    structure = vault_model.deploy(20.0)
    assert callable(structure._creases) and callable(structure._metrics)
    assert structure.deployed.shape == (10, 130, 3)  # the geometry is there at once
    creases = structure.creases
    assert not callable(structure._creases) and len(creases) == 9
    assert structure.creases is creases  # computed once
    assert structure.metrics["segments"] == 64 and not callable(structure._metrics)


def test_lazy_path_records_equal_each_state_alone(vault_model):
    """The records of a path, computed for all states at once, equal those of every state
    computed alone (and its contract survives a pickle round trip)."""
    import pickle

    from compas_ccu.kinematics.relations import crease_relations
    from compas_ccu.model.records import StateRecords

    alphas = np.linspace(0.0, 30.0, 7)
    path = vault_model.path(alphas)
    states = vault_model.mechanism.deploy(np.radians(alphas))
    for k, (structure, alpha) in enumerate(zip(path, alphas)):
        alone = vault_model.structure(states, k, float(alpha)).to_contract()
        assert structure.to_contract() == alone
        # and the records' angles are those of one crease at a time
        for ci, record in enumerate(alone["creases"]):
            link = vault_model.mechanism.creases[ci]
            hinge, other = vault_model.plates.crease_boundary(ci, states.near[k], states.far[k])
            rb = states.far[k, link.plate_b] - states.near[k, link.plate_b]
            rel = crease_relations(hinge, other - hinge, rb, states.plane_normals[k, ci])
            assert record["alpha"] == np.degrees(rel.alpha).tolist()
            assert record["sum_beta"] == np.degrees(rel.sum_beta[1:-1]).tolist()
    lazy = vault_model.deploy(12.0)
    copy = pickle.loads(pickle.dumps(lazy))
    assert copy.to_contract() == vault_model.deploy(12.0).to_contract()
    assert StateRecords(vault_model, states).creases(3) == path[3].creases


def test_metrics_keep_the_bounding_box_of_the_deployed_state(vault_model):
    structure = vault_model.deploy(20.0)
    box = np.ptp(structure.deployed.reshape(-1, 3), axis=0).tolist()
    structure.deployed = structure.deployed * 2.0  # moved before the metrics are read
    assert structure.metrics["bounding_box"] == box


def test_classify_is_vectorised_per_crease():
    from compas_ccu.kinematics.relations import classify

    two_pi = 2.0 * math.pi
    sums = np.array([[np.nan, two_pi - 0.1, two_pi, two_pi + 0.1, np.nan]] * 2)
    assert classify(sums[0], "ccu") == [None, "synclastic", "straight", "anticlastic", None]
    assert classify(sums, np.array(["ccu", "ccf"], dtype=object)) == [
        [None, "synclastic", "straight", "anticlastic", None],
        [None, "ccf", "ccf", "ccf", None],
    ]


@pytest.mark.parametrize(
    "name, fold_alpha, vertex_alpha",
    [
        # measured: every edge of Fig. 9e folds at 60.90 deg while its design alpha (30) is the
        # vertex angle on an inflection; Fig. 9d's point-load kink reads 29.68 at its vertex
        ("fig09e-freeform", 30.4506, 30.0),
        ("fig09d-funicular", 30.0116, 29.6797),
    ],
)
def test_crease_records_carry_the_fold_angle_of_every_edge(name, fold_alpha, vertex_alpha):
    """structure.json's per-edge fold angles, against the angle between the two quads'
    normals (another formula): for mirror partners 180 - fold = the angle between normals."""
    from compas_ccu.catalog import catalog_path
    from compas_ccu.key_figures import key_figures
    from compas_ccu.model import load_model

    model = load_model(catalog_path(name))
    s = model.deploy()
    n = model.segments
    ids = list(s.plate_ids)
    deployed = np.asarray(s.deployed, dtype=float)
    for c in s.creases:
        fold = np.asarray(c["fold_angles"])
        assert fold.shape == (n,)
        assert np.allclose(fold / 2.0, fold_alpha, atol=5e-5)
        a, b = (ids.index(p) for p in c["plates"])
        normals = []
        for plate, rows in ((a, c["vertices"][0]), (b, c["vertices"][1])):
            v = deployed[plate]
            rows = np.asarray(rows)
            other = rows + (n + 1) if rows[0] <= n else rows - (n + 1)
            p0, p1, q0 = v[rows[:-1]], v[rows[1:]], v[other[:-1]]
            nrm = np.cross(p1 - p0, q0 - p0)
            normals.append(nrm / np.linalg.norm(nrm, axis=1)[:, None])
        between = np.degrees(np.arccos(np.clip((normals[0] * normals[1]).sum(1), -1, 1)))
        assert np.allclose(np.minimum(between, 180 - between), np.minimum(fold, 180 - fold),
                           atol=1e-9)  # fmt: skip
    vertex = np.array([c["alpha"] for c in s.creases])
    assert np.isclose(vertex, vertex_alpha, atol=5e-5).any()  # the vertex that reads otherwise
    k = key_figures(model)
    assert (k.fold_alpha_min, k.fold_alpha_max) == pytest.approx((fold_alpha, fold_alpha),
                                                                 abs=5e-5)  # fmt: skip


@pytest.mark.parametrize("alpha", [10.0, 25.0, 40.0])
def test_the_fold_of_the_cone_is_the_analytic_one_edge_by_edge(cone_model, alpha):
    """The exact kinematic state of the circular-arc crease (the cone pair): every crease vertex
    lies R = 2 m from the apex, on a circle of radius R cos(alpha) at the height R sin(alpha)
    below it, so the fold between the two mirror cones across an edge of central angle d3
    (sin(d3/2) = sin(d2/2) / cos(alpha), d2 = 90 deg / n of the pattern) is
    2 atan(tan(alpha) / cos(d3/2)): slightly more than 2 alpha, the per-vertex angle."""
    n = cone_model.segments
    d2 = math.radians(90.0 / n)
    d3 = 2.0 * math.asin(math.sin(d2 / 2.0) / math.cos(math.radians(alpha)))
    exact = 2.0 * math.degrees(math.atan(math.tan(math.radians(alpha)) / math.cos(d3 / 2.0)))
    crease = cone_model.deploy(alpha).creases[0]
    np.testing.assert_allclose(crease["fold_angles"], exact, rtol=0, atol=1e-12)
    np.testing.assert_allclose(crease["fold_alpha"], exact / 2.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(crease["alpha"], alpha, rtol=0, atol=1e-12)  # the vertex angle
    assert exact / 2.0 - alpha == pytest.approx(
        {10.0: 0.00135, 25.0: 0.00358, 40.0: 0.00644}[alpha], abs=1e-5
    )


def test_bounding_box_is_the_extent_of_the_world_vertices():
    from compas_ccu.model import load_model

    model = load_model("examples/vault.toml")
    for structure in model.path([5.0, 22.0]):
        box = structure.metrics["bounding_box"]
        assert box == np.ptp(structure.deployed.reshape(-1, 3), axis=0).tolist()
