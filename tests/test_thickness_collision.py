"""Interpenetration of thick plates: unit cases with known depths, and along deployment paths."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from compas_ccu.catalog import catalog_path
from compas_ccu.errors import SelfIntersectionError
from compas_ccu.model import CCUModel, load_model
from compas_ccu.thickness import ThickModel, solid_faces, vertex_offsets
from compas_ccu.thickness.cells import accepted_from
from compas_ccu.thickness.collision import _contacts_all, plate_contacts
from compas_ccu.thickness.collision_check import first_contact, path_collisions
from compas_ccu.tolerances import EXACT_RELATIVE
from conftest import EXAMPLES, captured_plate_contacts, make_design, property_examples

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


def _contacts(strips, **options):
    near = np.stack([s[0] for s in strips])[None]
    far = np.stack([s[1] for s in strips])[None]
    nu = vertex_offsets(near, far)
    zero = np.zeros(near.shape[:-1])
    faces = solid_faces(near, far, nu, T, zero, zero)
    return plate_contacts(near, far, nu, faces, T, pairs=[(0, 1), (1, 0)], **options)


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


@pytest.mark.parametrize("alphas", [np.linspace(0.0, 77.3, 25), [77.0], [40.0]])
def test_the_first_contact_is_the_reports_first_without_the_clearances(funnel, alphas):
    """The thick scan's first contact (issue 31, item 3) looks only up to half the thickness
    over a cell and measures no clearance: its first interpenetration is the full report's,
    bit for bit, on the vault (clear), the funnel and the 2-plate cone (no clearance pair)."""
    cone = ThickModel(load_model(EXAMPLES / "cone.toml"), thickness=0.05)
    firsts = [first_contact(thick, alphas) for thick in (funnel, cone)]
    for thick, first in zip((funnel, cone), firsts):
        assert repr(first) == repr(path_collisions(thick, alphas, 1e-6, "cells").first)
    assert (firsts[0] is None) == (alphas[0] == 40.0)  # the funnel collides near its limit
    vault = ThickModel(load_model(EXAMPLES / "vault.toml"), thickness=T)
    assert first_contact(vault, np.linspace(0.0, 60.0, 13)) is None


def test_funnel_path_to_design_is_clear(funnel):
    report = funnel.check_collisions()
    assert report.ok and report.summary()["interpenetration"] is False


# -- the candidate search against the brute force --------------------------------------------


def _assert_same(fast, brute):
    for got, want in zip(fast, brute):
        assert got.dtype == want.dtype
        np.testing.assert_array_equal(got, want)


def _assert_cut_off_brute_force(call, fast):
    """Against the brute force without the reach cut-off: the same wherever its smallest gap
    lies within the reach, no contact beyond it; the same crossings."""
    args, kwargs = call
    reach = kwargs.get("reach", 0.1)
    depth, clearance, crossing, where = _contacts_all(
        *args, kwargs["pairs"], kwargs.get("hinged"), reach, EXACT_RELATIVE
    )
    within = -depth <= reach
    np.testing.assert_array_equal(fast[0][within], depth[within])
    np.testing.assert_array_equal(fast[1][within], clearance[within])
    np.testing.assert_array_equal(fast[3][within], where[within])
    assert np.isinf(fast[1][~within]).all() and (fast[3][~within] == 0).all()
    np.testing.assert_array_equal(fast[2], crossing)


def _path(name, alphas):
    if name == "vault":
        return load_model(EXAMPLES / "vault.toml"), alphas
    if name == "cone":
        return load_model(EXAMPLES / "cone.toml"), alphas
    return load_model(catalog_path(name)), alphas


LAYOUTS = {
    # parallel planes, 10 plates, the closed stack at alpha 0
    "vault": ("vault", np.linspace(0.0, 30.0, 5)),
    # 2 plates sharing their crease: depth only, no clearance pairs
    "cone": ("cone", np.linspace(0.0, 40.0, 4)),
    # inclined planes
    "inclined": ("fig11a-constant-apex", np.linspace(0.0, 30.0, 4)),
    # radial planes: a dome of 12 plates
    "radial": ("fig12b-dome", np.linspace(0.0, 40.0, 4)),
    # the funnel closes on itself: interpenetration (first state at 77.3 deg)
    "funnel": ("fig12c-funnel", np.linspace(70.0, 77.3, 4)),
    # neighbouring plates 7 and 8 touch away from their hinge
    "asymmetric": ("fig12a-asymmetric", np.linspace(60.0, 68.0, 4)),
}


@pytest.fixture(scope="module", params=list(LAYOUTS))
def layout_call(request):
    name, alphas = LAYOUTS[request.param]
    model, alphas = _path(name, alphas)
    thick = ThickModel(model, thickness=T)
    return request.param, thick, alphas, captured_plate_contacts(thick, alphas)


def test_candidate_search_equals_the_brute_force(layout_call):
    name, _, _, (args, kwargs) = layout_call
    fast = plate_contacts(*args, **kwargs)
    brute = plate_contacts(*args, **{**kwargs, "method": "all"})
    _assert_same(fast, brute)
    _assert_cut_off_brute_force((args, kwargs), fast)
    if name in ("vault", "radial", "funnel"):
        assert np.isfinite(fast[1]).any()  # clearances were measured, not only skipped
    if name == "funnel":
        assert (fast[0] > 1e-6).any()  # an interpenetration


def test_collision_reports_agree(layout_call):
    _, thick, alphas, _ = layout_call
    fast, brute = thick.collisions(alphas), thick.collisions(alphas, method="all")
    assert fast.summary() == brute.summary()
    np.testing.assert_array_equal(fast.clearance, brute.clearance)
    np.testing.assert_array_equal(fast.penetration, brute.penetration)
    np.testing.assert_array_equal(fast.crossing, brute.crossing)


def test_candidate_search_finds_crossings_beyond_the_overlap_limit():
    """Past its crease-overlap limit the funnel's plates pass through each other."""
    model = load_model(catalog_path("fig12c-funnel"))
    thick = ThickModel(model, thickness=T)
    alphas = np.linspace(77.3, 0.999 * model.alpha_limit, 6)
    args, kwargs = captured_plate_contacts(thick, alphas)
    fast = plate_contacts(*args, **kwargs)
    assert fast[2].any()
    _assert_same(fast, plate_contacts(*args, **{**kwargs, "method": "all"}))
    _assert_cut_off_brute_force((args, kwargs), fast)


