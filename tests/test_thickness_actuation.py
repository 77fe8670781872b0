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
    assert push.energy[-1] == pytest.approx(104.18, abs=0.01)
    assert push.force[-1] == pytest.approx(-509.5, abs=0.1) and push.force_max == -push.force[-1]
    assert main(["info", "examples/cone.toml"]) == 0
    assert (
        "deployment effort bending energy 104.2 J at the design; force between the feet "
        "509.5 N there, up to 509.5 N along the path" in capsys.readouterr().out
    )
