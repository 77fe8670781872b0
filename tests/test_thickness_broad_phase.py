"""The broad phase of the collision check never drops a pair that the narrow phase finds.

The oracle is the brute force with an infinite reach: every vertex against every cell of
every ordered pair, with no box test at all (``_contacts_all`` widens every box by the reach,
so nothing is ever apart). It shares the exact tests with the candidate search, not its
pruning (``box_pairs``, the block trees). A contact within the reach (less half the
thickness: a vertex at height ``d`` from a mid plane lies at least ``d`` from the plate's box)
and every crossing must be found with the same numbers, bit for bit; a contact beyond the
reach is no contact.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from compas_ccu.catalog import catalog_path
from compas_ccu.model import CCUModel, load_model
from compas_ccu.thickness import ThickModel, solid_faces, vertex_offsets
from compas_ccu.thickness.collision import _contacts_all, box_pairs, plate_contacts
from compas_ccu.tolerances import EXACT_RELATIVE
from conftest import EXAMPLES, captured_plate_contacts, make_design, property_examples

T = 0.008


def all_overlapping(lo, hi):
    """Every pair a < b of overlapping boxes, one state, by a double loop (the oracle)."""
    p = len(lo)
    found = set()
    for a in range(p):
        for b in range(a + 1, p):
            apart = any(lo[a, i] > hi[b, i] or lo[b, i] > hi[a, i] for i in range(3))
            if not apart:
                found.add((a, b))
    return found


@settings(max_examples=property_examples(60), deadline=None, database=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    states=st.integers(1, 3),
    plates=st.integers(1, 30),
    spread=st.sampled_from([0.0, 0.5, 3.0, 20.0]),
    special=st.sampled_from(["none", "nan", "inf", "touching"]),
)
def test_box_pairs_are_every_overlapping_pair(seed, states, plates, spread, special):
    rng = np.random.default_rng(seed)
    lo = rng.uniform(-spread, spread, (states, plates, 3))
    hi = lo + rng.uniform(0.0, 1.0, (states, plates, 3))
    if special == "nan":
        lo[0, rng.integers(plates), rng.integers(3)] = np.nan
    elif special == "inf":
        hi[0, rng.integers(plates)] = np.inf
    elif special == "touching" and plates > 1:  # equal faces overlap
        lo[:, 1] = lo[:, 0]
        lo[:, 1, 0] = hi[:, 0, 0]
    state, a, b = box_pairs(lo, hi)
    assert (a < b).all()
    for s in range(states):
        got = {(int(x), int(y)) for x, y in zip(a[state == s], b[state == s])}
        assert len(got) == int((state == s).sum())  # no pair twice
        assert got == all_overlapping(lo[s], hi[s])


def _assert_nothing_dropped(args, kwargs):
    """The candidate search against the brute force with an infinite reach."""
    reach = kwargs.get("reach", 0.1)
    fast = plate_contacts(*args, **kwargs)
    depth, clearance, crossing, where = _contacts_all(
        *args, kwargs["pairs"], kwargs.get("hinged"), np.inf, EXACT_RELATIVE
    )
    half = 0.5 * args[4]
    gap = -depth
    sure = gap <= reach - half - 1e-9  # within the reach of the boxes by any rounding
    np.testing.assert_array_equal(fast[0][sure], depth[sure])
    np.testing.assert_array_equal(fast[1][sure], clearance[sure])
    np.testing.assert_array_equal(fast[3][sure], where[sure])
    beyond = gap > reach
    assert np.isinf(fast[1][beyond]).all() and (fast[0][beyond] == -np.inf).all()
    # in between (a box of the pair further apart than the reach or not): found exactly or not
    between = ~sure & ~beyond
    same = fast[0][between] == depth[between]
    assert (same | (fast[0][between] == -np.inf)).all()
    np.testing.assert_array_equal(fast[2], crossing)
    return fast, depth


DESIGNS = {
    "vault": (EXAMPLES / "vault.toml", [0.0, 2.0, 10.0, 30.0]),
    "overbent": (EXAMPLES / "overbent.toml", [0.0, 15.0, 35.0]),
    "inclined": (catalog_path("fig11a-constant-apex"), [0.0, 12.0, 30.0]),
    "radial": (catalog_path("fig12b-dome"), [0.0, 5.0, 40.0]),
    "funnel": (catalog_path("fig12c-funnel"), [0.0, 40.0, 77.3, 78.0]),
    "asymmetric": (catalog_path("fig12a-asymmetric"), [0.0, 60.0, 68.0]),
}


@pytest.mark.parametrize("name", list(DESIGNS))
@pytest.mark.parametrize("reach", [0.02, 0.1])
def test_no_pair_dropped_along_the_examples(name, reach):
    path, alphas = DESIGNS[name]
    model = load_model(path)
    alphas = [a for a in alphas if a < model.alpha_limit]
    thick = ThickModel(model, thickness=T)
    args, kwargs = captured_plate_contacts(thick, alphas)
    fast, depth = _assert_nothing_dropped(args, {**kwargs, "reach": reach})
    assert np.isfinite(fast[1]).any()  # contacts were measured, not only skipped
    if reach == 0.1 and name in ("vault", "radial"):
        # the broad phase did drop pairs: some pairs of the brute force lie beyond the reach
        assert (-depth > reach).any()


def _random_strip(rng, n, spread):
    s = np.linspace(0.0, 1.0, n + 1)
    bend = rng.uniform(-1.5, 1.5)
    near = np.c_[s, 0.3 * bend * s * (1.0 - s), np.zeros_like(s)]
    far = near + np.c_[rng.uniform(-0.5, 0.5) * np.ones_like(s), np.full_like(s, 0.3), 0 * s]
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    shift = rng.uniform(-spread, spread, 3)
    return near @ q + shift, far @ q + shift


def _random_scene(rng, near, far, n, plates):
    """The stacked states' offsets and faces, every ordered pair, a random chain of hinges."""
    near, far = np.stack(near), np.stack(far)
    nu = vertex_offsets(near, far)
    zero = np.zeros(near.shape[:-1])
    faces = solid_faces(near, far, nu, T, zero, zero)
    m = n + 1
    first, second = np.divmod(np.arange(plates * plates), plates)
    pairs = np.c_[first, second][first != second]
    row = np.zeros(2 * m, dtype=bool)
    row[:m] = True
    hinged = {(a, a + 1): np.r_[row, row] for a in range(plates - 1) if rng.random() < 0.5}
    return near, far, nu, faces, pairs, hinged


