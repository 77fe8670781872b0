"""Least-squares relaxation of the placed plates (docs/geometry.md §2: the fallback where creases
leave their plane): exact states stay put, exact solutions are recovered, the residual of impossible
problems is bounded and reported, the analytic Jacobian is right, bad input is refused."""

from __future__ import annotations

import json

import numpy as np
import pytest

from compas_ccu.catalog import catalog_design
from compas_ccu.design import Design
from compas_ccu.errors import CCUError, GeometryError
from compas_ccu.kinematics.levenberg_marquardt import levenberg_marquardt
from compas_ccu.kinematics.relaxation import (
    Relaxation,
    links_from_mechanism,
    relax,
    relax_states,
)
from compas_ccu.kinematics.relaxation_problem import RelaxationProblem
from compas_ccu.model import CCUModel, load_model
from compas_ccu.tolerances import SOLVER
from conftest import EXAMPLES


@pytest.fixture(scope="module")
def vault():
    model = load_model(EXAMPLES / "vault.toml")
    return model, links_from_mechanism(model.mechanism)


def inclined_model(segments=64, plates=6):
    """Crease planes inclined perpendicular to the actuation axis (paper Fig. 12a): planar at
    the design state (alpha = 30 deg), not planar in between."""
    return CCUModel(
        Design(
            {
                "crease": {
                    "profile": "arc",
                    "span": 2.5,
                    "rise": 1.0,
                    "segments": segments,
                    "state": "deployed",
                },
                "rulings": {"type": "orthogonal", "side": "inside"},
                "deployment": {"alpha": 30.0},
                "layout": {
                    "type": "inclined",
                    "plates": plates,
                    "spacing": 0.12,
                    "spacing_start": 0.10,
                    "spacing_end": 0.14,
                },
            }
        )
    )


def shared_consistent(near, far, links):
    """Copy every plate's near boundary from its parent's boundary (parents come first)."""
    for plate, parent, boundary in sorted(links):
        near[plate] = near[parent] if boundary == "near" else far[parent]
    return near, far


def test_links_from_mechanism_follow_the_plates(vault):
    model, links = vault
    assert links[0] == (1, 0, "far")
    assert (5, 0, "near") in links
    assert [plate for plate, _, _ in links] == list(range(1, 10))


@pytest.mark.parametrize("k", [0, 1])
def test_an_exact_state_is_left_unchanged(vault, k):
    model, links = vault
    st = model.mechanism.deploy(np.radians([10.0, 30.0]))
    r = relax(st.near[k], st.far[k], model.reference_lengths, links)
    assert isinstance(r, Relaxation)
    assert r.converged and r.status > 0
    assert r.displacement < 1e-12
    assert r.max_strain < 1e-13
    assert r.initial_max_strain < 1e-13
    assert r.quad_planarity < 1e-12
    assert r.initial_hinge_gap == 0.0
    assert r.near.shape == r.far.shape == (10, 65, 3)
    assert r.strain.shape == (10, 64, 6)
    assert r.max_strain_per_plate.shape == r.displacement_per_plate.shape == (10,)
    np.testing.assert_allclose(r.far, st.far[k], atol=1e-12, rtol=0)


def test_a_perturbed_state_with_an_exact_solution_is_recovered(vault):
    model, links = vault
    st = model.mechanism.deploy(np.radians([20.0]))
    near, far = st.near[0].copy(), st.far[0].copy()
    rng = np.random.default_rng(7)
    far[1:] += rng.normal(0.0, 1e-3, far[1:].shape)
    near, far = shared_consistent(near, far, links)
    r = relax(near, far, model.reference_lengths, links)
    assert r.converged
    assert r.initial_max_strain > 1e-2  # the guess is far from isometric (short quads)
    assert r.initial_quad_planarity > 1e-4
    assert r.initial_hinge_gap == 0.0
    assert r.max_strain < 1e-10
    assert r.quad_planarity < 1e-10
    assert 1e-3 < r.displacement < 1e-2
    assert r.nfev < 20
    assert r.cost < 1e-18
    # with the leading plate held the mechanism is locked, so the positions come back too
    np.testing.assert_allclose(r.far, st.far[0], atol=1e-8, rtol=0)
    # hinge coincidence is exact by construction
    for plate, parent, boundary in links:
        hinge = r.near[parent] if boundary == "near" else r.far[parent]
        assert np.array_equal(r.near[plate], hinge)


