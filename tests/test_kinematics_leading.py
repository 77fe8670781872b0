from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from compas_ccu.errors import DeploymentLimitError
from compas_ccu.kinematics.leading import LeadingStrip
from compas_ccu.strips.intrinsics import strip_intrinsics
from conftest import arc_strip, property_examples, wavy_strip


def sequential_march(near2d, far2d, psi0):
    """Independent reference: docs/geometry.md §2's sequential construction, one quad at a time.

    Quad 0 is tilted by psi0 about its crease edge; every next quad is rotated about the shared
    ruling until its next crease vertex returns to z = 0 (circle-plane intersection, root
    continuous with the flat state). Returns near, far (n + 1, 3) or None at the limit.
    """
    n = len(near2d) - 1
    p3 = np.zeros((n + 1, 3))
    q3 = np.zeros((n + 1, 3))
    e = near2d[1] - near2d[0]
    c, s = e / np.linalg.norm(e)
    to_local = np.array([[c, -s], [s, c]])  # rows: x, y components

    def local(pt):
        return (pt - near2d[0]) @ to_local

    p3[1] = [np.linalg.norm(e), 0.0, 0.0]
    for i in (0, 1):
        x, y = local(far2d[i])
        q3[i] = [x, y * math.cos(psi0), y * math.sin(psi0)]
    for j in range(1, n):
        a = q3[j] - p3[j]
        a /= np.linalg.norm(a)
        r2 = far2d[j] - near2d[j]
        r2 /= np.linalg.norm(r2)
        d2 = near2d[j + 1] - near2d[j]
        t = d2 @ r2
        rho = abs(r2[0] * d2[1] - r2[1] * d2[0])
        centre = p3[j] + t * a
        e1 = np.cross(a, [0.0, 0.0, 1.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(a, e1)
        amp = math.hypot(e1[2], e2[2])
        arg = -centre[2] / (rho * amp)
        if abs(arg) > 1.0:
            return None
        phi0 = math.atan2(e2[2], e1[2])
        guess = p3[j] + (p3[j] - p3[j - 1])  # continue roughly straight ahead
        roots = [
            centre + rho * (math.cos(f) * e1 + math.sin(f) * e2)
            for f in (phi0 + math.acos(arg), phi0 - math.acos(arg))
        ]
        # the continuous root keeps the quad on the plate side (its far side rises)
        cand = []
        for root in roots:
            u = root - p3[j]
            side = np.cross(u, q3[j] - p3[j])[2]
            cand.append((side > 0.0, -np.linalg.norm(root - guess), root))
        cand.sort(key=lambda x: (x[0], x[1]))
        p3[j + 1] = cand[-1][2]
        # far vertex: same position in the quad frame (P_j, P_{j+1}, Q_j) as in the pattern
        b2 = np.c_[near2d[j + 1] - near2d[j], far2d[j] - near2d[j]].T
        coef = np.linalg.solve(b2.T, far2d[j + 1] - near2d[j])
        q3[j + 1] = p3[j] + coef[0] * (p3[j + 1] - p3[j]) + coef[1] * (q3[j] - p3[j])
    return p3, q3


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("psi0_deg", [5.0, 25.0, 50.0])
def test_closed_form_equals_the_sequential_march(seed, psi0_deg):
    near, far = wavy_strip(40, seed)
    strip = LeadingStrip(strip_intrinsics(near, far), reference=0)
    psi0 = math.radians(psi0_deg)
    ref = sequential_march(near, far, psi0)
    if ref is None:
        assert math.sin(psi0) > strip.s0_max
        return
    placed = strip.place(math.sin(psi0))
    # align: first crease vertex at the origin, first crease edge along +x (rotation about z)
    p, q = placed.near[0] - placed.near[0, 0], placed.far[0] - placed.near[0, 0]
    c, s = (p[1, :2]) / np.linalg.norm(p[1, :2])
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(p @ rot, ref[0], atol=1e-12)
    np.testing.assert_allclose(q @ rot, ref[1], atol=1e-12)


@pytest.mark.parametrize("n", [6, 24, 200])
@pytest.mark.parametrize("alpha_deg", [10.0, 40.0, 75.0])
def test_cone_crease_radius_is_R_cos_alpha(n, alpha_deg):
    radius = 2.0
    near, far = arc_strip(n, radius=radius, angle=math.radians(100.0), width=0.4)
    strip = LeadingStrip(strip_intrinsics(near, far), reference=n // 2)
    placed = strip.place_alpha(math.radians(alpha_deg)).near[0]
    # circumradius of the deployed crease polyline from three of its vertices
    a, b, c = placed[0, :2], placed[n // 2, :2], placed[-1, :2]
    lhs = np.array([2 * (b - a), 2 * (c - a)])
    centre = np.linalg.solve(lhs, [b @ b - a @ a, c @ c - a @ a])
    r3d = np.linalg.norm(placed[:, :2] - centre, axis=1)
    # the 2D polyline is inscribed in the circle of radius R: the same holds in 3D with R cos a
    np.testing.assert_allclose(r3d, radius * math.cos(math.radians(alpha_deg)), rtol=1e-12)
    # the rulings meet at one apex on the axis of the circle at height R sin(alpha)
    placed_all = strip.place_alpha(math.radians(alpha_deg))
    r = placed_all.rulings[0]
    apex = placed[:, :] + radius * r
    np.testing.assert_allclose(apex[:, :2], np.tile(centre, (n + 1, 1)), atol=1e-12)
    np.testing.assert_allclose(apex[:, 2], radius * math.sin(math.radians(alpha_deg)), rtol=1e-12)


def test_flat_state_is_the_pattern():
    near, far = wavy_strip(30)
    strip = LeadingStrip(
        strip_intrinsics(near, far), reference=7, anchor_point=near[7], anchor_angle=None
    )
    placed = strip.place_alpha(0.0)
    assert np.all(placed.near[0, :, 2] == 0.0) and np.all(placed.far[0, :, 2] == 0.0)
    # congruent to the pattern: all pairwise distances agree
    pts2d = np.r_[near, far]
    pts3d = np.r_[placed.near[0], placed.far[0]][:, :2]
    d2 = np.linalg.norm(pts2d[:, None] - pts2d[None], axis=-1)
    d3 = np.linalg.norm(pts3d[:, None] - pts3d[None], axis=-1)
    np.testing.assert_allclose(d3, d2, atol=1e-13)
    np.testing.assert_allclose(placed.near[0, 7, :2], near[7], atol=1e-15)


def test_reference_alpha_is_met_and_monotone():
    near, far = wavy_strip(50, seed=3)
    strip = LeadingStrip(strip_intrinsics(near, far), reference=25)
    alphas = np.radians(np.linspace(0.0, math.degrees(strip.alpha_limit), 40))
    s0 = strip.s0_for_alpha(alphas)
    np.testing.assert_allclose(strip.reference_alpha(s0), alphas, atol=1e-13)
    assert np.all(np.diff(s0) > 0.0)


@pytest.mark.parametrize("reference", [0, 1, 11, 31, 32])
def test_reference_alpha_equals_measured_alpha_at_the_vertex(reference):
    from compas_ccu.strips.frames import crease_frames
    from compas_ccu.strips.rulings import vertex_reflection_angles

    near, far = wavy_strip(32, seed=4)
    strip = LeadingStrip(
        strip_intrinsics(near, far),
        reference=reference,
        anchor_point=near[reference],
        anchor_angle=1.0,
    )
    placed = strip.place_alpha(math.radians(33.0))
    measured = vertex_reflection_angles(placed.near[0], placed.rulings[0])
    assert measured[reference] == pytest.approx(math.radians(33.0), abs=1e-13)
    # the anchor: reference vertex and its tangent keep their place
    np.testing.assert_allclose(placed.near[0, reference, :2], near[reference], atol=1e-14)
    t = crease_frames(placed.near[0]).tangents[reference]
    assert math.atan2(t[1], t[0]) == pytest.approx(1.0, abs=1e-13)


def test_beyond_the_limit_names_vertex_and_largest_alpha():
    near, far = wavy_strip(30, seed=1)
    strip = LeadingStrip(strip_intrinsics(near, far), reference=15)
    limit = math.degrees(strip.alpha_limit)
    j = strip.limit_segment
    with pytest.raises(DeploymentLimitError) as info:
        strip.s0_for_alpha(math.radians(limit + 0.5))
    err = info.value
    assert err.vertex == j and err.alpha_limit == pytest.approx(limit)
    assert f"crease segment {j} (crease vertices {j}-{j + 1})" in str(err)
    assert f"{limit:.6g} deg" in str(err)
    # at the limit that segment stands perpendicular to the crease plane
    placed = strip.place(strip.s0_max)
    assert placed.tilts[0, j] == pytest.approx(math.pi / 2, abs=1e-7)
    with pytest.raises(DeploymentLimitError, match="negative"):
        strip.s0_for_alpha(-0.1)


@settings(max_examples=property_examples(40), deadline=None)
@given(
    seed=st.integers(0, 10_000),
    n=st.integers(3, 80),
    fraction=st.floats(0.0, 1.0),
)
def test_isometry_and_planarity_hold_for_random_strips(seed, n, fraction):
    near, far = wavy_strip(n, seed)
    intr = strip_intrinsics(near, far)
    strip = LeadingStrip(intr, reference=n // 3)
    placed = strip.place(fraction * strip.s0_max)
    p, q = placed.near[0], placed.far[0]
    got = strip_intrinsics(p, q)
    size = 2.0
    np.testing.assert_allclose(got.edge_lengths, intr.edge_lengths, atol=1e-12 * size)
    np.testing.assert_allclose(got.ruling_lengths, intr.ruling_lengths, atol=1e-12 * size)
    np.testing.assert_allclose(
        np.linalg.norm(q[1:] - q[:-1], axis=1),
        np.linalg.norm(far[1:] - far[:-1], axis=1),
        atol=1e-12 * size,
    )
    diag3 = np.linalg.norm(q[1:] - p[:-1], axis=1)
    np.testing.assert_allclose(
        diag3, np.linalg.norm(far[1:] - near[:-1], axis=1), atol=1e-12 * size
    )
    normal = np.cross(p[1:] - p[:-1], q[:-1] - p[:-1])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    assert np.abs(np.einsum("ij,ij->i", q[1:] - p[:-1], normal)).max() < 1e-12 * size
    assert np.abs(p[:, 2]).max() == 0.0


@pytest.mark.parametrize("n, seed", [(2, 0), (3, 1), (17, 2), (64, 3)])
def test_one_angle_takes_the_array_paths_iterates_bit_for_bit(n, seed):
    """s0_for_alpha of one angle (Newton on floats) is the array path's result, bit for bit,
    whatever form the angle comes in, for every reference vertex kind (first, interior, last)."""
    near, far = wavy_strip(n, seed)
    intr = strip_intrinsics(near, far)
    rng = np.random.default_rng(seed)
    for reference in sorted({0, 1, n // 2, n - 1, n}):
        strip = LeadingStrip(intr, reference=reference)
        limit = strip.alpha_limit
        alphas = [0.0, 1e-12, limit, limit * (1.0 - 1e-15), *np.linspace(0.0, limit, 9)]
        alphas += list(rng.uniform(0.0, limit, 12))
        for alpha in alphas:
            expected = strip.s0_for_alpha(np.array([alpha, alpha]))[:1]  # the array path
            for form in (alpha, np.float64(alpha), np.array(alpha), np.array([alpha])):
                got = strip.s0_for_alpha(form)
                assert got.shape == (1,) and got.tobytes() == expected.tobytes(), (reference, alpha)


def test_one_segment_strip_inverts_an_angle():
    near, far = wavy_strip(1, 0)
    strip = LeadingStrip(strip_intrinsics(near, far), reference=1)
    s0 = strip.s0_for_alpha(0.4)
    assert s0.shape == (1,)
    assert strip.reference_alpha(s0)[0] == pytest.approx(0.4, abs=1e-14)


def plain_place(strip: LeadingStrip, s0: np.ndarray) -> tuple:
    """The leading strip placed as docs/geometry.md writes it, one array operation per step:
    ``(near, rulings, far, tilts)`` for (k,) ``s0``. The oracle of the placement's
    implementation (:class:`~compas_ccu.kinematics.leading.LeadingWriter`: kept arrays, fused
    calls), which must give the same bits."""
    n, k = strip.n, len(s0)
    # n + 1 columns: segments 0 ... n - 1, and segment n - 1 again for the last ruling
    sin_psi = np.minimum(np.maximum(s0[:, None] * strip._factors_ext[None, :], -1.0), 1.0)
    cos_psi = np.sqrt(1.0 - np.square(sin_psi))
    turns = strip._turns(s0, sin_psi[:, :n], cos_psi[:, :n])  # (K2)
    theta = np.zeros((k, n + 1))
    np.add.accumulate(turns, axis=1, out=theta[:, 1:n])
    theta[:, :n] += (strip.anchor_angle - strip._tangent_angle(theta[:, :n], turns))[:, None]
    theta[:, n] = theta[:, n - 1]
    cos_t, sin_t = np.cos(theta), np.sin(theta)
    h = strip.intrinsics.edge_lengths
    near = np.zeros((k, n + 1, 3))
    np.add.accumulate(h * cos_t[:, :n], axis=1, out=near[:, 1:, 0])
    np.add.accumulate(h * sin_t[:, :n], axis=1, out=near[:, 1:, 1])
    near[:, :, :2] += (strip.anchor_point - near[:, strip.reference, :2])[:, None, :]
    # ruling i in the frame of quad min(i, n - 1), from the vertex into the plate
    cb, sb = strip._ruling_cos, strip._ruling_sin
    rulings = np.empty((k, n + 1, 3))
    rulings[:, :, 0] = cb * cos_t - sb * cos_psi * sin_t
    rulings[:, :, 1] = cb * sin_t + sb * cos_psi * cos_t
    rulings[:, :, 2] = sb * sin_psi
    far = strip._ruling_xyz * rulings + near
    return near, rulings, far, np.arcsin(sin_psi[:, :n])


@pytest.mark.parametrize("n, seed", [(1, 0), (2, 0), (3, 1), (17, 2), (64, 3)])
def test_the_placement_is_the_plain_one_bit_for_bit(n, seed):
    """LeadingStrip.place, and its writer into kept arrays, give what the plain transcription
    (:func:`plain_place`) gives, to the last bit, signed zeros included, for every reference
    vertex kind, one or several states, the flat state, the limit, beyond it and a negative s0."""
    near, far = wavy_strip(n, seed)
    intr = strip_intrinsics(near, far)
    for reference in sorted({0, 1, n // 2, n - 1, n}):
        strip = LeadingStrip(intr, reference=reference)
        top = strip.s0_max
        for s0 in ([0.0], [0.3 * top], [top], [1.5 * top], [-0.2 * top], [0.0, 0.5 * top, top]):
            s0 = np.array(s0)
            out = [np.empty((len(s0), n + 1, 3)) for _ in range(3)]
            writer = strip.writer(*out)
            for values in (s0, s0[::-1].copy()):  # the second call reuses the arrays
                want = plain_place(strip, values)
                tilts = writer.place(values)
                placed = strip.place(values)
                for got, also, expected in zip([*out, tilts], placed, want):
                    assert got.tobytes() == expected.tobytes(), (reference, values)
                    assert also.tobytes() == expected.tobytes(), (reference, values)
