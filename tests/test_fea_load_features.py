"""Closed-form checks of the load-case features on both engines: lumped loads, spring supports,
hinge springs under load, hinge line forces (sign and size)."""

from __future__ import annotations

import numpy as np
import pytest
from tests.test_fea_engines import OPTIONS, column, grid, two_plates

from compas_ccu.fea.checks import resolve_hinge_forces
from compas_ccu.fea.loads import Action, nodal_loads
from compas_ccu.fea.problem import FEProblem, LoadPattern
from compas_ccu.materials import Material

UP = np.array([0.0, 0.0, 1.0])
X = np.array([1.0, 0.0, 0.0])
STRIP = Material.isotropic("strip", 1.0e9, 0.0, 1.0, 1.0e9)  # nu = 0: a plate strip is a beam


def strip(L=1.0, b=0.2, nx=16, ny=2):
    return grid(0.0, L, b, nx, ny)


@pytest.mark.slow
def test_simply_supported_strip_under_uniform_load(engine):
    """w_mid = 5 q L^4 / (384 EI), the load lumped by nodal_loads (surface action)."""
    L, b, t, q, nx, ny = 1.0, 0.2, 0.01, 10.0, 16, 2
    nodes, elements = strip(L, b, nx, ny)
    EI = STRIP.E1 * b * t**3 / 12.0
    loads = nodal_loads(elements, nodes, Action("q", q, "surface"), up=UP, span_axis=X, middle=0.5)
    assert loads[:, 2].sum() == pytest.approx(-q * L * b, rel=1e-12)
    ends = np.r_[column(0, ny), column(nx, ny)]
    prescribed = np.zeros((1, len(ends), 3))
    prescribed[:, ny + 1 :, 0] = np.nan  # a roller: no membrane action
    problem = FEProblem(
        nodes,
        elements,
        STRIP,
        t,
        1,
        fixed=ends,
        prescribed=prescribed,
        patterns=[LoadPattern("q", loads, np.array([1.0]))],
    )
    result = engine.solve(problem, **OPTIONS)
    assert result.converged, result.message
    mid = column(nx // 2, ny)
    w = -result.displacements[-1][mid, 2].mean()
    assert w == pytest.approx(5.0 * q * b * L**4 / (384.0 * EI), rel=0.01)
    assert result.reactions[-1][:, 2].sum() == pytest.approx(q * L * b, rel=1e-6)


@pytest.mark.slow
def test_springs_to_ground_nodes_add_the_support_settlement(engine):
    """The same strip on springs of stiffness K per end: w_mid grows by the settlement R / K."""
    L, b, t, q, nx, ny, K = 1.0, 0.2, 0.01, 10.0, 16, 2, 400.0
    nodes, elements = strip(L, b, nx, ny)
    EI = STRIP.E1 * b * t**3 / 12.0
    ends = np.r_[column(0, ny), column(nx, ny)]
    ground = len(nodes) + np.arange(len(ends))
    all_nodes = np.vstack([nodes, nodes[ends]])
    loads = np.zeros((len(all_nodes), 6))
    loads[: len(nodes)] = nodal_loads(
        elements, nodes, Action("q", q, "surface"), up=UP, span_axis=X, middle=0.5
    )
    stiffness = np.zeros((len(ends), 3))
    stiffness[:, 2] = K / (ny + 1)  # vertical springs, K per end
    fixed = np.r_[ends, ground]
    prescribed = np.zeros((1, len(fixed), 3))
    prescribed[0, : len(ends), 2] = np.nan  # the feet sit on the springs
    prescribed[0, ny + 1 : len(ends), 0] = np.nan
    problem = FEProblem(
        all_nodes,
        elements,
        STRIP,
        t,
        1,
        fixed=fixed,
        prescribed=prescribed,
        fixed_rotations=ground,
        springs=np.c_[ground, ends],
        spring_stiffness=stiffness,
        patterns=[LoadPattern("q", loads, np.array([1.0]))],
    )
    result = engine.solve(problem, **OPTIONS)
    assert result.converged, result.message
    settlement = q * L * b / 2.0 / K
    w_end = -result.displacements[-1][ends, 2]
    np.testing.assert_allclose(w_end, settlement, rtol=0.02)
    w = -result.displacements[-1][column(nx // 2, ny), 2].mean()
    assert w == pytest.approx(5.0 * q * b * L**4 / (384.0 * EI) + settlement, rel=0.01)
    # the ground nodes carry the load: their reactions are the spring forces
    assert result.reactions[-1][len(ends) :, 2].sum() == pytest.approx(q * L * b, rel=1e-6)


@pytest.mark.slow
def test_cantilever_through_a_spring_hinge_under_an_end_load(engine):
    """Plate A clamped, plate B on a rotational hinge spring k (N m/rad per m), end load P:
    tip deflection P (a + b)^3 / 3EI + P b^2 / (k B)."""
    n, t, P, k = 4, 0.008, 2.0, 400.0
    nodes, elements, ties, lengths, offset = two_plates(n, t)
    plywood = Material.isotropic("ply", 9.0e9, 0.0, 600.0, 30.0e6)
    EI = plywood.E1 * 1.0 * t**3 / 12.0
    clamp, tip = column(0, n), column(n, n, offset)
    loads = np.zeros((len(nodes), 6))
    loads[tip, 2] = -P / len(tip)
    problem = FEProblem(
        nodes,
        elements,
        plywood,
        t,
        2,
        ties=ties,
        tie_lengths=lengths,
        hinge_stiffness=k,
        fixed=clamp,
        fixed_rotations=clamp,
        patterns=[LoadPattern("P", loads, np.array([0.5, 1.0]))],
    )
    result = engine.solve(problem, **OPTIONS)
    assert result.converged, result.message
    w = -result.displacements[-1][tip, 2].mean()
    exact = P * 2.0**3 / (3.0 * EI) + P * 1.0**2 / (k * 1.0)
    assert w == pytest.approx(exact, rel=0.02)
    # the hinge passes the shear P to plate b: out-of-plane line force P / 1 m on average
    forces = result.tie_forces[-1]
    across, normal, along = resolve_hinge_forces(
        forces,
        lengths,
        np.tile([0.0, 1.0, 0.0], (len(ties), 1)),
        np.tile([0.0, 0.0, 1.0], (len(ties), 1)),
        np.tile([1.0, 0.0, 0.0], (len(ties), 1)),
    )
    assert (normal * lengths).sum() == pytest.approx(P, rel=0.01)


@pytest.mark.slow
def test_hinge_tension_has_the_sign_and_size_of_the_pull(engine):
    """Plate B pulled away from the hinge by P in its plane: tension P per metre of crease."""
    n, P = 4, 500.0
    nodes, elements, ties, lengths, offset = two_plates(n)
    clamp, far = column(0, n), column(n, n, offset)
    loads = np.zeros((len(nodes), 6))
    loads[far, 0] = P * lengths / lengths.sum()
    problem = FEProblem(
        nodes,
        elements,
        Material.isotropic("ply", 9.0e9, 0.3, 600.0, 30.0e6),
        0.008,
        1,
        ties=ties,
        tie_lengths=lengths,
        fixed=clamp,
        fixed_rotations=clamp,
        patterns=[LoadPattern("pull", loads, np.array([1.0]))],
    )
    result = engine.solve(problem, **OPTIONS)
    assert result.converged, result.message
    across, normal, along = resolve_hinge_forces(
        result.tie_forces[-1],
        lengths,
        np.tile([0.0, 1.0, 0.0], (len(ties), 1)),
        np.tile([0.0, 0.0, 1.0], (len(ties), 1)),
        np.tile([1.0, 0.0, 0.0], (len(ties), 1)),
    )
    assert (across * lengths).sum() == pytest.approx(P, rel=1e-6)
    np.testing.assert_allclose(across, P, rtol=0.01)  # Poisson: 0.35 % more at the middle
    assert normal.max() < 1e-6 * P and along.max() < 0.01 * P  # Poisson, symmetric
