from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from compas_ccu.curves import SplineProfile, discrete_curvature
from compas_ccu.errors import ProfileError

WAVE_X = np.linspace(0.0, 4.0, 9)
WAVE = np.column_stack([WAVE_X, 0.5 * np.sin(0.5 * math.pi * WAVE_X)])  # one inflection
BUMPY = [[0.0, 0.0], [1.0, 1.0], [2.0, 0.5], [3.0, -0.5], [4.0, 0.0]]


def speed_integral(spline: SplineProfile, t_start: float, t_end: float) -> float:
    """Arc length between two spline parameters by adaptive quadrature, split at the knots."""
    knots = spline.knots
    inner = knots[(knots > t_start) & (knots < t_end)]
    edges = np.concatenate([[t_start], inner, [t_end]])
    return sum(
        quad(spline.speed, a, b, epsabs=0.0, epsrel=1e-13, limit=200)[0]
        for a, b in zip(edges[:-1], edges[1:])
    )


def menger_errors(profile, segments):
    """Menger-curvature errors of ``sample(segments)``, and whether a knot splits the stencil."""
    s = profile.sample_s(segments)
    error = np.abs(discrete_curvature(profile.sample(segments)) - profile.curvature(s))[1:-1]
    knot_s = profile.arc_length_at_parameter(profile.knots)
    straddles = ((knot_s > s[:-2, None]) & (knot_s < s[2:, None])).any(axis=1)
    return error, straddles


def test_passes_through_control_points():
    spline = SplineProfile(BUMPY)
    knot_s = spline.arc_length_at_parameter(spline.knots)
    np.testing.assert_allclose(spline.point(knot_s), BUMPY, atol=1e-12)
    np.testing.assert_array_equal(spline.sample(10)[[0, -1]], [BUMPY[0], BUMPY[-1]])


def test_length_against_adaptive_quadrature():
    spline = SplineProfile(BUMPY)
    reference = speed_integral(spline, 0.0, spline.knots[-1])
    assert spline.length == pytest.approx(reference, rel=1e-13)


def test_straight_control_points_give_a_straight_line():
    spline = SplineProfile([[0.0, 0.0], [1.0, 2.0], [1.5, 3.0], [3.0, 6.0]])
    assert spline.length == pytest.approx(3.0 * math.sqrt(5.0), rel=1e-14)
    s = spline.sample_s(10)
    np.testing.assert_allclose(spline.curvature(s), 0.0, atol=1e-12)
    np.testing.assert_allclose(spline.tangent_angle(s), math.atan2(2.0, 1.0), atol=1e-12)
    np.testing.assert_allclose(
        spline.sample(6), np.outer(np.linspace(0, 1, 7), [3.0, 6.0]), atol=1e-12
    )


@pytest.mark.parametrize("points", [BUMPY, WAVE])
def test_arc_length_inversion(points):
    spline = SplineProfile(points)
    s = np.linspace(0.0, spline.length, 1001)
    t = spline.parameter_at(s)
    np.testing.assert_allclose(spline.arc_length_at_parameter(t), s, atol=1e-12 * spline.length)
    assert np.all(np.diff(t) > 0.0)


def test_equal_arc_length_sampling_with_adaptive_quadrature():
    spline = SplineProfile(BUMPY)
    segments = 12
    t = spline.parameter_at(spline.sample_s(segments))
    spacing = [speed_integral(spline, a, b) for a, b in zip(t[:-1], t[1:])]
    np.testing.assert_allclose(spacing, spline.length / segments, rtol=1e-12)


def test_inflection_has_both_curvature_signs_and_natural_ends():
    spline = SplineProfile(WAVE)
    curvature = spline.curvature(spline.sample_s(100))
    assert curvature.min() < -0.5 and curvature.max() > 0.5
    np.testing.assert_allclose(curvature[[0, -1]], 0.0, atol=1e-12)  # natural end conditions
    # Left-to-right sine: the first hump turns right (clockwise), the second left.
    assert curvature[25] < 0.0 < curvature[75]


