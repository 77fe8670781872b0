from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.curves import ArcProfile, discrete_curvature
from compas_ccu.errors import ProfileError


def polar_angles(profile: ArcProfile, points: np.ndarray) -> np.ndarray:
    """Angles of consecutive ``points`` seen from the centre, unwrapped."""
    offsets = points - profile.center
    return np.unwrap(np.arctan2(offsets[:, 1], offsets[:, 0]))


def test_minor_arc_closed_forms():
    arc = ArcProfile(span=4.0, rise=1.0)
    radius = (2.0**2 + 1.0**2) / (2.0 * 1.0)  # 2.5
    angle = 2.0 * math.asin(2.0 / radius)
    assert arc.radius == pytest.approx(2.5, rel=1e-15)
    assert arc.angle == pytest.approx(angle, rel=1e-15)
    assert arc.length == pytest.approx(radius * angle, rel=1e-15)
    np.testing.assert_allclose(arc.center, [0.0, -1.5], atol=1e-15)
    assert arc.parameters() == {"span": 4.0, "rise": 1.0}
    assert repr(arc) == "ArcProfile(span=4.0, rise=1.0)"
    assert arc.name == "arc"


def test_half_circle():
    arc = ArcProfile(span=2.0, rise=1.0)
    assert arc.radius == 1.0
    assert arc.angle == pytest.approx(math.pi, rel=1e-15)
    assert arc.length == pytest.approx(math.pi, rel=1e-15)
    np.testing.assert_allclose(arc.tangent_angle([0.0, arc.length]), [math.pi / 2, -math.pi / 2])


@pytest.mark.parametrize("span, rise", [(4.0, 1.0), (2.0, 1.8), (0.3, 7.0), (10.0, 0.01)])
def test_endpoints_apex_and_points_on_circle(span, rise):
    arc = ArcProfile(span=span, rise=rise)
    ends_and_apex = arc.point([0.0, 0.5 * arc.length, arc.length])
    np.testing.assert_array_equal(ends_and_apex[[0, 2]], [[-span / 2, 0.0], [span / 2, 0.0]])
    np.testing.assert_allclose(ends_and_apex[1], [0.0, rise], atol=1e-14 * (span + rise))
    points = arc.sample(64)
    distances = np.linalg.norm(points - arc.center, axis=1)
    np.testing.assert_allclose(distances, arc.radius, rtol=1e-14)


def test_major_arc():
    arc = ArcProfile(span=2.0, rise=1.8)
    radius = (1.0 + 1.8**2) / (2.0 * 1.8)
    angle = 2.0 * math.pi - 2.0 * math.asin(1.0 / radius)
    assert arc.radius == pytest.approx(radius, rel=1e-15)
    assert arc.angle == pytest.approx(angle, rel=1e-14)
    assert arc.angle > math.pi
    assert arc.length == pytest.approx(radius * angle, rel=1e-14)
    # The tangent starts above the vertical and the arc bulges beyond its end points.
    assert arc.tangent_angle(0.0) == pytest.approx(angle / 2, rel=1e-14)
    assert arc.sample(200)[:, 0].min() < -1.0


def test_from_radius_angle():
    arc = ArcProfile.from_radius_angle(radius=2.0, angle=90.0)
    assert arc.span == pytest.approx(2.0 * math.sqrt(2.0), rel=1e-15)
    assert arc.rise == pytest.approx(2.0 - math.sqrt(2.0), rel=1e-14)
    assert arc.angle == pytest.approx(math.pi / 2, rel=1e-15)
    assert arc.length == pytest.approx(math.pi, rel=1e-15)
    assert arc.parameters() == {"radius": 2.0, "angle": 90.0}
    np.testing.assert_allclose(arc.point(0.0), [-math.sqrt(2.0), 0.0], atol=1e-15)

    major = ArcProfile.from_radius_angle(radius=1.0, angle=270.0)
    assert major.rise == pytest.approx(1.0 + math.sqrt(0.5), rel=1e-15)
    assert major.length == pytest.approx(1.5 * math.pi, rel=1e-15)
    same = ArcProfile(span=major.span, rise=major.rise)
    assert same.radius == pytest.approx(1.0, rel=1e-14)
    assert same.angle == pytest.approx(major.angle, rel=1e-14)


def test_equal_arc_length_sampling_is_equal_angle():
    arc = ArcProfile(span=3.0, rise=2.2)
    segments = 37
    points = arc.sample(segments)
    np.testing.assert_allclose(arc.sample_s(segments), np.arange(38) * arc.length / segments)
    arc_lengths = arc.radius * -np.diff(polar_angles(arc, points))
    np.testing.assert_allclose(arc_lengths, arc.length / segments, rtol=1e-13)