def test_an_inconsistent_guess_hinge_takes_the_parent_vertices(vault):
    model, links = vault
    st = model.mechanism.deploy(np.radians([20.0]))
    near = st.near[0].copy()
    near[2, 10] += [0.0, 2e-3, 0.0]  # plate 2's crease vertex off plate 1's far boundary
    r = relax(near, st.far[0], model.reference_lengths, links)
    assert abs(r.initial_hinge_gap - 2e-3) < 1e-15
    assert r.initial_max_strain < 1e-13  # the start uses the parent's vertex: exact again
    assert r.max_strain < 1e-13
    assert abs(r.displacement - 2e-3) < 1e-15  # that vertex moved back, nothing else
    assert r.displacement_per_plate[1] < 1e-12


def test_conflicting_lengths_on_a_shared_crease_split_the_strain(vault):
    """Plate 3's far edges 0.2 % longer than plate 4's near edges, which are the same
    segments: no exact solution; least squares splits the conflict into about +-0.1 %."""
    model, links = vault
    st = model.mechanism.deploy(np.radians([20.0]))
    ref = model.reference_lengths.copy()
    ref[3, :, 2] *= 1.002
    r = relax(st.near[0], st.far[0], ref, links)
    assert r.converged
    assert abs(r.initial_max_strain - 0.002 / 1.002) < 1e-12
    assert 0.999e-3 < r.max_strain < 1.002e-3  # measured 1.00043e-3
    # the conflict shows where it is: plate 3's cd sides shrink, plate 4's ab sides stretch
    assert np.all((-1.002e-3 < r.strain[3, :, 2]) & (r.strain[3, :, 2] < -0.99e-3))
    assert np.all((0.99e-3 < r.strain[4, :, 0]) & (r.strain[4, :, 0] < 1.002e-3))
    assert np.abs(r.strain[3, :, :2]).max() < 2e-5 and np.abs(r.strain[3, :, 3:]).max() < 2e-5
    assert np.abs(r.strain[4, :, 1:]).max() < 2e-5
    assert r.max_strain_per_plate[[0, 5, 6, 7, 8, 9]].max() < 1e-12  # the other branch
    assert r.displacement_per_plate[[5, 6, 7, 8, 9]].max() < 1e-11
    assert 1e-3 < r.displacement < 2e-2  # measured 7.85 mm at the far end of plate 4
    assert 6.0e-5 < r.cost < 6.8e-5  # ~ 64 * 2 * (1e-3) ** 2 / 2
    assert r.quad_planarity < 1e-9


def test_a_leaf_plate_with_longer_far_edges_reshapes_almost_isometrically(vault):
    """Plate 9 (a leaf) with 0.2 % longer far edges: a slightly different planar-quad strip
    nearly fits (a trapezoid's diagonals change by far less), the residual is small but not 0."""
    model, links = vault
    st = model.mechanism.deploy(np.radians([20.0]))
    ref = model.reference_lengths.copy()
    ref[9, :, 2] *= 1.002
    r = relax(st.near[0], st.far[0], ref, links)
    assert r.converged
    assert abs(r.initial_max_strain - 0.002 / 1.002) < 1e-12
    assert 1e-5 < r.max_strain < 5e-5  # measured 2.12e-5: ~100 times less than before
    assert r.max_strain_per_plate[9] == r.max_strain
    assert r.quad_planarity < 1e-9  # the weighting prefers planar quads
    assert 1e-3 < r.displacement_per_plate[9] < 2e-2  # measured 6.6 mm
    assert r.displacement_per_plate[:8].max() < 1e-9
    assert r.cost > 1e-8


@pytest.fixture(scope="module")
def inclined():
    model = inclined_model()
    st = model.mechanism.deploy(np.radians([0.0, 10.0, 20.0, 30.0]))
    links = links_from_mechanism(model.mechanism)
    return model, st, links


