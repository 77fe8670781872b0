from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.errors import DesignError, DevelopabilityError, GeometryError
from compas_ccu.model import CCUModel
from compas_ccu.strips import rulings as rf
from compas_ccu.strips.frames import crease_frames
from conftest import make_design


def catenary(n=40):
    x = np.linspace(-1.0, 1.0, n + 1)
    return np.c_[x, 0.7 - 0.4 * (np.cosh(x / 0.4 * 0.6) - 1.0) * 0.5]


def arc(n=40, radius=1.5, angle=2.0):
    t = np.linspace(math.pi / 2 + angle / 2, math.pi / 2 - angle / 2, n + 1)
    return radius * np.c_[np.cos(t), np.sin(t)]


def quads_planar(points, rulings, length=0.3):
    p = np.c_[points, np.zeros(len(points))]
    q = p + length * rulings
    normal = np.cross(p[1:] - p[:-1], q[:-1] - p[:-1])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    return np.abs(np.einsum("ij,ij->i", q[1:] - p[:-1], normal)).max()


def right_side(points):
    """Flip so the plate side (centre of the arch) is on the left of the crease."""
    return points * [1.0, -1.0]


def test_orthogonal_rulings_on_an_arc_form_a_right_circular_cone():
    pts = right_side(arc())
    alpha = math.radians(35.0)
    r = rf.orthogonal_rulings(pts, alpha=alpha, reference=20)
    alphas = rf.vertex_reflection_angles(pts, r)
    np.testing.assert_allclose(alphas, alpha, atol=1e-13)
    # every ruling line passes through the apex above the arc centre, at height R tan(alpha)
    t = 1.5 / np.cos(alpha)
    apex = np.c_[pts, np.zeros(len(pts))] + t * r
    np.testing.assert_allclose(
        apex, np.tile([0.0, 0.0, 1.5 * math.tan(alpha)], (len(pts), 1)), atol=1e-12
    )


@pytest.mark.parametrize("maker", ["orthogonal", "cylindrical", "conical", "angle"])
def test_every_ruling_field_gives_planar_quads_and_the_reference_alpha(maker):
    pts = right_side(catenary())
    alpha = math.radians(28.0)
    if maker == "orthogonal":
        r = rf.orthogonal_rulings(pts, alpha=alpha, reference=12)
    elif maker == "cylindrical":
        r = rf.cylindrical_rulings(pts, direction=[0.2, 1.0], alpha=alpha, reference=12)
        np.testing.assert_allclose(r, np.tile(r[0], (len(r), 1)), atol=1e-15)
    elif maker == "conical":
        r = rf.conical_rulings(pts, apex=[0.3, 0.9], alpha=alpha, reference=12)
        # every ruling line passes through the apex projection (0.3, 0.9) in plan
        p = np.c_[pts, np.zeros(len(pts))]
        t = (0.9 - p[:, 1]) / r[:, 1]
        np.testing.assert_allclose((p + t[:, None] * r)[:, 0], 0.3, atol=1e-12)
    else:
        r, tilts = rf.ruling_angle_rulings(pts, gamma=math.radians(75.0), alpha=alpha, reference=12)
        assert np.all(np.diff(tilts) != 0.0)  # alpha varies along the crease when gamma != 90
    assert quads_planar(pts, r) < 1e-14
    assert rf.vertex_reflection_angles(pts, r)[12] == pytest.approx(alpha, abs=1e-12)


def test_conical_rulings_meet_at_one_apex():
    pts = right_side(catenary())
    r = rf.conical_rulings(pts, apex=[0.3, 0.9], alpha=math.radians(30.0), reference=10)
    p = np.c_[pts, np.zeros(len(pts))]
    # intersection of ruling 0 with every other ruling line (least squares) is the same point
    t = (0.9 - p[:, 1]) / r[:, 1]
    hits = p + t[:, None] * r
    np.testing.assert_allclose(hits, np.tile(hits[0], (len(p), 1)), atol=1e-12)
    np.testing.assert_allclose(hits[0, :2], [0.3, 0.9], atol=1e-12)


def test_ruling_angle_field_follows_the_ode():
    pts = right_side(catenary(200))
    gamma = math.radians(70.0)
    r, tilts = rf.ruling_angle_rulings(pts, gamma=gamma, alpha=math.radians(30.0), reference=100)
    f = crease_frames(pts)
    # realised intrinsic ruling angle: between the ruling and the tangent, in the quad's plane
    mid = np.c_[f.tangents, np.zeros(len(pts))]
    realised = np.arccos(np.einsum("ij,ij->i", r, mid))
    assert np.abs(realised[5:-5] - gamma).max() < 5e-3
    alpha = rf.vertex_reflection_angles(pts, r)
    rf.check_alpha_field(pts, np.full(len(pts), gamma), alpha)  # developable: no error


def test_constant_alpha_with_gamma_not_90_is_refused():
    pts = right_side(catenary())
    with pytest.raises(DevelopabilityError, match="constant reflection angle.*gamma = 90"):
        rf.check_alpha_field(
            pts, np.full(len(pts), math.radians(70.0)), np.full(len(pts), math.radians(30.0))
        )
    rf.check_alpha_field(pts, np.full(len(pts), math.pi / 2), np.full(len(pts), 0.5))


def test_constant_alpha_request_in_a_design_is_refused():
    with pytest.raises(DevelopabilityError, match="not developable"):
        CCUModel(make_design(rulings={"type": "angle", "gamma": 70.0, "alpha_field": "constant"}))
    with pytest.raises(DesignError, match="rulings.alpha_field.*gamma = 90"):
        CCUModel(
            make_design(
                crease={"state": "flat"},
                rulings={"type": "angle", "gamma": 70.0, "alpha_field": "constant"},
            )
        )
    # gamma = 90 with a constant alpha is the ultra-special case: accepted
    model = CCUModel(
        make_design(rulings={"type": "angle", "gamma": 90.0, "alpha_field": "constant"})
    )
    assert model.deploy().max_invariant_error < 1e-12


def test_unreachable_alpha_for_a_ruling_field_is_refused():
    pts = right_side(arc(40, angle=2.5))
    with pytest.raises(DevelopabilityError, match="cannot reach alpha"):
        rf.ruling_angle_rulings(
            pts, gamma=math.radians(20.0), alpha=math.radians(80.0), reference=0
        )


def test_bad_ruling_inputs_name_the_vertex():
    pts = right_side(arc(40, angle=2.5))
    with pytest.raises(GeometryError, match="does not point into the plate at crease vertex"):
        rf.cylindrical_rulings(pts, direction=[1.0, 0.0], alpha=0.5, reference=20)
    with pytest.raises(GeometryError, match="non-zero 2D vector"):
        rf.cylindrical_rulings(pts, direction=[0.0, 0.0], alpha=0.5, reference=20)
    with pytest.raises(GeometryError, match="not on one side of the crease"):
        rf.conical_rulings(pts, apex=[0.0, -1.5], alpha=0.5, reference=20)
    with pytest.raises(GeometryError, match=r"in \(0, 90\) deg"):
        rf.orthogonal_rulings(pts, alpha=math.radians(95.0), reference=20)
