"""Property tests shared by the analytic arches (arc, catenary, elastica, funicular).

The funicular arch is built with its default uniform load (the parabola).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from compas_ccu.curves import ArcProfile, CatenaryProfile, ElasticaProfile, FunicularProfile
from conftest import property_examples

ARCHES = {
    "arc": ArcProfile,
    "catenary": CatenaryProfile,
    "elastica": ElasticaProfile,
    "funicular": FunicularProfile,
}


def chord_from_unit_tangent(profile, s_start, s_end, order=20, pieces=32) -> np.ndarray:
    """``int (cos theta, sin theta) ds`` over each ``[s_start, s_end]``, composite Gauss-Legendre.

    Composite, because a tall catenary turns sharply near its apex (over a length ``a`` much
    shorter than a sample step of a coarse sample).
    """
    nodes, weights = np.polynomial.legendre.leggauss(order)
    fractions = (np.arange(pieces)[:, None] + 0.5 * (nodes + 1.0)) / pieces  # (pieces, order)
    step = (s_end - s_start)[:, None, None]
    theta = profile.tangent_angle(s_start[:, None, None] + step * fractions)
    scale = step[:, :, 0] / (2.0 * pieces)
    return np.stack(
        [
            scale[:, 0] * (np.cos(theta) @ weights).sum(axis=1),
            scale[:, 0] * (np.sin(theta) @ weights).sum(axis=1),
        ],
        axis=1,
    )


@settings(max_examples=property_examples(60), deadline=None, database=None)
@given(
    kind=st.sampled_from(sorted(ARCHES)),
    span=st.floats(min_value=0.05, max_value=50.0),
    ratio=st.floats(min_value=0.01, max_value=3.0),
    segments=st.integers(min_value=2, max_value=150),
)
def test_arches_hit_ends_and_apex_and_sample_at_equal_arc_length(kind, span, ratio, segments):
    rise = ratio * span
    profile = ARCHES[kind](span=span, rise=rise)
    scale = span + rise

    points = profile.sample(segments)
    assert points.shape == (segments + 1, 2)
    np.testing.assert_array_equal(points[[0, -1]], [[-span / 2, 0.0], [span / 2, 0.0]])
    np.testing.assert_allclose(profile.point(0.5 * profile.length), [0.0, rise], atol=1e-12 * scale)
    assert np.all(points[:, 1] >= -1e-12 * scale)

    # Each sample step is a piece of length length/segments of a unit-speed curve: the chord
    # equals the integral of the unit tangent over it (independent formulas for x, y and theta).
    s = profile.sample_s(segments)
    np.testing.assert_allclose(np.diff(s), profile.length / segments, rtol=1e-12)
    chords = chord_from_unit_tangent(profile, s[:-1], s[1:])
    np.testing.assert_allclose(np.diff(points, axis=0), chords, atol=1e-12 * profile.length)
