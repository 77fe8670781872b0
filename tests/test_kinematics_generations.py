"""Placement by generations (``Mechanism.place``) against a plate-by-plate reference loop.

``Mechanism.place`` places all the plates of one generation at once (one call of the crease-plane
strategy, one array operation for their reflections). The reference below is the placement as
it was written before: one plate at a time, in mechanism order, each mirrored across the plane
of its crease. Both must give the same numbers, bit for bit, on every example and catalog design
(parallel, inclined, radial layouts, the 2-plate cone, the CCF quadrants) for both strategies.
"""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest

from compas_ccu.catalog import CATALOG_DIR
from compas_ccu.geometry import dot, reflect_points
from compas_ccu.kinematics.generations import as_slice
from compas_ccu.kinematics.mechanism import CreasePlanes
from compas_ccu.kinematics.plates import boundary_rows
from compas_ccu.model import load_model
from compas_ccu.thickness.axis_shift import HingePlanes, crease_sides
from conftest import EXAMPLES

DESIGNS = sorted(EXAMPLES.glob("*.toml")) + sorted(CATALOG_DIR.glob("*.toml"))


def sequential_place(mechanism, s0, planes):
    """The plate-by-plate placement loop (the reference): plate ``i`` hangs off its parent,
    mirrored across the plane of crease ``plate.crease`` (``planes.plane`` of that crease)."""
    lead = mechanism.leading.place(s0)
    k, m = lead.near.shape[:2]
    p, c = len(mechanism.plates), len(mechanism.creases)
    near, far, rays = np.empty((k, p, m, 3)), np.empty((k, p, m, 3)), np.empty((k, p, m, 3))
    near[:, 0], far[:, 0], rays[:, 0] = lead.near, lead.far, lead.rulings
    origins, normals, planarity = np.zeros((k, c, 3)), np.zeros((k, c, 3)), np.zeros((k, c))
    placed = np.zeros(c, dtype=bool)
    planes.begin(k, c, m)
    for i, plate in enumerate(mechanism.plates[1:], start=1):
        j, ci = plate.parent, plate.crease
        hinge = boundary_rows(near[:, j], far[:, j], plate.boundary)[0]
        away = rays[:, j] if plate.boundary == "near" else -rays[:, j]
        origin, normal, planarity[:, ci] = planes.plane(mechanism, ci, near, far)
        origins[:, ci], normals[:, ci] = origin, normal
        mirrored = away - 2.0 * dot(away, normal[:, None])[..., None] * normal[:, None]
        if plate.relation == "ccf":
            mirrored = -mirrored
        if planes.mirror_rows:
            hinge = reflect_points(hinge, origin, normal)
        near[:, i] = hinge
        far[:, i] = hinge + plate.intrinsics.ruling_lengths[None, :, None] * mirrored
        rays[:, i] = mirrored
        placed[ci] = True
    for ci in np.flatnonzero(~placed):
        origins[:, ci], normals[:, ci], planarity[:, ci] = planes.plane(mechanism, ci, near, far)
    return near, far, origins, normals, planarity, lead.tilts


@pytest.fixture(scope="module", params=DESIGNS, ids=lambda path: path.stem)
def model(request):
    return load_model(request.param)


def _s0(model, states):
    alphas = np.linspace(0.0, 0.95 * min(model.alpha_limit, 89.0), states)
    return model.mechanism.leading.s0_for_alpha(np.radians(alphas))


def test_generations_place_every_plate_after_its_parent(model):
    mech = model.mechanism
    generation = {int(i): g for g, plates in enumerate(mech.generations) for i in plates}
    assert sorted(generation) == list(range(len(mech.plates)))
    assert list(mech.generations[0]) == [0]
    for i, plate in enumerate(mech.plates[1:], start=1):
        assert generation[plate.parent] < generation[i]
        assert generation[mech.creases[plate.crease].plate_a] < generation[i]


@pytest.mark.parametrize("states", [1, 7])
def test_thin_placement_equals_the_plate_by_plate_loop(model, states):
    mech = model.mechanism
    s0 = _s0(model, states)
    got = mech.place(s0)
    want = sequential_place(mech, s0, CreasePlanes())
    for name, a, b in zip(got._fields, got, want):
        np.testing.assert_array_equal(a, b, err_msg=name)
    # and every crease plane refitted at once is the one placed by
    refit = mech.refit(got, got.near, got.far)
    np.testing.assert_array_equal(refit.plane_normals, got.plane_normals)
    np.testing.assert_array_equal(refit.planarity, got.planarity)


def test_thick_placement_equals_the_plate_by_plate_loop(model):
    mech = model.mechanism
    if any(c.relation != "ccu" for c in mech.creases):
        pytest.skip("the axis-shift model takes CCU creases only")
    probe = mech.deploy(math.radians(min(20.0, 0.5 * model.alpha_limit)))
    sides = crease_sides(mech, probe)
    s0 = _s0(model, 5)
    batched, reference = HingePlanes(0.006, sides), HingePlanes(0.006, sides)
    got = mech.place(s0, planes=batched)
    want = sequential_place(mech, s0, reference)
    for name, a, b in zip(got._fields, got, want):
        np.testing.assert_array_equal(a, b, err_msg=name)
    for name in ("mid_planarity", "offset_planarity", "corrections"):
        np.testing.assert_array_equal(getattr(batched, name), getattr(reference, name))


