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

:func:`crease_relations` takes one crease or a batch of them (leading axes, e.g. every crease of
every state of a path, with a relation per crease): a deployed state has one crease per plate
pair, and evaluating them one by one costs more in NumPy's per-call overhead than in arithmetic.
Every value is the same, bit for bit, as for the crease alone (the same element-wise operations;
the vector products that are matrix products for one crease are batched matrix products).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import cross3, norm3, unit3
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["CreaseRelations", "crease_relations", "classify"]

TWO_PI = 2.0 * np.pi


class CreaseRelations(NamedTuple):
    """Per-vertex crease quantities, shape (n + 1,) each (NaN where undefined).

    ``sector_angles`` is (n + 1, 4). Residuals: ``eq1`` and ``eq3`` are filled for CCF creases,
    ``eq2`` and ``eq4`` for CCU creases, ``eq5`` for both.

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> relations = model.relations(model.mechanism.deploy(np.radians([20.0])), 0, 0)
    >>> relations.sector_angles.shape, relations.kinds[:2]
    ((49, 4), [None, 'synclastic'])
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


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _matvec(a, v):
    """``a @ v`` of (..., m, 3) rows and (..., 3) vectors: the product ``rows @ vector`` of one
    crease, batched over the leading axes (the same matrix-vector kernel for every crease)."""
    return np.matmul(a, v[..., :, None])[..., 0]


def _vecvec(a, b):
    """``a @ b`` of (..., 3) vectors, one inner product per leading index."""
    return np.matmul(a[..., None, :], b[..., :, None])[..., 0, 0]


def _angle(a, b):
    return np.arctan2(norm3(cross3(a, b)), _dot(a, b))


#: The vertex kinds by code (0: an end vertex, no kind).
KINDS = np.array([None, "ccf", "synclastic", "anticlastic", "straight"], dtype=object)


def _is_ccf(relation) -> np.ndarray:
    """Bool array: ``relation`` (a string or an array of them) is "ccf"."""
    if isinstance(relation, str):
        return np.asarray(relation == "ccf")
    return np.asarray(relation, dtype=object) == "ccf"


def classify(sum_beta: np.ndarray, relation, *, tol: float = EXACT_RELATIVE) -> list:
    """Kind of every crease vertex from its sector-angle sum (ends: None).

    ``sum_beta`` is (..., n + 1); ``relation`` is "ccu" or "ccf", or an array of them that
    broadcasts against the leading axes of ``sum_beta`` (one per crease). Returns a list
    (nested lists for leading axes) of "synclastic", "anticlastic", "straight", "ccf" or None.

    Examples
    --------
    Sector-angle sums below, at and above 360 degrees:

    >>> import numpy as np
    >>> classify(np.radians([np.nan, 350.0, 360.0, 370.0, np.nan]), "ccu")
    [None, 'synclastic', 'straight', 'anticlastic', None]
    """
    s = np.asarray(sum_beta, dtype=float)
    ccf = _is_ccf(relation)
    ccf = ccf.reshape(ccf.shape + (1,) * (ccf.ndim > 0))  # one per crease: over its vertices
    code = np.select(
        [~np.isfinite(s), ccf, s < TWO_PI - tol, s > TWO_PI + tol],
        [0, 1, 2, 3],
        default=4,
    )
    return KINDS[code].tolist()


def crease_relations(
    hinge: np.ndarray,
    ruling_a: np.ndarray,
    ruling_b: np.ndarray,
    plane_normal: np.ndarray,
    *,
    relation="ccu",
) -> CreaseRelations:
    """Evaluate sector angles, curvatures, alpha, alpha', torsion and Eq. 1-5 on a crease.

    Any leading axes batch creases (for example ``(k, c)``: every crease of every state): the
    result has the same leading axes, and every crease's values are those of the crease alone.

    Parameters
    ----------
    hinge : (..., n + 1, 3) float
        Deployed crease vertices.
    ruling_a, ruling_b : (..., n + 1, 3) float
        Directions from the crease into plate a and plate b (any length).
    plane_normal : (..., 3) float
        Normal of the crease plane O.
    relation : {"ccu", "ccf"} or array of them
        How plate b is joined to plate a (an array: per crease, broadcasting against the
        leading axes).

    Returns
    -------
    CreaseRelations
        Arrays with the leading axes; ``kinds`` a list (nested for leading axes).

    Examples
    --------
    The cone pair of ``examples/cone.toml`` (crease radius 2 m in the pattern) at 20 degrees:
    orthogonal rulings, a constant reflection angle and a crease of curvature
    ``1 / (2 cos 20 deg)`` in space:

    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> states = load_model("examples/cone.toml").mechanism.deploy(np.radians([20.0]))
    >>> near, far = states.near[0], states.far[0]
    >>> normal = states.plane_normals[0, 0]
    >>> rel = crease_relations(near[0], far[0] - near[0], far[1] - near[1], normal)
    >>> round(float(np.degrees(rel.gamma_a[1])), 6), round(float(np.degrees(rel.alpha[1])), 6)
    (90.0, 20.0)
    >>> round(float(rel.kappa_3d[1]), 6), round(1.0 / (2.0 * float(np.cos(np.radians(20.0)))), 6)
    (0.532089, 0.532089)
    >>> bool(np.nanmax(np.abs(rel.eq2)) < 1e-12), rel.kinds[1]
    (True, 'synclastic')
    """
    p = np.asarray(hinge, dtype=float)
    ra = unit3(np.asarray(ruling_a, dtype=float))
    rb = unit3(np.asarray(ruling_b, dtype=float))
    nrm = unit3(np.asarray(plane_normal, dtype=float))
    m = p.shape[-2]
    edges = np.diff(p, axis=-2)
    h = norm3(edges)
    u = edges / h[..., None]
    nan = np.full(p.shape[:-1], np.nan)

    beta = np.full(p.shape[:-1] + (4,), np.nan)
    beta[..., 1:-1, 0] = _angle(u[..., 1:, :], ra[..., 1:-1, :])
    beta[..., 1:-1, 1] = _angle(ra[..., 1:-1, :], -u[..., :-1, :])
    beta[..., 1:-1, 2] = _angle(-u[..., :-1, :], rb[..., 1:-1, :])
    beta[..., 1:-1, 3] = _angle(rb[..., 1:-1, :], u[..., 1:, :])
    sum_beta = beta.sum(axis=-1)
    gamma_a = 0.5 * (np.pi + beta[..., 0] - beta[..., 1])
    gamma_b = 0.5 * (np.pi + beta[..., 3] - beta[..., 2])

    # curvature in plate a's pattern (intrinsic: law of cosines with the plate angle)
    plate_angle = beta[..., 0] + beta[..., 1]
    kappa_2d = nan.copy()
    h0, h1 = h[..., :-1], h[..., 1:]
    inner = plate_angle[..., 1:-1]
    chord_2d = np.sqrt(h0**2 + h1**2 - 2 * h0 * h1 * np.cos(inner))
    kappa_2d[..., 1:-1] = 2.0 * np.sin(np.pi - inner) / chord_2d
    # curvature in space, signed towards plate a
    kappa_3d = nan.copy()
    turn = _angle(u[..., :-1, :], u[..., 1:, :])
    p0, p1, p2 = p[..., :-2, :], p[..., 1:-1, :], p[..., 2:, :]
    chord_3d = norm3(p2 - p0)
    towards = np.sign(_dot(0.5 * (p2 + p0) - p1, ra[..., 1:-1, :]))
    kappa_3d[..., 1:-1] = towards * 2.0 * np.sin(turn) / chord_3d

    # reflection angle at the vertices: elevation of S (normal to T in span(T, ruling a))
    tangent = np.empty_like(p)
    tangent[..., 0, :], tangent[..., -1, :] = u[..., 0, :], u[..., -1, :]
    tangent[..., 1:-1, :] = unit3(u[..., :-1, :] + u[..., 1:, :])
    if m >= 3:  # ends: the neighbouring tangent reflected in the end edge (as in strips.frames)
        t1, t2 = tangent[..., 1, :], tangent[..., -2, :]
        u0, u1 = u[..., 0, :], u[..., -1, :]
        tangent[..., 0, :] = 2.0 * _vecvec(t1, u0)[..., None] * u0 - t1
        tangent[..., -1, :] = 2.0 * _vecvec(t2, u1)[..., None] * u1 - t2
    n3 = nrm[..., None, :]
    tangent = unit3(tangent - _matvec(tangent, nrm)[..., None] * n3)
    s = ra - _dot(ra, tangent)[..., None] * tangent
    out_of_plane = np.abs(_matvec(s, nrm))
    alpha = np.arctan2(out_of_plane, norm3(s - _matvec(s, nrm)[..., None] * n3))
    # reflection angle of every segment: tilt of quad j of plate a about crease edge j
    ra0 = ra[..., :-1, :]
    w = ra0 - _dot(ra0, u)[..., None] * u
    segment_alpha = np.arctan2(np.abs(_matvec(w, nrm)), norm3(w - _matvec(w, nrm)[..., None] * n3))
    alpha_prime = nan.copy()
    alpha_prime[..., 1:-1] = np.diff(segment_alpha, axis=-1) / (0.5 * (h0 + h1))

    # discrete torsion: angle between consecutive osculating planes (mod pi) per edge length
    torsion = nan.copy()
    if m >= 4:
        binormal = cross3(u[..., :-1, :], u[..., 1:, :])
        size = norm3(binormal)
        with np.errstate(invalid="ignore", divide="ignore"):
            binormal = binormal / size[..., None]
            b0, b1 = binormal[..., :-1, :], binormal[..., 1:, :]
            edge_tau = (
                np.arctan2(
                    _dot(cross3(b0, b1), u[..., 1:-1, :]),
                    np.abs(_dot(b0, b1)),
                )
                / h[..., 1:-1]
            )
        torsion[..., 2:-2] = 0.5 * (edge_tau[..., :-1] + edge_tau[..., 1:])

    cot_a, cot_b = 1.0 / np.tan(gamma_a), 1.0 / np.tan(gamma_b)
    drive = 0.5 * kappa_2d * np.tan(alpha)
    ccf = _is_ccf(relation)
    ccf = ccf.reshape(ccf.shape + (1,) * (ccf.ndim > 0))
    eq1 = np.where(ccf, alpha_prime - (cot_a - cot_b) * drive, np.nan)
    eq3 = np.where(ccf, torsion + (cot_a + cot_b) * drive, np.nan)
    eq2 = np.where(ccf, np.nan, alpha_prime - (cot_a + cot_b) * drive)
    eq4 = np.where(ccf, np.nan, torsion + (cot_a - cot_b) * drive)
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
