"""Bending check of bending-active plates: κ ≤ f / (Q̄11 · t/2) (plate theory; paper §5.3).

A developable plate bends across its rulings only: the curvature tensor at a ruling is
``κ n ⊗ n`` with ``n`` the bending direction (normal to the ruling in the cut pattern), with no
curvature along the ruling and no twist. A wide plate cannot contract across the bend (that
would curve it anticlastically, and the kinematics hold the rulings straight), so the
outer-fibre stress is the plate stress, not the beam's ``E κ t/2``:

    σ = Q̄11(φ) κ t/2,   Q̄11 = E / (1 - ν²) for isotropic plates

with κ the principal curvature (:func:`compas_ccu.strips.curvature.plate_curvature`) and
``Q̄11(φ)`` the reduced stiffness of the plate along the bending direction at the angle φ to
the material's direction 1, the face grain (:meth:`compas_ccu.materials.Material.plate_modulus`;
docs/thickness.md derives it, Timoshenko & Woinowsky-Krieger §1-2). The utilisation is

    u = |κ| / κ_lim(φ),   κ_lim(φ) = f(φ) / (Q̄11(φ) t / 2)

with Hankinson's off-axis strength ``f(φ)``. The beam formula (Lienhard 2014) gives a stress
``1 - ν²`` (9 % for ν = 0.3) lower: on the cone the FE's peak bending stress is 20.2 MPa, the
beam formula's 18.9 MPa, this check's 20.8 MPa (tests/test_thickness_bending_fe.py).

The strength is the design strength ``f_d = k_mod f_k / γ_M`` of the given
:class:`compas_ccu.materials.DesignFactors` (docs/thickness.md, "Design values"), or the
characteristic strength ``f_k`` (no factors, or the characteristic basis): the characteristic
limit is computed first and multiplied by ``k_mod / γ_M``, which is exactly 1 for the
characteristic basis, so those numbers are the same bit for bit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from compas_ccu.kinematics.plates import stack_rows
from compas_ccu.materials import DesignFactors
from compas_ccu.strips.curvature import plate_curvature

__all__ = [
    "BendingCheck",
    "bending_check",
    "bending_angles",
    "bending_verdict",
    "path_bending",
    "path_curvature",
    "curvature_check",
    "CURVATURE_KEPT",
]

#: Placed states whose curvature a model keeps per thickness (:func:`path_curvature`).
CURVATURE_KEPT = 256


class BendingCheck(NamedTuple):
    """Bending utilisation of every plate in ``k`` states.

    Attributes
    ----------
    curvature : (k, p, 2n + 2) float
        Signed principal curvature at every vertex, 1/m.
    limit : (p, 2n + 2) float
        Curvature limit at every vertex (depends on the bending direction to the grain), 1/m:
        with the design strength ``k_mod f_k / γ_M`` of ``factors``.
    utilisation : (k, p, 2n + 2) float
        ``|κ| / κ_lim``.
    factors : compas_ccu.materials.DesignFactors
        The basis: code, service class, load duration, k_mod, γ_M, k_def.
    limit_characteristic : (p, 2n + 2) float
        The curvature limit with the characteristic strength ``f_k``, 1/m.
    """

    curvature: np.ndarray
    limit: np.ndarray
    utilisation: np.ndarray
    factors: DesignFactors = DesignFactors()
    limit_characteristic: np.ndarray | None = None

    @property
    def utilisation_characteristic(self) -> np.ndarray:
        """(k, p, 2n + 2) ``|κ| / κ_lim`` with the characteristic strength."""
        if self.limit_characteristic is None:
            return self.utilisation
        return np.abs(self.curvature) / self.limit_characteristic[None]

    @property
    def max_characteristic(self) -> float:
        return float(self.utilisation_characteristic.max())

    @property
    def per_plate(self) -> np.ndarray:
        """(k, p) largest utilisation of every plate in every state."""
        return self.utilisation.max(axis=2)

    @property
    def max(self) -> float:
        return float(self.utilisation.max())

    def worst(self) -> tuple:
        """(state, plate, vertex) of the largest utilisation."""
        u = self.utilisation
        return tuple(int(i) for i in np.unravel_index(u.argmax(), u.shape))


def bending_angles(flat, grain: float) -> np.ndarray:
    """(p, 2n + 2) angle φ (radians) between the bending direction and the grain at every vertex.

    Parameters
    ----------
    flat : (p, 2n + 2, 2 or 3) float
        Cut patterns (plane coordinates).
    grain : float
        Grain direction in the cut patterns, radians from the x axis.
    """
    flat = np.asarray(flat, dtype=float)
    n = flat.shape[1] // 2 - 1
    ruling = flat[:, n + 1 :, :2] - flat[:, : n + 1, :2]
    # bending direction: normal to the ruling in the pattern
    bend = np.arctan2(ruling[..., 0], -ruling[..., 1])
    phi = np.mod(bend - grain, np.pi)
    return np.concatenate([phi, phi], axis=1)


def bending_check(
    vertices, flat, thickness: float, material, *, grain: float = 0.0, factors=None
) -> BendingCheck:
    """Curvature against the material's limit at every vertex of every plate and state.

    Parameters
    ----------
    vertices : (k, p, 2n + 2, 3) float
        Deployed mid-surfaces.
    flat : (p, 2n + 2, 2 or 3) float
        Their cut patterns.
    thickness : float
        m.
    material : compas_ccu.materials.Material
    grain : float
        Grain direction in the cut patterns, radians from the x axis.
    factors : compas_ccu.materials.DesignFactors, optional
        The design factors (:func:`compas_ccu.materials.design_factors`); default: the
        characteristic strengths.

    Returns
    -------
    BendingCheck

    Examples
    --------
    A cylinder of radius 2 m in 8 mm plywood (E 9 GPa, ν 0.3, f 30 MPa): κ = 0.5 1/m against
    the limit 30e6 · (1 - 0.3²) / (9e9 · 0.004) = 0.7583 1/m, utilisation 0.659.

    >>> import numpy as np
    >>> from compas_ccu.materials import material
    >>> phi = np.linspace(0.0, 1.0, 41)
    >>> ring = np.c_[2 * np.cos(phi), 2 * np.sin(phi), np.zeros_like(phi)]
    >>> plate = np.concatenate([ring, ring + [0.0, 0.0, 0.5]])[None, None]
    >>> flat = np.concatenate([np.c_[2 * phi, 0 * phi], np.c_[2 * phi, 0 * phi + 0.5]])[None]
    >>> check = bending_check(plate, flat, 0.008, material("plywood"))
    >>> round(check.max, 3)
    0.659

    With the design strength for a permanent action in service class 1 (k_mod 0.6, γ_M 1.2),
    f_d = 15 MPa and the utilisation doubles: 0.659 · 1.2 / 0.6 = 1.319.

    >>> from compas_ccu.materials import design_factors
    >>> check = bending_check(plate, flat, 0.008, material("plywood"),
    ...                       factors=design_factors("plywood"))
    >>> round(check.max, 3), round(check.max_characteristic, 3), check.factors.label
    (1.319, 0.659, 'EC5 SC1 permanent')
    """
    return curvature_check(plate_curvature(vertices), flat, thickness, material, grain, factors)


def curvature_check(kappa, flat, thickness, material, grain=0.0, factors=None) -> BendingCheck:
    """:func:`bending_check` of the principal curvature ``kappa`` (k, p, 2n + 2) of the
    deployed mid-surfaces (:func:`compas_ccu.strips.curvature.plate_curvature`)."""
    if factors is None:
        factors = DesignFactors()
    characteristic = material.curvature_limit_at(thickness, bending_angles(flat, grain))
    limit = characteristic * factors.strength_factor
    return BendingCheck(kappa, limit, np.abs(kappa) / limit[None], factors, characteristic)


def bending_verdict(exceeded: bool, basis: dict) -> str:
    """What an exceeded (or passed) bending check means on its basis, in words: above the
    characteristic strength the plates would break; above the design strength the check of the
    code fails (``ccu info``, the report, ``ccu fabricate`` and the studio say the same).

    >>> bending_verdict(True, {"code": "EC5", "service_class": 1, "load_duration": "permanent"})
    'EXCEEDED: above the design bending strength (EC5 SC1 permanent)'
    >>> bending_verdict(True, {"code": "characteristic"})
    'EXCEEDED: above the characteristic bending strength: the plates would break'
    """
    if not exceeded:
        return "within the limit"
    if basis.get("code", "characteristic") == "characteristic":
        return "EXCEEDED: above the characteristic bending strength: the plates would break"
    label = f"{basis['code']} SC{basis['service_class']} {basis['load_duration']}"
    return f"EXCEEDED: above the design bending strength ({label})"


def path_curvature(thick, alphas) -> np.ndarray:
    """(k, p, 2n + 2) principal curvature of the thick plates' mid-surfaces at reference angles
    ``alphas`` (degrees), plates in id order.

    The curvature of a state depends on the placed geometry, the thickness and the hinge sides
    only (not the material), and every state is placed and measured on its own (the vectorised
    placement gives a state the same numbers in any batch), so the model keeps the curvature of
    the last :data:`CURVATURE_KEPT` angles per thickness in :attr:`CCUModel.limits` (shared by
    the models of one geometry: a new material measures nothing again) and places only the
    angles it has not seen: the key figures' path states and the studio's checks panel (the
    same angles from the flat stack, computed the other way round) are placed once.
    """
    alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
    limits = getattr(thick.model, "limits", None)
    keys = [a.tobytes() for a in alphas]
    kept = {} if limits is None else limits.measure(_curvature_key(thick), dict)
    found = {k: row for k in keys if (row := kept.get(k)) is not None}
    missing = [k for k in dict.fromkeys(keys) if k not in found]
    if missing or not keys:
        angles = np.frombuffer(b"".join(missing), dtype=float).copy()
        st = thick.place(angles)
        mid = thick.model.plates.to_output(stack_rows(st.near, st.far), axis=1)
        kappa = plate_curvature(mid)
        if len(kept) + len(missing) > CURVATURE_KEPT:
            kept.clear()
        if not keys:
            return kappa
        for k, row in zip(missing, kappa):
            found[k] = kept[k] = row
    return np.stack([found[k] for k in keys])


def _curvature_key(thick) -> tuple:
    sides = np.ascontiguousarray(thick.sides, dtype=float).tobytes()
    return ("thick_curvature", float(thick.thickness), sides)


def path_bending(thick, alphas=None) -> BendingCheck:
    """The bending check of ``thick`` (a :class:`compas_ccu.thickness.ThickModel`) at
    reference angles ``alphas`` (degrees; default: 21 states from the flat stack to the design),
    plates in id order (:meth:`ThickModel.bending`; the curvature of :func:`path_curvature`)."""
    if alphas is None:
        alphas = np.linspace(0.0, thick.model.alpha_design, 21)
    return curvature_check(
        path_curvature(thick, alphas),
        thick.model.flat(),
        thick.thickness,
        thick.material,
        grain=math.radians(thick.grain),
        factors=thick.factors,
    )
