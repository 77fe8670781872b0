"""Eurocode design values of the FE checks: design stiffness, creep, final deflection, k_mod.

The FE runs with the mean stiffness E_mean of the material (EN 1995-1-1 2.2.2(1)P: a first-order
analysis whose stiffness distribution does not change the internal forces). The checks turn its
results into design values (docs/structural.md, "Design values"):

=================================================  ==============================================
value                                              clause
=================================================  ==============================================
``f_d = k_mod f_k / γ_M``                          EN 1995-1-1 2.4.1(1)P, eq. (2.14)
``k_mod`` by service class and load duration       EN 1995-1-1 Table 3.1 (plywood, EN 636)
``k_mod`` of a combination: its shortest action    EN 1995-1-1 3.1.3(2)
``γ_M`` (plywood 1.2)                              EN 1995-1-1 Table 2.3
``k_def`` by service class (plywood 0.8/1.0/2.5)   EN 1995-1-1 Table 3.2
``E_d = E_mean / γ_M`` (stability)                 EN 1995-1-1 2.4.1(2)P, eq. (2.15)
``E_mean,fin = E_mean / (1 + ψ2 k_def)`` (ULS)     EN 1995-1-1 2.3.2.2(2), eq. (2.10)
``u_fin = u_G (1 + k_def) + u_Q (1 + ψ2 k_def)``   EN 1995-1-1 2.2.3(5), eq. (2.2)-(2.4)
``ψ2`` of the variable actions                     EN 1990 Table A1.1 (A2.1 for Q_c)
=================================================  ==============================================

**Buckling.** The linear buckling factor λ of the engine solves ``det(A + λ B) = 0`` with
``A = K_E + K_G(σ_prestress)`` and ``B`` the geometric stiffness of the loads
(:meth:`compas_ccu.fea.engines.kratos` ``buckling``). The elastic stiffness K_E and the active-
bending prestress of the displacement-controlled deployment are both proportional to E, the
stresses of the loads are not (all elements share one E): scaling E by ``r`` scales A by ``r``
and λ by ``r``. Hence ``λ_d = λ_mean E_d / E_mean`` exactly for that linearised problem, up to the
change of the loaded geometry (displacements ∝ 1/E, of the order of the deflection over the
span) and except for stiffnesses that do not scale with E (support and hinge springs, kept at
their given values). With creep, ``E_d = E_mean / (γ_M (1 + ψ2 k_def))``: 2.3.2.2(2) takes ψ2
of the action causing the largest stress in relation to strength, ψ2 = 1 if it is permanent.
A CCU structure carries its active bending, a permanent action, for its whole life; the check
compares the deployed state's stress over the permanent design strength with the stress the
case adds over the case's design strength (:func:`creep_psi2`); no split of the load itself is
used (λ multiplies all loads of the case together).

**Aluminium** (EN 1999-1-1): no creep at ambient temperature (k_def = 0), no load-duration factor
(k_mod = 1), γ_M1 = 1.1 (6.1.3). Its strength is the elastic limit ``f_o / γ_M1`` (0.2 % proof
strength), not the plastic resistance ``W_pl f_o / γ_M1`` of a class 1 or 2 section (6.2.5.1):
an actively bent sheet must spring back without a permanent set, so its outer fibre stays
elastic. The buckling factor takes ``E / γ_M1`` (a choice: EN 1999-1-1 puts γ_M1 on the
member's instability resistance; the reduction χ of 6.3 is not applied). GFRP and kind
``other``: no code table; creep only with a given ``k_def``.

>>> round(design_modulus(9.0e9, 1.2) / 1e9, 3), round(design_modulus(9.0e9, 1.2, 0.8, 1.0) / 1e9, 4)
(7.5, 4.1667)
>>> final_deflection(1.0, 0.0, k_def=0.8, psi2=0.0)
1.8
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.fea.problem import FEError
from compas_ccu.materials import (
    ACTION_DURATIONS,
    K_DEF_PLYWOOD,
    LOAD_DURATIONS,
    k_mod_plywood,
)

__all__ = [
    "CLAUSES",
    "PSI_2",
    "StiffnessBasis",
    "action_duration",
    "clauses",
    "combination_duration",
    "creep_psi2",
    "design_buckling_factor",
    "design_modulus",
    "final_deflection",
    "k_def",
    "k_mod",
]

#: Where every factor and formula of the plywood checks comes from.
CLAUSES = {
    "f_d": "EN 1995-1-1 2.4.1(1)P, eq. (2.14)",
    "k_mod": "EN 1995-1-1 Table 3.1, shortest action 3.1.3(2)",
    "gamma_M": "EN 1995-1-1 Table 2.3",
    "k_def": "EN 1995-1-1 Table 3.2",
    "E_d": "EN 1995-1-1 2.4.1(2)P, eq. (2.15)",
    "E_fin": "EN 1995-1-1 2.3.2.2(2), eq. (2.10)",
    "u_fin": "EN 1995-1-1 2.2.3(5), eq. (2.2)-(2.4)",
    "psi2": "EN 1990 Table A1.1 (construction loads: A2.1)",
}

#: The same for aluminium (EN 1999-1-1): see the module's docstring for the choices.
_ALUMINIUM = {
    "f_d": "f_o / gamma_M1, elastic limit (EN 1999-1-1 6.2.5.1)",
    "k_mod": "1: no load-duration factor (EN 1999-1-1)",
    "gamma_M": "EN 1999-1-1 6.1.3 (gamma_M1)",
    "k_def": "0: no creep at ambient temperature (EN 1999-1-1)",
    "E_d": "E / gamma_M1 (gamma_M1 of instability, EN 1999-1-1 6.1.3)",
    "E_fin": "no creep",
    "u_fin": "u_fin = u_inst (no creep)",
    "psi2": "EN 1990 Table A1.1",
}

#: ψ2 (quasi-permanent factor) of every variable action of :mod:`compas_ccu.fea.loads`, by
#: its ``[loads]`` key, with its source. Snow H <= 1000 m a.s.l. (0.2 above: give the action
#: as permanent-like with a longer duration if it lies long), wind and a roof's imposed load
#: (category H) are 0 (EN 1990 Table A1.1); the wet concrete and the construction load are
#: construction loads Q_c, taken as quasi-permanent, ψ2 = 1.0 (EN 1990 Table A2.1; Annex A1
#: gives none for buildings: the conservative choice).
PSI_2 = {
    "concrete": (1.0, "construction load Q_c, EN 1990 Table A2.1"),
    "live": (1.0, "construction load Q_c, EN 1990 Table A2.1"),
    "snow": (0.0, "snow, H <= 1000 m, EN 1990 Table A1.1"),
    "wind": (0.0, "wind, EN 1990 Table A1.1"),
    "area": (0.0, "roof imposed load, category H, EN 1990 Table A1.1"),
}


def clauses(kind: str) -> dict:
    """The clause of every factor for a material ``kind`` (:data:`CLAUSES`; aluminium's own): the
    ``clauses`` section :meth:`StiffnessBasis.to_dict` writes into ``validation.json``."""
    return dict(_ALUMINIUM) if kind == "aluminium" else dict(CLAUSES)


def action_duration(action: str, loads) -> str:
    """The load-duration class of the variable ``action`` of a ``[loads]`` mapping.

    ``loads[action + "_duration"]`` if given, else the EN default of
    :data:`compas_ccu.materials.ACTION_DURATIONS`.

    >>> action_duration("snow", {}), action_duration("snow", {"snow_duration": "medium-term"})
    ('short-term', 'medium-term')
    """
    if action not in ACTION_DURATIONS:
        raise FEError(f"no load-duration class for action {action!r}: {sorted(ACTION_DURATIONS)}")
    default, allowed = ACTION_DURATIONS[action]
    key = f"{action}_duration"
    value = (loads or {}).get(key) or default
    if value not in allowed:
        raise FEError(
            f"loads.{key} must be one of {', '.join(repr(c) for c in allowed)}, got {value!r}"
        )
    return value


def combination_duration(durations) -> str:
    """The load-duration class of a combination: that of its shortest action (3.1.3(2)).

    >>> combination_duration(["permanent", "short-term", "medium-term"])
    'short-term'
    """
    durations = list(durations)
    bad = [d for d in durations if d not in LOAD_DURATIONS]
    if bad or not durations:
        raise FEError(
            f"load duration must be one of {', '.join(LOAD_DURATIONS)}, got "
            f"{(bad[0] if bad else durations)!r}"
        )
    return max(durations, key=LOAD_DURATIONS.index)


def k_mod(kind: str, service_class: int, durations) -> float:
    """k_mod of a combination of actions of ``durations`` (Table 3.1 and 3.1.3(2)).

    Plywood: :func:`compas_ccu.materials.k_mod_plywood` of the shortest duration; aluminium 1.

    >>> k_mod("plywood", 1, ["permanent", "short-term"]), k_mod("plywood", 3, ["permanent"])
    (0.9, 0.5)
    """
    duration = combination_duration(durations)
    if kind == "plywood":
        return k_mod_plywood(service_class, duration)
    if kind == "aluminium":
        return 1.0
    raise FEError(f"no k_mod table for material kind {kind!r}: give design_code.k_mod")


def k_def(kind: str, service_class: int) -> float | None:
    """k_def by material kind and service class (Table 3.2); aluminium 0; None if unknown.

    >>> k_def("plywood", 2), k_def("aluminium", 1), k_def("gfrp", 1)
    (1.0, 0.0, None)
    """
    if service_class not in K_DEF_PLYWOOD:
        raise FEError(f"service class must be 1, 2 or 3, got {service_class!r}")
    return {"plywood": K_DEF_PLYWOOD[service_class], "aluminium": 0.0}.get(kind)


def design_modulus(E_mean, gamma_M: float, k_def: float = 0.0, psi2: float = 0.0):
    """Design stiffness ``E_mean / (γ_M (1 + ψ2 k_def))`` (2.4.1(2)P with 2.3.2.2(2)).

    ``k_def = 0`` (or ``psi2 = 0``): the instantaneous ``E_d = E_mean / γ_M``. Scalars or
    arrays of any shape.
    """
    _positive("gamma_M", gamma_M)
    _non_negative("k_def", k_def)
    _non_negative("psi2", psi2)
    out = np.asarray(E_mean, dtype=float) / (gamma_M * (1.0 + psi2 * k_def))
    return float(out) if out.ndim == 0 else out


def design_buckling_factor(factor, gamma_M: float, k_def: float = 0.0, psi2: float = 0.0):
    """``λ_d = λ_mean E_d / E_mean`` (the linear buckling factor is linear in E).

    None (no buckling analysis) stays None, infinity (no buckling) stays infinity.

    >>> design_buckling_factor(9.0, 1.2), design_buckling_factor(None, 1.2)
    (7.5, None)
    """
    if factor is None:
        return None
    return float(design_modulus(float(factor), gamma_M, k_def, psi2))


def final_deflection(u_G, u_Q, k_def: float, psi2: float):
    """``u_fin = u_inst,G (1 + k_def) + u_inst,Q (1 + ψ2 k_def)`` (2.2.3(5), eq. (2.2)-(2.4)).

    Parameters
    ----------
    u_G, u_Q : float or (..., 3) float
        Instantaneous deflection of the permanent and of the (leading) variable actions, m;
        displacement vectors add as vectors.
    k_def : float
    psi2 : float
        ψ2 of the variable action.

    Returns
    -------
    float or (..., 3) float
    """
    _non_negative("k_def", k_def)
    _non_negative("psi2", psi2)
    out = np.asarray(u_G, dtype=float) * (1.0 + k_def) + np.asarray(u_Q, dtype=float) * (
        1.0 + psi2 * k_def
    )
    return float(out) if out.ndim == 0 else out


def creep_psi2(permanent_ratio: float, variable_ratio: float, psi2_variable: float) -> float:
    """ψ2 of 2.3.2.2(2): that of the action causing the largest stress in relation to strength.

    ``permanent_ratio``: the permanent stress over its design strength; ``variable_ratio``:
    the variable one over its. A permanent action has ψ2 = 1.

    >>> creep_psi2(1.15, 0.04, 0.0), creep_psi2(0.1, 0.5, 0.0)
    (1.0, 0.0)
    """
    return 1.0 if permanent_ratio >= variable_ratio else float(psi2_variable)


@dataclass(frozen=True)
class StiffnessBasis:
    """The design stiffness of a case's stability and deflection checks.

    Attributes
    ----------
    kind : str
        Material kind (:data:`compas_ccu.materials.MATERIAL_KINDS`).
    gamma_M : float
        1 for the characteristic basis.
    k_def : float or None
        None: unknown (gfrp, other without ``design_code.k_def``): no final values.
    psi2 : float
        ψ2 of the creep of the stability check (:func:`creep_psi2`).
    governing : str
        ``"permanent"`` or ``"variable"``: which action decided ψ2.
    """

    kind: str
    gamma_M: float
    k_def: float | None
    psi2: float = 1.0
    governing: str = "permanent"

    @property
    def instantaneous(self) -> float:
        """``E_d / E_mean = 1 / γ_M``."""
        return design_modulus(1.0, self.gamma_M)

    @property
    def final(self) -> float | None:
        """``E_d,fin / E_mean = 1 / (γ_M (1 + ψ2 k_def))``; None without k_def."""
        if self.k_def is None:
            return None
        return design_modulus(1.0, self.gamma_M, self.k_def, self.psi2)

    def text(self) -> str:
        """One line with every factor and its clause (console, report)."""
        c = clauses(self.kind)
        line = (
            f"buckling with E_d = E_mean / gamma_M ({c['E_d']}), gamma_M {self.gamma_M:g} "
            f"({c['gamma_M']})"
        )
        if self.k_def is None:
            return line + "; creep not included: no k_def for this material (design_code.k_def)"
        return line + (
            f"; with creep E_mean / (gamma_M (1 + psi2 k_def)) ({c['E_fin']}), k_def "
            f"{self.k_def:g} ({c['k_def']}), psi2 {self.psi2:g} (the {self.governing} action "
            f"governs); deflection u_fin = u_G (1 + k_def) + u_Q (1 + psi2 k_def) ({c['u_fin']})"
        )

    def to_dict(self) -> dict:
        return {
            "kind": self.kind,
            "gamma_M": self.gamma_M,
            "k_def": self.k_def,
            "psi2": self.psi2,
            "governing": self.governing,
            "E_d_over_E_mean": self.instantaneous,
            "E_d_fin_over_E_mean": self.final,
            "clauses": clauses(self.kind),
            "text": self.text(),
        }


def _positive(name: str, value) -> None:
    if not (isinstance(value, (int, float)) and np.isfinite(value) and value > 0.0):
        raise FEError(f"{name} must be > 0, got {value!r}")


def _non_negative(name: str, value) -> None:
    if not (isinstance(value, (int, float)) and np.isfinite(value) and value >= 0.0):
        raise FEError(f"{name} must be >= 0, got {value!r}")
