from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import ellipe, ellipk

from compas_ccu.curves import ElasticaProfile, discrete_curvature
from compas_ccu.curves.elastica import largest_modulus
from compas_ccu.errors import ProfileError

RATIOS = [1e-4, 0.05, 0.25, 0.5, 0.8346, 1.5, 4.0, 50.0]


def observed_orders(profile, segment_counts=(50, 100, 200)) -> np.ndarray:
    """Convergence orders of the max Menger-curvature error of ``sample(n)``."""
    errors = []
    for segments in segment_counts:
        menger = discrete_curvature(profile.sample(segments))[1:-1]
        exact = profile.curvature(profile.sample_s(segments))[1:-1]
        errors.append(np.abs(menger - exact).max())
    errors = np.asarray(errors)
    return np.log2(errors[:-1] / errors[1:])


def chord_from_unit_tangent(profile, s_start, s_end, order=20) -> np.ndarray:
    """``int (cos theta, sin theta) ds`` over each ``[s_start, s_end]`` by Gauss-Legendre."""
    nodes, weights = np.polynomial.legendre.leggauss(order)
    half = 0.5 * (s_end - s_start)
    s = (0.5 * (s_start + s_end))[:, None] + half[:, None] * nodes
    theta = profile.tangent_angle(s)
    return np.stack([half * (np.cos(theta) @ weights), half * (np.sin(theta) @ weights)], axis=1)


def test_largest_modulus():
    k_max = largest_modulus()
    assert k_max == pytest.approx(0.9089085575, abs=1e-9)
    assert 2.0 * ellipe(k_max**2) == pytest.approx(ellipk(k_max**2), rel=1e-14)


@pytest.mark.parametrize("ratio", RATIOS)
def test_endpoints_apex_and_closed_forms(ratio):
    span = 2.0
    rise = ratio * span
    elastica = ElasticaProfile(span=span, rise=rise)
    k, lam = elastica.modulus, elastica.wavenumber
    complete_k, complete_e = ellipk(k * k), ellipe(k * k)
    assert 0.0 < k < largest_modulus()
    assert k / (2.0 * complete_e - complete_k) == pytest.approx(ratio, rel=1e-12)
    assert 2.0 * k / lam == pytest.approx(rise, rel=1e-12)
    assert 2.0 * (2.0 * complete_e - complete_k) / lam == pytest.approx(span, rel=1e-14)
    assert elastica.length == pytest.approx(2.0 * complete_k / lam, rel=1e-15)

    ends = elastica.point([0.0, elastica.length])
    np.testing.assert_allclose(ends, [[-span / 2, 0.0], [span / 2, 0.0]], atol=1e-12)
    ends_unsnapped = elastica._point(np.array([0.0, elastica.length]))
    np.testing.assert_allclose(ends_unsnapped, ends, atol=1e-12 * max(1.0, rise))
    apex = elastica.point(0.5 * elastica.length)
    np.testing.assert_allclose(apex, [0.0, rise], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(elastica.curvature([0.0, elastica.length]), 0.0, atol=1e-12)
    np.testing.assert_allclose(
        elastica.tangent_angle([0.0, elastica.length]),
        [elastica.end_angle, -elastica.end_angle],
        rtol=1e-12,
    )


@pytest.mark.parametrize("ratio", RATIOS)
def test_curvature_proportional_to_height(ratio):
    elastica = ElasticaProfile(span=2.0, rise=2.0 * ratio)
    s = elastica.sample_s(200)[1:-1]
    curvature = elastica.curvature(s)
    height = elastica.point(s)[:, 1]
    load = curvature / height  # the same constant P everywhere
    np.testing.assert_allclose(load, load[0], rtol=1e-11)
    assert load[0] == pytest.approx(-(elastica.wavenumber**2), rel=1e-12)


@pytest.mark.parametrize("ratio", RATIOS)
def test_unit_speed_and_equal_arc_length(ratio):
    # x(s), y(s) come from E(am u) and cn(u); the tangent from sn(u): independent formulas.
    elastica = ElasticaProfile(span=2.0, rise=2.0 * ratio)
    s = elastica.sample_s(300)
    points = elastica.sample(300)
    chords = chord_from_unit_tangent(elastica, s[:-1], s[1:])
    np.testing.assert_allclose(np.diff(points, axis=0), chords, atol=1e-13 * elastica.length)


def test_dense_finite_difference_curvature_matches():
    elastica = ElasticaProfile(span=3.0, rise=2.0)
    segments = 4000
    menger = discrete_curvature(elastica.sample(segments))[1:-1]
    exact = elastica.curvature(elastica.sample_s(segments))[1:-1]
    scale = np.abs(exact).max()
    np.testing.assert_allclose(menger, exact, atol=1e-6 * scale)


def test_curvature_is_derivative_of_tangent_angle():
    elastica = ElasticaProfile(span=3.0, rise=1.0)
    s = np.linspace(0.1, elastica.length - 0.1, 30)
    step = 1e-5
    finite_difference = (elastica.tangent_angle(s + step) - elastica.tangent_angle(s - step)) / (
        2.0 * step
    )
    np.testing.assert_allclose(finite_difference, elastica.curvature(s), rtol=1e-7, atol=1e-9)


def test_small_rise_is_a_cosine():
    span, rise = 4.0, 4e-3
    elastica = ElasticaProfile(span=span, rise=rise)
    x, y = elastica.sample(100).T
    np.testing.assert_allclose(y, rise * np.cos(math.pi * x / span), atol=1e-5 * rise)
    assert elastica.modulus == pytest.approx(math.pi * rise / (2.0 * span), rel=1e-5)


def test_tall_elastica_bulges_beyond_its_ends():
    elastica = ElasticaProfile(span=1.0, rise=4.0)
    assert elastica.end_angle > math.pi / 2
    x = elastica.sample(400)[:, 0]
    assert x.min() < -0.5 and x.max() > 0.5
    assert elastica.end_angle < 2.0 * math.asin(largest_modulus())


@pytest.mark.parametrize("ratio", [0.25, 1.0])
def test_discrete_curvature_converges_at_second_order(ratio):
    orders = observed_orders(ElasticaProfile(span=4.0, rise=4.0 * ratio))
    assert np.all((orders > 1.8) & (orders < 2.2)), orders


def test_parameters_and_repr():
    elastica = ElasticaProfile(span=4.0, rise=1.0)
    assert elastica.parameters() == {"span": 4.0, "rise": 1.0}
    assert repr(elastica) == "ElasticaProfile(span=4.0, rise=1.0)"
    assert elastica.name == "elastica"


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"span": 4.0, "rise": -0.2}, r"rise must be > 0 m, got -0\.2"),
        ({"span": 0, "rise": 1.0}, r"span must be > 0 m, got 0\.0"),
        ({"span": 4.0, "rise": math.inf}, r"rise must be a real finite number \(m\), got inf"),
    ],
)
def test_invalid_parameters(kwargs, message):
    with pytest.raises(ProfileError, match=message):
        ElasticaProfile(**kwargs)
