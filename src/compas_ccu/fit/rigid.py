"""Rigid motions for the fits: rotation vectors, 4 x 4 matrices, Kabsch alignment."""

from __future__ import annotations

import itertools

import numpy as np

from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = ["rotation", "rotations", "matrix", "apply", "invert", "kabsch", "axis_rotations"]


def rotation(r) -> np.ndarray:
    """(3, 3) rotation of the rotation vector ``r`` (3,) (Rodrigues)."""
    r = np.asarray(r, dtype=np.float64)
    angle = float(np.linalg.norm(r))
    if angle < DIVISION_FLOOR:
        return np.eye(3)
    k = r / angle
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * kx + (1.0 - np.cos(angle)) * (kx @ kx)


def rotations(r) -> np.ndarray:
    """(b, 3, 3) rotations of the rotation vectors ``r`` (b, 3) (:func:`rotation` of each)."""
    r = np.asarray(r, dtype=np.float64).reshape(-1, 3)
    angle = np.linalg.norm(r, axis=1)
    turn = angle >= DIVISION_FLOOR
    k = r / np.where(turn, angle, 1.0)[:, None]
    kx = np.zeros((len(r), 3, 3))
    kx[:, 0, 1], kx[:, 0, 2], kx[:, 1, 2] = -k[:, 2], k[:, 1], -k[:, 0]
    kx[:, 1, 0], kx[:, 2, 0], kx[:, 2, 1] = k[:, 2], -k[:, 1], k[:, 0]
    sin = np.where(turn, np.sin(angle), 0.0)[:, None, None]
    cos = np.where(turn, 1.0 - np.cos(angle), 0.0)[:, None, None]
    return np.eye(3) + sin * kx + cos * (kx @ kx)


def matrix(rot, t) -> np.ndarray:
    """(4, 4) homogeneous matrix of ``x -> rot x + t``."""
    m = np.eye(4)
    m[:3, :3] = rot
    m[:3, 3] = t
    return m


def apply(m, points) -> np.ndarray:
    """(n, 3) points moved by the (4, 4) matrix ``m``."""
    return np.asarray(points, dtype=np.float64) @ m[:3, :3].T + m[:3, 3]


def invert(m) -> np.ndarray:
    """Inverse of a rigid (4, 4) matrix."""
    rot = m[:3, :3].T
    return matrix(rot, -rot @ m[:3, 3])


def kabsch(source, target, weights=None) -> np.ndarray:
    """(4, 4) proper rigid motion that moves ``source`` (n, 3) onto ``target`` (n, 3) in the
    (weighted) least-squares sense."""
    w = np.ones(len(source)) if weights is None else np.asarray(weights, dtype=np.float64)
    w = w / w.sum()
    cs, ct = w @ source, w @ target
    h = (source - cs).T @ ((target - ct) * w[:, None])
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(vt.T @ u.T)) or 1.0
    rot = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
    return matrix(rot, ct - rot @ cs)


def axis_rotations() -> np.ndarray:
    """(24, 3, 3) the proper rotations that map the coordinate axes onto themselves (signed
    permutation matrices with determinant +1): the ambiguities of principal axes."""
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1.0, -1.0), repeat=3):
            m = np.zeros((3, 3))
            m[range(3), perm] = signs
            if np.linalg.det(m) > 0:
                out.append(m)
    return np.array(out)