def test_curvature_is_derivative_of_tangent_angle():
    spline = SplineProfile(BUMPY, bc_type="not-a-knot")
    s = np.linspace(0.1, spline.length - 0.1, 40)
    step = 1e-6
    finite_difference = (spline.tangent_angle(s + step) - spline.tangent_angle(s - step)) / (
        2.0 * step
    )
    np.testing.assert_allclose(finite_difference, spline.curvature(s), rtol=1e-6, atol=1e-7)


def test_circle_through_many_points():
    angles = np.linspace(0.75 * math.pi, 0.25 * math.pi, 41)
    spline = SplineProfile(np.column_stack([np.cos(angles), np.sin(angles)]), bc_type="not-a-knot")
    assert spline.length == pytest.approx(0.5 * math.pi, rel=1e-7)
    s = spline.sample_s(50)[5:-5]
    np.testing.assert_allclose(spline.curvature(s), -1.0, atol=1e-3)


def test_discrete_curvature_converges_at_second_order_within_pieces():
    spline = SplineProfile(WAVE)
    errors = []
    for segments in (50, 100, 200):
        error, straddles = menger_errors(spline, segments)
        errors.append(error[~straddles].max())
    orders = np.log2(np.divide(errors[:-1], errors[1:]))
    assert np.all((orders > 1.8) & (orders < 2.2)), orders


def test_discrete_curvature_converges_at_first_order_across_control_points():
    # The curvature derivative jumps at the control points: first order where a stencil
    # contains one (the samples only settle in the asymptotic regime from n = 100 on).
    spline = SplineProfile(WAVE)
    errors = [menger_errors(spline, segments)[0].max() for segments in (100, 200, 400)]
    orders = np.log2(np.divide(errors[:-1], errors[1:]))
    assert np.all((orders > 0.8) & (orders < 1.2)), orders


def test_parameters_and_repr():
    spline = SplineProfile(np.array(BUMPY), bc_type="not-a-knot")
    assert spline.parameters() == {"points": BUMPY, "bc_type": "not-a-knot"}
    assert repr(spline) == "SplineProfile(points=<5 points>, bc_type='not-a-knot')"
    np.testing.assert_array_equal(spline.control_points, BUMPY)
    assert spline.name == "spline"


@pytest.mark.parametrize(
    "points, message",
    [
        ([[0.0, 0.0], [1.0, 1.0]], r"points must contain at least 3 points, got 2"),
        (
            [[0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [2.0, 0.0]],
            r"consecutive points must be distinct, got points\[1\] = \[1\.0, 1\.0\] and "
            r"points\[2\] = \[1\.0, 1\.0\]",
        ),
        ([[0.0, 0.0], [1.0, math.nan], [2.0, 0.0]], r"points must be finite, got points\[1\]"),
        ([[0.0, 0.0, 0.0]] * 3, r"points must have shape \(n, 2\), got shape \(3, 3\)"),
        ([0.0, 1.0, 2.0], r"points must have shape \(n, 2\), got shape \(3,\)"),
        ([[0.0, 0.0], [1.0], [2.0, 0.0]], r"points must be an \(n, 2\) array of real numbers"),
        ([["a", "b"], ["c", "d"], ["e", "f"]], r"points must be an \(n, 2\) array of real"),
        ("points", r"points must be an \(n, 2\) array of real numbers \(m\), got 'points'"),
    ],
)
def test_invalid_points(points, message):
    with pytest.raises(ProfileError, match=message):
        SplineProfile(points)


@pytest.mark.parametrize("bc_type", ["clamped", "periodic", None, 2])
def test_invalid_bc_type(bc_type):
    with pytest.raises(ProfileError, match=r"bc_type must be one of 'natural', 'not-a-knot'"):
        SplineProfile(BUMPY, bc_type=bc_type)
