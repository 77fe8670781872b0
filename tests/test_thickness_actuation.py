"""The effort of deploying: bending energy and the force between the feet."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.model import load_model
from compas_ccu.thickness import ThickModel
from compas_ccu.thickness.actuation import actuation_force, bending_energy


def test_the_bending_energy_of_a_cylinder_and_of_a_flat_plate():
    phi = np.linspace(0.0, 0.5, 21)
    ring = np.c_[2 * np.cos(phi), 2 * np.sin(phi), np.zeros_like(phi)]
    plate = np.concatenate([ring, ring + [0.0, 0.0, 0.5]])[None, None]
    # kappa = 1/2 on 20 chords of 2 R sin(dphi / 2) by 0.5 m
    area = 20 * (2 * 2.0 * np.sin(0.025 / 2)) * 0.5
    assert bending_energy(plate, 100.0)[0] == pytest.approx(50.0 * 0.25 * area, rel=1e-3)
    flat = plate.copy()
    flat[..., 1] = 0.0
    flat[..., 0] = np.r_[2 * phi, 2 * phi]
    assert bending_energy(flat, 100.0)[0] == pytest.approx(0.0, abs=1e-12)


def test_the_force_is_the_energy_per_span_and_undefined_at_the_flat_stack():
    a = np.linspace(0.0, 40.0, 9)
    f = actuation_force(a, 3.0 * a**2, 2.0 - 0.002 * a**2)
    assert np.isnan(f[0]) and f[1:] == pytest.approx(-1500.0, rel=1e-9)
    still = actuation_force(a, a, np.full_like(a, 2.0))
    assert np.all(np.isnan(still))


def test_the_cone_pair_and_the_command_line(capsys):
    push = ThickModel(load_model("examples/cone.toml")).actuation(np.linspace(0.0, 40.0, 21))
    assert push.energy[0] == pytest.approx(0.0, abs=1e-9)
    assert np.all(np.diff(push.energy) > 0.0)  # bending more with every step
    # 5 mm plates: the 8 mm pair's 104.18 J and 509.5 N times (5/8)^3 (energy ~ t^3)
    assert push.energy[-1] == pytest.approx(104.18 * (5 / 8) ** 3, abs=0.003)
    assert push.energy[-1] == pytest.approx(25.436, abs=0.001)
    assert push.force[-1] == pytest.approx(-124.40, abs=0.01) and push.force_max == -push.force[-1]
    assert main(["info", "examples/cone.toml"]) == 0
    assert (
        "deployment effort bending energy 25.44 J at the design; force between the feet "
        "124.4 N there, up to 124.4 N along the path" in capsys.readouterr().out
    )


@pytest.mark.slow  # a 22-plate dome (~1.6 s)
def test_a_dome_is_held_by_a_ring_through_its_feet(tmp_path, capsys):
    """Radial layouts: the ring tension T = -dE/dalpha / (dL/dalpha) of a tie through the feet
    (the vault's tie, T = -F, with the ring in place of the span), checked against central
    differences of the energy and the ring's length measured afresh at alpha +- 0.5 deg; the
    half dome would close back into its stack, so the ring is in compression."""
    from compas_ccu.design.presets import write_preset
    from compas_ccu.key_figures import key_figures
    from compas_ccu.thickness.actuation import foot_ring
    from compas_ccu.thickness.model import radial_feet

    write_preset("dome", tmp_path / "dome.toml")
    model = load_model(tmp_path / "dome.toml")
    thick = ThickModel(model)
    push = thick.actuation(np.linspace(0.0, 30.0, 81))
    near = thick.actuation([29.5, 30.0, 30.5])
    dE = near.energy[2] - near.energy[0]
    dL = near.ring_length[2] - near.ring_length[0]
    assert push.ring_tension[-1] == pytest.approx(-dE / dL, rel=2e-3)
    assert push.ring_tension[-1] == pytest.approx(-81.95, abs=0.01)  # N, compression
    assert np.degrees(push.ring_angle[-1]) == pytest.approx(180.0, abs=1e-9)  # half a turn
    assert push.ring_thrust[-1] == pytest.approx(push.ring_tension[-1] / push.ring_radius[-1])
    # the feet: the lower end of the creases, on the vertical axis of the layout (x = y = 0)
    vertices = np.array([model.deploy(30.0).deployed])
    origin, axis, end = radial_feet(model, vertices)
    assert end == model.segments and np.allclose(np.cross(axis, [0, 0, 1]), 0, atol=1e-12)
    radii = np.hypot(*vertices[0, :, [end, 2 * model.segments + 1]].reshape(-1, 3)[:, :2].T)
    assert push.ring_radius[-1] == pytest.approx(radii.mean(), rel=1e-12)
    assert foot_ring(vertices, origin, axis, end)[0][0] == pytest.approx(near.ring_length[1])
    k = key_figures(model, path=24, thickness=True)
    assert k.ring_tension == pytest.approx(-81.9, abs=0.2) and k.ring_tension < 0
    assert k.ring_thrust == pytest.approx(k.ring_tension / k.ring_radius)
    assert main(["info", str(tmp_path / "dome.toml")]) == 0
    out = capsys.readouterr().out
    assert "the feet pull inwards on a ring through them (radius 1.647 m, 180 deg)" in out
    assert "with 49.61 N/m: ring compression 81.73 N" in out  # 21 states
    vault = ThickModel(load_model("examples/vault.toml")).actuation([15.0, 30.0])
    assert vault.ring_length is None and vault.ring_tension is None  # a vault has its tie


def test_the_series_of_phi2_is_taken_only_where_it_is_used():
    """``_phi2`` evaluates its series on the small ``x`` only (issue 31, item 3): every value
    is the one it has alone, series or closed form, bit for bit."""
    from compas_ccu.thickness import actuation

    x = np.r_[np.linspace(-0.5, 0.5, 41), np.linspace(-0.012, 0.012, 25), 0.0, 0.00999]
    whole = actuation._phi2(x)
    alone = np.array([float(actuation._phi2(np.array([v]))[0]) for v in x])
    assert whole.tobytes() == alone.tobytes()
    assert actuation._phi2(0.0) == pytest.approx(0.5) and np.ndim(actuation._phi2(0.3)) == 0
    small = np.abs(x) < 1e-2
    series = sum((-1) ** k * (k - 1) / k * x ** (k - 2) for k in range(2, 10))
    assert (whole[small] == series[small]).all()


@pytest.mark.parametrize(
    "alphas", [[30.0], [10.0, 10.0], [20.0, 10.0, 30.0], [0.0, float("nan"), 30.0]]
)
def test_a_path_of_one_state_or_out_of_order_is_refused_in_one_line(alphas):
    from compas_ccu.errors import OptionError

    thick = ThickModel(load_model("examples/cone.toml"))
    with pytest.raises(OptionError, match=r"at least 2 reference angles in increasing order"):
        thick.actuation(alphas)
    with pytest.raises(OptionError, match=r"path_states must be an integer >= 2 .*got 1"):
        thick.summary(path_states=1)
    assert np.isfinite(thick.actuation([10.0, 20.0]).force).all()  # two states suffice