def test_relax_states_on_non_planar_creases(inclined):
    model, st, links = inclined
    assert st.planarity[[1, 2]].max() > 1e-4  # the creases leave their planes in between
    rs = relax_states(st.near, st.far, model.reference_lengths, links)
    assert len(rs) == 4
    for k in (0, 3):  # flat and design state: exact
        assert rs[k].displacement < 1e-12 and rs[k].max_strain < 1e-13
    for k, (before, after) in {1: (5.74e-5, 3.08e-5), 2: (1.482e-4, 3.47e-5)}.items():
        r = rs[k]
        assert r.converged
        assert abs(r.initial_max_strain - before) < 0.01 * before
        assert abs(r.max_strain - after) < 0.01 * after  # bounded, not zero: no exact solution
        assert r.max_strain < 0.6 * r.initial_max_strain
        assert r.max_strain_per_plate[0] < 1e-13  # the leading plate is held and exact
        assert r.quad_planarity < 1e-4
        assert r.displacement < 2e-3
    # the relaxation starts where the mechanism leaves off
    mech = model.invariants(st).isometry
    assert mech[1] > 1e-6 and mech[2] > 1e-6


def test_planarity_weight_trades_planarity_for_strain(inclined):
    model, st, links = inclined
    ref = model.reference_lengths
    soft = relax(st.near[2], st.far[2], ref, links, planarity_weight=1.0)
    stiff = relax(st.near[2], st.far[2], ref, links, planarity_weight=10.0)
    assert stiff.converged and soft.converged
    assert stiff.quad_planarity < 0.1 * soft.quad_planarity
    assert stiff.max_strain > 2.0 * soft.max_strain


def test_holding_more_plates_only_adds_constraints(inclined):
    model, st, links = inclined
    ref = model.reference_lengths
    one = relax(st.near[2], st.far[2], ref, links)
    two = relax(st.near[2], st.far[2], ref, links, fixed=(0, 3))
    assert two.fixed == (0, 3)
    assert two.displacement_per_plate[3] == 0.0
    assert two.max_strain >= one.max_strain - 1e-12
    assert two.cost >= one.cost - 1e-15


def test_dense_and_sparse_subproblem_solvers_agree():
    model = inclined_model(segments=12, plates=4)
    st = model.mechanism.deploy(np.radians([15.0]))
    links = links_from_mechanism(model.mechanism)
    args = (st.near[0], st.far[0], model.reference_lengths, links)
    exact = relax(*args, tr_solver="exact")
    lsmr = relax(*args, tr_solver="lsmr")
    auto = relax(*args)  # 3 * 3 * 13 = 117 unknowns: dense
    assert exact.converged and lsmr.converged
    assert exact.initial_max_strain > 1e-5
    assert abs(exact.cost - lsmr.cost) < 1e-9 * exact.cost
    assert abs(exact.max_strain - lsmr.max_strain) < 1e-6 * exact.max_strain
    assert auto.cost == exact.cost


def _finite_difference(problem, pos, h=1e-7):
    x0 = pos[~problem.held].ravel()
    out = np.empty((problem.nres, x0.size))
    for i in range(x0.size):
        xp, xm = x0.copy(), x0.copy()
        xp[i] += h
        xm[i] -= h
        out[:, i] = problem.residuals(problem.positions(xp, pos)) - problem.residuals(
            problem.positions(xm, pos)
        )
    return out / (2.0 * h)


@pytest.mark.parametrize("weight", [1.0, 2.5])
def test_analytic_jacobian_matches_finite_differences(weight):
    model = inclined_model(segments=10, plates=5)
    st = model.mechanism.deploy(np.radians([15.0]))
    links = links_from_mechanism(model.mechanism)
    p, m = st.near.shape[1], st.near.shape[2]
    problem = RelaxationProblem(p, m - 1, model.reference_lengths, links, (0,), weight)
    rng = np.random.default_rng(3)
    pos = problem.start(st.near[0], st.far[0]) + rng.normal(0.0, 5e-3, (problem.node_rep.size, 3))
    jac = problem.jacobian(pos)
    assert jac.shape == (7 * 4 * 10, 3 * problem.nfree)  # 4 moving plates of 10 quads
    # one 3-block per free quad vertex in every row: 6 x 2 for the lengths, 4 for planarity
    free = problem.free_index[problem.quads] >= 0  # (40, 4)
    pairs = free[:, [0, 1, 2, 3, 0, 1]].astype(int) + free[:, [1, 2, 3, 0, 2, 3]]
    assert jac.nnz == 3 * (pairs.sum() + free.sum())
    assert not free.all()  # held crease vertices are not unknowns
    dense = jac.toarray()
    fd = _finite_difference(problem, pos)
    scale = np.abs(dense).max()
    assert scale > 1.0
    assert np.abs(dense - fd).max() < 1e-6 * scale
    # the planarity rows really are exercised (non-planar quads, non-zero curvature terms)
    assert np.median(np.abs(problem.residuals(pos)[-40:])) > 1e-3