def test_known_generations_of_the_vault(vault_model):
    """Ten plates in parallel planes: a chain both ways from the leading plate, so two
    plates per generation (the placement is sequential along a chain: each crease plane is
    fitted to the plate placed before)."""
    sizes = [len(g) for g in vault_model.mechanism.generations]
    assert sum(sizes) == 10 and sizes[0] == 1 and max(sizes) == 2
    st = vault_model.mechanism.deploy(math.radians(30.0))
    # parallel planes keep every crease planar and every plate an isometry of its pattern
    assert st.planarity.max() < 1e-12 * vault_model.size


class _GeneralLoop(CreasePlanes):
    """The default planes through the general placement loop (a strategy other than the
    default itself), the reference of :class:`DefaultPlacement`."""


@pytest.mark.parametrize("states", [1, 4])
def test_default_placement_is_the_general_loop_to_the_last_bit(model, states):
    """``DefaultPlacement`` (the planned fast path) writes the same bytes as the general loop
    with the same planes, signed zeros included, at the flat state and up to the limit."""
    mech = model.mechanism
    s0 = np.linspace(0.0, mech.leading.s0_max, states + 1)[:states]
    for values in (s0, s0[-1:], np.array([mech.leading.s0_max])):
        got = mech.place(values)
        want = mech.place(values, planes=_GeneralLoop())
        for name, a, b in zip(got._fields, got, want):
            assert a.shape == b.shape and a.tobytes() == b.tobytes(), name


def test_default_placement_hands_rows_that_are_not_finite_to_the_general_loop(vault_model):
    mech = vault_model.mechanism
    lead = mech.leading.place([0.1, np.nan])
    assert mech._default.place(lead) is None  # the masked plane fit of the general loop
    with np.errstate(invalid="ignore"):
        got = mech.place([0.1, np.nan])
        want = mech.place([0.1, np.nan], planes=_GeneralLoop())
    for name, a, b in zip(got._fields, got, want):
        np.testing.assert_array_equal(a, b, err_msg=name)
    assert np.isfinite(got.near[0]).all() and np.isfinite(got.plane_normals[0]).all()
    free = ~mech.crease_fixed
    assert np.isnan(got.plane_normals[1, free]).all()  # the fixed leading plane stays z = 0


def test_a_placement_keeps_nothing_between_calls(vault_model):
    """Every array of a placement is its own: the next call does not change it."""
    mech = vault_model.mechanism
    first = mech.deploy(math.radians(20.0))
    kept = [a.copy() for a in first]
    mech.deploy(math.radians(40.0))
    for a, b in zip(first, kept):
        assert a.tobytes() == b.tobytes()


def test_evenly_spaced_indices_are_slices():
    assert as_slice(np.array([3, 7, 11])) == slice(3, 12, 4)
    assert as_slice(np.array([0])) == slice(0, 1, 1)
    for indices in ([0, 0], [2, 1], [0, 1, 3]):
        assert isinstance(as_slice(np.array(indices)), np.ndarray)


def test_default_placement_without_the_svd_gufunc_is_the_same(vault_model, monkeypatch):
    """Where NumPy does not name ``svd_s`` / ``svd_f`` (NumPy 1.x), ``numpy.linalg.svd``
    itself fits the planes: the same bytes."""
    from compas_ccu.kinematics import generations

    mech = vault_model.mechanism
    s0 = np.array([0.0, 0.4 * mech.leading.s0_max])
    want = mech.place(s0)
    monkeypatch.setattr(generations, "_SVD", None)
    monkeypatch.setattr(mech._default, "_local", threading.local())  # a new plan of the calls
    got = mech.place(s0)
    for name, a, b in zip(got._fields, got, want):
        assert a.tobytes() == b.tobytes(), name


def test_two_threads_place_one_mechanism_at_once(vault_model):
    """Each thread keeps its own work arrays: the states of concurrent placements are those of
    one thread alone, bit for bit."""
    mech = vault_model.mechanism
    alphas = np.radians(np.linspace(5.0, 60.0, 12))
    want = [mech.deploy(a) for a in alphas]
    results = {}

    def run(name):
        for _ in range(20):
            results[name] = [mech.deploy(a) for a in alphas]
            for got, expected in zip(results[name], want):
                for a, b in zip(got, expected):
                    assert a.tobytes() == b.tobytes()

    threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert sorted(results) == [0, 1]


def test_a_mechanism_pickles_without_its_work_arrays(vault_model):
    import pickle

    mech = vault_model.mechanism
    want = mech.deploy(math.radians(30.0))
    copy = pickle.loads(pickle.dumps(mech))
    for a, b in zip(copy.deploy(math.radians(30.0)), want):
        assert a.tobytes() == b.tobytes()


@pytest.mark.parametrize("change", ["plate order", "general form"])
def test_the_planned_calls_in_any_order_are_the_same(model, change, monkeypatch):
    """The planned calls with the rows in plate and crease order (not generation order), or
    every generation in the general form (an einsum of another order), write the same bytes."""
    from compas_ccu.kinematics import generations

    mech = model.mechanism
    s0 = np.array([0.0, 0.3 * mech.leading.s0_max, mech.leading.s0_max])
    want = [mech.place(s0), mech.place(s0[1:2])]
    if change == "plate order":
        monkeypatch.setattr(generations, "_generation_order", lambda plan: (None, None))
    else:
        monkeypatch.setattr(generations, "_EINSUM_ORDER", False)
    monkeypatch.setattr(mech._default, "_local", threading.local())  # a new plan of the calls
    for got, expected in zip([mech.place(s0), mech.place(s0[1:2])], want):
        for name, a, b in zip(got._fields, got, expected):
            assert a.shape == b.shape and a.tobytes() == b.tobytes(), name