@pytest.mark.parametrize("segments", [4, 9, 33])
@pytest.mark.parametrize("reach", [0.02, 0.1, 1.0])
def test_candidate_search_at_any_size_and_reach(segments, reach):
    """Block sizes that do not divide the cells or rulings; a reach below and above the gaps."""
    model = CCUModel(
        make_design(
            crease={"segments": segments},
            layout={"type": "parallel", "plates": 5, "spacing": 0.1},
        )
    )
    thick = ThickModel(model, thickness=T)
    args, kwargs = captured_plate_contacts(thick, np.linspace(0.0, 30.0, 3))
    kwargs = {**kwargs, "reach": reach}
    fast = plate_contacts(*args, **kwargs)
    _assert_same(fast, plate_contacts(*args, **{**kwargs, "method": "all"}))
    _assert_cut_off_brute_force((args, kwargs), fast)


def _random_strip(rng, n, spread):
    """A random curved, tilted strip (n cells) somewhere in a box of size ``spread``."""
    s = np.linspace(0.0, 1.0, n + 1)
    bend = rng.uniform(-1.5, 1.5)
    near = np.c_[s, 0.3 * bend * s * (1.0 - s), np.zeros_like(s)]
    width = rng.uniform(0.1, 0.4)
    lean = rng.uniform(-0.5, 0.5)
    far = near + np.c_[lean * np.ones_like(s), np.full_like(s, width), 0.2 * bend * (s - 0.5)]
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    shift = rng.uniform(-spread, spread, 3)
    return near @ q + shift, far @ q + shift


@settings(max_examples=property_examples(40), deadline=None, database=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    plates=st.integers(2, 6),
    n=st.integers(1, 20),
    spread=st.sampled_from([0.0, 0.02, 0.1, 0.5]),
)
def test_candidate_search_on_random_strips(seed, plates, n, spread):
    """Random strips crossing, touching and passing through each other at random."""
    rng = np.random.default_rng(seed)
    strips = [_random_strip(rng, n, spread) for _ in range(plates)]
    near = np.stack([s[0] for s in strips])[None]
    far = np.stack([s[1] for s in strips])[None]
    nu = vertex_offsets(near, far)
    zero = np.zeros(near.shape[:-1])
    faces = solid_faces(near, far, nu, T, zero, zero)
    pairs = [(a, b) for a in range(plates) for b in range(plates) if a != b]
    args = (near, far, nu, faces, T)
    kwargs = {"pairs": pairs}
    fast = plate_contacts(*args, **kwargs)
    _assert_same(fast, plate_contacts(*args, **kwargs, method="all"))
    _assert_cut_off_brute_force((args, kwargs), fast)


