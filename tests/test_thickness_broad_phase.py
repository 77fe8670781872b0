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
from compas_ccu.model import load_model
from compas_ccu.thickness import ThickModel, solid_faces, vertex_offsets
from compas_ccu.thickness.collision import _contacts_all, box_pairs, plate_contacts
from compas_ccu.tolerances import EXACT_RELATIVE
from conftest import EXAMPLES, captured_plate_contacts

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


@settings(max_examples=60, deadline=None, database=None)
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


@settings(max_examples=40, deadline=None, database=None)
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
    args = (near, far, nu, faces, T)
    _assert_nothing_dropped(args, {"pairs": pairs, "hinged": hinged, "reach": reach})
