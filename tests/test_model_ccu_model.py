"""The one model object: COMPAS data round trip, public plate index / frame / reference lengths,
and the crease-plane strategies of the mechanism (thin and thick placement share one loop)."""

from __future__ import annotations

import math

import compas
import numpy as np
import pytest

from compas_ccu.io import write_obj
from compas_ccu.kinematics.mechanism import CreasePlanes
from compas_ccu.model import CCUModel, load_model
from compas_ccu.strips.intrinsics import quad_lengths
from compas_ccu.thickness.axis_shift import HingePlanes, crease_sides
from conftest import EXAMPLES


@pytest.mark.parametrize("name", ["vault.toml", "cone.toml"])
def test_model_round_trips_through_compas_json(name):
    model = load_model(EXAMPLES / name)
    again = compas.json_loads(compas.json_dumps(model))
    assert isinstance(again, CCUModel)
    assert again.sha256() == model.sha256()
    assert np.array_equal(again.deploy(20.0).deployed, model.deploy(20.0).deployed)
    assert again.name == model.design.name


def test_reference_lengths_are_the_design_state_quads(vault_model):
    g = vault_model.geometry
    ref = vault_model.reference_lengths
    assert ref.shape == (10, vault_model.segments, 6)
    assert np.array_equal(ref, quad_lengths(g.design_near, g.design_far))
    flat = vault_model.mechanism.place(0.0)
    err = np.abs(quad_lengths(flat.near[0], flat.far[0]) - ref).max()
    assert err < 1e-12 * vault_model.size  # the cut pattern is an isometry of the design


def test_frame_maps_the_local_leading_crease_to_the_design_plane(vault_model):
    st = vault_model.mechanism.deploy(math.radians(30.0))
    world = vault_model.to_world(st.near[0, 0])
    normal = vault_model.frame.axes[2]
    # the leading crease lies in the world plane of [plane]
    assert np.abs((world - vault_model.frame.origin) @ normal).max() < 1e-12
    assert np.allclose(np.linalg.norm(vault_model.frame.axes, axis=1), 1.0)


def test_relations_are_public_and_classify_the_vault(vault_model):
    st = vault_model.mechanism.deploy(math.radians(30.0))
    kinds = {vault_model.relations(st, 0, ci).kinds[5] for ci in range(9)}
    assert kinds == {"synclastic", "anticlastic"}


def test_default_strategy_is_the_plain_placement(vault_model):
    mech = vault_model.mechanism
    s0 = mech.leading.s0_for_alpha(np.radians([10.0, 30.0]))
    a, b = mech.place(s0), mech.place(s0, planes=CreasePlanes())
    assert all(np.array_equal(x, y) for x, y in zip(a, b))


def test_hinge_planes_of_zero_thickness_reproduce_the_thin_mechanism(vault_model):
    """Parallel creases stay planar, so mirroring the hinge rows across their planes (the thick
    strategy) moves nothing when t = 0."""
    mech = vault_model.mechanism
    probe = mech.deploy(math.radians(20.0))
    s0 = mech.leading.s0_for_alpha(np.radians([5.0, 30.0]))
    thin = mech.place(s0)
    planes = HingePlanes(0.0, crease_sides(mech, probe))
    thick = mech.place(s0, planes=planes)
    size = vault_model.size
    assert np.abs(thick.near - thin.near).max() < 1e-12 * size
    assert np.abs(thick.far - thin.far).max() < 1e-12 * size
    assert planes.corrections.shape == (2, 9, vault_model.segments + 1)
    assert np.abs(planes.corrections).max() < 1e-12 * size


def test_a_state_name_is_checked_not_guessed(cone_model, tmp_path):
    s = cone_model.deploy()
    assert s.points("flat") is s.flat and s.points("deployed") is s.deployed
    for bad in ("Deployed", "deployed ", "folded"):
        with pytest.raises(ValueError, match=r"state must be one of 'deployed', 'flat', got"):
            write_obj(s, tmp_path / "x.obj", state=bad)
        with pytest.raises(ValueError, match=r"state must be one of"):
            s.to_meshes(state=bad)
