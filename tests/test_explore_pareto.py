"""Pareto front, feasibility and the choice of the best variants."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from compas_ccu.explore.pareto import feasible, pareto_mask, rank_best
from conftest import property_examples


def brute_force(v: np.ndarray, senses) -> np.ndarray:
    w = v * np.where(np.asarray(senses) == "max", -1.0, 1.0)
    out = []
    for i in range(len(w)):
        if np.isnan(w[i]).any():
            out.append(False)
            continue
        dominated = any(
            not np.isnan(w[j]).any() and (w[j] <= w[i]).all() and (w[j] < w[i]).any()
            for j in range(len(w))
        )
        out.append(not dominated)
    return np.array(out, dtype=bool)


@settings(max_examples=property_examples(60), deadline=None)
@given(
    st.integers(1, 40).flatmap(
        lambda n: st.tuples(
            st.lists(
                st.lists(st.sampled_from([0.0, 1.0, 2.0, 3.0, np.nan]), min_size=3, max_size=3),
                min_size=n,
                max_size=n,
            ),
            st.lists(st.sampled_from(["min", "max"]), min_size=3, max_size=3),
            st.integers(1, 7),
        )
    )
)
def test_pareto_mask_matches_the_definition(case):
    """Ties, duplicates and NaN included; the chunk size does not matter."""
    rows, senses, chunk = case
    v = np.array(rows, dtype=float)
    assert pareto_mask(v, senses, chunk=chunk).tolist() == brute_force(v, senses).tolist()


def test_pareto_of_a_trade_off_curve_is_all_of_it():
    x = np.linspace(0.0, 1.0, 50)
    v = np.c_[x, 1.0 - x**2]  # the second falls as the first grows
    assert pareto_mask(v, ["min", "min"]).all()  # a trade-off: every point is optimal
    assert pareto_mask(v, ["max", "max"]).all()
    assert np.flatnonzero(pareto_mask(v, ["min", "max"])).tolist() == [0]  # x = 0 wins both
    assert np.flatnonzero(pareto_mask(v, ["max", "min"])).tolist() == [49]


def test_pareto_mask_refuses_bad_input():
    with pytest.raises(ValueError, match=r"values must be \(n, 2\)"):
        pareto_mask(np.zeros((3, 3)), ["min", "max"])
    with pytest.raises(ValueError, match="senses must be 'min' or 'max'"):
        pareto_mask(np.zeros((3, 1)), ["up"])


ROWS = [
    {"status": "ok", "rise": 1.0, "u": 0.5, "free": True},
    {"status": "ok", "rise": 1.2, "u": 0.9, "free": True},
    {"status": "ok", "rise": 1.4, "u": 1.2, "free": True},  # breaks: infeasible
    {"status": "ok", "rise": 1.3, "u": 0.6, "free": False},  # collides: infeasible
    {"status": "failed", "rise": None, "u": None, "free": None},
    {"status": "ok", "rise": 0.8, "u": 0.7, "free": True},  # dominated by row 0
]


def test_feasible_needs_success_and_every_constraint():
    mask = feasible(ROWS, {"u": {"max": 1.0}, "free": True})
    assert mask.tolist() == [True, True, False, False, False, True]
    assert feasible(ROWS, {"rise": {"min": 1.1, "max": 1.3}}).tolist() == [
        False,
        True,
        False,
        True,
        False,
        False,
    ]


def test_rank_best_picks_the_balanced_front_variants():
    front, best = rank_best(ROWS, {"rise": "max", "u": "min"}, {"u": {"max": 1.0}, "free": True}, 5)
    assert front.tolist() == [True, True, False, False, False, False]
    # scaled over the feasible rows: row 0 (rise 1.0 -> 0.5, u 0.5 -> 0), row 1 (0, 1)
    assert [i for i, _ in best] == [0, 1]
    assert best[0][1] == pytest.approx(0.5) and best[1][1] == pytest.approx(1.0)
    front, best = rank_best(ROWS, {"rise": "max"}, {"u": {"max": 0.1}}, 3)
    assert not front.any() and best == []
