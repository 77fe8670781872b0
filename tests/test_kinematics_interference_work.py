"""The certificate's scan keeps its work arrays between calls
(kinematics/interference_blocks.py ``work_arrays``): what a call returns is never changed by the
next one, two threads scan at once, and the kept arrays change no result."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from compas_ccu.kinematics import interference_blocks, interference_events
from compas_ccu.model import load_model
from compas_ccu.work_arrays import KEPT_SIZE, WorkArrays
from conftest import EXAMPLES


@pytest.fixture(scope="module")
def chunks():
    """Runs of 17 states of the vault's and the quadrants' whole ranges, as the scan takes
    them, with their certificates' constants."""
    out = []
    for name in ("vault.toml", "quadrants.toml"):
        c = load_model(EXAMPLES / name).certificate
        for start in range(0, len(c.alphas) - 1, 16):
            vertices = c._vertices_at(c.alphas[start : start + 17])
            out.append((vertices, c._n, c._excluded, c._tol))
    return out


def _events(chunk):
    return interference_events.path_events(*chunk)


def _key(result):
    """Every number of ``path_events``' result, as bytes."""
    events, tol = result
    return [(k, kind, a, b, point.tobytes()) for k, kind, a, b, point in events], tol


def test_the_chunks_hold_events(chunks):
    assert sum(len(_events(c)[0]) for c in chunks) > 100


def test_a_second_call_leaves_the_first_results_unchanged(chunks):
    first = [_events(c) for c in chunks]
    kept = [_key(r) for r in first]
    for c in chunks[::-1]:  # every other run of states, other sizes, the same kept arrays
        _events(c)
    assert [_key(r) for r in first] == kept
    assert [_key(_events(c)) for c in chunks] == kept  # and the same again


def test_the_kept_arrays_change_no_result(chunks, monkeypatch):
    """The scan with new arrays everywhere (``work=None``) finds the same, bit for bit."""
    kept = [_key(_events(c)) for c in chunks]
    plain = interference_blocks.sided_blocks

    def fresh(*args):
        return plain(*args, work=None)

    monkeypatch.setattr(interference_events, "sided_blocks", fresh)
    assert [_key(_events(c)) for c in chunks] == kept


def test_sided_blocks_returns_a_new_array(chunks, monkeypatch):
    captured = []

    def keep(*args):
        live = interference_blocks.sided_blocks(*args)
        captured.append(live)
        return live

    monkeypatch.setattr(interference_events, "sided_blocks", keep)
    _events(chunks[0])
    live = captured[-1].copy()
    for c in chunks[1:]:
        _events(c)
    assert np.array_equal(captured[0], live)
    assert captured[0].base is None  # not a view of a kept buffer


def test_two_threads_at_once(chunks):
    expected = [_key(_events(c)) for c in chunks]
    results, errors = {}, []

    def scan(i, order):
        try:
            for _ in range(3):
                for j in order:
                    results[(i, j)] = _key(_events(chunks[j]))
        except Exception as error:  # pragma: no cover - reported below
            errors.append(error)

    order = list(range(len(chunks)))
    threads = [
        threading.Thread(target=scan, args=(0, order)),
        threading.Thread(target=scan, args=(1, order[::-1])),
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for (_, j), key in results.items():
        assert key == expected[j]


def test_a_buffer_grows_by_a_quarter_and_large_ones_are_not_kept():
    work = WorkArrays()
    a = work.get("a", 1000)
    assert a.shape == (1000,) and a.base.nbytes == 8000
    b = work.get("a", 1001)  # a little more: grown by a quarter, then reused
    assert b.base.nbytes == 10000
    assert work.get("a", (25, 50)).base is b.base
    assert work.get("a", 7, np.intp).base is b.base
    big = work.get("big", KEPT_SIZE + 1)
    assert work.get("big", KEPT_SIZE + 1) is not big and big.base is None
