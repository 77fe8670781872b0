"""The overlap limit (compas_ccu.kinematics.invariants.overlap_limit): one state placed per
bisection and the crease found overlapping last tested first, alone; the same angle, bit for bit,
as the sequential bisection that tests every suspect crease of every state."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from compas_ccu.errors import CCUError
from compas_ccu.kinematics import invariants
from compas_ccu.kinematics.checks import planar_overlaps, self_intersecting, total_turning
from compas_ccu.kinematics.invariants import crease_polylines, overlap_limit, overlapping_creases
from compas_ccu.model import load_model
from conftest import EXAMPLES, sequential_overlap_limit

DATA = Path(__file__).resolve().parents[1] / "src" / "compas_ccu" / "data"
CATALOG = sorted((DATA / "catalog").glob("*.toml"))


def same_as_sequential(path):
    try:
        mechanism = load_model(path).mechanism
    except CCUError:
        pytest.skip("not a model here")
    found = overlap_limit(mechanism)
    assert found == sequential_overlap_limit(mechanism), path.name
    for levels in (2, 3):  # the same angle at any level
        assert overlap_limit(mechanism, levels=levels) == found


@pytest.mark.parametrize("name", ["vault.toml", "cone.toml", "quadrants.toml"])
def test_the_overlap_limit_is_the_sequential_bisections_bit_for_bit(name):
    same_as_sequential(EXAMPLES / name)


@pytest.mark.slow
@pytest.mark.parametrize("path", CATALOG, ids=[p.stem for p in CATALOG])
def test_the_overlap_limit_is_the_sequential_bisections_on_the_catalog(path):
    """Every catalog design (~0.1 s each)."""
    same_as_sequential(path)


def test_the_crease_found_last_is_tested_first_and_the_others_after_it():
    mechanism = load_model(EXAMPLES / "vault.toml").mechanism
    states = mechanism.deploy(np.array([0.99, 1.01]) * overlap_limit(mechanism))
    hinges, origins, normals, turning = crease_polylines(mechanism, states)
    overlapping = overlapping_creases(mechanism, states)
    assert not overlapping[0].any() and overlapping[1].all()  # before, and every crease after
    assert (turning > np.pi).all()  # every crease a suspect in both
    for first in (-1, 0, 3):
        assert invariants._overlapping(hinges[0], origins[0], normals[0], turning[0], first) == -1
        found = invariants._overlapping(hinges[1], origins[1], normals[1], turning[1], first)
        assert found == max(first, 0)
    # the crease found last no longer overlaps (crease 3 as it was before): the others are tested
    hinges = hinges.copy()
    hinges[1, 3] = hinges[0, 3]
    assert invariants._overlapping(hinges[1], origins[1], normals[1], turning[1], 3) == 0
    hinges[1, :3] = hinges[0, :3]
    assert invariants._overlapping(hinges[1], origins[1], normals[1], turning[1], 3) == 4
    # a crease that turns by at most pi is no suspect, even the one found last
    straight = turning[1].copy()
    straight[3:] = 0.0
    assert invariants._overlapping(hinges[1], origins[1], normals[1], straight, 3) == -1


def test_planar_overlaps_is_self_intersecting_on_the_suspects():
    mechanism = load_model(EXAMPLES / "vault.toml").mechanism
    states = mechanism.deploy(np.linspace(0.5, 1.0, 6) * mechanism.alpha_limit)
    hinges, origins, normals, _ = crease_polylines(mechanism, states)
    points = hinges.reshape((-1,) + hinges.shape[2:])
    origins, normals = origins.reshape(-1, 3), normals.reshape(-1, 3)
    suspects = np.flatnonzero(total_turning(points) > np.pi)
    assert len(suspects) > 10
    expected = self_intersecting(points, origins, normals)[suspects]
    found = planar_overlaps(points[suspects], origins[suspects], normals[suspects])
    assert found.tolist() == expected.tolist() and found.any() and not found.all()
    for i in suspects[::7]:  # alone, the same answer
        assert (
            planar_overlaps(points[i : i + 1], origins[i : i + 1], normals[i : i + 1])[0]
            == (expected[list(suspects).index(i)])
        )
