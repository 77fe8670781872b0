"""Interpenetration of thick plates: unit cases with known depths, and along deployment paths."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.catalog import catalog_path
from compas_ccu.errors import SelfIntersectionError
from compas_ccu.model import load_model
from compas_ccu.thickness import ThickModel, solid_faces, vertex_offsets
from compas_ccu.thickness.collision import plate_contacts

T = 0.008


def _strip(z=0.0, tilt=None, n=4, x0=0.0):
    """A flat 1 m x 0.3 m strip at height z (or standing upright across x = x0 if tilt)."""
    s = np.linspace(0.0, 1.0, n + 1)
    if tilt is None:
        near = np.c_[s, np.zeros_like(s), np.full_like(s, z)]
        far = near + [0.0, 0.3, 0.0]
    else:  # upright strip along y, crossing the first one
        near = np.c_[np.full_like(s, x0), s * 0.3 - 0.0 + 0.0, np.full_like(s, -0.2)]
        far = near + [0.0, 0.0, 0.4]
    return near, far


def _contacts(strips):
    near = np.stack([s[0] for s in strips])[None]
    far = np.stack([s[1] for s in strips])[None]
    nu = vertex_offsets(near, far)
    zero = np.zeros(near.shape[:-1])
    faces = solid_faces(near, far, nu, T, zero, zero)
    return plate_contacts(near, far, nu, faces, T, pairs=[(0, 1), (1, 0)])


@pytest.mark.parametrize("z, depth", [(0.006, 0.002), (0.004, 0.004), (0.0079, 0.0001)])
def test_known_penetration_depth(z, depth):
    d, clearance, crossing, _ = _contacts([_strip(), _strip(z)])
    assert d[0, 0] == pytest.approx(depth, abs=1e-15)
    assert clearance[0, 0] == 0.0
    assert not crossing.any()


@pytest.mark.parametrize("z, gap", [(0.008, 0.0), (0.010, 0.002), (0.05, 0.042)])
def test_known_clearance(z, gap):
    d, clearance, _, _ = _contacts([_strip(), _strip(z)])
    assert clearance[0, 0] == pytest.approx(gap, abs=1e-15)
    assert d[0, 0] <= 1e-15  # touching face on face is not interpenetration


def test_crossing_without_vertex_inside():
    """An upright strip through the middle of a flat one: no vertex inside, but a crossing."""
    d, _, crossing, _ = _contacts([_strip(), _strip(tilt=True, x0=0.55)])
    assert d.max() <= 0.0
    assert crossing[0, 0]


def test_flat_stack_and_vault_path_do_not_interpenetrate(vault_model):
    thick = ThickModel(vault_model, thickness=T)
    report = thick.collisions(np.linspace(0.0, 30.0, 16))
    assert report.ok and report.first is None
    assert report.penetration.max() < 1e-12
    # closed folded: plates two apart are separated by exactly one plate thickness
    assert report.clearance[0] == pytest.approx(T, abs=1e-12)
    assert report.closest["alpha"] == 0.0
    assert (report.clearance[1:] > T).all()  # and they only move apart


@pytest.fixture(scope="module")
def funnel():
    model = load_model(catalog_path("fig12c-funnel"))
    return ThickModel(model, thickness=T)


def test_funnel_collides_near_its_limit(funnel):
    alphas = np.linspace(70.0, 77.3, 8)
    report = funnel.collisions(alphas)
    assert not report.ok
    first = report.first
    assert 70.0 < first["alpha"] <= 77.3
    a, b = first["plates"]
    assert abs(a - b) > 1  # plates that share no crease: the funnel closes on itself
    assert first["depth"] > 1e-6
    with pytest.raises(SelfIntersectionError, match=rf"plates {a} and {b} .* at alpha = "):
        funnel.check_collisions(alphas)


def test_funnel_path_to_design_is_clear(funnel):
    report = funnel.check_collisions()
    assert report.ok and report.summary()["interpenetration"] is False
