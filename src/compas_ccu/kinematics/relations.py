"""Sector angles, crease kind and the smooth relations (Eq. 1-5) evaluated on a crease.

For a crease between plates ``a`` and ``b`` (docs/geometry.md §1, paper Fig. 3), at every crease
vertex the sector angles counter-clockwise are

    beta_0 = (forward edge, ruling a)     beta_1 = (ruling a, backward edge)
    beta_2 = (backward edge, ruling b)    beta_3 = (ruling b, forward edge)

They lie inside planar quads, so they are the same in the cut pattern and in every deployed
state. ``sum(beta) < 2 pi``: synclastic CCU (Q2), ``> 2 pi``: anticlastic CCU (Q4), ``= 2 pi``:
CCF (Q1 / Q3). The ruling angles are ``gamma_a = (pi + beta_0 - beta_1) / 2`` and
``gamma_b = (pi + beta_3 - beta_2) / 2`` (angle to the forward tangent in each plate's pattern):
CCU gives gamma_a = gamma_b, CCF gives gamma_a = pi - gamma_b.

The Fuchs-Tabachnikov relations, with kappa_2D the crease curvature in plate a's pattern (signed,
positive when the crease bends towards plate a), kappa_3D in space, alpha the reflection angle:

    (1) alpha'_CCF = (cot g_a - cot g_b) / 2 kappa_2D tan(alpha)
    (2) alpha'_CCU = (cot g_a + cot g_b) / 2 kappa_2D tan(alpha)
    (3) tau_CCF = -(cot g_a + cot g_b) / 2 kappa_2D tan(alpha)
    (4) tau_CCU = -(cot g_a - cot g_b) / 2 kappa_2D tan(alpha)
    (5) cos(alpha) = kappa_2D / kappa_3D

are evaluated with discrete, vertex-centred quantities; the residuals are reported and converge
to zero as the crease is refined (second order; see the tests).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import unit
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["CreaseRelations", "crease_relations", "classify"]

TWO_PI = 2.0 * np.pi


class CreaseRelations(NamedTuple):
    """Per-vertex crease quantities, shape (n + 1,) each (NaN where undefined).

    ``sector_angles`` is (n + 1, 4). Residuals: ``eq1`` and ``eq3`` are filled for CCF creases,
    ``eq2`` and ``eq4`` for CCU creases, ``eq5`` for both.
    """

    sector_angles: np.ndarray
    sum_beta: np.ndarray
    kinds: list
    gamma_a: np.ndarray
    gamma_b: np.ndarray
    kappa_2d: np.ndarray
    kappa_3d: np.ndarray
    alpha: np.ndarray
    segment_alpha: np.ndarray
    alpha_prime: np.ndarray
    torsion: np.ndarray
    eq1: np.ndarray
    eq2: np.ndarray
    eq3: np.ndarray
    eq4: np.ndarray
    eq5: np.ndarray


def _angle(a, b):
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("...i,...i", a, b))


def classify(sum_beta: np.ndarray, relation: str, *, tol: float = EXACT_RELATIVE) -> list:
    """Kind of every crease vertex from its sector-angle sum (ends: None)."""
    kinds = []
    for s in sum_beta:
        if not np.isfinite(s):
            kinds.append(None)
        elif relation == "ccf":
            kinds.append("ccf")
        elif s < TWO_PI - tol:
            kinds.append("synclastic")
        elif s > TWO_PI + tol:
            kinds.append("anticlastic")
        else:
            kinds.append("straight")
    return kinds


def crease_relations(
    hinge: np.ndarray,
    ruling_a: np.ndarray,
    ruling_b: np.ndarray,
    plane_normal: np.ndarray,
    *,
    relation: str = "ccu",
) -> CreaseRelations:
    """Evaluate sector angles, curvatures, alpha, alpha', torsion and Eq. 1-5 on a crease.

    Parameters
    ----------
    hinge : (n + 1, 3) float
        Deployed crease vertices.
    ruling_a, ruling_b : (n + 1, 3) float
        Directions from the crease into plate a and plate b (any length).
    plane_normal : (3,) float
        Normal of the crease plane O.
    relation : {"ccu", "ccf"}
        How plate b is joined to plate a.

    Returns
    -------
    CreaseRelations
    """
    p = np.asarray(hinge, dtype=float)
    ra = unit(np.asarray(ruling_a, dtype=float))
    rb = unit(np.asarray(ruling_b, dtype=float))
    nrm = unit(np.asarray(plane_normal, dtype=float))
    m = len(p)
    edges = np.diff(p, axis=0)
    h = np.linalg.norm(edges, axis=1)
    u = edges / h[:, None]
    nan = np.full(m, np.nan)

    beta = np.full((m, 4), np.nan)
    beta[1:-1, 0] = _angle(u[1:], ra[1:-1])
    beta[1:-1, 1] = _angle(ra[1:-1], -u[:-1])
    beta[1:-1, 2] = _angle(-u[:-1], rb[1:-1])
    beta[1:-1, 3] = _angle(rb[1:-1], u[1:])
    sum_beta = beta.sum(axis=1)
    gamma_a = 0.5 * (np.pi + beta[:, 0] - beta[:, 1])
    gamma_b = 0.5 * (np.pi + beta[:, 3] - beta[:, 2])

    # curvature in plate a's pattern (intrinsic: law of cosines with the plate angle)
    plate_angle = beta[:, 0] + beta[:, 1]
    kappa_2d = nan.copy()
    chord_2d = np.sqrt(h[:-1] ** 2 + h[1:] ** 2 - 2 * h[:-1] * h[1:] * np.cos(plate_angle[1:-1]))
    kappa_2d[1:-1] = 2.0 * np.sin(np.pi - plate_angle[1:-1]) / chord_2d
    # curvature in space, signed towards plate a
    kappa_3d = nan.copy()
    turn = _angle(u[:-1], u[1:])
    chord_3d = np.linalg.norm(p[2:] - p[:-2], axis=1)
    towards = np.sign(np.einsum("ij,ij->i", 0.5 * (p[2:] + p[:-2]) - p[1:-1], ra[1:-1]))
    kappa_3d[1:-1] = towards * 2.0 * np.sin(turn) / chord_3d

    # reflection angle at the vertices: elevation of S (normal to T in span(T, ruling a))
    tangent = np.empty_like(p)
    tangent[0], tangent[-1] = u[0], u[-1]
    tangent[1:-1] = unit(u[:-1] + u[1:])
    if m >= 3:  # ends: the neighbouring tangent reflected in the end edge (as in strips.frames)
        tangent[0] = 2.0 * (tangent[1] @ u[0]) * u[0] - tangent[1]
        tangent[-1] = 2.0 * (tangent[-2] @ u[-1]) * u[-1] - tangent[-2]
    tangent = unit(tangent - np.outer(tangent @ nrm, nrm))
    s = ra - np.einsum("ij,ij->i", ra, tangent)[:, None] * tangent
    out_of_plane = np.abs(s @ nrm)
    alpha = np.arctan2(out_of_plane, np.linalg.norm(s - np.outer(s @ nrm, nrm), axis=1))
    # reflection angle of every segment: tilt of quad j of plate a about crease edge j
    w = ra[:-1] - np.einsum("ij,ij->i", ra[:-1], u)[:, None] * u
    segment_alpha = np.arctan2(np.abs(w @ nrm), np.linalg.norm(w - np.outer(w @ nrm, nrm), axis=1))
    alpha_prime = nan.copy()
    alpha_prime[1:-1] = np.diff(segment_alpha) / (0.5 * (h[:-1] + h[1:]))

    # discrete torsion: angle between consecutive osculating planes (mod pi) per edge length
    torsion = nan.copy()
    if m >= 4:
        binormal = np.cross(u[:-1], u[1:])
        size = np.linalg.norm(binormal, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            binormal = binormal / size[:, None]
            b0, b1 = binormal[:-1], binormal[1:]
            edge_tau = (
                np.arctan2(
                    np.einsum("ij,ij->i", np.cross(b0, b1), u[1:-1]),
                    np.abs(np.einsum("ij,ij->i", b0, b1)),
                )
                / h[1:-1]
            )
        torsion[2:-2] = 0.5 * (edge_tau[:-1] + edge_tau[1:])

    cot_a, cot_b = 1.0 / np.tan(gamma_a), 1.0 / np.tan(gamma_b)
    drive = 0.5 * kappa_2d * np.tan(alpha)
    eq1, eq2, eq3, eq4 = nan.copy(), nan.copy(), nan.copy(), nan.copy()
    if relation == "ccf":
        eq1 = alpha_prime - (cot_a - cot_b) * drive
        eq3 = torsion + (cot_a + cot_b) * drive
    else:
        eq2 = alpha_prime - (cot_a + cot_b) * drive
        eq4 = torsion + (cot_a - cot_b) * drive
    with np.errstate(divide="ignore", invalid="ignore"):  # straight vertices: kappa = 0
        eq5 = np.where(kappa_3d != 0.0, np.cos(alpha) - kappa_2d / kappa_3d, np.nan)
    return CreaseRelations(
        beta,
        sum_beta,
        classify(sum_beta, relation),
        gamma_a,
        gamma_b,
        kappa_2d,
        kappa_3d,
        alpha,
        segment_alpha,
        alpha_prime,
        torsion,
        eq1,
        eq2,
        eq3,
        eq4,
        eq5,
    )