@settings(max_examples=property_examples(40), deadline=None, database=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    plates=st.integers(2, 12),
    n=st.integers(2, 12),
    spread=st.sampled_from([0.05, 0.3, 1.0, 3.0]),
    reach=st.sampled_from([0.01, 0.1, 0.5]),
    states=st.integers(1, 3),
)
def test_no_pair_dropped_among_random_strips(seed, plates, n, spread, reach, states):
    """Random strips scattered so that some boxes overlap and some do not, a random chain
    of hinges among them; several states."""
    rng = np.random.default_rng(seed)
    near, far = [], []
    for _ in range(states):
        strips = [_random_strip(rng, n, spread) for _ in range(plates)]
        near.append(np.stack([s[0] for s in strips]))
        far.append(np.stack([s[1] for s in strips]))
    near, far, nu, faces, pairs, hinged = _random_scene(rng, near, far, n, plates)
    args = (near, far, nu, faces, T)
    _assert_nothing_dropped(args, {"pairs": pairs, "hinged": hinged, "reach": reach})


# -- what a collision report needs (compas_ccu.thickness.report_pairs) -----------------------


def _report(contacts, marked, tolerance):
    """The numbers a CollisionReport takes from the contact arrays: per state the largest
    penetration, any crossing and the smallest clearance over the marked pairs; the first bad
    (state, pair), its depth, crossing and vertex; the first smallest clearance's (state, pair)
    and vertex."""
    depth, clearance, crossing, where = contacts
    masked = np.where(marked[None], clearance, np.inf)
    out = [np.maximum(depth.max(axis=1), 0.0), crossing.any(axis=1), masked.min(axis=1)]
    bad = (depth > tolerance) | crossing
    if bad.any():
        k = int(np.flatnonzero(bad.any(axis=1))[0])
        q = int(np.flatnonzero(bad[k])[0])
        out.append((k, q, depth[k, q], crossing[k, q], where[k, q]))
    if np.isfinite(masked).any():
        k, q = np.unravel_index(np.argmin(masked), masked.shape)
        out.append((int(k), int(q), masked[k, q], where[k, q]))
    return out


