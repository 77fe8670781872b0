from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.curves import PolylineProfile, discrete_curvature
from compas_ccu.errors import ProfileError

TRAPEZOID = [[0.0, 0.0], [1.0, 1.0], [3.0, 1.0], [4.0, 0.0]]


def arc_length_along(polyline: PolylineProfile, points: np.ndarray) -> np.ndarray:
    """Arc length of points lying on the polyline, found from the nearest edge."""
    vertices = polyline.vertices
    starts, edges = vertices[:-1], np.diff(vertices, axis=0)
    lengths = np.linalg.norm(edges, axis=1)
    relative = points[:, None, :] - starts[None, :, :]
    along = np.einsum("kij,ij->ki", relative, edges) / lengths
    across = np.abs(relative[..., 0] * edges[:, 1] - relative[..., 1] * edges[:, 0]) / lengths
    on_edge = (along > -1e-12) & (along < lengths + 1e-12) & (across < 1e-12)
    assert on_edge.any(axis=1).all(), "a point is not on the polyline"
    edge = np.argmax(on_edge, axis=1)
    return polyline.vertex_s[edge] + along[np.arange(len(points)), edge]


def test_vertices_length_and_sample_none():
    polyline = PolylineProfile(TRAPEZOID)
    np.testing.assert_array_equal(polyline.vertices, TRAPEZOID)
    np.testing.assert_array_equal(polyline.sample(None), TRAPEZOID)
    np.testing.assert_array_equal(polyline.sample(), TRAPEZOID)
    np.testing.assert_allclose(
        polyline.vertex_s, [0.0, math.sqrt(2), 2 + math.sqrt(2), 2 + 2 * math.sqrt(2)]
    )
    np.testing.assert_array_equal(polyline.sample_s(None), polyline.vertex_s)
    assert polyline.length == pytest.approx(2.0 + 2.0 * math.sqrt(2.0), rel=1e-15)
    polyline.sample(None)[0] = 99.0  # a copy
    assert polyline.vertices[0, 0] == 0.0


def test_point_interpolates_linearly():
    polyline = PolylineProfile(TRAPEZOID)
    np.testing.assert_array_equal(polyline.point(polyline.vertex_s), TRAPEZOID)
    half_diagonal = 0.5 * math.sqrt(2.0)
    np.testing.assert_allclose(
        polyline.point([half_diagonal, math.sqrt(2.0) + 1.0]),
        [[0.5, 0.5], [2.0, 1.0]],
        atol=1e-15,
    )


def test_resampling_at_equal_arc_length():
    polyline = PolylineProfile(TRAPEZOID)
    segments = 9
    points = polyline.sample(segments)
    assert points.shape == (10, 2)
    np.testing.assert_array_equal(points[[0, -1]], [TRAPEZOID[0], TRAPEZOID[-1]])
    arc_lengths = arc_length_along(polyline, points)
    np.testing.assert_allclose(np.diff(arc_lengths), polyline.length / segments, rtol=1e-12)


def test_tangent_angle_is_edge_angle():
    polyline = PolylineProfile(TRAPEZOID)
    s = [0.0, 0.5, math.sqrt(2.0), 2.5, polyline.length - 0.1, polyline.length]
    expected = [math.pi / 4, math.pi / 4, 0.0, 0.0, -math.pi / 4, -math.pi / 4]
    np.testing.assert_allclose(polyline.tangent_angle(s), expected, atol=1e-15)


def test_discrete_curvature_interpolated_between_vertices():
    polyline = PolylineProfile(TRAPEZOID)
    # Circle through (0, 0), (1, 1), (3, 1): centre (2, -1), radius sqrt(5); turning right.
    kappa = -1.0 / math.sqrt(5.0)
    np.testing.assert_allclose(polyline.vertex_curvature, [kappa] * 4, rtol=1e-14)
    np.testing.assert_allclose(polyline.curvature(polyline.vertex_s), [kappa] * 4, rtol=1e-14)

    zigzag = PolylineProfile([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [3.0, 1.0], [4.0, 1.0]])
    vertex_curvature = zigzag.vertex_curvature
    np.testing.assert_allclose(vertex_curvature[1:4], discrete_curvature(zigzag.vertices)[1:4])
    assert vertex_curvature[0] == vertex_curvature[1] == pytest.approx(-1.0)
    assert vertex_curvature[2] == pytest.approx(1.0)
    assert vertex_curvature[-1] == vertex_curvature[-2]
    middle = 0.5 * (zigzag.vertex_s[1] + zigzag.vertex_s[2])
    assert zigzag.curvature(middle) == pytest.approx(0.0, abs=1e-15)


def test_vertices_on_an_arc_recover_its_curvature():
    angles = np.linspace(0.8 * math.pi, 0.2 * math.pi, 12)
    polyline = PolylineProfile(3.0 * np.column_stack([np.cos(angles), np.sin(angles)]))
    s = np.linspace(0.0, polyline.length, 33)
    np.testing.assert_allclose(polyline.curvature(s), -1.0 / 3.0, rtol=1e-12)


def test_parameters_and_repr():
    polyline = PolylineProfile(TRAPEZOID)
    assert polyline.parameters() == {"points": TRAPEZOID}
    assert repr(polyline) == "PolylineProfile(points=<4 points>)"
    assert polyline.name == "polyline"


@pytest.mark.parametrize(
    "points, message",
    [
        ([[0.0, 0.0], [1.0, 1.0]], r"points must contain at least 3 points, got 2"),
        ([[0.0, 0.0], [0.0, 0.0], [1.0, 1.0]], r"consecutive points must be distinct"),
        ([[0.0, 0.0], [1.0, 1.0], [math.inf, 0.0]], r"points must be finite, got points\[2\]"),
        (np.zeros((4, 3)), r"points must have shape \(n, 2\), got shape \(4, 3\)"),
        ([[True, False], [False, True], [True, True]], r"points must be an \(n, 2\) array"),
    ],
)
def test_invalid_points(points, message):
    with pytest.raises(ProfileError, match=message):
        PolylineProfile(points)


@pytest.mark.parametrize("segments", [1, 2.5, "4"])
def test_invalid_segments(segments):
    with pytest.raises(ProfileError, match=r"segments must be an integer >= 2, got"):
        PolylineProfile(TRAPEZOID).sample(segments)
