from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from compas_ccu.curves import FunicularProfile, funicular_moment, profile_from_dict
from compas_ccu.errors import ProfileError
from conftest import property_examples

# Span 4, x in [-2, 2]: uniform load 1 over the span, 2 more over the left half, 3 at x = -1.
ASYMMETRIC = {
    "span": 4.0,
    "rise": 1.0,
    "point_loads": [[-1.0, 3.0]],
    "distributed_loads": [[-2.0, 2.0, 1.0, 1.0], [-2.0, 0.0, 2.0, 2.0]],
}
# Two point loads, a uniform and a linearly varying partial load: every kind of piece.
GENERAL = {
    "span": 4.0,
    "rise": 1.5,
    "point_loads": [[-1.2, 2.0], [0.7, 1.0]],
    "distributed_loads": [[-2.0, 2.0, 1.0, 1.0], [-1.5, 0.5, 0.5, 3.0]],
}
GENERAL_BREAKS_X = [-1.5, -1.2, 0.5, 0.7]  # kinks and curvature jumps inside the span


def asymmetric_moment(x):
    """M(x) of ASYMMETRIC by hand, u = x + 2 from the left support.

    Statics: R_B 4 = 4 * 2 (uniform) + 4 * 1 (partial) + 3 * 1 (point), R_B = 3.75, and
    R_A = 11 - 3.75 = 7.25. Then M = 7.25 u - 1.5 u^2 (u <= 1), minus 3 (u - 1) past the point
    load, and M = 3.75 (4 - u) - (4 - u)^2 / 2 right of the partial load (u >= 2).
    """
    u = np.asarray(x, dtype=float) + 2.0
    left = 7.25 * u - 1.5 * u * u - 3.0 * np.maximum(u - 1.0, 0.0)
    right = 3.75 * (4.0 - u) - 0.5 * (4.0 - u) ** 2
    return np.where(u <= 2.0, left, right)


def asymmetric_moment_slope(x):
    """dM/dx of ASYMMETRIC by hand, on the open pieces."""
    u = np.asarray(x, dtype=float) + 2.0
    return np.where(u < 1.0, 7.25 - 3.0 * u, np.where(u < 2.0, 4.25 - 3.0 * u, 0.25 - u))


def unit_tangent_integral(profile, s_start, s_end, breaks_s, order=20, tolerance=1e-15):
    """``int (cos theta, sin theta) ds`` over ``[s_start, s_end]``, split at ``breaks_s``.

    Adaptive Gauss-Legendre on each smooth stretch: a cell is bisected until the rule on it
    agrees with the sum over its halves to ``tolerance * length`` (a tall arch under a short
    load turns within a small fraction of its length).
    """
    nodes, weights = np.polynomial.legendre.leggauss(order)

    def rule(lower, upper):
        half = 0.5 * (upper - lower)
        theta = profile.tangent_angle((0.5 * (lower + upper))[:, None] + half[:, None] * nodes)
        return half[:, None] * np.stack([np.cos(theta) @ weights, np.sin(theta) @ weights], 1)

    inner = [b for b in breaks_s if s_start < b < s_end]
    edges = np.concatenate([[s_start], inner, [s_end]])
    lower, upper = edges[:-1], edges[1:]
    total = np.zeros(2)
    for _ in range(60):
        middle = 0.5 * (lower + upper)
        halves = rule(lower, middle) + rule(middle, upper)
        done = np.abs(halves - rule(lower, upper)).max(axis=1) <= tolerance * profile.length
        total += halves[done].sum(axis=0)
        lower, upper = np.r_[lower[~done], middle[~done]], np.r_[middle[~done], upper[~done]]
        if lower.size == 0:
            break
    return total


# -- shape -----------------------------------------------------------------------------------------


