"""The effort of deploying: the plates' bending energy and the force between the feet.

Deploying bends the plates; the work the actuators put in is stored as bending energy

    E(α) = Σ_plates D/2 ∫ κ² dA,    D = E t³ / 12 (1 − ν²)

(κ the principal curvature of the developable mid-surface, :func:`compas_ccu.strips.curvature.
plate_curvature`; the material's isotropic equivalent). Pushing the feet of a crease together
(or pulling them apart) by the quasi-static force F moves them by d span, so

    F(α) = dE/dα / (d span/dα)

is the force between the feet that holds the structure at α — the actuation force of a tie or a
jack across the span, without friction or self-weight. Negative: the feet must be pushed
together (the span shrinks as the plates bend). The FE deployment measures the same work as the
work of its supports (``validation.json`` ``load_path``; docs/structural.md compares the two).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.kinematics.plates import plate_quads
from compas_ccu.strips.curvature import plate_curvature

__all__ = ["bending_energy", "actuation_force", "Actuation"]


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
    """

    alphas: np.ndarray
    energy: np.ndarray
    span: np.ndarray
    force: np.ndarray

    @property
    def force_max(self) -> float:
        """The largest |force| along the path, N."""
        f = np.abs(self.force[np.isfinite(self.force)])
        return float(f.max()) if f.size else 0.0


def bending_energy(vertices: np.ndarray, rigidity: float) -> np.ndarray:
    """(k,) bending energy ``D/2 Σ κ² A`` of the plates of k kinematic states, J.

    Parameters
    ----------
    vertices : (k, p, 2n + 2, 3) float
    rigidity : float
        Plate bending stiffness ``D = E t³ / 12 (1 - ν²)``, N m.

    Examples
    --------
    A cylinder of radius 2 m, 1 m long, 0.5 m wide: E = D/2 κ² A = D/2 · 0.25 · 0.5.

    >>> phi = np.linspace(0.0, 0.5, 21)
    >>> ring = np.c_[2 * np.cos(phi), 2 * np.sin(phi), np.zeros_like(phi)]
    >>> plate = np.concatenate([ring, ring + [0.0, 0.0, 0.5]])[None, None]
    >>> round(float(bending_energy(plate, 100.0)[0]), 3)
    6.25
    """
    v = np.asarray(vertices, dtype=float)
    n = v.shape[-2] // 2 - 1
    kappa = plate_curvature(v)
    q = plate_quads(n)
    a, b, c, d = (v[..., q[:, i], :] for i in range(4))
    area = 0.5 * np.linalg.norm(np.cross(c - a, d - b), axis=-1)
    k2 = (kappa[..., q[:, 0]] ** 2 + kappa[..., q[:, 1]] ** 2) / 2.0
    k2 = (k2 + (kappa[..., q[:, 3]] ** 2 + kappa[..., q[:, 2]] ** 2) / 2.0) / 2.0
    return 0.5 * rigidity * (k2 * area).sum(axis=(-1, -2))


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
    still = (np.abs(ds) <= 1e-12 * np.maximum(np.abs(np.asarray(span)), 1.0)) | (a <= 0.0)
    return np.where(still, np.nan, de / np.where(still, 1.0, ds))