def test_summary_is_plain_json(vault):
    model, links = vault
    st = model.mechanism.deploy(np.radians([20.0]))
    ref = model.reference_lengths.copy()
    ref[9, :, 2] *= 1.002
    s = relax(st.near[0], st.far[0], ref, links).summary()
    back = json.loads(json.dumps(s))
    assert back == s
    assert isinstance(s["max_strain"], float) and isinstance(s["converged"], bool)
    assert len(s["max_strain_per_plate"]) == 10
    assert s["initial_max_strain"] > s["max_strain"] > 0.0


# -- bad input ---------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def small():
    model = inclined_model(segments=6, plates=3)
    st = model.mechanism.deploy(np.radians([20.0]))
    return st.near[0], st.far[0], model.reference_lengths, links_from_mechanism(model.mechanism)


@pytest.mark.parametrize(
    "change, error, words",
    [
        (lambda a: {**a, "far": a["far"][:, :-1]}, GeometryError, "same shape"),
        (lambda a: {**a, "near": a["near"][0], "far": a["far"][0]}, GeometryError, "(p, n + 1"),
        (lambda a: {**a, "ref": a["ref"][:, :-1]}, GeometryError, "reference_lengths"),
        (lambda a: {**a, "ref": a["ref"] * 0.0}, GeometryError, "positive"),
        (lambda a: {**a, "ref": -a["ref"]}, GeometryError, "positive"),
        (lambda a: {**a, "ref": a["ref"] * np.nan}, GeometryError, "positive"),
        (lambda a: {**a, "near": a["near"] + np.inf}, GeometryError, "finite"),
        (lambda a: {**a, "links": [*a["links"], (3, 0, "far")]}, GeometryError, "not exist"),
        (lambda a: {**a, "links": [(1, 0, "far"), (2, 7, "far")]}, GeometryError, "parent 7"),
        (lambda a: {**a, "links": [(1, 2, "far"), (2, 0, "far")]}, GeometryError, "before"),
        (lambda a: {**a, "links": [(1, 0, "far"), (2, 2, "far")]}, GeometryError, "before"),
        (lambda a: {**a, "links": [(1, 0, "side"), (2, 0, "near")]}, GeometryError, "'side'"),
        (lambda a: {**a, "links": [(1, 0, "far")]}, GeometryError, "no link"),
        (lambda a: {**a, "links": [*a["links"], (1, 0, "far")]}, GeometryError, "more than one"),
        (lambda a: {**a, "links": [(1, 0)]}, GeometryError, "(plate, parent, boundary)"),
        (lambda a: {**a, "fixed": (5,)}, GeometryError, "fixed plate 5"),
        (lambda a: {**a, "fixed": ()}, CCUError, "at least one"),
        (lambda a: {**a, "planarity_weight": -1.0}, CCUError, "planarity_weight"),
        (lambda a: {**a, "tr_solver": "qr"}, CCUError, "tr_solver"),
    ],
)
def test_bad_input_is_refused_with_a_clear_error(small, change, error, words):
    near, far, ref, links = small
    a = change(
        {
            "near": near,
            "far": far,
            "ref": ref,
            "links": links,
            "fixed": (0,),
            "planarity_weight": 1.0,
            "tr_solver": "auto",
        }
    )
    with pytest.raises(error) as info:
        relax(
            a["near"],
            a["far"],
            a["ref"],
            a["links"],
            fixed=a["fixed"],
            planarity_weight=a["planarity_weight"],
            tr_solver=a["tr_solver"],
        )
    assert isinstance(info.value, ValueError)
    assert words in str(info.value)


def test_a_degenerate_guess_quad_is_refused(small):
    near, far, ref, links = small
    far = far.copy()
    far[2, 3] = near[2, 4]  # quad 3's diagonal b-d has zero length
    with pytest.raises(GeometryError, match="plate 2, quad 3"):
        relax(near, far, ref, links)


def test_relax_states_wants_stacks(small):
    near, far, ref, links = small
    with pytest.raises(GeometryError, match=r"\(k, p, n \+ 1, 3\)"):
        relax_states(near, far, ref, links)
    rs = relax_states(near[None], far[None], ref, links, planarity_weight=2.0)
    assert len(rs) == 1 and rs[0].converged


