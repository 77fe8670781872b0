"""Plate bending curvature against the cylinder and the cone of the ultra-special case."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.design import Design
from compas_ccu.model import CCUModel
from compas_ccu.strips.curvature import plate_curvature


def cylinder(n: int, radius: float, height: float = 0.5, angle: float = math.pi / 2):
    phi = np.linspace(0.0, angle, n + 1)
    ring = np.c_[radius * np.cos(phi), radius * np.sin(phi), np.zeros_like(phi)]
    return np.concatenate([ring, ring + [0.0, 0.0, height]]), angle / n


@pytest.mark.parametrize("n", [8, 32, 128])
def test_cylinder_matches_the_discrete_closed_form(n):
    v, phi = cylinder(n, 2.0)
    k = plate_curvature(v)
    expected = phi / (2.0 * 2.0 * math.sin(phi / 2.0))
    np.testing.assert_allclose(np.abs(k), expected, rtol=1e-10)
    assert np.all(np.sign(k) == np.sign(k[0]))


def test_flat_strip_has_zero_curvature_and_sign_follows_the_normal():
    v, _ = cylinder(16, 1.0)
    flat = v.copy()
    flat[:, 1] = 0.0
    flat[:, 0] = np.r_[np.linspace(0, 1, 17), np.linspace(0, 1, 17)]
    assert np.abs(plate_curvature(flat)).max() == 0.0
    mirrored = v * np.array([1.0, 1.0, -1.0])  # reversed orientation of the quads
    np.testing.assert_allclose(plate_curvature(mirrored), -plate_curvature(v), rtol=1e-12)


def test_cone_curvature_is_tan_alpha_over_the_distance_to_the_apex():
    # orthogonal rulings on a flat circular crease of radius R deploy to a cone whose
    # generators reach the apex after R; at distance rho from it, kappa = tan(alpha) / rho
    errors = []
    for n in (24, 48, 96):
        d = Design(
            {
                "crease": {
                    "profile": "arc",
                    "radius": 2.0,
                    "angle": 90.0,
                    "segments": n,
                    "state": "flat",
                },
                "rulings": {"type": "orthogonal", "side": "inside"},
                "deployment": {"alpha": 40.0},
                "layout": {"type": "single", "width": 0.4},
            }
        )
        s = CCUModel(d).deploy()
        k = np.abs(plate_curvature(s.deployed))[0]
        t = math.tan(math.radians(40.0))
        err = max(
            np.abs(k[: n + 1] - t / 2.0).max() / (t / 2.0),
            np.abs(k[n + 1 :] - t / 1.6).max() / (t / 1.6),
        )
        errors.append(err)
    assert errors[-1] < 1e-4
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    np.testing.assert_allclose(orders, 2.0, atol=0.05)


def test_vectorised_over_plates_and_states(vault_model):
    states = vault_model.path([10.0, 30.0])
    stacked = np.stack([s.deployed for s in states])
    k = plate_curvature(stacked)
    assert k.shape == stacked.shape[:-1]
    np.testing.assert_array_equal(k[1], plate_curvature(states[1].deployed))
    # opening the vault bends the plates more
    assert np.abs(k[1]).mean() > np.abs(k[0]).mean()


@pytest.mark.parametrize("shape", [(5, 3), (6, 2), (2, 3), (7, 3)])
def test_bad_shapes_are_refused(shape):
    with pytest.raises(ValueError, match="2n \\+ 2, 3"):
        plate_curvature(np.zeros(shape))
