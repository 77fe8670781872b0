"""Bending check κ ≤ f / (Q̄11 t/2) (plate stress of a cylindrical bend): hand examples,
orthotropy, flags."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.design import load_design
from compas_ccu.kinematics.plates import stack_rows
from compas_ccu.materials import MaterialError, design_factors, material
from compas_ccu.strips.curvature import plate_curvature
from compas_ccu.thickness import ThickModel, bending_check
from compas_ccu.thickness.bending import bending_angles
from conftest import EXAMPLES

BIRCH_PF = 1 - 0.05 * 0.05 * 6 / 11  # 1 - nu12 nu21 of birch-plywood


def _cylinder(radius=2.0, angle=1.0, width=0.5, n=40, grain_axis="x"):
    """A plate rolled to a cylinder of ``radius``: rulings along z, bending along the arc."""
    phi = np.linspace(0.0, angle, n + 1)
    ring = np.c_[radius * np.cos(phi), radius * np.sin(phi), np.zeros_like(phi)]
    plate = np.concatenate([ring, ring + [0.0, 0.0, width]])[None, None]
    s = radius * phi
    flat = np.concatenate([np.c_[s, 0 * s], np.c_[s, 0 * s + width]])[None]
    return plate, flat


def test_hand_example_plywood_cylinder():
    """R = 2 m, 8 mm plywood: κ = 0.5 1/m, κ_lim = 30 MPa (1 - 0.3²) / (9 GPa · 4 mm) = 0.7583 1/m
    → 0.6593 (the beam formula without 1 - ν² gave 0.6)."""
    plate, flat = _cylinder()
    check = bending_check(plate, flat, 0.008, material("plywood"))
    assert np.abs(check.curvature).max() == pytest.approx(0.5, rel=2e-4)
    assert check.limit.min() == pytest.approx(30e6 * 0.91 / (9e9 * 0.004), rel=1e-12)
    assert check.max == pytest.approx(0.6 / 0.91, rel=2e-4)
    assert check.per_plate.shape == (1, 1)


@pytest.mark.parametrize(
    "grain, limit",
    [
        # plate factor 1 - nu12 nu21 = 1 - 0.05 * 0.05 * 6 / 11 = 0.99864
        (0.0, 45e6 * BIRCH_PF / (11e9 * 0.004)),  # along the grain: f1 / (Q11 t/2) = 1.0213
        (90.0, 35e6 * BIRCH_PF / (6e9 * 0.004)),  # across: f2 / (Q22 t/2) = 1.4563
        # 45°: Q̄11 = (Q11 + Q22 + 2 Q12 + 4 G12) / 4 = 5.0060 GPa;
        # Hankinson f = f1 f2 / ((f1 + f2) / 2) = 39.375 MPa -> 1.9664 1/m
        (45.0, 39.375e6 / ((17e9 / BIRCH_PF + 2 * 0.05 * 6e9 / BIRCH_PF + 2.4e9) / 4 * 0.004)),
    ],
)
def test_orthotropic_birch_limit_by_grain_direction(grain, limit):
    plate, flat = _cylinder()
    check = bending_check(plate, flat, 0.008, material("birch-plywood"), grain=math.radians(grain))
    assert check.limit[0, 1:-1] == pytest.approx(np.full(check.limit.shape[1] - 2, limit), rel=1e-6)
    assert check.max == pytest.approx(0.5 / limit, rel=2e-4)


def test_poplar_is_more_flexible_across_than_along():
    m = material("poplar-plywood")
    along, across = m.curvature_limit_at(0.008, 0.0), m.curvature_limit_at(0.008, math.pi / 2)
    factor = 1 - 0.05 * 0.05 * 2.5 / 6.5
    assert along == pytest.approx(30e6 * factor / (6.5e9 * 0.004))
    assert across == pytest.approx(18e6 * factor / (2.5e9 * 0.004))


def test_vault_utilisation_per_plate(vault_model):
    thick = ThickModel(vault_model, thickness=0.008, material="plywood")
    check = thick.bending(np.linspace(0.0, 30.0, 7))
    assert check.utilisation[0].max() < 1e-12  # the flat stack is unbent
    per_plate = check.per_plate
    assert per_plate.shape == (7, 10)
    assert np.all(np.diff(per_plate.max(axis=1)) > 0)  # bending grows as the vault opens
    # u_k = |κ| / (f_k (1 - ν²) / (E t/2)) with the measured curvature
    kappa = np.abs(check.curvature).max()
    assert check.max_characteristic == pytest.approx(kappa / (30e6 * 0.91 / 36e6), rel=1e-12)
    assert 0.4 < check.max_characteristic < 0.7
    # the default basis: EC5 design strength f_d = 0.6 f_k / 1.2 = f_k / 2 (docs/thickness.md)
    assert check.max == pytest.approx(kappa / (15e6 * 0.91 / 36e6), rel=1e-12)
    summary = thick.summary(path_states=7)["bending"]
    assert summary["exceeded"] is True  # 8 mm plywood exceeds the design strength
    assert summary["max_utilisation"] == pytest.approx(check.max)
    assert summary["max_utilisation_characteristic"] == pytest.approx(check.max_characteristic)
    characteristic = ThickModel(vault_model, design_code={"code": "characteristic"})
    assert characteristic.summary(path_states=7)["bending"]["exceeded"] is False


def test_thicker_plates_fail_and_are_flagged(vault_model, capsys):
    """Doubling t halves the curvature limit: 12 mm plywood would break in the 6 mm vault."""
    assert vault_model.design.plates.thickness == 0.006
    thick = ThickModel(vault_model, thickness=0.012)
    summary = thick.summary(path_states=5)["bending"]
    assert summary["max_utilisation"] == pytest.approx(
        2 * ThickModel(vault_model).summary(path_states=5)["bending"]["max_utilisation"], rel=1e-9
    )
    assert summary["exceeded"] is True


def test_info_flags_exceeded_bending(tmp_path, capsys):
    text = (EXAMPLES / "vault.toml").read_text()
    assert text.count("thickness = 0.006 ") == 1  # the example's [plates] thickness
    text = text.replace("thickness = 0.006 ", "thickness = 0.016 ")
    path = tmp_path / "thick-vault.toml"
    path.write_text(text)
    assert load_design(path).values["plates"]["thickness"] == 0.016
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "EXCEEDED" in out
    assert "16 mm plywood" in out


# -- design values (docs/thickness.md, "Design values") -------------------------------------------
def test_cylinder_characteristic_and_design_utilisation_exactly():
    """R = 2 m, 8 mm plywood: u_k = 0.6 / 0.91 = 0.6593 characteristic; u_k · γ_M / k_mod =
    u_k · 1.2 / 0.6 = 1.3187 with the design strength of a permanent action in service class 1."""
    plate, flat = _cylinder()
    ply = material("plywood")
    characteristic = bending_check(plate, flat, 0.008, ply)
    design = bending_check(plate, flat, 0.008, ply, factors=design_factors(ply))
    # at the exact curvature κ = 0.5 1/m of the cylinder (the limits are uniform)
    u_k = 0.6 / 0.91
    assert abs(0.5 / characteristic.limit.max() - u_k) < 1e-12
    assert abs(0.5 / design.limit.max() - 2.0 * u_k) < 1e-12
    assert np.ptp(design.limit) == 0.0
    # measured on the 40-segment polyline (κ within 3e-5 of 0.5): the same ratio
    assert round(characteristic.max, 4) == 0.6594 and round(design.max, 4) == 1.3187
    assert abs(design.max / characteristic.max - 1.2 / 0.6) < 1e-12
    assert design.max_characteristic == characteristic.max
    assert characteristic.factors.is_characteristic
    assert design.factors.label == "EC5 SC1 permanent"
    assert (design.factors.k_mod, design.factors.gamma_M) == (0.6, 1.2)
    assert np.array_equal(design.limit_characteristic, characteristic.limit)
    # service class 3, short-term: k_mod 0.70 -> u_k · 1.2 / 0.7
    factors = design_factors(ply, "EC5", 3, "short-term")
    sc3 = bending_check(plate, flat, 0.008, ply, factors=factors)
    assert abs(0.5 / sc3.limit.max() - u_k * 1.2 / 0.7) < 1e-12


def test_characteristic_basis_reproduces_the_old_numbers(vault_model):
    """``code = "characteristic"`` is the check with f_k: |κ| / (f (1 - ν²) / (E t/2)); the two
    code paths give the same floats in one process."""
    thick = ThickModel(vault_model, design_code={"code": "characteristic"})
    alphas = np.linspace(0.0, 30.0, 5)
    check = thick.bending(alphas)
    st = thick.place(alphas)
    mid = thick.model.plates.to_output(stack_rows(st.near, st.far), axis=1)
    kappa = plate_curvature(mid)
    old_limit = material("plywood").curvature_limit_at(
        0.006, bending_angles(vault_model.flat(), 0.0)
    )
    assert np.array_equal(check.limit, old_limit)
    assert np.array_equal(check.utilisation, np.abs(kappa) / old_limit[None])
    # a reduction: another CPU (SIMD path) rounds the last digits differently
    # 6 mm: 0.460851 = the 8 mm vault's 0.614468 x 6/8 (docs/thickness.md)
    assert check.max == pytest.approx(0.46085130145578085, rel=1e-12)
    design = ThickModel(vault_model).bending(alphas)
    assert np.array_equal(design.utilisation_characteristic, check.utilisation)
    assert design.max == pytest.approx(2.0 * check.max, rel=1e-15)


def test_info_states_the_basis_and_the_factors(tmp_path, capsys):
    assert main(["info", str(EXAMPLES / "vault.toml")]) == 0
    out = capsys.readouterr().out
    assert "utilisation 0.922" in out and "EXCEEDED" not in out
    assert (
        "bending basis     EC5 SC1 permanent: f_d = k_mod f_k / gamma_M, k_mod 0.6, gamma_M 1.2, "
        "k_def 0.8 (k_mod EN 1995-1-1 Table 3.1; gamma_M EN 1995-1-1 Table 2.3; k_def EN 1995-1-1 "
        "Table 3.2)" in out
    )
    assert "characteristic utilisation 0.461" in out
    assert "creep: k_def 0.8, final stiffness E/(1 + k_def) 5 / 5 GPa (E1 / E2)" in out
    path = tmp_path / "characteristic.toml"
    path.write_text(
        (EXAMPLES / "vault.toml").read_text() + '\n[design_code]\ncode = "characteristic"\n'
    )
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "utilisation 0.461" in out and "EXCEEDED" not in out
    assert "bending basis     characteristic strengths f_k (k_mod = gamma_M = 1)" in out
    sc2 = tmp_path / "sc2.toml"
    sc2.write_text(
        (EXAMPLES / "vault.toml").read_text()
        + '\n[design_code]\nservice_class = 2\nload_duration = "long-term"\ngamma_M = 1.3\n'
    )
    assert main(["info", str(sc2)]) == 0
    out = capsys.readouterr().out
    assert "EC5 SC2 long-term: f_d = k_mod f_k / gamma_M, k_mod 0.7, gamma_M 1.3" in out
    assert "k_def 1," in out


def test_thick_model_uses_the_design_code_section(vault_model):
    from_section = ThickModel(vault_model).factors
    assert from_section == design_factors("plywood")
    given = ThickModel(vault_model, design_code=design_factors("plywood", k_mod=0.9))
    assert given.factors.k_mod == 0.9
    with pytest.raises(MaterialError, match="has no default k_mod"):
        ThickModel(vault_model, material="gfrp")
    gfrp = ThickModel(vault_model, material="gfrp", design_code={"k_mod": 0.5, "gamma_M": 1.5})
    assert gfrp.factors.strength_factor == 0.5 / 1.5


@pytest.mark.parametrize("name", ["vault", "cone"])
def test_the_kept_curvature_is_the_curvature_of_the_placed_states(name):
    """path_curvature places only the angles it has not seen, once per geometry and thickness:
    every state has the numbers of the states placed together (the key figures' 24 path
    states and the studio's 25 from the flat stack), and a new material measures nothing."""
    from compas_ccu.model import load_model
    from compas_ccu.model.self_intersection import adopt_limits
    from compas_ccu.thickness.bending import path_curvature

    model = load_model(EXAMPLES / f"{name}.toml")
    thick = ThickModel(model)
    d = model.alpha_design

    place = thick.place

    def mid(alphas):
        st = place(alphas)
        return model.plates.to_output(stack_rows(st.near, st.far), axis=1)

    def placed(alphas):
        return plate_curvature(mid(alphas))

    calls = []
    thick.place = lambda alphas: calls.append(len(alphas)) or place(alphas)
    path = np.linspace(d / 24, d, 24)
    panel = np.linspace(0.0, d, 25)
    for alphas in (path, panel, panel[::-1], [0.0, 0.0, d], path):
        got = path_curvature(thick, alphas)
        assert got.tobytes() == placed(alphas).tobytes()
    fresh = sorted(set(path.tolist()) | set(panel.tolist()))
    assert calls == [24, len(fresh) - 24]  # the panel's new angles only, then none
    # a new material on the same geometry keeps the curvature (the model's limits)
    other = load_model(EXAMPLES / f"{name}.toml")
    other.design.values["plates"]["material"] = "birch-plywood"
    assert adopt_limits(other, model)
    again = ThickModel(other, material="birch-plywood")
    again.place = lambda alphas: calls.append(len(alphas)) or place(alphas)
    check = again.bending(panel)
    assert calls == [24, len(fresh) - 24]
    assert check.curvature.tobytes() == placed(panel).tobytes()
    assert check.utilisation.tobytes() == bending_check(
        mid(panel), other.flat(), again.thickness, again.material,
        grain=math.radians(again.grain), factors=again.factors,
    ).utilisation.tobytes()  # fmt: skip