@pytest.mark.parametrize("method", ["cells", "all"])
def test_unit_cases_by_both_methods(method):
    d, clearance, crossing, _ = _contacts([_strip(), _strip(0.006)], method=method)
    assert d[0, 0] == pytest.approx(0.002, abs=1e-15) and clearance[0, 0] == 0.0
    d, clearance, _, _ = _contacts([_strip(), _strip(0.05)], method=method)
    assert clearance[0, 0] == pytest.approx(0.042, abs=1e-15)
    _, clearance, _, _ = _contacts([_strip(), _strip(0.05)], method=method, reach=0.04)
    assert clearance[0, 0] == np.inf  # a gap beyond the reach is no contact
    _, _, crossing, _ = _contacts([_strip(), _strip(tilt=True, x0=0.55)], method=method)
    assert crossing[0, 0]


def test_unknown_method():
    with pytest.raises(ValueError, match="method"):
        _contacts([_strip(), _strip(0.05)], method="kd")


@settings(max_examples=property_examples(30), deadline=None, database=None)
@given(seed=st.integers(0, 2**32 - 1), plates=st.integers(2, 5), n=st.integers(2, 20))
def test_candidate_search_on_random_hinged_strips(seed, plates, n):
    """A chain of random strips, each hinged to the far row of the one before: the hinge rows
    are left out of those pairs, and so is their crossing test."""
    rng = np.random.default_rng(seed)
    near, far = _random_strip(rng, n, 0.0)
    strips = [(near, far)]
    for _ in range(plates - 1):
        base = strips[-1][1]
        turn = rng.normal(size=3)
        strips.append((base, base + 0.3 * turn / np.linalg.norm(turn) + rng.normal(0, 0.01, 3)))
    near = np.stack([s[0] for s in strips])[None]
    far = np.stack([s[1] for s in strips])[None]
    nu = vertex_offsets(near, far)
    zero = np.zeros(near.shape[:-1])
    faces = solid_faces(near, far, nu, T, zero, zero)
    m = n + 1
    row = np.zeros(2 * m, dtype=bool)
    near_row, far_row = row.copy(), row.copy()
    near_row[:m], far_row[m:] = True, True
    pairs, hinged = [], []
    for a in range(plates):
        for b in range(plates):
            if a == b:
                continue
            pairs.append((a, b))
            if b == a + 1:  # b's near row on a's far row
                hinged.append(np.concatenate([near_row, near_row]))
            elif a == b + 1:
                hinged.append(np.concatenate([far_row, far_row]))
            else:
                hinged.append(None)
    args = (near, far, nu, faces, T)
    kwargs = {"pairs": pairs, "hinged": hinged}
    fast = plate_contacts(*args, **kwargs)
    _assert_same(fast, plate_contacts(*args, **kwargs, method="all"))
    _assert_cut_off_brute_force((args, kwargs), fast)


@pytest.mark.parametrize("tol", [0.0, EXACT_RELATIVE, 1e-3])
def test_accepted_heights_are_the_lateral_tests_without_the_subtraction(tol):
    """``h >= accepted_from(offset, tol)`` is ``fl(h - offset) >= -tol`` for every height:
    the floats at and next to the threshold, signed zeros, infinities and NaN, offsets of
    every scale, near 0 and near ``tol`` (where ``h - offset`` is not exact), at ``4 tol``."""
    rng = np.random.default_rng(7)
    scale = 10.0 ** rng.integers(-14, 4, 20000)
    special = [0.0, -0.0, tol, -tol, 2 * tol, 5e-324, -5e-324, 1e-300, 1e308, -1e308, 1e8, -1e20]
    special += [np.nextafter(4 * tol, to) for to in (0.0, 1.0)] + [4 * tol, -4 * tol]
    special += [-s for s in special[-4:]] + list(np.arange(-12, 13) * tol)
    offset = np.r_[rng.standard_normal(20000) * scale, special, np.inf, -np.inf, np.nan]
    accepted = accepted_from(offset, tol)
    heights = [np.full_like(offset, v) for v in (np.inf, -np.inf, np.nan, 0.0, -0.0)]
    heights.append(offset + rng.standard_normal(len(offset)) * max(tol, 1e-12))
    with np.errstate(invalid="ignore", over="ignore"):
        for step in (-np.inf, np.inf):
            h = accepted
            for _ in range(3):
                heights.append(h)
                h = np.nextafter(h, step)
        for h in heights:
            np.testing.assert_array_equal(h >= accepted, (h - offset) >= -tol)
