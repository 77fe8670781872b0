"""Thick plates by the axis-shift approach (paper §5.3, Fig. 8c): exact invariants and errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.catalog import catalog_design
from compas_ccu.errors import DesignError, GeometryError
from compas_ccu.materials import MaterialError
from compas_ccu.model import CCUModel, load_model
from compas_ccu.thickness import ThickModel, vertex_offsets
from conftest import EXAMPLES, make_design

T = 0.008


@pytest.fixture(scope="module")
def thick_vault(vault_model):
    return ThickModel(vault_model, thickness=T)


@pytest.fixture(scope="module")
def leaning():
    """Rulings at 70° to the crease: alpha varies along it, offset creases are not planar."""
    model = CCUModel(make_design(rulings={"type": "angle", "gamma": 70.0}))
    return ThickModel(model, thickness=T)


def test_vertex_offsets_lie_on_both_offset_planes(vault_model):
    st = vault_model.mechanism.deploy(math.radians(30.0))
    near, far = st.near[0, 3], st.far[0, 3]
    nu = vertex_offsets(near, far)
    a, b, c, d = near[:-1], near[1:], far[1:], far[:-1]
    normals = np.cross(c - a, d - b)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    # ν·n = 1 for the quads on both sides of every ruling (ends: the one quad)
    assert np.allclose(np.einsum("ij,ij->i", nu[:-1], normals), 1.0, atol=1e-13)
    assert np.allclose(np.einsum("ij,ij->i", nu[1:], normals), 1.0, atol=1e-13)
    # and ν is perpendicular to its ruling
    r = (far - near) / np.linalg.norm(far - near, axis=1)[:, None]
    assert np.abs(np.einsum("ij,ij->i", nu, r)).max() < 1e-13


@pytest.mark.parametrize("name", ["vault", "leaning", "fig12b-dome"])
def test_placed_offsets_are_vertex_offsets_of_the_placed_plates(name, thick_vault, leaning):
    """The face offsets of a thick placement, those of the parent plates kept from the
    placement itself, are vertex_offsets of the placed boundaries, bit for bit."""
    if name == "fig12b-dome":
        thick = ThickModel(CCUModel(catalog_design(name)), thickness=0.004)
    else:
        thick = thick_vault if name == "vault" else leaning
    st = thick.place(np.linspace(0.0, thick.model.alpha_design, 7))
    np.testing.assert_array_equal(st.offsets, vertex_offsets(st.near, st.far))


def test_flat_stack_height_is_sum_of_thicknesses(thick_vault, vault_model):
    p = len(vault_model.plate_ids)
    assert thick_vault.stack_height == pytest.approx(p * T, abs=1e-14)
    stack = thick_vault.flat_stack()
    up = vault_model.axes[2]
    heights = np.einsum("pfvi,i->pfv", stack.solids - vault_model.origin, up)
    layers = np.sort(heights.reshape(p, -1).min(axis=1))
    assert np.allclose(np.diff(layers), T, atol=1e-14)  # plates lie on top of each other
    assert np.ptp(heights, axis=(1, 2)) == pytest.approx(np.full(p, T), abs=1e-14)
    assert sorted(thick_vault.stack_position) == list(range(p))


def test_vault_thick_invariants_exact_along_path(thick_vault):
    """Orthogonal rulings (ultra-special case): offset creases planar, hinges closed."""
    st = thick_vault.place(np.linspace(0.0, thick_vault.model.alpha_limit * 0.95, 9))
    m = thick_vault.metrics(st)
    size = thick_vault.model.size
    for key in ("isometry", "quad_planarity", "mirror_error", "hinge_gap"):
        assert getattr(m, key).shape == (9,) and getattr(m, key).max() < 1e-12 * size, key
    c = len(thick_vault.model.plates.crease_plates)
    assert m.offset_planarity.shape == m.correction.shape == (9, c)
    assert m.offset_planarity.max() < 1e-12 * size
    assert m.correction.max() < 1e-12 * size


def test_cone_hinge_plane_offset_is_half_t_cos_alpha(cone_model):
    """The cone: the hinge lies (t/2) cos α above the mid crease; the mid creases t cos α apart."""
    thick = ThickModel(cone_model, thickness=T)
    for alpha in (10.0, 25.0, 40.0):
        st = thick.place([alpha])
        shift = abs(st.hinge_origins[0, 0, 2])
        assert shift == pytest.approx(0.5 * T * math.cos(math.radians(alpha)), rel=2e-4)
        gap = np.abs(st.near[0, 1, :, 2] - st.near[0, 0, :, 2])
        assert np.allclose(gap, 2.0 * shift, atol=1e-15)
        assert thick.metrics(st).hinge_gap[0] < 1e-15


def test_fig8c_pairing_synclastic_intrados_anticlastic_extrados(thick_vault, vault_model):
    kinds = [k[0] for k in vault_model.crease_kinds()]
    pairing = thick_vault.pairing()
    assert kinds.count("synclastic") == 5 and kinds.count("anticlastic") == 4
    for kind, pair in zip(kinds, pairing):
        assert pair == {"synclastic": "intrados", "anticlastic": "extrados"}[kind]


def test_leaning_rulings_offset_crease_corrected(leaning):
    """γ = 70°: α runs from ~20° to ~43°; the offset crease leaves its plane by ~(t/2)Δcos α."""
    model = leaning.model
    st = leaning.place([model.alpha_design])
    alpha = np.radians(model.deploy().creases[0]["alpha"])
    spread = 0.5 * T * (np.cos(alpha).max() - np.cos(alpha).min())
    assert 0.3 * spread < st.offset_planarity[0, 0] < spread
    assert st.corrections[0, 0].max() > 1e-4  # the correction is real and reported
    # the correction puts the facing crease in the hinge plane: the hinge closes exactly
    m = leaning.metrics(st)
    assert m.hinge_gap[0] < 1e-15
    assert m.isometry[0] < 1e-15
    faces = leaning.deploy().solids
    assert np.isfinite(faces).all()
    # at other states the fixed (design) correction leaves a small, reported gap
    other = leaning.metrics(leaning.place([10.0]))
    assert 1e-7 < other.hinge_gap[0] < 1e-3


@pytest.mark.parametrize("bad", [0.0, -0.008, float("nan"), float("inf"), "8mm", True])
def test_bad_thickness_refused(vault_model, bad):
    with pytest.raises(GeometryError, match="thickness"):
        ThickModel(vault_model, thickness=bad)


def test_thickness_beyond_plate_width_refused(cone_model):
    with pytest.raises(GeometryError, match=r"more than half the narrowest plate width \(0\.4"):
        ThickModel(cone_model, thickness=0.25)


def test_unknown_material_refused(vault_model):
    with pytest.raises(MaterialError, match="unknown material 'oak'"):
        ThickModel(vault_model, material="oak")


def test_ccf_creases_refused(quadrants_model):
    with pytest.raises(GeometryError, match="CCF"):
        ThickModel(quadrants_model)


@pytest.mark.parametrize(
    "plates, key",
    [
        ({"thickness": -0.001}, "plates.thickness"),
        ({"thickness": 0.5}, "plates.thickness"),
        ({"material": "wood"}, "plates.material"),
        ({"hinge_width": 0.0}, "plates.hinge_width"),
        ({"colour": "red"}, "plates.colour"),
    ],
)
def test_bad_plates_section_refused(plates, key):
    with pytest.raises(DesignError, match=key.replace(".", r"\.")):
        make_design(plates=plates)


def test_design_plates_section_is_used():
    model = load_model(EXAMPLES / "vault.toml")
    values = model.design.values["plates"]
    thick = ThickModel(model)
    assert thick.thickness == values["thickness"]
    assert thick.material.name == values["material"]