# -- the Levenberg-Marquardt solver (default) against scipy's least_squares (reference) ---------
@pytest.fixture(
    scope="module",
    params=[
        ("fig12a-asymmetric", (10.0, 17.5, 25.0)),
        pytest.param(("fig12c-funnel", (12.5, 22.5)), marks=pytest.mark.slow),  # ~7 s
    ],
    ids=["fig12a-inclined", "fig12c-radial"],
)
def both_solvers(request):
    name, alphas = request.param
    model = CCUModel(catalog_design(name))
    st = model.mechanism.deploy(np.radians(alphas))
    args = (st.near, st.far, model.reference_lengths, links_from_mechanism(model.mechanism))
    return relax_states(*args), relax_states(*args, solver="scipy")


def test_levenberg_marquardt_reaches_the_residuals_of_scipy_least_squares(both_solvers):
    """Same minimum to the solver tolerance (measured: cost within 1e-12 relative, strain and
    planarity within 2e-7, vertices within 4e-8 m), in 5-9 evaluations against scipy's 5-38."""
    for lm, ref in zip(*both_solvers):
        assert lm.solver == "lm" and ref.solver == "scipy"
        assert lm.converged and ref.converged
        assert ref.max_strain < 0.5 * ref.initial_max_strain  # a real relaxation
        assert lm.initial_max_strain == ref.initial_max_strain
        assert abs(lm.cost - ref.cost) < 1e-10 * ref.cost
        assert abs(lm.max_strain - ref.max_strain) < 1e-5 * ref.max_strain
        assert abs(lm.quad_planarity - ref.quad_planarity) < 1e-5 * ref.quad_planarity
        np.testing.assert_allclose(lm.near, ref.near, atol=1e-6, rtol=0)
        np.testing.assert_allclose(lm.far, ref.far, atol=1e-6, rtol=0)
        np.testing.assert_allclose(lm.max_strain_per_plate, ref.max_strain_per_plate, rtol=1e-4)
        assert lm.optimality < 1e-10
        assert lm.nfev <= 15 and lm.njev <= lm.nfev
        assert lm.summary()["solver"] == "lm"


def test_the_banded_normal_equations_are_those_of_the_sparse_jacobian():
    model = inclined_model(segments=10, plates=5)
    st = model.mechanism.deploy(np.radians([15.0]))
    links = links_from_mechanism(model.mechanism)
    p, m = st.near.shape[1], st.near.shape[2]
    problem = RelaxationProblem(p, m - 1, model.reference_lengths, links, (0,), 1.5)
    rng = np.random.default_rng(5)
    pos = problem.start(st.near[0], st.far[0]) + rng.normal(0.0, 1e-3, (problem.node_rep.size, 3))
    r = problem.quad_residuals(pos)
    ab, g = problem.normal_equations(pos, r)
    jac = problem.jacobian(pos).toarray()[:, problem.columns]  # unknowns in the banded order
    full = jac.T @ jac
    size = 3 * problem.nfree
    assert ab.shape == (problem.band + 1, size)
    # reverse Cuthill-McKee: 4 boundaries of 11 free vertices, plate by plate ~ 3 x 11 apart
    assert problem.band < 3 * 6
    offsets = np.subtract.outer(np.arange(size), np.arange(size))
    assert np.all(full[offsets > problem.band] == 0.0)
    rows, cols = np.nonzero(offsets >= 0)
    keep = offsets[rows, cols] <= problem.band
    rows, cols = rows[keep], cols[keep]
    np.testing.assert_allclose(ab[rows - cols, cols], full[rows, cols], rtol=1e-12, atol=1e-9)
    flat = np.concatenate([r[:, :6].ravel(), r[:, 6]])
    np.testing.assert_array_equal(flat, problem.residuals(pos))
    np.testing.assert_allclose(g, jac.T @ flat, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("solver", ["lm", "scipy"])
def test_a_relaxation_that_runs_out_of_evaluations_says_it_did_not_converge(solver):
    model = CCUModel(catalog_design("fig12a-asymmetric"))
    structure, r = model.relax(17.5, solver=solver, max_nfev=2)
    assert not r.converged and r.status == 0
    assert "maximum number of function evaluations" in r.message
    assert r.nfev == 2
    assert r.optimality > 1e-6  # far from stationary: the gradient says so too
    assert r.max_strain < r.initial_max_strain  # the one step taken is kept and reported
    assert structure.metrics["relaxation"]["converged"] is False
    assert structure.metrics["relaxation"]["solver"] == solver


def _dense_lm(residuals, jacobian, x0, **options):
    def linearise(x, r):
        jac = jacobian(x)
        return jac, jac.T @ r, (jac**2).sum(axis=0)

    def solve(jac, g, damping, scale):
        lower = np.linalg.cholesky(jac.T @ jac + damping * np.diag(scale))
        return -np.linalg.solve(lower.T, np.linalg.solve(lower, g))

    tolerances = {"ftol": SOLVER, "xtol": SOLVER, "gtol": SOLVER, "max_nfev": 200, **options}
    return levenberg_marquardt(residuals, linearise, solve, np.asarray(x0, float), **tolerances)


def test_levenberg_marquardt_solves_rosenbrock():
    x, out = _dense_lm(
        lambda x: np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]]),
        lambda x: np.array([[-20.0 * x[0], 10.0], [-1.0, 0.0]]),
        [-1.2, 1.0],
    )
    assert out["status"] > 0
    np.testing.assert_allclose(x, [1.0, 1.0], atol=1e-10)
    assert out["cost"] < 1e-20
    assert out["nfev"] < 100 and out["njev"] <= out["nfev"]


