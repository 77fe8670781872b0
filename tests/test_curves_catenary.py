from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.curves import CatenaryProfile, discrete_curvature
from compas_ccu.errors import ProfileError


def observed_orders(profile, segment_counts=(50, 100, 200)) -> np.ndarray:
    """Convergence orders of the max Menger-curvature error of ``sample(n)``."""
    errors = []
    for segments in segment_counts:
        menger = discrete_curvature(profile.sample(segments))[1:-1]
        exact = profile.curvature(profile.sample_s(segments))[1:-1]
        errors.append(np.abs(menger - exact).max())
    errors = np.asarray(errors)
    return np.log2(errors[:-1] / errors[1:])


def test_known_parameter():
    # a = 1: span 2 gives rise cosh(1) - 1.
    catenary = CatenaryProfile(span=2.0, rise=math.cosh(1.0) - 1.0)
    assert catenary.a == pytest.approx(1.0, rel=1e-14)
    assert catenary.length == pytest.approx(2.0 * math.sinh(1.0), rel=1e-14)


@pytest.mark.parametrize("ratio", [1e-7, 1e-3, 0.1, 0.25, 1.0, 3.0, 30.0, 300.0])
def test_parameter_solves_rise_equation(ratio):
    span = 3.0
    rise = ratio * span
    catenary = CatenaryProfile(span=span, rise=rise)
    a = catenary.a
    # cosh(t) - 1 = 2 sinh(t/2)^2 avoids cancellation for small rise.
    assert a * 2.0 * math.sinh(span / (4.0 * a)) ** 2 == pytest.approx(rise, rel=1e-14)
    assert catenary.length == pytest.approx(2.0 * a * math.sinh(span / (2.0 * a)), rel=1e-14)


@pytest.mark.parametrize("span, rise", [(4.0, 1.0), (1.0, 2.5), (20.0, 0.05)])
def test_endpoints_apex_and_shape(span, rise):
    catenary = CatenaryProfile(span=span, rise=rise)
    a = catenary.a
    ends_and_apex = catenary.point([0.0, 0.5 * catenary.length, catenary.length])
    np.testing.assert_array_equal(ends_and_apex[[0, 2]], [[-span / 2, 0.0], [span / 2, 0.0]])
    np.testing.assert_allclose(ends_and_apex[1], [0.0, rise], atol=1e-15 * (span + rise))
    x, y = catenary.sample(101).T
    np.testing.assert_allclose(y, rise - a * (np.cosh(x / a) - 1.0), atol=1e-13 * (span + rise))


def test_equal_arc_length_sampling():
    catenary = CatenaryProfile(span=4.0, rise=1.5)
    segments = 40
    points = catenary.sample(segments)
    arc_lengths = catenary.arc_length_at_x(points[:, 0])
    np.testing.assert_allclose(arc_lengths, catenary.sample_s(segments), atol=1e-13)
    np.testing.assert_allclose(np.diff(arc_lengths), catenary.length / segments, rtol=1e-12)


def test_tangent_and_curvature_closed_forms():
    catenary = CatenaryProfile(span=4.0, rise=1.0)
    a = catenary.a
    s = catenary.sample_s(50)
    x = catenary.point(s)[:, 0]
    np.testing.assert_allclose(catenary.tangent_angle(s), np.arctan(-np.sinh(x / a)), atol=1e-14)
    np.testing.assert_allclose(catenary.curvature(s), -1.0 / (a * np.cosh(x / a) ** 2), rtol=1e-13)
    assert catenary.curvature(0.5 * catenary.length) == pytest.approx(-1.0 / a, rel=1e-15)


def test_curvature_is_derivative_of_tangent_angle():
    catenary = CatenaryProfile(span=4.0, rise=1.0)
    s = np.linspace(0.1, catenary.length - 0.1, 30)
    step = 1e-5
    finite_difference = (catenary.tangent_angle(s + step) - catenary.tangent_angle(s - step)) / (
        2.0 * step
    )
    np.testing.assert_allclose(finite_difference, catenary.curvature(s), rtol=1e-8)


def test_discrete_curvature_converges_at_second_order():
    orders = observed_orders(CatenaryProfile(span=4.0, rise=1.0))
    assert np.all((orders > 1.8) & (orders < 2.2)), orders


def test_parameters_and_repr():
    catenary = CatenaryProfile(span=4, rise=1)
    assert catenary.parameters() == {"span": 4.0, "rise": 1.0}
    assert repr(catenary) == "CatenaryProfile(span=4.0, rise=1.0)"
    assert catenary.name == "catenary"


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"span": 4.0, "rise": -0.2}, r"rise must be > 0 m, got -0\.2"),
        ({"span": -1, "rise": 1.0}, r"span must be > 0 m, got -1\.0"),
        ({"span": 4.0, "rise": False}, r"rise must be a real finite number \(m\), got False"),
        ({"span": 4.0, "rise": [1.0]}, r"rise must be a real finite number \(m\), got \[1\.0\]"),
    ],
)
def test_invalid_parameters(kwargs, message):
    with pytest.raises(ProfileError, match=message):
        CatenaryProfile(**kwargs)