def test_tangent_and_curvature():
    arc = ArcProfile(span=4.0, rise=1.0)
    s = arc.sample_s(20)
    radial = arc.point(s) - arc.center
    clockwise_tangent = np.stack([radial[:, 1], -radial[:, 0]], axis=1) / arc.radius
    theta = arc.tangent_angle(s)
    np.testing.assert_allclose(
        np.stack([np.cos(theta), np.sin(theta)], 1), clockwise_tangent, atol=1e-14
    )
    np.testing.assert_array_equal(arc.curvature(s), -1.0 / 2.5)


def test_discrete_curvature_of_samples_is_exact():
    # Three points of a circle define that circle: the Menger curvature is exact at any n.
    arc = ArcProfile(span=4.0, rise=1.0)
    for segments in (50, 100, 200):
        menger = discrete_curvature(arc.sample(segments))[1:-1]
        np.testing.assert_allclose(menger, -1.0 / arc.radius, rtol=1e-9)


def test_scalar_and_nd_arguments():
    arc = ArcProfile(span=2.0, rise=1.0)
    assert arc.point(0.5 * arc.length).shape == (2,)
    assert arc.point(np.zeros((3, 4))).shape == (3, 4, 2)
    assert arc.curvature(np.zeros((3, 4))).shape == (3, 4)
    # Round-off outside [0, length] is clipped, and the ends are exact.
    np.testing.assert_array_equal(arc.point(arc.length * (1 + 1e-14)), [1.0, 0.0])


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"span": 4.0, "rise": -0.2}, r"rise must be > 0 m, got -0\.2"),
        ({"span": 0.0, "rise": 1.0}, r"span must be > 0 m, got 0\.0"),
        ({"span": math.nan, "rise": 1.0}, r"span must be a real finite number \(m\), got nan"),
        ({"span": 4.0, "rise": math.inf}, r"rise must be a real finite number \(m\), got inf"),
        ({"span": True, "rise": 1.0}, r"span must be a real finite number \(m\), got True"),
        ({"span": "4", "rise": 1.0}, r"span must be a real finite number \(m\), got '4'"),
    ],
)
def test_invalid_span_rise(kwargs, message):
    with pytest.raises(ProfileError, match=message):
        ArcProfile(**kwargs)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"radius": -1.0, "angle": 90.0}, r"radius must be > 0 m, got -1\.0"),
        ({"radius": 1.0, "angle": 0.0}, r"angle must be in \(0, 360\) degrees .*got 0\.0"),
        ({"radius": 1.0, "angle": 360.0}, r"angle must be in \(0, 360\) degrees .*got 360\.0"),
        ({"radius": 1.0, "angle": -30}, r"angle must be in \(0, 360\) degrees .*got -30\.0"),
        ({"radius": 1.0, "angle": None}, r"angle must be a real finite number \(degrees\)"),
    ],
)
def test_invalid_radius_angle(kwargs, message):
    with pytest.raises(ProfileError, match=message):
        ArcProfile.from_radius_angle(**kwargs)


def test_keyword_only():
    with pytest.raises(TypeError):
        ArcProfile(4.0, 1.0)


@pytest.mark.parametrize(
    "segments, message",
    [
        (1, r"segments must be an integer >= 2, got 1"),
        (0, r"segments must be an integer >= 2, got 0"),
        (10.0, r"segments must be an integer >= 2, got 10\.0"),
        (True, r"segments must be an integer >= 2, got True"),
        (None, r"segments must be an integer >= 2, got None"),
    ],
)
def test_invalid_segments(segments, message):
    arc = ArcProfile(span=4.0, rise=1.0)
    with pytest.raises(ProfileError, match=message):
        arc.sample(segments)
    with pytest.raises(ProfileError, match=message):
        arc.sample_s(segments)


def test_sample_accepts_numpy_integer():
    assert ArcProfile(span=4.0, rise=1.0).sample(np.int64(4)).shape == (5, 2)


@pytest.mark.parametrize(
    "s, message",
    [
        (-0.1, r"s must lie in \[0, 4\.63647\d*\] m \(the profile length\), got -0\.1"),
        ([1.0, 5.0], r"s must lie in \[0, 4\.63647\d*\] m \(the profile length\), got 5\.0"),
        ([1.0, math.nan], r"s must be finite arc lengths in \[0, 4\.63647\d*\] m, got nan"),
        ("x", r"s must be real arc lengths in \[0, length\] m, got 'x'"),
    ],
)
def test_invalid_arc_length(s, message):
    arc = ArcProfile(span=4.0, rise=1.0)
    for method in (arc.point, arc.tangent_angle, arc.curvature):
        with pytest.raises(ProfileError, match=message):
            method(s)