@pytest.mark.parametrize("span, rise", [(4.0, 1.0), (1.0, 3.0), (50.0, 0.5), (0.05, 0.15)])
def test_uniform_load_is_the_parabola(span, rise):
    parabola = FunicularProfile(span=span, rise=rise)
    x, y = parabola.sample(101).T
    np.testing.assert_allclose(y, rise * (1.0 - (2.0 * x / span) ** 2), rtol=0, atol=1e-12 * rise)
    np.testing.assert_array_equal(
        parabola.sample(101)[[0, -1]], [[-span / 2, 0.0], [span / 2, 0.0]]
    )
    np.testing.assert_allclose(parabola.apex, [0.0, rise], atol=1e-15 * span)
    # closed-form arc length of y = rise (1 - (2x/span)^2), k = 8 rise / span^2
    k = 8.0 * rise / span**2
    length = 0.5 * span * math.hypot(1.0, 0.5 * k * span) + math.asinh(0.5 * k * span) / k
    assert parabola.length == pytest.approx(length, rel=1e-13)
    s = parabola.sample_s(40)
    np.testing.assert_allclose(np.diff(s), parabola.length / 40, rtol=1e-12)
    x = parabola.point(s)[:, 0]
    np.testing.assert_allclose(parabola.tangent_angle(s), np.arctan(-k * x), atol=1e-13)
    np.testing.assert_allclose(
        parabola.curvature(s), -k / (1.0 + (k * x) ** 2) ** 1.5, rtol=1e-12, atol=0
    )
    # uniform load of intensity 1: M = span^2 / 8 at the apex, reactions span / 2
    assert parabola.thrust == pytest.approx(span**2 / (8.0 * rise), rel=1e-14)
    np.testing.assert_allclose(parabola.reactions, [span / 2, span / 2], rtol=1e-15)
    assert parabola.kinks.size == 0
    assert parabola.parameters() == {"span": float(span), "rise": float(rise)}
    np.testing.assert_array_equal(parabola.distributed_loads, [[-span / 2, span / 2, 1.0, 1.0]])
    assert parabola.point_loads.shape == (0, 2)


def test_any_uniform_load_gives_the_same_parabola():
    default = FunicularProfile(span=4.0, rise=1.0)
    heavy = FunicularProfile(span=4.0, rise=1.0, distributed_loads=[[-2.0, 2.0, 7.5, 7.5]])
    np.testing.assert_allclose(heavy.sample(30), default.sample(30), atol=1e-15)
    assert heavy.thrust == pytest.approx(7.5 * default.thrust, rel=1e-15)
    assert heavy.total_load == pytest.approx(30.0, rel=1e-15)


def test_central_point_load_gives_a_triangle():
    triangle = FunicularProfile(span=4.0, rise=1.0, point_loads=[[0.0, 10.0]])
    assert triangle.length == pytest.approx(2.0 * math.hypot(2.0, 1.0), rel=1e-15)
    np.testing.assert_allclose(triangle.kinks, [0.5 * triangle.length], rtol=1e-15)
    np.testing.assert_array_equal(triangle.point(triangle.kinks), [[0.0, 1.0]])
    assert triangle.thrust == 10.0  # P span / (4 rise)
    np.testing.assert_array_equal(triangle.reactions, [5.0, 5.0])
    s = np.linspace(0.0, triangle.length, 41)
    np.testing.assert_array_equal(triangle.curvature(s), 0.0)
    slope = math.atan(0.5)
    expected_angles = np.where(s < triangle.kinks[0], slope, -slope)  # outgoing at the kink
    np.testing.assert_allclose(triangle.tangent_angle(s), expected_angles, atol=1e-15)
    x, y = triangle.point(s).T
    np.testing.assert_allclose(y, 1.0 - np.abs(x) / 2.0, atol=1e-15)
    for segments in (2, 7, 10):  # odd counts too: the apex stays a sample
        points = triangle.sample(segments)
        assert [0.0, 1.0] in points.tolist()


