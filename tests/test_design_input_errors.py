"""Inputs that used to give NaN geometry, overflow, a solver's words or an unnamed decode error
now give a DesignError naming the key (issue: zero silent failures)."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.design import Design, load_design
from compas_ccu.errors import DesignError, DevelopabilityError
from compas_ccu.model import CCUModel
from compas_ccu.strips.intrinsics import QUAD_LENGTH_PAIRS

BASE = {
    "crease": {"profile": "arc", "span": 2.5, "rise": 1.0, "segments": 16},
    "rulings": {"type": "orthogonal"},
    "deployment": {"alpha": 30.0},
    "layout": {"width": 0.3},
}


def build(**sections):
    doc = {**BASE, **sections}
    return CCUModel(Design(doc))


@pytest.mark.parametrize(
    "plane,message",
    [
        ({"xaxis": [0, 0, 0]}, r"plane\.xaxis: must be a finite non-zero direction"),
        ({"yaxis": [0.0, 0.0, 0.0]}, r"plane\.yaxis: must be a finite non-zero direction"),
        ({"xaxis": [1, 0, 0], "yaxis": [2, 0, 0]}, r"plane\.yaxis: must not be parallel"),
    ],
)
def test_degenerate_plane_axes_are_refused(plane, message):
    with pytest.raises(DesignError, match=message):
        build(plane=plane)


@pytest.mark.parametrize("size", [1e-200, 1e200])
def test_plane_axes_of_any_finite_size_are_directions(size):
    model = build(plane={"xaxis": [size, 0.0, 0.0], "yaxis": [0.0, 0.0, size]})
    s = model.deploy()
    assert np.isfinite(s.deployed).all()
    assert s.max_invariant_error < 1e-12
    assert np.allclose(model.axes, [[1, 0, 0], [0, 0, 1], [0, -1, 0]])


@pytest.mark.parametrize(
    "crease,message",
    [
        (
            {"profile": "polyline", "points": [[0, 0], [1, 1], [0, 0]], "segments": 2},
            r"\[crease\]: the crease doubles back on itself at vertex 1",
        ),
        (
            {"profile": "polyline", "points": [[0, 0], [1, 0], [1, 1], [0, 0]], "segments": 3},
            r"\[crease\]: the crease is closed",
        ),
        ({"profile": "arc", "span": 10**400, "rise": 1.0}, r"crease\.span: must be a finite"),
        ({"profile": "arc", "span": 1e308, "rise": 1.0}, r"crease\.span: must be > 0 and <= 1e6"),
        ({"profile": "catenary", "span": 2.0, "rise": 1e-12}, r"the crease is straight"),
    ],
)
def test_impossible_creases_are_named(crease, message):
    with pytest.raises(DesignError, match=message):
        build(crease=crease)


def test_a_full_ring_of_radial_planes_is_refused():
    with pytest.raises(DesignError, match=r"layout\.angle: the planes turn by 360 deg in total"):
        build(layout={"type": "radial", "plates": 36, "angle": 10.0, "axis": 3.0})


def test_inside_on_a_straight_stretch_is_judged_from_the_whole_crease():
    """A polyline whose reference vertex sits on a straight stretch: 'inside' is the side the
    crease turns to as a whole, as 'left' says explicitly."""
    points = [[-1.2, 0.0], [-0.6, 0.5], [-0.2, 0.6], [0.0, 0.6], [0.2, 0.6], [0.6, 0.5], [1.2, 0]]
    crease = {"profile": "polyline", "points": points, "segments": 6}
    inside = build(crease=crease, rulings={"type": "orthogonal", "side": "inside"})
    right = build(crease=crease, rulings={"type": "orthogonal", "side": "right"})
    assert inside.flip == right.flip == -1.0
    assert np.array_equal(inside.deploy().deployed, right.deploy().deployed)


def test_a_utf16_design_file_is_named(tmp_path):
    path = tmp_path / "windows.toml"
    path.write_text('[crease]\nprofile = "arc"\n', encoding="utf-16")
    with pytest.raises(DesignError, match=r"windows\.toml' is not UTF-8 text \(it looks saved as"):
        load_design(path)


def _written_isometry(structure) -> float:
    """Largest quad side / diagonal length change of the written numbers, deployed vs cut."""
    pairs = QUAD_LENGTH_PAIRS
    worst = 0.0
    for faces, flat, deployed in zip(structure.faces, structure.flat, structure.deployed):
        a, b = flat[faces], deployed[faces]
        cut = np.linalg.norm(a[:, pairs[:, 1]] - a[:, pairs[:, 0]], axis=-1)
        built = np.linalg.norm(b[:, pairs[:, 1]] - b[:, pairs[:, 0]], axis=-1)
        worst = max(worst, float(np.abs(built - cut).max()))
    return worst


def test_georeferenced_coordinates_report_the_invariants_of_the_written_numbers():
    """At 5e6 m (UTM northings) float64 holds the vault to ~1e-9 m: the reported invariants are
    those of the world coordinates, not the 1e-16 of the local frame."""
    local = build().deploy()
    far = build(plane={"origin": [5e6, 5e6, 0.0]}).deploy()
    assert local.metrics["isometry_relative"] < 1e-15
    assert 1e-12 < far.metrics["isometry_relative"] < 1e-9
    written = _written_isometry(far)
    assert written == pytest.approx(far.metrics["isometry"], rel=0.5)


def test_coordinates_too_far_for_the_exactness_bar_are_refused():
    with pytest.raises(DesignError, match=r"plane\.origin: world coordinates 1e\+08 m from the"):
        build(plane={"origin": [1e8, 0.0, 0.0]})


def test_a_ruling_field_crossing_the_crease_at_the_reference_is_named():
    """Found by the campaign (seed 2): a 2-segment arc with gamma 111.7 deg and the reference at
    its end gave scipy's 'f(a) and f(b) must have different signs'."""
    with pytest.raises(DevelopabilityError, match=r"cannot reach alpha = 2 deg at the reference"):
        build(
            crease={"profile": "arc", "span": 0.2, "rise": 1.6, "segments": 2, "reference": 0.0},
            rulings={"type": "angle", "side": "right", "gamma": 111.657046794371},
            deployment={"alpha": 2.0},
            layout={"type": "single", "width": 0.39, "quadrants": True},
        )
