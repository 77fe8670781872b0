"""The mechanism on its own: reflected plates, plane fits, and honest planarity reporting."""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.geometry import fit_planes
from compas_ccu.kinematics.leading import LeadingStrip
from compas_ccu.kinematics.mechanism import CreaseLink, Mechanism, PlateLink
from compas_ccu.strips.frames import crease_frames
from compas_ccu.strips.intrinsics import strip_intrinsics
from compas_ccu.strips.rulings import orthogonal_rulings


def test_fit_planes_recovers_a_plane_and_the_deviation():
    rng = np.random.default_rng(0)
    xy = rng.uniform(-1, 1, (50, 2))
    normal = np.array([0.2, -0.3, 0.9])
    normal /= np.linalg.norm(normal)
    e1 = np.cross(normal, [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    pts = 0.5 + xy[:, :1] * e1 + xy[:, 1:] * e2
    pts[7] += 1e-3 * normal
    origin, nrm, dev = fit_planes(pts[None], -normal)
    np.testing.assert_allclose(nrm[0], -normal, atol=1e-4)
    assert 9e-4 < dev[0] < 1e-3 + 1e-12


def inclined_mechanism(tilt_deg=5.0, n=32, alpha_deg=30.0):
    """Leading arc strip + one plate mirrored across a plane inclined perpendicular to the
    actuation axis (paper Fig. 6c): the subsequent crease does not stay planar."""
    alpha = math.radians(alpha_deg)
    t = np.linspace(math.pi * 0.85, math.pi * 0.15, n + 1)
    crease = 1.5 * np.c_[np.cos(t), -np.sin(t)]  # centre of the arc on the left
    r = orthogonal_rulings(crease, alpha=alpha, reference=n // 2)
    near = np.c_[crease, np.zeros(n + 1)]
    phi = math.radians(tilt_deg)
    n1 = np.array([math.sin(phi), 0.0, math.cos(phi)])
    o1 = np.array([0.0, 0.0, 0.3])
    t1 = ((o1 - near) @ n1) / (r @ n1)
    assert np.all(t1 > 0.0)
    far = near + t1[:, None] * r
    q = (near - far) / np.linalg.norm(near - far, axis=1)[:, None]
    child_dir = q - 2 * (q @ n1)[:, None] * n1
    o2 = o1 + 0.15 * n1
    child_far = far + (((o2 - far) @ n1) / (child_dir @ n1))[:, None] * child_dir
    lead_intr = strip_intrinsics(near, far)
    child_intr = strip_intrinsics(far, child_far)
    f = crease_frames(crease)
    leading = LeadingStrip(
        lead_intr,
        reference=n // 2,
        anchor_point=crease[n // 2],
        anchor_angle=math.atan2(f.tangents[n // 2][1], f.tangents[n // 2][0]),
    )
    plates = [
        PlateLink(lead_intr),
        PlateLink(child_intr, parent=0, boundary="far", relation="ccu", crease=0),
    ]
    creases = [CreaseLink(0, "far", 1, "ccu", False, tuple(n1))]
    return Mechanism(leading, plates, creases), (near, far, child_far), child_intr


def test_inclined_plane_crease_planarity_is_measured_along_the_path():
    mech, design, child_intr = inclined_mechanism()
    alphas = np.radians([0.0, 10.0, 20.0, 30.0, 40.0])
    st = mech.deploy(alphas)
    dev = st.planarity[:, 0]
    assert dev[0] < 1e-14  # flat: everything in one plane
    assert dev[3] < 1e-14  # the design state: planar by construction
    assert dev[1] > 1e-5 and dev[2] > 1e-6 and dev[4] > 1e-6  # in between and beyond: not
    np.testing.assert_allclose(st.near[3, 1], design[1], atol=1e-13)
    np.testing.assert_allclose(st.far[3, 1], design[2], atol=1e-13)
    # the reflected plate's isometry error is reported where the crease is not planar
    got = strip_intrinsics(st.near[1, 1], st.far[1, 1])
    sector_error = np.nanmax(np.abs(got.sector_forward - child_intr.sector_forward))
    assert sector_error > 1e-6
    got = strip_intrinsics(st.near[3, 1], st.far[3, 1])
    assert np.nanmax(np.abs(got.sector_forward - child_intr.sector_forward)) < 1e-12


def test_crease_rows_of_any_selection_are_the_masked_rows():
    """Mechanism.crease_rows / crease_boundaries through the kept CreaseSelection: plate a's
    crease row (and its other row), creases on near and far boundaries mixed or not."""
    from compas_ccu.model import load_model

    mech = load_model("examples/vault.toml").mechanism
    st = mech.deploy(np.radians([12.0, 27.0]))
    everything = np.arange(len(mech.creases))
    for creases in (everything, everything[::-1], np.array([0, 4]), np.array([4]), np.array([2])):
        on_far = mech.crease_far[creases][None, :, None, None]
        a = mech.crease_plate_a[creases]
        row = np.where(on_far, st.far[:, a], st.near[:, a])
        other = np.where(on_far, st.near[:, a], st.far[:, a])
        for _ in range(2):  # made, then kept
            np.testing.assert_array_equal(mech.crease_rows(creases, st.near, st.far), row)
            got_row, got_other = mech.crease_boundaries(creases, st.near, st.far)
            np.testing.assert_array_equal(got_row, row)
            np.testing.assert_array_equal(got_other, other)
    assert mech.crease_selection([0, 4]) is mech.crease_selection(np.array([0, 4]))


def test_fit_planes_of_a_set_with_a_nan_leaves_the_others_alone():
    rng = np.random.default_rng(1)
    pts = rng.uniform(-1.0, 1.0, (3, 20, 3)) * [1.0, 1.0, 1e-3]
    orient = np.array([0.0, 0.0, 1.0])
    clean = fit_planes(pts, orient)
    bad = pts.copy()
    bad[1, 5, 0] = np.nan
    origin, normal, deviation = fit_planes(bad, orient)
    assert np.isnan(normal[1]).all() and np.isnan(deviation[1])
    for i in (0, 2):
        assert normal[i].tobytes() == clean[1][i].tobytes()
        assert origin[i].tobytes() == clean[0][i].tobytes()
        assert deviation[i] == clean[2][i]


def test_the_generations_crease_selections_are_kept_whatever_else_is_read():
    """A long chain has more generations than the bound on other kept selections: its own stay."""
    from compas_ccu.model import load_model

    mech = load_model("examples/vault.toml").mechanism
    own = [np.array([mech.plates[i].crease for i in g]) for g in mech.generations[1:]]
    before = [mech.crease_selection(creases) for creases in own]
    for i in range(len(mech.creases)):
        for j in range(len(mech.creases)):
            mech.crease_selection([i, j])  # 81 sets read from outside: more than are kept
    assert all(mech.crease_selection(c) is b for c, b in zip(own, before))


def test_planes_put_in_crease_order_by_a_take_are_those_of_the_scatter():
    """The vault finds its creases out of order (0, 4, 1, 5, ...) and places plates 1, 5 / 2, 6
    ... as strided slices: the same bytes as zeros, a scatter and index arrays."""
    from compas_ccu.model import load_model

    mech = load_model("examples/vault.toml").mechanism
    assert mech._found_take and isinstance(mech._batches[1].target, slice)
    fast = mech.place(np.array([0.1, 0.3]))
    mech._found_inverse = None  # the general path: zeros and a scatter
    mech._batches = [b._replace(target=b.plates) for b in mech._batches]
    slow = mech.place(np.array([0.1, 0.3]))
    for a, b in zip(fast, slow):
        assert a.shape == b.shape and a.tobytes() == b.tobytes()