def test_asymmetric_loads_against_hand_computed_moment():
    arch = FunicularProfile(**ASYMMETRIC)
    x = np.array([-2.0, -1.5, -1.0, -0.5, -7.0 / 12.0, 0.0, 0.5, 1.0, 2.0])
    np.testing.assert_allclose(arch.moment(x), asymmetric_moment(x), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(arch.moment([-1.0, 0.0, 1.0]), [5.75, 5.5, 3.25], rtol=1e-15)
    np.testing.assert_allclose(arch.reactions, [7.25, 3.75], rtol=1e-15)
    assert arch.total_load == 11.0
    # max M where 4.25 - 3u = 0: u = 17/12, M = 1731/288
    assert arch.thrust == pytest.approx(1731.0 / 288.0, rel=1e-15)
    np.testing.assert_allclose(arch.apex, [-7.0 / 12.0, 1.0], rtol=1e-15)
    points = arch.sample(60)
    np.testing.assert_allclose(
        points[:, 1], asymmetric_moment(points[:, 0]) * 288.0 / 1731.0, atol=1e-14
    )

    # arc length against adaptive quadrature of sqrt(1 + y'^2), split at the breaks
    def speed(x):
        return math.hypot(1.0, float(asymmetric_moment_slope(x)) * 288.0 / 1731.0)

    edges = [-2.0, -1.0, 0.0, 2.0]
    length = sum(quad(speed, a, b, epsabs=0.0, epsrel=2e-14)[0] for a, b in zip(edges, edges[1:]))
    assert arch.length == pytest.approx(length, rel=1e-13)
    np.testing.assert_allclose(arch.arc_length_at_x(-1.0), arch.kinks, rtol=1e-15)
    assert arch.arc_length_at_x(-1.0) == pytest.approx(
        quad(speed, -2.0, -1.0, epsabs=0.0, epsrel=2e-14)[0], rel=1e-13
    )


def test_triangular_load_over_the_span():
    # q from 0 at the left to 3 at the right: M = q L u/6 - q u^3/(6 L), max q L^2/(9 sqrt 3)
    span, q = 4.0, 3.0
    arch = FunicularProfile(span=span, rise=2.0, distributed_loads=[[-2.0, 2.0, 0.0, q]])
    u = np.linspace(0.0, span, 33)
    np.testing.assert_allclose(
        arch.moment(u - 2.0), q * span * u / 6.0 - q * u**3 / (6.0 * span), rtol=1e-13, atol=1e-14
    )
    assert arch.thrust == pytest.approx(q * span**2 / (9.0 * math.sqrt(3.0)) / 2.0, rel=1e-14)
    assert arch.apex[0] == pytest.approx(span / math.sqrt(3.0) - 2.0, rel=1e-14)
    np.testing.assert_allclose(arch.reactions, [q * span / 6.0, q * span / 3.0], rtol=1e-15)
    # M'' = -q(x): curvature y'' / (1 + y'^2)^(3/2) with y'' = -q(x) rise / max M
    s = arch.sample_s(20)
    x = arch.point(s)[:, 0]
    slope = (q * span / 6.0 - q * (x + 2.0) ** 2 / (2.0 * span)) / arch.thrust
    second = -q * (x + 2.0) / span / arch.thrust
    np.testing.assert_allclose(arch.curvature(s), second / (1 + slope**2) ** 1.5, atol=1e-13)


def test_partial_linear_load_and_point_load_against_quadrature():
    span, half = 5.0, 2.5
    x0, x1, q0, q1, a, load = -1.0, 1.5, 2.0, 0.5, 0.5, 1.0
    arch = FunicularProfile(
        span=span, rise=1.0, point_loads=[[a, load]], distributed_loads=[[x0, x1, q0, q1]]
    )

    def q(xi):
        return q0 + (q1 - q0) * (xi - x0) / (x1 - x0) if x0 <= xi <= x1 else 0.0

    def integral(f, lower, upper):
        return quad(f, lower, upper, points=[x0, x1], epsabs=1e-15, epsrel=2e-14, limit=200)[0]

    left = (integral(lambda xi: q(xi) * (half - xi), -half, half) + load * (half - a)) / span
    x = np.linspace(-half, half, 23)

    def moment(v):
        carried = integral(lambda xi: q(xi) * (v - xi), -half, v)
        return left * (v + half) - carried - load * max(v - a, 0.0)

    reference = [moment(v) for v in x]
    np.testing.assert_allclose(arch.moment(x), reference, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(arch.reactions.sum(), load + 0.5 * (q0 + q1) * (x1 - x0), rtol=1e-15)


def test_symmetric_loads_give_a_symmetric_curve():
    arch = FunicularProfile(
        span=6.0,
        rise=2.0,
        point_loads=[[-1.0, 2.0], [1.0, 2.0]],
        distributed_loads=[[-3.0, 3.0, 1.0, 1.0], [-2.5, -0.5, 0.0, 2.0], [0.5, 2.5, 2.0, 0.0]],
    )
    s = np.linspace(0.0, arch.length, 57)
    points, mirrored = arch.point(s), arch.point(arch.length - s)
    np.testing.assert_allclose(mirrored, points * [-1.0, 1.0], atol=1e-13)
    np.testing.assert_allclose(arch.apex, [0.0, 2.0], atol=1e-13)
    np.testing.assert_allclose(arch.kinks.sum(), arch.length, rtol=1e-15)
    np.testing.assert_allclose(arch.reactions[0], arch.reactions[1], rtol=1e-15)
    inner = s[(np.abs(s[:, None] - arch.kinks) > 1e-9).all(axis=1)]  # one-sided at kinks
    np.testing.assert_allclose(
        arch.tangent_angle(arch.length - inner), -arch.tangent_angle(inner), atol=1e-13
    )
    np.testing.assert_allclose(
        arch.curvature(arch.length - inner), arch.curvature(inner), rtol=1e-11, atol=1e-13
    )


@pytest.mark.parametrize("spec", [ASYMMETRIC, GENERAL])
def test_apex_height_and_moment_equilibrium(spec):
    arch = FunicularProfile(**spec)
    points = arch.sample(400)
    assert points[:, 1].max() <= spec["rise"] * (1.0 + 1e-12)
    assert points[:, 1].max() >= spec["rise"] * (1.0 - 1e-4)
    apex_s = arch.arc_length_at_x(arch.apex[0])
    np.testing.assert_allclose(arch.point(apex_s), arch.apex, rtol=0, atol=1e-12)
    assert arch.point(apex_s)[1] == pytest.approx(spec["rise"], rel=1e-12)
    np.testing.assert_allclose(arch.thrust * points[:, 1], arch.moment(points[:, 0]), atol=1e-12)
    np.testing.assert_allclose(arch.reactions.sum(), arch.total_load, rtol=1e-15)


# -- consistency of point, tangent and curvature ---------------------------------------------------


def test_finite_differences_are_consistent_at_second_order():
    arch = FunicularProfile(**GENERAL)
    breaks_s = arch.arc_length_at_x(GENERAL_BREAKS_X)
    s = np.linspace(0.05, arch.length - 0.05, 80)
    s = s[(np.abs(s[:, None] - breaks_s) > 0.01).all(axis=1)]  # stencils on one smooth piece
    point_errors, angle_errors = [], []
    for step in (2e-3, 1e-3):
        chord = (arch.point(s + step) - arch.point(s - step)) / (2.0 * step)
        theta = arch.tangent_angle(s)
        point_errors.append(np.abs(chord - np.column_stack([np.cos(theta), np.sin(theta)])).max())
        turning = (arch.tangent_angle(s + step) - arch.tangent_angle(s - step)) / (2.0 * step)
        angle_errors.append(np.abs(turning - arch.curvature(s)).max())
    for errors in (point_errors, angle_errors):
        assert errors[1] < 1e-5, errors
        assert 3.5 < errors[0] / errors[1] < 4.5, errors  # halving the step quarters the error


def test_kinks_tangent_and_curvature_are_one_sided():
    arch = FunicularProfile(**GENERAL)
    kinks = arch.kinks
    np.testing.assert_allclose(arch.point(kinks)[:, 0], [-1.2, 0.7], rtol=1e-15)
    step = 1e-7
    for kink in kinks:
        before, at, after = arch.tangent_angle([kink - step, kink, kink + step])
        assert before - at > 0.05  # the slope drops at a point load (the arch turns right)
        assert at == pytest.approx(after, abs=1e-6)
        assert arch.curvature(kink) == pytest.approx(arch.curvature(kink + step), rel=1e-5)


def test_sample_steps_are_chords_of_the_unit_tangent():
    arch = FunicularProfile(**GENERAL)
    breaks_s = arch.arc_length_at_x(GENERAL_BREAKS_X)
    s = arch.sample_s(25)
    points = arch.point(s)
    for index in range(25):
        chord = unit_tangent_integral(arch, s[index], s[index + 1], breaks_s)
        np.testing.assert_allclose(points[index + 1] - points[index], chord, atol=1e-13)


# -- sampling --------------------------------------------------------------------------------------


def test_sample_s_puts_the_kinks_on_samples():
    arch = FunicularProfile(**GENERAL)
    kinks = arch.kinks
    for segments in (3, 4, 7, 48, 301):
        s = arch.sample_s(segments)
        assert s.shape == (segments + 1,)
        assert s[0] == 0.0 and s[-1] == arch.length
        assert np.all(np.diff(s) > 0.0)
        assert np.isin(kinks, s).all()
        bounds = np.concatenate([[0.0], kinks, [arch.length]])
        counts = []
        for lower, upper in zip(bounds[:-1], bounds[1:]):
            part = s[(s >= lower) & (s <= upper)]
            np.testing.assert_allclose(np.diff(part), (upper - lower) / (len(part) - 1), rtol=1e-12)
            counts.append(len(part) - 1)
        assert sum(counts) == segments and min(counts) >= 1
        ideal = segments * np.diff(bounds) / arch.length
        assert np.all(np.abs(np.array(counts) - ideal) < 1.0 + 1e-9), (counts, ideal)
    np.testing.assert_array_equal(arch.sample(7), arch.point(arch.sample_s(7)))
    np.testing.assert_allclose(arch.point(kinks)[:, 0], [-1.2, 0.7], rtol=1e-15)


def test_sample_s_shares_segments_in_proportion_to_piece_lengths():
    # kink at a quarter of the length of a straight two-piece arch: counts 2 and 6 of 8
    arch = FunicularProfile(span=4.0, rise=1e-3, point_loads=[[-1.0, 1.0]])
    assert arch.kinks[0] / arch.length == pytest.approx(0.25, abs=1e-6)
    s = arch.sample_s(8)
    assert np.flatnonzero(s == arch.kinks[0]).tolist() == [2]


def test_kinks_within_round_off_share_a_sample():
    # loads one ulp apart, and one ulp from the left support: no zero-length segments
    close = np.nextafter(0.3, 1.0)
    arch = FunicularProfile(
        span=4.0,
        rise=1.0,
        point_loads=[[0.3, 1.0], [close, 1.0], [np.nextafter(-2.0, 0.0), 1.0]],
    )
    # the loads a round-off apart are one load position (one kink), the one a round-off from
    # the support is at the support: no kink twice, no piece of round-off length
    assert arch.kinks.tolist() == [0.0, arch.arc_length_at_x([0.3])[0]]
    for segments in (2, 9):
        s = arch.sample_s(segments)
        assert s.shape == (segments + 1,)
        assert np.diff(s).min() > 0.1
        assert np.isin(arch.kinks, s).all()


def test_point_loads_at_the_same_place_add_up():
    twice = FunicularProfile(span=4.0, rise=1.0, point_loads=[[0.5, 1.0], [0.5, 2.0]])
    once = FunicularProfile(span=4.0, rise=1.0, point_loads=[[0.5, 3.0]])
    assert twice.kinks.size == 1
    np.testing.assert_allclose(twice.sample(9), once.sample(9), atol=1e-15)
    assert twice.thrust == pytest.approx(once.thrust, rel=1e-15)
    assert len(twice.parameters()["point_loads"]) == 2


# -- properties ------------------------------------------------------------------------------------


settings_random = settings(max_examples=property_examples(40), deadline=None, database=None)


@settings_random
@given(
    span=st.floats(min_value=0.1, max_value=20.0),
    ratio=st.floats(min_value=0.05, max_value=2.0),
    point_loads=st.lists(
        st.tuples(st.floats(0.02, 0.98), st.floats(0.1, 10.0)), min_size=0, max_size=3
    ),
    distributed_loads=st.lists(
        st.tuples(
            st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.1, 5.0), st.floats(0.0, 5.0)
        ),
        min_size=0,
        max_size=2,
    ),
    extra=st.integers(min_value=0, max_value=40),
)
def test_random_loads(span, ratio, point_loads, distributed_loads, extra):
    rise = ratio * span
    half = 0.5 * span
    points = [[(f - 0.5) * span, p] for f, p in point_loads]
    distributed = [
        [(min(a, b) - 0.5) * span, (max(a, b) - 0.5) * span, q0, q1]
        for a, b, q0, q1 in distributed_loads
        if abs(a - b) > 1e-3
    ]
    if not points and not distributed:
        distributed = [[-half, half, 1.0, 0.0]]
    arch = FunicularProfile(span=span, rise=rise, point_loads=points, distributed_loads=distributed)
    pieces = arch.kinks.size + 1
    segments = max(2, pieces + extra)
    s = arch.sample_s(segments)
    samples = arch.point(s)
    np.testing.assert_array_equal(samples[[0, -1]], [[-half, 0.0], [half, 0.0]])
    assert np.isin(arch.kinks, s).all()
    assert samples[:, 1].max() <= rise * (1.0 + 1e-12)
    assert np.all(samples[1:-1, 1] > 0.0)
    assert np.all(np.diff(samples[:, 0]) > 0.0)
    apex = arch.point(arch.arc_length_at_x(arch.apex[0]))
    np.testing.assert_allclose(apex, arch.apex, rtol=0, atol=1e-12 * (span + rise))
    np.testing.assert_allclose(
        arch.thrust * samples[:, 1], arch.moment(samples[:, 0]), atol=1e-12 * arch.thrust * rise
    )
    edges = [x for row in distributed for x in row[:2]] + [x for x, _ in points]
    breaks_s = arch.arc_length_at_x(edges)
    for index in range(0, segments, max(1, segments // 6)):
        chord = unit_tangent_integral(arch, s[index], s[index + 1], breaks_s)
        np.testing.assert_allclose(
            samples[index + 1] - samples[index], chord, atol=1e-12 * arch.length
        )


# -- parameters, factory, errors -------------------------------------------------------------------


@pytest.mark.parametrize(
    "spec",
    [
        {"span": 4.0, "rise": 1.0},
        ASYMMETRIC,
        GENERAL,
        {"span": 3, "rise": 2, "point_loads": np.array([[0.5, 1.0]])},
        {"span": 3.0, "rise": 2.0, "distributed_loads": [(-1.5, 0.0, 0.0, 1)]},
    ],
)
def test_parameters_round_trip_through_the_factory(spec):
    arch = FunicularProfile(**spec)
    parameters = arch.parameters()
    json.dumps(parameters)
    rebuilt = profile_from_dict({"profile": "funicular", **json.loads(json.dumps(parameters))})
    assert type(rebuilt) is FunicularProfile
    assert rebuilt.parameters() == parameters
    assert rebuilt.length == arch.length
    np.testing.assert_array_equal(rebuilt.sample(12), arch.sample(12))
    np.testing.assert_array_equal(rebuilt.kinks, arch.kinks)


def test_parameters_and_repr():
    arch = FunicularProfile(**ASYMMETRIC)
    assert arch.parameters() == ASYMMETRIC
    assert arch.name == "funicular"
    assert repr(arch) == (
        "FunicularProfile(span=4.0, rise=1.0, point_loads=<1 load>, distributed_loads=<2 loads>)"
    )
    assert repr(FunicularProfile(span=4, rise=1)) == "FunicularProfile(span=4.0, rise=1.0)"
    np.testing.assert_array_equal(arch.point_loads, ASYMMETRIC["point_loads"])
    np.testing.assert_array_equal(arch.distributed_loads, ASYMMETRIC["distributed_loads"])
    arch.point_loads[0, 1] = 99.0  # copies
    arch.kinks[0] = 99.0
    assert arch.point_loads[0, 1] == 3.0 and arch.kinks[0] != 99.0


def test_factory_keys():
    arch = profile_from_dict({"profile": "funicular", "span": 4, "rise": 1, "segments": 10})
    assert isinstance(arch, FunicularProfile)
    with pytest.raises(
        ProfileError,
        match=r"unknown key 'loads'; allowed keys for profile 'funicular': span, rise, "
        r"point_loads, distributed_loads",
    ):
        profile_from_dict({"profile": "funicular", "span": 4, "rise": 1, "loads": []})
    with pytest.raises(ProfileError, match=r"missing key 'rise'"):
        profile_from_dict({"profile": "funicular", "span": 4, "point_loads": [[0, 1]]})


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"span": 4.0, "rise": -1.0}, r"rise must be > 0 m, got -1\.0"),
        ({"span": "4", "rise": 1.0}, r"span must be a real finite number \(m\), got '4'"),
        (
            {"point_loads": "0 1"},
            r"point_loads must be a list of \[x, P\] lists, got '0 1'",
        ),
        ({"point_loads": 3.0}, r"point_loads must be a list of \[x, P\] lists, got 3\.0"),
        (
            {"point_loads": [[0.0, 1.0], [0.5, 1.0, 2.0]]},
            r"point_loads\[1\] must be a list \[x, P\], got \[0\.5, 1\.0, 2\.0\]",
        ),
        ({"point_loads": [0.0, 1.0]}, r"point_loads\[0\] must be a list \[x, P\], got 0\.0"),
        (
            {"point_loads": [[0.0, "1"]]},
            r"point_loads\[0\] P must be a real finite number \(load units\), got '1'",
        ),
        (
            {"point_loads": [[math.nan, 1.0]]},
            r"point_loads\[0\] x must be a real finite number \(m\), got nan",
        ),
        (
            {"point_loads": [[True, 1.0]]},
            r"point_loads\[0\] x must be a real finite number \(m\), got True",
        ),
        (
            {"point_loads": [[0.0, 1.0], [2.0, 1.0]]},
            r"point_loads\[1\]: x must lie inside the span, -2\.0 < x < 2\.0 m, got 2\.0",
        ),
        (
            {"point_loads": [[-3.0, 1.0]]},
            r"point_loads\[0\]: x must lie inside the span, -2\.0 < x < 2\.0 m, got -3\.0",
        ),
        ({"point_loads": [[0.0, 1.0], [1.0, 0]]}, r"point_loads\[1\]: P must be > 0, got 0\.0"),
        ({"point_loads": [[0.0, -2.5]]}, r"point_loads\[0\]: P must be > 0, got -2\.5"),
        (
            {"distributed_loads": [[-1.0, 1.0, 1.0]]},
            r"distributed_loads\[0\] must be a list \[x0, x1, q0, q1\], got \[-1\.0, 1\.0, 1\.0\]",
        ),
        (
            {"distributed_loads": {"x0": 0}},
            r"distributed_loads must be a list of \[x0, x1, q0, q1\] lists, got \{'x0': 0\}",
        ),
        (
            {"distributed_loads": [[-1.0, 1.0, 1.0, None]]},
            r"distributed_loads\[0\] q1 must be a real finite number \(load units\), got None",
        ),
        (
            {"distributed_loads": [[1.0, 0.5, 1.0, 1.0]]},
            r"distributed_loads\[0\]: need -2\.0 <= x0 < x1 <= 2\.0 m, got x0 = 1\.0, x1 = 0\.5",
        ),
        (
            {"distributed_loads": [[1.0, 1.0, 1.0, 1.0]]},
            r"distributed_loads\[0\]: need .* got x0 = 1\.0, x1 = 1\.0",
        ),
        (
            {"distributed_loads": [[-2.0, 2.0, 1.0, 1.0], [-2.5, 0.0, 1.0, 1.0]]},
            r"distributed_loads\[1\]: need -2\.0 <= x0 < x1 <= 2\.0 m, got x0 = -2\.5, x1 = 0\.0",
        ),
        (
            {"distributed_loads": [[0.0, 2.1, 1.0, 1.0]]},
            r"distributed_loads\[0\]: need .* got x0 = 0\.0, x1 = 2\.1",
        ),
        (
            {"distributed_loads": [[0.0, 1.0, -1.0, 1.0]]},
            r"distributed_loads\[0\]: q0 must be >= 0, got -1\.0",
        ),
        (
            {"distributed_loads": [[0.0, 1.0, 1.0, -0.5]]},
            r"distributed_loads\[0\]: q1 must be >= 0, got -0\.5",
        ),
        (
            {"distributed_loads": [[0.0, 1.0, 0.0, 0.0]]},
            r"distributed_loads\[0\]: q0 and q1 are both 0 \(no load\)",
        ),
        (
            {"point_loads": [], "distributed_loads": []},
            r"the total load is zero: give at least one load, or give neither point_loads nor "
            r"distributed_loads for a uniform load",
        ),
        ({"point_loads": []}, r"the total load is zero"),
        ({"distributed_loads": [[0.0, 1e-10, 5e-324, 0.0]]}, r"the total load is zero"),
        (
            {"distributed_loads": [[-2.0, 2.0, 1e308, 1e308]]},
            r"the total load must be finite, got inf",
        ),
    ],
)
def test_invalid_parameters(kwargs, message):
    arguments = {"span": 4.0, "rise": 1.0, **kwargs}
    with pytest.raises(ProfileError, match=message):
        FunicularProfile(**arguments)


