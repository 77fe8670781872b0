from __future__ import annotations

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import compas_ccu
from compas_ccu.curves import (
    ArcProfile,
    CatenaryProfile,
    ElasticaProfile,
    FunicularProfile,
    PolylineProfile,
    SplineProfile,
    discrete_curvature,
    profile_from_dict,
)
from compas_ccu.errors import ProfileError

POINTS = [[0.0, 0.0], [1.0, 1.0], [2.0, 0.5], [3.0, 0.0]]
ALLOWED_ARC = (
    r"allowed keys for profile 'arc': span, rise, radius, angle \(and 'profile', 'segments'\)"
)


@pytest.mark.parametrize(
    "spec, cls",
    [
        ({"profile": "arc", "span": 4, "rise": 1}, ArcProfile),
        ({"profile": "arc", "radius": 2.0, "angle": 120}, ArcProfile),
        ({"profile": "catenary", "span": 4.0, "rise": 1.0, "segments": 30}, CatenaryProfile),
        ({"profile": "elastica", "span": np.float64(4.0), "rise": np.int64(1)}, ElasticaProfile),
        ({"profile": "spline", "points": POINTS}, SplineProfile),
        ({"profile": "spline", "points": POINTS, "bc_type": "not-a-knot"}, SplineProfile),
        ({"profile": "polyline", "points": POINTS, "segments": None}, PolylineProfile),
        ({"profile": "polyline", "points": np.array(POINTS)}, PolylineProfile),
        ({"profile": "funicular", "span": 4, "rise": 1}, FunicularProfile),
        (
            {"profile": "funicular", "span": 4.0, "rise": 1.0, "point_loads": [[0.5, 2]]},
            FunicularProfile,
        ),
    ],
)
def test_builds_each_profile_and_round_trips(spec, cls):
    profile = profile_from_dict(spec)
    assert type(profile) is cls
    rebuilt = profile_from_dict({"profile": profile.name, **profile.parameters()})
    assert rebuilt.parameters() == profile.parameters()
    assert rebuilt.length == profile.length
    np.testing.assert_array_equal(rebuilt.sample(8), profile.sample(8))


def test_arc_by_radius_and_angle():
    arc = profile_from_dict({"profile": "arc", "radius": 2.0, "angle": 90})
    assert arc.radius == 2.0
    assert arc.length == pytest.approx(math.pi, rel=1e-15)
    assert arc.parameters() == {"radius": 2.0, "angle": 90.0}


def test_parameters_are_json_able():
    import json

    for spec in (
        {"profile": "arc", "span": 4, "rise": 1},
        {"profile": "spline", "points": np.array(POINTS)},
    ):
        json.dumps(profile_from_dict(spec).parameters())


