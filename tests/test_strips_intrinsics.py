from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.errors import GeometryError
from compas_ccu.strips.intrinsics import sector_angles, strip_intrinsics


def test_sector_angles_of_a_fan():
    near = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    far = np.array([[1.0, 1.0], [1.0, 1.0], [1.0, 1.0]])
    back, fwd = sector_angles(near, far)
    assert np.isnan(back[0]) and np.isnan(fwd[2])
    np.testing.assert_allclose(np.degrees(fwd[:2]), [45.0, 90.0], atol=1e-12)
    np.testing.assert_allclose(np.degrees(back[1:]), [90.0, 45.0], atol=1e-12)


def test_intrinsics_are_the_same_in_2d_and_rotated_3d():
    t = np.linspace(0.0, 1.0, 9)
    near = np.c_[np.cos(t), np.sin(t)]
    far = 0.7 * near + [0.05, 0.0]
    a = strip_intrinsics(near, far)
    rot = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])
    b = strip_intrinsics(np.c_[near, np.zeros(9)] @ rot, np.c_[far, np.zeros(9)] @ rot)
    for x, y in zip(a, b):
        np.testing.assert_allclose(x, y, atol=1e-14)
    np.testing.assert_allclose(a.plate_angles[1:-1], np.pi - 1.0 / 8, atol=1e-12)


def test_zero_length_edge_is_refused():
    near = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]])
    with pytest.raises(GeometryError, match="crease edge 1 has zero length"):
        strip_intrinsics(near, near + [0.0, 1.0])


def test_ruling_along_the_crease_is_refused():
    near = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    far = near + [[0.0, 1.0], [0.5, 0.0], [0.0, 1.0]]
    with pytest.raises(GeometryError, match="ruling at crease vertex 1 lies along the crease"):
        strip_intrinsics(near, far)


def test_zero_length_ruling_is_refused():
    near = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    far = near + [[0.0, 1.0], [0.0, 0.0], [0.0, 1.0]]
    with pytest.raises(GeometryError, match="ruling at crease vertex 1 has zero length"):
        strip_intrinsics(near, far)