def _assert_same_report(args, kwargs, marked):
    """The pruned check (``smallest=marked``) against the brute force with an infinite reach
    cut off at the reach (no box test): every number of the report bit for bit."""
    reach = kwargs.get("reach", 0.1)
    pruned = plate_contacts(*args, **kwargs, smallest=marked)
    brute = _contacts_all(*args, kwargs["pairs"], kwargs.get("hinged"), np.inf, EXACT_RELATIVE)
    gap = -brute[0]
    far = gap > reach  # the cut-off of plate_contacts
    brute = (
        np.where(far, -np.inf, brute[0]),
        np.where(far, np.inf, brute[1]),
        brute[2],
        np.where(far, 0, brute[3]),
    )
    full = plate_contacts(*args, **kwargs)
    for tolerance in (1e-6, 0.0):
        expected = _report(brute, marked, tolerance)
        for got in (_report(pruned, marked, tolerance), _report(full, marked, tolerance)):
            assert len(got) == len(expected)
            for x, y in zip(got, expected):
                np.testing.assert_array_equal(np.asarray(x, dtype=float), np.asarray(y, float))
    # what it keeps, it keeps exactly: every penetration and crossing, every gap up to the
    # smallest clearance of its state (none when no pair's clearance counts: the first contact
    # of a path, or two plates with one hinge)
    np.testing.assert_array_equal(pruned[2], full[2])
    bound = _report(full, marked, 0.0)[2] if marked.any() else np.zeros(len(full[0]))
    kept = (full[0] >= 0.0) | (-full[0] <= bound[:, None])
    for x, y in zip(pruned, full):
        np.testing.assert_array_equal(x[kept], y[kept])
    return pruned, full


REPORT_DESIGNS = {
    **DESIGNS,
    "cone": (EXAMPLES / "cone.toml", [0.0, 20.0, 40.0]),  # 2 plates, one crease
    "funnel-crossing": (catalog_path("fig12c-funnel"), None),  # past its overlap limit
}


@pytest.mark.parametrize(
    ("reach", "name"),
    [
        # ~0.3-1.3 s a design and reach: the quick loop checks every design at one reach
        pytest.param(reach, name, marks=pytest.mark.slow) if reach == 0.02 else (reach, name)
        for reach in (0.02, 0.1)
        for name in REPORT_DESIGNS
    ],
    ids=lambda value: str(value),
)
def test_report_pairs_give_the_report_of_every_pair(name, reach):
    """The vault, the dome, inclined and radial planes, two plates, crossings: the pruned
    check gives the report's numbers of the full check and the brute force."""
    path, alphas = REPORT_DESIGNS[name]
    model = load_model(path)
    if alphas is None:  # the plates pass through each other
        alphas = np.linspace(77.3, 0.999 * model.alpha_limit, 6)
    alphas = [a for a in alphas if a < model.alpha_limit]
    thick = ThickModel(model, thickness=T)
    args, kwargs = captured_plate_contacts(thick, alphas, report=True)
    assert "smallest" in kwargs  # the report asks for the pruned check
    marked = kwargs.pop("smallest")
    pruned, full = _assert_same_report(args, {**kwargs, "reach": reach}, marked)
    if name == "vault" and reach == 0.1:  # the stack: most pairs' gaps are not measured
        assert np.isfinite(full[1][0]).sum() > 2 * np.isfinite(pruned[1][0]).sum()
    if name == "funnel-crossing":
        assert pruned[2].any()
    fast, brute = thick.collisions(alphas), thick.collisions(alphas, method="all")
    assert fast.summary() == brute.summary()