def test_moment_guard(monkeypatch):
    # Loads >= 0 always give M > 0 inside the span; the guard catches a broken moment.
    original = funicular_moment.coefficients_from_left

    def negated(*args):
        return -original(*args)

    monkeypatch.setattr(funicular_moment, "coefficients_from_left", negated)
    with pytest.raises(
        ProfileError, match=r"the bending moment of the loads must be > 0 inside the span, got M = "
    ):
        FunicularProfile(span=4.0, rise=1.0)


@pytest.mark.parametrize(
    "segments, message",
    [
        (2, r"segments must be >= 3 to put a sample on each of the 2 kinks \(point loads\), got 2"),
        (1, r"segments must be an integer >= 2, got 1"),
        (4.0, r"segments must be an integer >= 2, got 4\.0"),
    ],
)
def test_invalid_segments(segments, message):
    arch = FunicularProfile(**GENERAL)
    with pytest.raises(ProfileError, match=message):
        arch.sample(segments)
    with pytest.raises(ProfileError, match=message):
        arch.sample_s(segments)


def test_arc_lengths_are_checked():
    arch = FunicularProfile(**GENERAL)
    with pytest.raises(ProfileError, match=r"s must lie in \[0, "):
        arch.point(-1.0)
    assert arch.point(arch.length * (1 + 1e-12)).tolist() == [2.0, 0.0]
    assert arch.point(0.3).shape == (2,)
    assert arch.curvature(np.zeros((2, 3))).shape == (2, 3)


def test_loads_a_round_off_apart_share_one_kink():
    """Found by the property test: two point loads one ulp apart gave two equal kinks, and a
    distributed load starting 1e-15 m from a support three crease vertices on one point."""
    twins = FunicularProfile(span=1.0, rise=1.0, point_loads=[[0.48, 1.0], [0.48 - 1e-17, 1.0]])
    assert twins.kinks.size == 1
    s = twins.sample_s(4)
    assert np.isin(twins.kinks, s).all()
    edge = FunicularProfile(
        span=8.744950205632824,
        rise=2.186,
        distributed_loads=[[-4.372475102816411, 4.3724751, 1.0, 0.0]],
    )
    x = edge.point(edge.sample_s(7))[:, 0]
    assert np.all(np.diff(x) > 0.0)
