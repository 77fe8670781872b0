"""The effort of deploying: the plates' bending energy and the force between the feet.

Deploying bends the plates; the work the actuators put in is stored as bending energy

    E(α) = Σ_plates D/2 ∫ κ² dA,    D = Q̄11(φ) t³ / 12   (isotropic: E t³ / 12 (1 − ν²))

(κ the principal curvature of the developable mid-surface, :func:`compas_ccu.strips.curvature.
plate_curvature`; ``Q̄11(φ)`` the plate modulus along the bending direction, the same model as
the bending check, :mod:`compas_ccu.thickness.bending`). Pushing the feet of a crease together
(or pulling them apart) by the quasi-static force F moves them by d span, so

    F(α) = dE/dα / (d span/dα)

is the force between the feet that holds the structure at α — the actuation force of a tie or a
jack across the span, without friction or self-weight. Negative: the feet must be pushed
together (the span shrinks as the plates bend). The FE deployment measures the same work as the
work of its supports (``validation.json`` ``load_path``; docs/structural.md compares the two).

A radial dome or funnel has no span between two feet: its feet stand on a ring about the
layout's axis. The same statics, with the ring in place of the tie: a ring through the feet (a
band of plan length ``L``) of tension ``T`` does the work ``−T dL`` as the feet move, so

    T(α) = −dE/dα / (dL/dα),    h = T / R

is the ring's tension (positive: tension, the feet push outwards on it; negative: they pull
inwards, the structure would close back into its stack, and the ring is in compression) and
``h`` the horizontal thrust of the feet on it per metre of ring (a circular ring of radius
``R`` carries a radial line load ``T / R``; ``R`` the mean distance of the feet from the axis;
:func:`foot_ring`, :func:`ring_tension`). For the vault's tie ``T = −F``. Like ``F``, it is the
active bending's alone: self-weight and loads add their own thrust (the FE reactions).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.model.checks import check_path
from compas_ccu.model.records import leading_span
from compas_ccu.strips.curvature import plate_curvature
from compas_ccu.thickness.bending import bending_angles
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = [
    "bending_energy",
    "actuation_force",
    "ring_tension",
    "foot_ring",
    "Actuation",
    "radial_feet",
    "path_actuation",
]


#: Paths whose geometry :func:`path_actuation` keeps per model geometry.
ACTUATION_PATHS_KEPT = 8


class Actuation(NamedTuple):
    """Energy and foot force along a deployment path.

    Attributes
    ----------
    alphas : (k,) float
        Reference angles, degrees.
    energy : (k,) float
        Bending energy of all plates, J.
    span : (k,) float
        Span of the leading crease, m.
    force : (k,) float
        Force between the feet, N (NaN where the span does not change: the flat stack).
    ring_length, ring_angle, ring_radius : (k,) float or None
        A radial layout's ring of feet (:func:`foot_ring`): its plan length, m, the angle the
        feet span about the axis, radians, and their mean distance from it, m; None for
        other layouts.
    """

    alphas: np.ndarray
    energy: np.ndarray
    span: np.ndarray
    force: np.ndarray
    ring_length: np.ndarray | None = None
    ring_angle: np.ndarray | None = None
    ring_radius: np.ndarray | None = None

    @property
    def ring_tension(self) -> np.ndarray | None:
        """(k,) tension of the ring that holds the feet, N (:func:`ring_tension`), or None."""
        if self.ring_length is None:
            return None
        return ring_tension(self.alphas, self.energy, self.ring_length)

    @property
    def ring_thrust(self) -> np.ndarray | None:
        """(k,) thrust of the feet on the ring, ``h = T / R``, N/m (positive outwards)."""
        if self.ring_length is None:
            return None
        return self.ring_tension / self.ring_radius

    @property
    def force_max(self) -> float:
        """The largest |force| along the path, N."""
        f = np.abs(self.force[np.isfinite(self.force)])
        return float(f.max()) if f.size else 0.0


def bending_energy(vertices: np.ndarray, rigidity) -> np.ndarray:
    """(k,) bending energy ``Σ D/2 ∫ κ² dA`` of the plates of k kinematic states, J.

    The integral is exact for a developable plate whose curvature follows the law of a
    ruling: along a straight ruling the principal curvature of a developable surface is
    ``κ(s) = κ0 / (1 + c s)`` (1/κ linear in the arc length s), so between the ruling's two
    vertices 1/κ is interpolated linearly, not κ²: averaging κ² at the vertices over-estimates
    a cone's energy by 3.4 % (docs/thickness.md, "Bending energy"). Each quad is the bilinear
    patch of its four vertices; its area density along a ruling is linear, and
    ``∫ L(σ) / h(σ)² dσ`` (L, h linear) has a closed form; across the quad, between its two
    rulings, the trapezoidal rule.

    Parameters
    ----------
    vertices : (k, p, 2n + 2, 3) float
    rigidity : float or (p, 2n + 2) float
        Plate bending stiffness ``D = Q̄11 t³ / 12`` (isotropic ``E t³ / 12 (1 - ν²)``), N m,
        one value or one per vertex (:meth:`compas_ccu.materials.Material.plate_rigidity` at
        the bending direction; the near vertex of every ruling is used).

    Examples
    --------
    A cylinder of radius 2 m, 1 m long, 0.5 m wide: E = D/2 κ² A = D/2 · 0.25 · 0.5.

    >>> phi = np.linspace(0.0, 0.5, 21)
    >>> ring = np.c_[2 * np.cos(phi), 2 * np.sin(phi), np.zeros_like(phi)]
    >>> plate = np.concatenate([ring, ring + [0.0, 0.0, 0.5]])[None, None]
    >>> round(float(bending_energy(plate, 100.0)[0]), 3)
    6.25

    A cone of half-angle θ between the distances ρ0 = 1 and ρ1 = 3 from its apex, over the
    azimuth Φ: ``D/2 cot²θ sinθ Φ ln(ρ1/ρ0)`` (κ = cot θ / ρ).

    >>> theta, az = np.radians(60.0), np.linspace(0.0, 1.0, 41)
    >>> s, c = np.sin(theta), np.cos(theta)
    >>> axis = np.c_[s * np.cos(az), s * np.sin(az), np.full(41, c)]
    >>> cone = np.concatenate([axis, 3.0 * axis])[None, None]
    >>> exact = 50.0 * np.cos(theta) ** 2 / np.sin(theta) * np.log(3.0)
    >>> round(float(bending_energy(cone, 100.0)[0] / exact), 3)  # 1.6e-4: the curvature's O(h²)
    1.0
    """
    v = np.asarray(vertices, dtype=float)
    return _energy(_ruling_lines(v), rigidity, v.shape)


def _ruling_lines(v: np.ndarray) -> tuple:
    """The integrals ``∫ L κ² dσ`` of every quad along its two rulings (the geometry's part of
    :func:`bending_energy`; the material's is the rigidity)."""
    n = v.shape[-2] // 2 - 1
    kappa = plate_curvature(v)
    near, far = v[..., : n + 1, :], v[..., n + 1 :, :]
    k_near, k_far = kappa[..., : n + 1], kappa[..., n + 1 :]
    # quad j: a = near j, b = near j+1, c = far j+1, d = far j; σ runs from near to far.
    # Its bilinear patch's area density on ruling j is |X_u(σ) × (d - a)|, X_u(σ) linear in σ
    # between the quad's near edge b - a and far edge c - d (and the same on ruling j + 1).
    edge_near, edge_far = near[..., 1:, :] - near[..., :-1, :], far[..., 1:, :] - far[..., :-1, :]
    ruling = far - near
    lines = []
    for side, r in ((slice(None, -1), ruling[..., :-1, :]), (slice(1, None), ruling[..., 1:, :])):
        l0 = np.linalg.norm(np.cross(edge_near, r), axis=-1)
        l1 = np.linalg.norm(np.cross(edge_far, r), axis=-1)
        lines.append(_ruling_integral(k_near[..., side], k_far[..., side], l0, l1))
    return tuple(lines)


def _energy(lines: tuple, rigidity, shape: tuple) -> np.ndarray:
    """(k,) bending energy of the plates from their :func:`_ruling_lines` and ``rigidity``."""
    n = shape[-2] // 2 - 1
    d = np.broadcast_to(np.asarray(rigidity, dtype=float), shape[:-1])[..., : n + 1]
    total = 0.0
    for side, line in zip((slice(None, -1), slice(1, None)), lines):
        total = total + 0.5 * (0.5 * d[..., side] * line)
    return total.sum(axis=(-1, -2))


def _ruling_integral(k0, k1, l0, l1):
    """``∫_0^1 (l0 (1 - σ) + l1 σ) κ(σ)² dσ`` along a ruling: 1/κ linear in σ where κ0 κ1 > 0
    (the developable law), κ linear elsewhere (a sign change or a zero: the flat stack)."""
    same = k0 * k1 > 0.0
    safe1 = np.where(same, k1, 1.0)
    x = np.where(same, k0 / safe1, 1.0) - 1.0  # κ(σ) = κ0 / (1 + x σ)
    phi2 = _phi2(x)  # ∫ σ / (1 + x σ)² dσ
    phi1 = 1.0 / (1.0 + x) - phi2  # ∫ (1 - σ) / (1 + x σ)² dσ
    harmonic = k0**2 * (l0 * phi1 + l1 * phi2)
    linear = l0 * (k0**2 / 4.0 + k0 * k1 / 6.0 + k1**2 / 12.0) + l1 * (
        k0**2 / 12.0 + k0 * k1 / 6.0 + k1**2 / 4.0
    )
    return np.where(same, harmonic, linear)


def _phi2(x):
    """``∫_0^1 σ / (1 + x σ)² dσ = (ln(1 + x) - x / (1 + x)) / x²`` (x > -1); its series
    ``Σ_{k >= 2} (-1)^k (k - 1)/k x^(k-2)`` for |x| < 0.01, where the closed form cancels."""
    x = np.asarray(x, dtype=float)
    small = np.abs(x) < 1e-2
    xs = np.where(small, 1.0, x)
    out = np.asarray((np.log1p(xs) - xs / (1.0 + xs)) / xs**2)
    if small.any():  # the series only where it is used (its powers are slow)
        t = x[small]
        out[small] = sum((-1) ** k * (k - 1) / k * t ** (k - 2) for k in range(2, 10))
    return out


def actuation_force(alphas, energy, span) -> np.ndarray:
    """(k,) ``F = dE/dα / (d span/dα)`` along a path (N; NaN at the flat stack, α = 0, and
    where the span stands still).

    >>> a = np.linspace(0.0, 30.0, 7)
    >>> f = actuation_force(a, 2.0 * a**2, 3.0 - 0.01 * a**2)  # E and span quadratic in α
    >>> np.round(f[1:], 9).tolist()
    [-200.0, -200.0, -200.0, -200.0, -200.0, -200.0]
    """
    a = np.radians(np.asarray(alphas, dtype=float))
    order = 2 if len(a) > 2 else 1
    de = np.gradient(np.asarray(energy, dtype=float), a, edge_order=order)
    ds = np.gradient(np.asarray(span, dtype=float), a, edge_order=order)
    # the flat stack: both derivatives vanish there (a 0/0 limit the one-sided differences
    # cannot resolve), and wherever the span stands still
    still = (np.abs(ds) <= ZERO_LENGTH * np.maximum(np.abs(np.asarray(span)), 1.0)) | (a <= 0.0)
    return np.where(still, np.nan, de / np.where(still, 1.0, ds))


def ring_tension(alphas, energy, length) -> np.ndarray:
    """(k,) ``T = -dE/dα / (dL/dα)``: the tension of a ring through the feet that holds them,
    N (negative: compression; NaN at the flat stack and where the ring's length stands
    still). The statics of :func:`actuation_force` with the ring in place of the tie across
    the span: a band of plan length ``L`` and tension ``T`` does the work ``-T dL``.

    Energy and length quadratic in α (radians), the energy growing as the ring opens:
    ``T = -4 α / (0.02 α) = -200`` N (compression) at every state.

    >>> a = np.linspace(0.0, 30.0, 7)
    >>> x = np.radians(a)
    >>> np.round(ring_tension(a, 2.0 * x**2, 3.0 + 0.01 * x**2)[1:], 9).tolist()
    [-200.0, -200.0, -200.0, -200.0, -200.0, -200.0]
    """
    return -actuation_force(alphas, energy, length)


def foot_ring(vertices, origin, axis, end: int) -> tuple:
    """The ring of feet of a radial layout: its plan length, the angle it spans, its radius.

    Every plate stands on its end ruling ``end`` (0 or ``n``: the row of crease vertex ``end``
    and its far vertex). Projected on the plane perpendicular to the axis, the ring's length
    ``L`` is the sum of the feet's lengths (a tie through the feet, corrugated as they stand),
    ``Θ`` the sum of the angles they span about the axis and ``R`` the mean distance of the
    feet's ends from it.

    Parameters
    ----------
    vertices : (k, p, 2n + 2, 3) float
        Deployed plates.
    origin, axis : (3,) float
        A point of the layout's axis and its direction.
    end : int
        The crease vertex of the feet, 0 or n.

    Returns
    -------
    length : (k,) float
        m.
    angle : (k,) float
        Radians.
    radius : (k,) float
        m.

    Examples
    --------
    Two plates whose feet are chords of a circle of radius 2 about the z axis, 45 deg each:

    >>> import math
    >>> phi = np.radians([0.0, 45.0, 90.0])
    >>> ring = np.c_[2.0 * np.cos(phi), 2.0 * np.sin(phi), np.zeros(3)]
    >>> top = 0.5 * ring + [0.0, 0.0, 1.0]
    >>> plates = np.array([[ring[0], top[0], ring[1], top[1]], [ring[1], top[1], ring[2],
    ...                     top[2]]])  # n = 1: near 0, 1 then far 0, 1
    >>> length, angle, radius = foot_ring(plates[None], np.zeros(3), [0.0, 0.0, 1.0], 0)
    >>> round(float(length[0]), 12), round(2 * 4.0 * math.sin(math.pi / 8), 12)  # 2 chords
    (3.061467458921, 3.061467458921)
    >>> round(float(np.degrees(angle[0])), 9), round(float(radius[0]), 12)
    (90.0, 2.0)
    """
    v = np.asarray(vertices, dtype=float)
    n = v.shape[-2] // 2 - 1
    e = np.asarray(axis, dtype=float)
    e = e / np.linalg.norm(e)

    def radial(p):  # the part perpendicular to the axis, from the axis
        d = p - np.asarray(origin, dtype=float)
        return d - (d @ e)[..., None] * e

    a, b = radial(v[..., end, :]), radial(v[..., n + 1 + end, :])
    angle = np.arctan2(np.abs(np.cross(a, b) @ e), np.einsum("...i,...i->...", a, b))
    radius = 0.5 * (np.linalg.norm(a, axis=-1) + np.linalg.norm(b, axis=-1)).mean(axis=-1)
    return np.linalg.norm(b - a, axis=-1).sum(axis=-1), angle.sum(axis=-1), radius


def radial_feet(model, vertices) -> tuple | None:
    """The axis and the feet of a radial layout: ``(origin, axis, end)`` for
    :func:`foot_ring`, or None for other layouts.

    The axis is the line every crease plane contains (world coordinates); the feet are the end
    rulings at the lower end of the creases (world z, at the last state of ``vertices``).
    """
    planes = model.planes
    if model.design.values["layout"]["type"] != "radial" or planes is None:
        return None
    # plane k holds the axis line x = axis, z = 0 of the leading frame: n . (axis, y, 0) = d
    k = int(np.argmax(np.abs(planes.normals[:, 0])))
    x = planes.offsets[k] / planes.normals[k, 0]
    origin, ahead = model.to_world(np.array([[x, 0.0, 0.0], [x, 1.0, 0.0]]))
    n = model.segments
    last = np.asarray(vertices, dtype=float)[-1]
    end = 0 if last[:, 0, 2].mean() <= last[:, n, 2].mean() else n
    return origin, ahead - origin, end


def path_actuation(thick, alphas=None) -> Actuation:
    """Bending energy and the force between the feet of ``thick`` (a
    :class:`compas_ccu.thickness.ThickModel`) at reference angles ``alphas`` (degrees; default:
    21 states from the flat stack to the design; :meth:`ThickModel.actuation`)."""
    if alphas is None:
        alphas = np.linspace(0.0, thick.model.alpha_design, 21)
    alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
    if len(alphas) < 2 or not np.all(np.diff(alphas) > 0.0):  # NaN fails too
        shown = np.round(alphas[:6], 6).tolist() + (["..."] if len(alphas) > 6 else [])
        raise OptionError(
            "the actuation force is dE/dα along a path: give at least 2 reference angles in "
            f"increasing order, got {shown}"
        )
    model = thick.model
    check_path(model, len(alphas))  # as CCUModel.path, whose vertices and spans these are
    limits = getattr(model, "limits", None)
    if limits is None:
        shape, lines, span, feet = _path_geometry(model, alphas)
    else:  # the geometry's part, kept per path for the models of one geometry (a new material)
        kept = limits.measure(("actuation_paths",), dict)
        key = alphas.tobytes()
        found = kept.get(key)
        if found is None:
            found = _path_geometry(model, alphas)
            if len(kept) >= ACTUATION_PATHS_KEPT:
                kept.clear()
            kept[key] = found
        shape, lines, span, feet = found
    angles = bending_angles(model.flat(), math.radians(thick.grain))
    rigidity = thick.material.plate_rigidity(thick.thickness, angles)
    energy = _energy(lines, rigidity, shape)
    feet = tuple(None if f is None else np.array(f) for f in feet)  # copies of the kept ones
    return Actuation(alphas, energy, span.copy(), actuation_force(alphas, energy, span), *feet)


def _path_geometry(model, alphas) -> tuple:
    """What :func:`path_actuation` measures on the zero-thickness path states: the shape of
    their vertices, the :func:`_ruling_lines`, the spans and the ring of feet."""
    states = model.mechanism.deploy(np.radians(alphas))
    vertices = np.array([model.state_vertices(states, k) for k in range(len(alphas))])
    span = np.array([leading_span(states, k) for k in range(len(alphas))])
    ring = radial_feet(model, vertices)
    feet = (None, None, None) if ring is None else foot_ring(vertices, *ring)
    return vertices.shape, _ruling_lines(vertices), span, feet
