from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.model import CCUModel
from conftest import make_design

RULINGS = {
    "cylindrical": {"type": "cylindrical", "direction": [0.3, -1.0]},
    "conical": {"type": "conical", "apex": [0.5, -0.8]},
    "angle": {"type": "angle", "gamma": 70.0},
}


def relations_at(n, rulings, alpha=30.0, side="inside"):
    d = make_design(
        crease={"profile": "catenary", "span": 2.0, "rise": 0.7, "segments": n},
        rulings={**rulings, "side": side},
    )
    m = CCUModel(d)
    states = m.mechanism.deploy(math.radians(alpha))
    return m.relations(states, 0, 0)


@pytest.mark.parametrize("kind", sorted(RULINGS))
def test_eq2_and_eq5_converge_at_second_order(kind):
    """alpha' = cot(gamma) kappa_2D tan(alpha) (Eq. 2) and cos(alpha) = kappa_2D / kappa_3D
    (Eq. 5 / Eq. 8) hold up to O(h^2) on the exact discrete model, for gamma != 90 deg."""
    errors = []
    for n in (40, 80, 160):
        rel = relations_at(n, RULINGS[kind])
        inner = slice(2, -2)
        errors.append([np.nanmax(np.abs(rel.eq2[inner])), np.nanmax(np.abs(rel.eq5[inner]))])
    errors = np.array(errors)
    assert errors[0, 0] > 1e-6  # the relations are not trivially satisfied ...
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all((orders > 1.9) & (orders < 2.1)), orders  # ... they converge, second order


def test_orthogonal_rulings_satisfy_eq8_exactly_and_alpha_is_constant():
    rel = relations_at(64, {"type": "orthogonal"}, alpha=40.0)
    inner = slice(1, -1)
    np.testing.assert_allclose(rel.eq5[inner], 0.0, atol=1e-13)
    np.testing.assert_allclose(rel.segment_alpha, rel.segment_alpha[0], atol=1e-13)
    np.testing.assert_allclose(rel.gamma_a[inner], math.pi / 2, atol=1e-13)


def test_planar_crease_has_zero_torsion_and_eq4_holds():
    rel = relations_at(64, RULINGS["conical"])
    assert np.nanmax(np.abs(rel.torsion)) < 1e-12
    assert np.nanmax(np.abs(rel.eq4)) < 1e-12


@pytest.mark.parametrize("side,kind", [("inside", "synclastic"), ("outside", "anticlastic")])
def test_sum_beta_classification(side, kind):
    rel = relations_at(
        32,
        RULINGS["cylindrical"]
        if side == "inside"
        else {"type": "cylindrical", "direction": [0.3, 1.0]},
        side=side,
    )
    sums = rel.sum_beta[1:-1]
    assert np.all(sums < 2 * math.pi) if kind == "synclastic" else np.all(sums > 2 * math.pi)
    assert set(rel.kinds[1:-1]) == {kind}
    # CCU: beta_0 = beta_3, beta_1 = beta_2, gamma_0 = gamma_3
    b = rel.sector_angles[1:-1]
    np.testing.assert_allclose(b[:, 0], b[:, 3], atol=1e-12)
    np.testing.assert_allclose(b[:, 1], b[:, 2], atol=1e-12)
    np.testing.assert_allclose(rel.gamma_a[1:-1], rel.gamma_b[1:-1], atol=1e-12)
    half = b[:, 0] + b[:, 1]
    assert np.all(half < math.pi) if kind == "synclastic" else np.all(half > math.pi)
