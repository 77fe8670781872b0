"""The four quadrants of one planar crease (paper Fig. 2 / Fig. 3, docs/geometry.md §1)."""

from __future__ import annotations

import math

import numpy as np
import pytest


@pytest.mark.parametrize("alpha", [0.0, 15.0, 35.0, 60.0])
def test_four_quadrants_kinds_sector_angles_and_gamma(quadrants_model, alpha):
    s = quadrants_model.deploy(alpha)
    kinds = {tuple(c["plates"]): c["kind"] for c in s.creases}
    assert kinds == {(0, 1): "synclastic", (0, 2): "ccf", (2, 3): "anticlastic", (1, 3): "ccf"}
    states = quadrants_model.mechanism.deploy(math.radians(alpha))
    for ci, crease in enumerate(quadrants_model.mechanism.creases):
        rel = quadrants_model.relations(states, 0, ci)
        b = rel.sector_angles[1:-1]
        sums = rel.sum_beta[1:-1]
        if crease.relation == "ccf":  # developable: one sheet folded
            np.testing.assert_allclose(sums, 2 * math.pi, atol=1e-12)
            np.testing.assert_allclose(rel.gamma_a[1:-1] + rel.gamma_b[1:-1], math.pi, atol=1e-12)
            assert np.all((b[:, 0] + b[:, 1] < math.pi) != (b[:, 2] + b[:, 3] < math.pi))
        else:  # mirror sheets
            np.testing.assert_allclose(b[:, 0], b[:, 3], atol=1e-12)
            np.testing.assert_allclose(b[:, 1], b[:, 2], atol=1e-12)
            np.testing.assert_allclose(rel.gamma_a[1:-1], rel.gamma_b[1:-1], atol=1e-12)
    assert s.max_invariant_error < 1e-12


def test_ccf_rulings_are_collinear_in_the_pattern(quadrants_model):
    flat = quadrants_model.flat()
    n = quadrants_model.segments
    crease = flat[0, : n + 1, :2]
    ra = flat[0, n + 1 :, :2] - crease  # plate 0 (Q2 / Q1 leading plate)
    rc = flat[2, n + 1 :, :2] - crease  # its CCF continuation
    cross = ra[:, 0] * rc[:, 1] - ra[:, 1] * rc[:, 0]
    np.testing.assert_allclose(cross, 0.0, atol=1e-14)
    assert np.all(np.einsum("ij,ij->i", ra, rc) < 0.0)  # opposite sides of the crease


def test_flat_folded_mirror_partners_coincide(quadrants_model):
    flat = quadrants_model.flat()
    np.testing.assert_allclose(flat[1], flat[0], atol=1e-14)
    np.testing.assert_allclose(flat[3], flat[2], atol=1e-14)
    assert np.all(flat[..., 2] == 0.0)


def test_ccf_fold_angle_and_ccu_fold_angle(quadrants_model):
    """CCU fold angle between mirror plates is 2 alpha, CCF fold angle is pi - 2 alpha."""
    alpha = 35.0
    states = quadrants_model.mechanism.deploy(math.radians(alpha))
    j = quadrants_model.segments // 2  # quad at the reference vertex
    near, far = states.near[0], states.far[0]

    def quad_normal(p):
        a, b, d = near[p, j], near[p, j + 1], far[p, j]
        nrm = np.cross(b - a, d - a)
        return nrm / np.linalg.norm(nrm)

    def dihedral(p, q):
        return math.degrees(math.acos(abs(quad_normal(p) @ quad_normal(q))))

    psi = math.degrees(states.tilts[0, j])
    assert dihedral(0, 1) == pytest.approx(2 * psi, abs=1e-9)
    assert dihedral(0, 2) == pytest.approx(2 * psi, abs=1e-9)  # = pi - (pi - 2 alpha) folded
