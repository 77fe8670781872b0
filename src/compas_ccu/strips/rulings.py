"""Ruling fields of a planar-quad developable strip at a deployed (3D target) state.

All functions work in the local frame of the crease plane O: the crease polyline lies in
``z = 0``, the plate lies on the left of the crease direction and rises towards ``+z``.
They return unit ruling directions ``(n + 1, 3)`` from the crease into the plate such that every
quad between consecutive rulings is planar, i.e. a discrete developable. The reflection angle
alpha at the reference vertex (docs/geometry.md §1, measured as in
:mod:`compas_ccu.kinematics.leading`) equals the requested design angle.

Ruling types (docs/geometry.md, "developable types"):

* :func:`orthogonal_rulings` -- gamma = 90 deg, constant reflection angle: the ultra-special case
  (a circular crease gives a right circular cone).
* :func:`cylindrical_rulings` -- all rulings parallel.
* :func:`conical_rulings` -- all rulings through one apex.
* :func:`ruling_angle_rulings` -- a general ruling-angle field gamma(s); alpha(s) follows
  alpha' = cot(gamma) kappa_2D tan(alpha), integrated exactly in the 3D form
  d ln tan(alpha / 2) = cot(gamma) d phi_3D.
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.errors import DevelopabilityError, GeometryError
from compas_ccu.strips.frames import crease_frames
from compas_ccu.tolerances import EXACT_RELATIVE, MACHINE, ZERO_ANGLE, ZERO_LENGTH

__all__ = [
    "rulings_from_tilts",
    "orthogonal_rulings",
    "cylindrical_rulings",
    "conical_rulings",
    "ruling_angle_rulings",
    "vertex_reflection_angles",
    "check_alpha_field",
]


def vertex_reflection_angles(points: np.ndarray, rulings: np.ndarray) -> np.ndarray:
    """(n + 1,) reflection angle alpha at every crease vertex (local frame, radians).

    alpha_i is the angle between O and the surface tangent ``S_i``: the unit vector normal to the
    discrete tangent ``T_i`` in the plane spanned by ``T_i`` and the ruling.

    Examples
    --------
    >>> import numpy as np
    >>> phi = np.linspace(0.75 * np.pi, 0.25 * np.pi, 5)
    >>> arc = 2.0 * np.c_[np.cos(phi), np.sin(phi)]
    >>> rulings = orthogonal_rulings(arc, alpha=np.radians(20.0), reference=0)
    >>> np.degrees(vertex_reflection_angles(arc, rulings)).round(6).tolist()
    [20.0, 20.0, 20.0, 20.0, 20.0]
    """
    f = crease_frames(points)
    r = np.asarray(rulings, dtype=float)
    along_n = r[:, 0] * f.normals[:, 0] + r[:, 1] * f.normals[:, 1]
    return np.arctan2(r[:, 2], along_n)


def rulings_from_tilts(points: np.ndarray, tilts: np.ndarray, gamma=None) -> np.ndarray:
    """Rulings of the strip whose quad ``j`` is tilted by ``tilts[j]`` about crease edge ``j``.

    Interior rulings are the intersection lines of consecutive quad planes. The end rulings lie
    in the end quads. Without ``gamma`` they continue the pattern symmetrically: the end quad
    makes the same angle with its crease edge at both ends (exact for a circular crease with
    constant tilt). With a ruling-angle field ``gamma`` the end ruling keeps the field's angle:
    its angle to the end edge is ``gamma_end + gamma_next - angle(r_next, edge)``, which is the
    symmetric rule when gamma = 90 deg.

    Parameters
    ----------
    points : (n + 1, 2 or 3) float
        Crease polyline in O.
    tilts : (n,) float
        Quad tilt angles psi_j in (0, pi/2), radians.
    gamma : (n + 1,) float, optional
        Ruling angles, radians; only the two values at each end are used.

    Returns
    -------
    (n + 1, 3) float
        Unit ruling directions.

    Examples
    --------
    Every quad of a circular crease (radius 2 m, 4 edges) tilted by 30 degrees:

    >>> import numpy as np
    >>> phi = np.linspace(0.75 * np.pi, 0.25 * np.pi, 5)
    >>> arc = 2.0 * np.c_[np.cos(phi), np.sin(phi)]
    >>> rulings = rulings_from_tilts(arc, np.full(4, np.radians(30.0)))
    >>> rulings.shape, np.degrees(vertex_reflection_angles(arc, rulings)).round(6).tolist()
    ((5, 3), [29.520997, 29.520997, 29.520997, 29.520997, 29.520997])
    """
    f = crease_frames(points)
    tilts = np.asarray(tilts, dtype=float)
    u = np.c_[f.edges, np.zeros(len(f.edges))]
    v = np.c_[-f.edges[:, 1], f.edges[:, 0], np.zeros(len(f.edges))]
    z = np.array([0.0, 0.0, 1.0])
    c, s = np.cos(tilts)[:, None], np.sin(tilts)[:, None]
    w = c * v + s * z  # in-quad direction normal to the crease edge
    normals = c * z - s * v
    r = np.empty((len(f.turns), 3))
    inner = np.cross(normals[:-1], normals[1:])
    size = np.linalg.norm(inner, axis=1)
    coplanar = size < ZERO_LENGTH
    inner = np.where(coplanar[:, None], w[1:], inner / np.where(coplanar, 1.0, size)[:, None])
    inner *= np.sign(np.einsum("ij,ij->i", inner, w[1:]))[:, None]
    r[1:-1] = inner
    if gamma is None:
        r[0] = r[1] - 2.0 * (r[1] @ u[0]) * u[0]
        r[-1] = r[-2] - 2.0 * (r[-2] @ u[-1]) * u[-1]
        return r
    g = np.asarray(gamma, dtype=float)
    for end, nxt, e, g_end, g_next in ((0, 1, u[0], g[0], g[1]), (-1, -2, u[-1], g[-1], g[-2])):
        # angles to the forward edge direction, in the end quad's plane
        across = r[nxt] - (r[nxt] @ e) * e
        across /= np.linalg.norm(across)
        phi = g_end + g_next - math.acos(float(np.clip(r[nxt] @ e, -1.0, 1.0)))
        r[end] = math.cos(phi) * e + math.sin(phi) * across
    return r


def _reference_turn(points: np.ndarray, reference: int) -> float:
    """The crease turn that sets the discrete tangent at ``reference``.

    At an end vertex the tangent is the end edge turned back by half the neighbouring turn
    (:func:`compas_ccu.strips.frames.crease_frames`), so the neighbouring turn counts there.
    """
    turns = crease_frames(points).turns
    if len(turns) > 2 and reference in (0, len(turns) - 1):
        return float(turns[1] if reference == 0 else turns[-2])
    return float(turns[reference])


def orthogonal_rulings(points: np.ndarray, *, alpha: float, reference: int) -> np.ndarray:
    """Rulings orthogonal to the crease (gamma = 90 deg) at reflection angle ``alpha``.

    All quads tilt by the same psi with ``tan(psi) = tan(alpha) / cos(turn_ref / 2)``, so the
    ruling at the reference vertex has reflection angle exactly ``alpha``.

    Examples
    --------
    On a circular crease (radius 2 m) the reflection angle is ``alpha`` at every vertex:

    >>> import numpy as np
    >>> phi = np.linspace(0.75 * np.pi, 0.25 * np.pi, 5)
    >>> arc = 2.0 * np.c_[np.cos(phi), np.sin(phi)]
    >>> rulings = orthogonal_rulings(arc, alpha=np.radians(30.0), reference=2)
    >>> (rulings[2].round(6) + 0.0).tolist()  # the crown's ruling: cos 30, sin 30
    [0.0, 0.866025, 0.5]
    >>> np.degrees(vertex_reflection_angles(arc, rulings)).round(6).tolist()
    [30.0, 30.0, 30.0, 30.0, 30.0]
    """
    _check_alpha(alpha)
    psi = math.atan(math.tan(alpha) / math.cos(0.5 * _reference_turn(points, reference)))
    n = len(points) - 1
    return rulings_from_tilts(points, np.full(n, psi))


def _check_alpha(alpha: float) -> None:
    if not (0.0 < alpha < 0.5 * math.pi):
        raise GeometryError(
            f"the design reflection angle must be in (0, 90) deg, got {math.degrees(alpha):.6g}"
        )


def cylindrical_rulings(
    points: np.ndarray, *, direction, alpha: float, reference: int
) -> np.ndarray:
    """Parallel rulings (a cylinder) whose in-plane direction is ``direction``.

    The out-of-plane component follows from ``alpha`` at the reference vertex; the sign of
    ``direction`` is chosen so that the rulings point into the plate (left side).

    Raises
    ------
    GeometryError
        The direction is parallel to the crease tangent at some vertex, or points to the other
        side of the crease there (the strip would fold over itself).

    Examples
    --------
    The direction's sign is turned so that the rulings point into the plate (the left side):

    >>> import numpy as np
    >>> phi = np.linspace(0.75 * np.pi, 0.25 * np.pi, 5)
    >>> arc = 2.0 * np.c_[np.cos(phi), np.sin(phi)]
    >>> alpha = np.radians(30.0)
    >>> rulings = cylindrical_rulings(arc, direction=[0.0, -1.0], alpha=alpha, reference=2)
    >>> (rulings.round(6) + 0.0).tolist() == [[0.0, 0.866025, 0.5]] * 5
    True
    """
    _check_alpha(alpha)
    f = crease_frames(points)
    d = np.asarray(direction, dtype=float)[:2]
    norm = float(np.hypot(*d))
    if not np.isfinite(norm) or norm == 0.0:
        raise GeometryError(f"cylindrical ruling direction must be a non-zero 2D vector, got {d}")
    d = d / norm
    into = f.normals @ d
    if into[reference] < 0.0:
        d, into = -d, -into
    bad = np.flatnonzero(into <= EXACT_RELATIVE)
    if bad.size:
        i = int(bad[0])
        raise GeometryError(
            f"cylindrical ruling direction {d.round(6).tolist()} does not point into the plate "
            f"at crease vertex {i}: the crease turns past the ruling direction there"
        )
    rise = math.tan(alpha) * float(into[reference])
    r = np.r_[d, rise] / math.sqrt(1.0 + rise * rise)
    return np.tile(r, (len(points), 1))


def conical_rulings(points: np.ndarray, *, apex, alpha: float, reference: int) -> np.ndarray:
    """Rulings through one apex whose projection on O is ``apex`` (2D, local frame).

    The apex height follows from ``alpha`` at the reference vertex. The plate extends towards the
    apex when the apex lies on the plate side of the reference vertex, else away from it.

    Raises
    ------
    GeometryError
        The apex lies on the crease line at some vertex, or on different sides of the crease
        along it.

    Examples
    --------
    With the apex at the centre of a circular crease the cone's rulings are orthogonal to it:

    >>> import numpy as np
    >>> phi = np.linspace(0.75 * np.pi, 0.25 * np.pi, 5)
    >>> arc = 2.0 * np.c_[np.cos(phi), np.sin(phi)]
    >>> cone = conical_rulings(arc, apex=[0.0, 0.0], alpha=np.radians(30.0), reference=2)
    >>> bool(np.allclose(cone, orthogonal_rulings(arc, alpha=np.radians(30.0), reference=2)))
    True
    """
    _check_alpha(alpha)
    f = crease_frames(points)
    p = np.asarray(points, dtype=float)[:, :2]
    a = np.asarray(apex, dtype=float)[:2]
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise GeometryError(f"cone apex must be a finite 2D point, got {apex!r}")
    to_apex = a - p
    side = np.einsum("ij,ij->i", to_apex, f.normals)
    sign = 1.0 if side[reference] > 0.0 else -1.0
    dist = np.linalg.norm(to_apex, axis=1)
    bad = np.flatnonzero(sign * side <= EXACT_RELATIVE * dist.max())
    if bad.size:
        i = int(bad[0])
        raise GeometryError(
            f"cone apex {a.tolist()} is not on one side of the crease: at crease vertex {i} the "
            "ruling towards the apex would lie along or across the crease"
        )
    height = math.tan(alpha) * float(side[reference])
    r = sign * np.c_[to_apex, np.full(len(p), height)]
    return r / np.linalg.norm(r, axis=1)[:, None]


def check_alpha_field(points: np.ndarray, gamma: np.ndarray, alpha: np.ndarray) -> None:
    """Refuse a prescribed alpha(s) that violates alpha' = cot(gamma) kappa_2D tan(alpha).

    For a planar crease the reflection angle is not free once the ruling angles are given
    (docs/geometry.md §1); in particular a constant alpha requires gamma = 90 deg everywhere.

    Parameters
    ----------
    points : (n + 1, 2) float
        The 3D crease polyline in O.
    gamma, alpha : (n + 1,) float
        Ruling angle and reflection angle at every vertex, radians.

    Raises
    ------
    DevelopabilityError
        The prescribed field is not developable, with the worst vertex and the mismatch.

    Examples
    --------
    A constant reflection angle is developable with orthogonal rulings only:

    >>> import numpy as np
    >>> phi = np.linspace(0.75 * np.pi, 0.25 * np.pi, 5)
    >>> arc = 2.0 * np.c_[np.cos(phi), np.sin(phi)]
    >>> alpha = np.full(5, np.radians(30.0))
    >>> check_alpha_field(arc, np.full(5, np.radians(90.0)), alpha) is None
    True
    >>> check_alpha_field(arc, np.full(5, np.radians(60.0)), alpha)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    compas_ccu.errors.DevelopabilityError: the prescribed reflection angles are not developable: ...
    """
    f = crease_frames(points)
    gamma = np.asarray(gamma, dtype=float)
    alpha = np.asarray(alpha, dtype=float)
    # d ln tan(alpha/2) / ds  ==  cot(gamma) * kappa_3D  (3D form of the ODE)
    s = np.r_[0.0, np.cumsum(f.lengths)]
    lhs = np.gradient(np.log(np.tan(0.5 * alpha)), s)
    kappa3d = np.zeros_like(s)
    kappa3d[1:-1] = f.turns[1:-1] / (0.5 * (f.lengths[:-1] + f.lengths[1:]))
    kappa3d[0], kappa3d[-1] = kappa3d[1], kappa3d[-2]
    rhs = kappa3d / np.tan(gamma)
    scale = max(float(np.max(np.abs(kappa3d))), ZERO_LENGTH)
    mismatch = np.abs(lhs - rhs)
    mismatch[:2] = mismatch[-2:] = 0.0  # one-sided differences and extrapolated end rulings
    i = int(np.argmax(mismatch))
    if mismatch[i] > 1e-2 * scale + EXACT_RELATIVE:
        constant = np.ptp(alpha) < ZERO_ANGLE
        hint = (
            "a constant reflection angle along a planar crease needs gamma = 90 deg everywhere "
            "(the ultra-special case); "
            if constant
            else ""
        )
        raise DevelopabilityError(
            f"the prescribed reflection angles are not developable: {hint}at crease vertex {i} "
            f"gamma = {math.degrees(gamma[i]):.6g} deg and alpha = {math.degrees(alpha[i]):.6g} "
            f"deg require alpha' = cot(gamma) kappa_2D tan(alpha) = "
            f"{rhs[i] * math.sin(alpha[i]):.6g} rad/m, the prescribed field has "
            f"{lhs[i] * math.sin(alpha[i]):.6g} rad/m"
        )


def ruling_angle_rulings(
    points: np.ndarray, *, gamma, alpha: float, reference: int
) -> tuple[np.ndarray, np.ndarray]:
    """Rulings for a prescribed ruling-angle field gamma(s).

    Parameters
    ----------
    points : (n + 1, 2) float
        Crease polyline in O (the 3D target).
    gamma : float or (n + 1,) float
        Ruling angle at each vertex in (0, pi), radians, measured on the plate from the forward
        crease tangent (90 deg: orthogonal).
    alpha : float
        Reflection angle at the reference vertex, radians.

    Returns
    -------
    rulings : (n + 1, 3) float
    tilts : (n,) float
        Reflection angle of every crease segment from the ODE.

    Raises
    ------
    DevelopabilityError
        The field needs a reflection angle of 90 deg or more somewhere along the crease.

    Examples
    --------
    >>> import numpy as np
    >>> phi = np.linspace(0.75 * np.pi, 0.25 * np.pi, 5)
    >>> arc = 2.0 * np.c_[np.cos(phi), np.sin(phi)]
    >>> rulings, tilts = ruling_angle_rulings(
    ...     arc, gamma=np.radians(90.0), alpha=np.radians(30.0), reference=2
    ... )
    >>> rulings.shape, np.degrees(tilts).round(6).tolist()
    ((5, 3), [30.483672, 30.483672, 30.483672, 30.483672])
    """
    from scipy.optimize import brentq

    _check_alpha(alpha)
    f = crease_frames(points)
    n = len(points) - 1
    gamma = np.broadcast_to(np.asarray(gamma, dtype=float), (n + 1,))
    if np.any((gamma <= 0.0) | (gamma >= math.pi)) or not np.all(np.isfinite(gamma)):
        i = int(np.flatnonzero(~((gamma > 0.0) & (gamma < math.pi)))[0])
        raise GeometryError(
            f"ruling angle gamma must be in (0, 180) deg, got {math.degrees(gamma[i]):.6g} deg "
            f"at crease vertex {i}"
        )
    # ln tan(psi_j / 2) = c + sum_{i <= j} cot(gamma_i) turn_i
    increments = f.turns[1:-1] / np.tan(gamma[1:-1])
    log_tan = np.r_[0.0, np.cumsum(increments)]
    top = float(log_tan.max())

    def tilts_for(c: float) -> np.ndarray:
        return 2.0 * np.arctan(np.exp(c + log_tan))

    def ref_alpha(c: float) -> float:
        r = rulings_from_tilts(points, tilts_for(c), gamma)
        return float(vertex_reflection_angles(points, r)[reference])

    hi = -top + math.log(math.tan(0.5 * math.radians(89.999)))
    lo = hi - 60.0
    if ref_alpha(hi) < alpha:
        j = int(np.argmax(log_tan))
        raise DevelopabilityError(
            f"the ruling-angle field cannot reach alpha = {math.degrees(alpha):.6g} deg at the "
            f"reference vertex: alpha' = cot(gamma) kappa_2D tan(alpha) drives the reflection "
            f"angle of crease segment {j} to 90 deg first (largest reachable reference alpha "
            f"{math.degrees(ref_alpha(hi)):.6g} deg)"
        )
    flat = ref_alpha(lo)
    if not flat < alpha:
        # the rulings at the reference vertex do not lie in the plate's half-plane however
        # little the plate is tilted (an end ruling that the field turns across the crease)
        raise DevelopabilityError(
            f"the ruling-angle field cannot reach alpha = {math.degrees(alpha):.6g} deg at the "
            f"reference vertex {reference}: even an almost flat plate has a reflection angle of "
            f"{math.degrees(flat):.6g} deg there (its ruling points across the crease); use "
            "more segments, a reference vertex inside the crease or a ruling angle nearer 90 deg"
        )
    c = brentq(lambda c: ref_alpha(c) - alpha, lo, hi, xtol=MACHINE, rtol=MACHINE, maxiter=200)
    tilts = tilts_for(c)
    return rulings_from_tilts(points, tilts, gamma), tilts