@pytest.mark.parametrize(
    "spec, message",
    [
        ([("profile", "arc")], r"profile spec must be a dict, got list"),
        (
            {"span": 4.0, "rise": 1.0},
            r"missing key 'profile'; allowed profiles: arc, catenary, elastica, spline, "
            r"polyline, funicular",
        ),
        (
            {"profile": "parabola"},
            r"profile must be one of arc, catenary, elastica, spline, polyline, funicular, "
            r"got 'parabola'",
        ),
        ({"profile": 3}, r"profile must be one of .*, got 3"),
        (
            {"profile": "arc", "span": 4.0, "rise": 1.0, "sag": 2.0},
            r"unknown key 'sag'; " + ALLOWED_ARC,
        ),
        ({"profile": "arc", "span": 4.0}, r"missing key 'rise'; " + ALLOWED_ARC),
        ({"profile": "arc", "angle": 40.0}, r"missing key 'radius'; " + ALLOWED_ARC),
        (
            {"profile": "arc", "span": 4.0, "rise": 1.0, "radius": 3.0},
            r"conflicting keys 'radius', 'rise', 'span' for profile 'arc': "
            r"give either \(span, rise\) or \(radius, angle\)",
        ),
        (
            {"profile": "catenary", "span": 4.0, "radius": 3.0},
            r"unknown key 'radius'; allowed keys for profile 'catenary': span, rise",
        ),
        (
            {"profile": "elastica", "rise": 1.0},
            r"missing key 'span'; allowed keys for profile 'elastica': span, rise",
        ),
        (
            {"profile": "polyline", "points": POINTS, "bc_type": "natural"},
            r"unknown key 'bc_type'; allowed keys for profile 'polyline': points",
        ),
        (
            {"profile": "spline"},
            r"missing key 'points'; allowed keys for profile 'spline': points, bc_type",
        ),
        (
            {"profile": "catenary", "span": True, "rise": 1.0},
            r"span must be a real finite number \(m\), got True",
        ),
        (
            {"profile": "catenary", "span": "4", "rise": 1.0},
            r"span must be a real finite number \(m\), got '4'",
        ),
        (
            {"profile": "elastica", "span": 4.0, "rise": float("nan")},
            r"rise must be a real finite number \(m\), got nan",
        ),
        ({"profile": "arc", "span": 4.0, "rise": -1.0}, r"rise must be > 0 m, got -1\.0"),
        (
            {"profile": "arc", "radius": 1.0, "angle": 400.0},
            r"angle must be in \(0, 360\) degrees \(exclusive\), got 400\.0",
        ),
        (
            {"profile": "arc", "radius": 1.0, "angle": None},
            r"angle must be a real finite number \(degrees\), got None",
        ),
        (
            {"profile": "polyline", "points": "0,0 1,1 2,0"},
            r"points must be a list of \[x, y\] pairs \(m\), got str",
        ),
        (
            {"profile": "polyline", "points": [[0, 0], [1, 1, 1], [2, 0]]},
            r"points\[1\] must be a pair \[x, y\] \(m\), got \[1, 1, 1\]",
        ),
        (
            {"profile": "polyline", "points": [[0, 0], [1, "1"], [2, 0]]},
            r"points\[1\]\[1\] must be a real finite number \(m\), got '1'",
        ),
        (
            {"profile": "spline", "points": [[0, 0], [False, 1], [2, 0]]},
            r"points\[1\]\[0\] must be a real finite number \(m\), got False",
        ),
        (
            {"profile": "spline", "points": [[0, 0], [1, float("inf")], [2, 0]]},
            r"points\[1\]\[1\] must be a real finite number \(m\), got inf",
        ),
        (
            {"profile": "spline", "points": [[0, 0], [2, 0]]},
            r"points must contain at least 3 points, got 2",
        ),
        (
            {"profile": "spline", "points": POINTS, "bc_type": "clamped"},
            r"bc_type must be one of 'natural', 'not-a-knot', got 'clamped'",
        ),
    ],
)
def test_invalid_specs(spec, message):
    with pytest.raises(ProfileError, match=message):
        profile_from_dict(spec)


def test_profile_error_is_a_value_error():
    with pytest.raises(ValueError):
        profile_from_dict({"profile": "arc"})


def test_discrete_curvature_values_and_sign():
    # Circle through the three points: centre (1, 0), radius 1, turning right.
    np.testing.assert_allclose(discrete_curvature([[0, 0], [1, 1], [2, 0]]), [np.nan, -1.0, np.nan])
    np.testing.assert_allclose(discrete_curvature([[0, 0], [1, -1], [2, 0]])[1], 1.0)
    np.testing.assert_array_equal(discrete_curvature([[0, 0], [1, 1], [2, 2], [4, 4]])[1:-1], 0.0)
    # A hairpin has no circumcircle.
    assert np.isnan(discrete_curvature([[0, 0], [1, 0], [0, 0]])[1])


@pytest.mark.parametrize(
    "points, message",
    [
        ([[0, 0], [1, 1]], r"points must contain at least 3 points, got 2"),
        ([[0, 0], [1, 1], [1, 1]], r"consecutive points must be distinct"),
        ([[0, 0, 0], [1, 1, 1], [2, 0, 0]], r"points must have shape \(n, 2\)"),
    ],
)
def test_discrete_curvature_errors(points, message):
    with pytest.raises(ProfileError, match=message):
        discrete_curvature(points)


def test_import_does_not_load_scipy():
    source_root = os.path.dirname(os.path.dirname(compas_ccu.__file__))
    code = "import sys, compas_ccu.curves; print('scipy' in sys.modules)"
    environment = dict(os.environ, PYTHONPATH=source_root, PYTHONDONTWRITEBYTECODE="1")
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=environment, check=True
    )
    assert result.stdout.strip() == "False"