def test_levenberg_marquardt_that_cannot_converge_reports_it():
    def residuals(x):
        return np.array([x[0] - 3.0, x[1] + 1.0])

    def jacobian(x):
        return np.eye(2)

    # the budget: stops after max_nfev evaluations with the best point so far
    x, out = _dense_lm(residuals, jacobian, [0.0, 0.0], ftol=None, xtol=None, gtol=0.0, max_nfev=4)
    assert out["status"] == 0 and out["nfev"] == 4
    np.testing.assert_allclose(x, [3.0, -1.0], atol=1e-9)  # solved, but no test could say so

    # steps into a region where the residuals are not finite are refused (the step shrinks)
    def walled(x):
        return np.array([x[0] - 3.0, x[1]]) if x[0] < 1.0 else np.array([np.nan, 0.0])

    x, out = _dense_lm(walled, jacobian, [0.0, 0.0], max_nfev=12)
    assert out["status"] == 0 and 0.0 < x[0] < 1.0 and np.isfinite(out["cost"])

    # a linear system that cannot be solved for any damping: status -1, nothing moves
    def singular(jac, g, damping, scale):
        raise np.linalg.LinAlgError("not positive definite")

    x, out = levenberg_marquardt(
        residuals,
        lambda x, r: (None, r, np.ones(2)),
        singular,
        np.zeros(2),
        ftol=SOLVER,
        xtol=SOLVER,
        gtol=SOLVER,
        max_nfev=50,
    )
    assert out["status"] == -1 and out["nfev"] == 1
    assert "could not be solved" in out["message"]
    np.testing.assert_array_equal(x, [0.0, 0.0])


@pytest.mark.parametrize(
    "options, words",
    [
        ({"solver": "newton"}, "solver must be 'lm' or 'scipy'"),
        ({"max_nfev": 0}, "max_nfev"),
        ({"max_nfev": 2.5}, "max_nfev"),
        ({"ftol": -1.0}, "ftol"),
        ({"gtol": np.nan}, "gtol"),
        ({"ftol": None, "xtol": None, "gtol": 0.0}, "at least one of ftol, xtol and gtol"),
    ],
)
def test_bad_solver_options_are_refused(small, options, words):
    near, far, ref, links = small
    with pytest.raises(CCUError, match=words):
        relax(near, far, ref, links, **options)


def test_the_solvers_agree_on_a_small_problem_with_either_subproblem_solver(small):
    near, far, ref, links = small
    out = {
        (solver, tr): relax(near, far, ref, links, solver=solver, tr_solver=tr)
        for solver in ("lm", "scipy")
        for tr in ("exact", "lsmr")
    }
    costs = np.array([r.cost for r in out.values()])
    assert all(r.converged for r in out.values())
    assert costs.min() > 0.0 and costs.max() - costs.min() < 1e-9 * costs.min()
    assert relax(near, far, ref, links).cost == out["lm", "exact"].cost  # auto: exact
