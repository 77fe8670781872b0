"""The collision search's work arrays kept between calls (thickness/work_arrays.py): what a call
returns is never changed by the next one, and two threads search at once."""

from __future__ import annotations

import pickle
import threading

import numpy as np
import pytest

from compas_ccu.model import load_model
from compas_ccu.thickness import ThickModel
from compas_ccu.thickness.axis_shift import offset_faces
from compas_ccu.thickness.collision import plate_contacts
from compas_ccu.thickness.work_arrays import KEPT_SIZE, WorkArrays, work_arrays
from conftest import EXAMPLES


@pytest.fixture(scope="module")
def thick():
    return ThickModel(load_model(EXAMPLES / "vault.toml"))


def _contacts(thick, alphas):
    """plate_contacts (the candidate search, kept work arrays) of ``thick`` at ``alphas``."""
    st = thick.place(np.asarray(alphas, dtype=float))
    mid_near, mid_far = thick.corrected_boundaries(st)
    faces = offset_faces(mid_near, mid_far, st.offsets, thick.thickness)
    pairs, rows, _ = thick.contact_pairs()
    return plate_contacts(
        mid_near, mid_far, st.offsets, faces, thick.thickness, pairs=pairs, hinged=rows
    )


def _same(a, b):
    for x, y in zip(a, b):
        assert x.dtype == y.dtype and x.shape == y.shape
        assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f")


def test_a_second_call_leaves_the_first_results_unchanged(thick):
    limit = thick.model.alpha_limit
    first = _contacts(thick, np.linspace(0.0, limit, 25))
    kept = [x.copy() for x in first]
    _contacts(thick, np.linspace(0.1 * limit, 0.9 * limit, 25))  # other states, same arrays
    _contacts(thick, [0.5 * limit])  # fewer states
    _same(first, kept)
    report = thick.collisions(np.linspace(0.0, limit, 9))
    summary = report.summary()
    penetration, clearance = report.penetration.copy(), report.clearance.copy()
    thick.collisions(np.linspace(0.0, 0.5 * limit, 9))
    assert report.summary() == summary
    assert np.array_equal(report.penetration, penetration)
    assert np.array_equal(report.clearance, clearance)


def test_two_threads_at_once(thick):
    limit = thick.model.alpha_limit
    runs = [np.linspace(0.0, limit, 25), np.linspace(0.2 * limit, 0.8 * limit, 13)]
    expected = [_contacts(thick, alphas) for alphas in runs]
    barrier = threading.Barrier(2)
    found, errors = [[], []], []

    def search(i):
        try:
            barrier.wait()
            for _ in range(6):
                found[i].append(_contacts(thick, runs[i]))
        except Exception as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=search, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for i in range(2):
        assert len(found[i]) == 6
        for result in found[i]:
            _same(result, expected[i])


def test_work_arrays_kept_per_thread_and_dropped_when_pickled():
    work = WorkArrays()
    a = work.get("x", (4, 5))
    assert a.shape == (4, 5) and a.dtype == np.float64 and a.flags.c_contiguous
    assert np.shares_memory(work.get("x", (2, 3)), a)  # the same buffer, smaller
    other = []
    t = threading.Thread(target=lambda: other.append(work.get("x", (4, 5))))
    t.start()
    t.join()
    assert not np.shares_memory(other[0], a)  # another thread's own
    big = work.get("big", KEPT_SIZE + 1)
    assert not np.shares_memory(work.get("big", KEPT_SIZE + 1), big)  # too large to keep
    copy = pickle.loads(pickle.dumps(work))
    assert not np.shares_memory(copy.get("x", (4, 5)), a)
    assert pickle.loads(pickle.dumps(work_arrays)) is not work_arrays