def test_report_pairs_of_three_parallel_plates():
    model = CCUModel(
        make_design(
            layout={"type": "parallel", "plates": 3, "spacing": 0.05}, crease={"segments": 9}
        )
    )
    thick = ThickModel(model, thickness=T)
    args, kwargs = captured_plate_contacts(thick, np.linspace(0.0, 30.0, 4), report=True)
    marked = kwargs.pop("smallest")
    assert marked.any() and not marked.all()
    _assert_same_report(args, kwargs, marked)


@settings(max_examples=property_examples(40), deadline=None, database=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    plates=st.integers(2, 12),
    n=st.integers(2, 12),
    spread=st.sampled_from([0.0, 0.05, 0.3, 1.0]),
    reach=st.sampled_from([0.01, 0.1, 0.5]),
    states=st.integers(1, 3),
    stacked=st.booleans(),
)
def test_report_pairs_among_random_strips(seed, plates, n, spread, reach, states, stacked):
    """Random strips (or a random stack of parallel ones), a random chain of hinges, a random
    set of marked pairs: the report's numbers of the pruned check are the brute force's."""
    rng = np.random.default_rng(seed)
    near, far = [], []
    for _ in range(states):
        if stacked:  # the flat stack: one strip, copies at random heights along its normal
            base = _random_strip(rng, n, spread)
            normal = np.cross(base[0][-1] - base[0][0], base[1][0] - base[0][0])
            normal /= np.linalg.norm(normal)
            lift = np.sort(rng.uniform(0.0, 0.1, plates))[:, None, None] * normal
            strips = [(base[0] + h, base[1] + h) for h in lift]
        else:
            strips = [_random_strip(rng, n, spread) for _ in range(plates)]
        near.append(np.stack([s[0] for s in strips]))
        far.append(np.stack([s[1] for s in strips]))
    near, far, nu, faces, pairs, hinged = _random_scene(rng, near, far, n, plates)
    marked = rng.random(len(pairs)) < 0.7
    args = (near, far, nu, faces, T)
    _assert_same_report(args, {"pairs": pairs, "hinged": hinged, "reach": reach}, marked)


def test_report_pairs_give_the_depth_of_a_crossing_pair():
    """A flat strip, a flat one 2 mm over it and a third plate whose first rulings pass through
    both (their ends beside the strips) while its last ones lie 4-5 cm over them: the crossing
    pairs are the first bad ones, and their depth is that of the full check although their
    vertices lie far beyond the smallest clearance (the state is checked again in full)."""
    s = np.linspace(0.0, 1.0, 17)
    flat = np.c_[s, np.zeros_like(s), np.zeros_like(s)]
    x = 0.3 + 0.04 * np.arange(17.0)
    through = np.arange(17) < 8
    odd = np.c_[x, np.where(through, -0.3, 0.05), np.where(through, -0.2, 0.05)]
    odd_far = np.c_[x, np.where(through, 0.6, 0.25), np.where(through, 0.2, 0.06)]
    lift = [0.0, 0.0, 0.01]
    near = np.stack([flat, odd, flat + lift])[None]
    far = np.stack([flat + [0.0, 0.3, 0.0], odd_far, flat + [0.0, 0.3, 0.01]])[None]
    nu = vertex_offsets(near, far)
    zero = np.zeros(near.shape[:-1])
    faces = solid_faces(near, far, nu, T, zero, zero)
    pairs = [(a, b) for a in range(3) for b in range(3) if a != b]
    marked = np.ones(len(pairs), dtype=bool)
    args = (near, far, nu, faces, T)
    pruned, full = _assert_same_report(args, {"pairs": pairs, "reach": 0.5}, marked)
    assert pruned[2][0, 0] and -0.06 < pruned[0][0, 0] < -0.03
