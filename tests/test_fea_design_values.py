"""Eurocode design values of the FE checks (compas_ccu.fea.design_values), in closed form:
the design stiffness of a buckling check, the final deflection with creep, k_mod of a
combination, the load-duration classes of the design file."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.design import Design
from compas_ccu.errors import DesignError
from compas_ccu.fea.design_values import (
    CLAUSES,
    PSI_2,
    StiffnessBasis,
    action_duration,
    combination_duration,
    creep_psi2,
    design_buckling_factor,
    design_modulus,
    final_deflection,
    k_def,
    k_mod,
)
from compas_ccu.fea.loads import load_cases
from compas_ccu.fea.problem import FEError
from compas_ccu.materials import K_DEF_PLYWOOD, design_factors, material

E, INERTIA, L, P = 9.0e9, 1.0e-3 * 0.008**3 / 12.0, 0.5, 10.0  # an 8 mm plywood strip 1 mm wide


def strut_buckling_factor(E_mean: float, prestress_per_E: float = 0.0, n: int = 400) -> float:
    """Smallest λ of a pinned strut by finite differences: (EI D2 + N) w = λ P w.

    D2 is the (SPD) matrix of -w'' with w = 0 at both ends: the pinned strut's
    (EI D2² + N D2) w = λ P D2 w divided by D2. ``N = prestress_per_E × E`` is a tension
    prestress that scales with E (the active bending of a displacement-controlled deployment
    does). Closed form: λ P = π² EI / L² + N (plus the O(h²) of the differences).
    """
    h = L / (n + 1)
    d2 = (2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)) / h**2
    a = E_mean * INERTIA * d2 + prestress_per_E * E_mean * np.eye(n)
    return float(np.linalg.eigvalsh(a).min() / P)


def test_euler_strut_with_the_design_stiffness():
    """P_cr,d = π² E_d INERTIA / L² with E_d = E_mean / γ_M (EN 1995-1-1 2.4.1(2)P)."""
    assert design_modulus(E, 1.2) == pytest.approx(7.5e9, rel=1e-15)
    euler_mean = math.pi**2 * E * INERTIA / L**2 / P
    euler_d = math.pi**2 * 7.5e9 * INERTIA / L**2 / P
    assert strut_buckling_factor(E) == pytest.approx(euler_mean, rel=1e-5)  # h² convergence
    assert design_buckling_factor(euler_mean, 1.2) == pytest.approx(euler_d, rel=1e-14)
    # λ_d = λ_mean E_d / E_mean: the FE eigenproblem with E_d gives the same factor
    assert strut_buckling_factor(7.5e9) == pytest.approx(
        design_buckling_factor(strut_buckling_factor(E), 1.2), rel=1e-9
    )


def test_the_buckling_factor_is_linear_in_E_with_a_prestress_that_scales_with_E():
    """The deployment's prestress is ∝ E: λ still scales with E (the module's claim)."""
    c = 1.0e-9  # N = 9 N at E_mean
    mean = strut_buckling_factor(E, c)
    assert mean * P == pytest.approx(math.pi**2 * E * INERTIA / L**2 + c * E, rel=1e-5)
    # creep of the permanent part: E_mean / (γ_M (1 + ψ2 k_def)), ψ2 = 1, k_def 0.8 (SC1)
    fin = E / (1.2 * 1.8)
    assert design_modulus(E, 1.2, 0.8, 1.0) == pytest.approx(fin, rel=1e-15)
    assert strut_buckling_factor(fin, c) == pytest.approx(
        design_buckling_factor(mean, 1.2, 0.8, 1.0), rel=1e-9
    )
    # a prestress that did not scale with E would break it: the claim can fail
    fixed = strut_buckling_factor(fin, c * E / fin)
    assert fixed / design_buckling_factor(mean, 1.2, 0.8, 1.0) > 1.0 + 1e-3


def test_final_deflection_of_a_permanent_load_is_the_instantaneous_times_1_plus_k_def():
    """u_fin,G = u_inst,G (1 + k_def) (EN 1995-1-1 2.2.3(5), eq. 2.3): the simply supported
    beam under its self-weight, 5 q L⁴ / 384 EI, with E_mean,fin = E_mean / (1 + k_def)."""
    q = 600.0 * 9.81 * 0.008 * 1e-3  # N/m of the strip
    for kd in K_DEF_PLYWOOD.values():
        inst = 5.0 * q * L**4 / (384.0 * E * INERTIA)
        crept = 5.0 * q * L**4 / (384.0 * (E / (1.0 + kd)) * INERTIA)
        assert final_deflection(inst, 0.0, kd, 0.0) == pytest.approx(crept, rel=1e-14)
        assert final_deflection(inst, 0.0, kd, 0.0) == pytest.approx(inst * (1.0 + kd), rel=1e-15)
    u = np.array([[0.0, 0.0, -1e-3], [2e-4, 0.0, -5e-4]])  # node displacement vectors
    np.testing.assert_allclose(final_deflection(u, np.zeros_like(u), 0.8, 0.0), 1.8 * u)


def test_final_deflection_of_a_variable_load_takes_its_psi2():
    # snow (ψ2 = 0, EN 1990 Table A1.1): no creep; construction loads (ψ2 = 1): full creep
    assert PSI_2["snow"][0] == 0.0 and PSI_2["wind"][0] == 0.0 and PSI_2["concrete"][0] == 1.0
    assert final_deflection(1e-3, 4e-3, 0.8, 0.0) == pytest.approx(1.8e-3 + 4e-3, rel=1e-15)
    assert final_deflection(1e-3, 4e-3, 0.8, 1.0) == pytest.approx(1.8e-3 * 5.0, rel=1e-15)
    assert final_deflection(1e-3, 4e-3, 0.0, 1.0) == pytest.approx(5e-3, rel=1e-15)  # aluminium


def test_k_mod_of_a_combination_is_that_of_its_shortest_action():
    """EN 1995-1-1 3.1.3(2) with Table 3.1."""
    assert combination_duration(["permanent", "medium-term", "short-term"]) == "short-term"
    assert k_mod("plywood", 1, ["permanent"]) == 0.6
    assert k_mod("plywood", 1, ["permanent", "medium-term"]) == 0.8
    assert k_mod("plywood", 2, ["permanent", "short-term"]) == 0.9
    assert k_mod("plywood", 3, ["permanent", "instantaneous"]) == 0.9
    assert k_mod("aluminium", 1, ["permanent"]) == 1.0
    assert (k_def("plywood", 1), k_def("plywood", 3), k_def("aluminium", 2)) == (0.8, 2.5, 0.0)
    assert k_def("gfrp", 1) is None


def test_snow_is_short_term_unless_the_design_says_medium_term():
    loads = {"snow": 800.0, "wind": -300.0}
    by = {c.name: c for c in load_cases(loads, self_weight=47.1)}
    assert (by["snow"].duration, by["wind"].duration) == ("short-term", "instantaneous")
    by = {
        c.name: c for c in load_cases({**loads, "snow_duration": "medium-term"}, self_weight=47.1)
    }
    assert (by["snow"].duration, by["snow-half"].duration) == ("medium-term", "medium-term")
    assert by["self-weight"].duration == "permanent" and by["self-weight"].psi2 is None
    f = design_factors(material("plywood"), load_duration=by["snow"].duration)
    assert f.k_mod * 30.0 / f.gamma_M == pytest.approx(20.0, rel=1e-15)  # f_d, MPa
    assert by["snow"].to_dict()["actions"][1]["duration"] == "medium-term"


@pytest.mark.parametrize(
    "call, message",
    [
        (
            lambda: action_duration("snow", {"snow_duration": "medium"}),
            "loads.snow_duration must be one of 'medium-term', 'short-term', got 'medium'",
        ),
        (
            lambda: load_cases({"wind_duration": "permanent"}, self_weight=47.1),
            "loads.wind_duration must be one of 'short-term', 'instantaneous', got 'permanent'",
        ),
        (
            lambda: combination_duration(["permanent", "weekly"]),
            "load duration must be one of permanent, .*, got 'weekly'",
        ),
        (lambda: k_mod("gfrp", 1, ["permanent"]), "no k_mod table for material kind 'gfrp'"),
        (lambda: k_def("plywood", 4), "service class must be 1, 2 or 3, got 4"),
        (lambda: design_modulus(E, 0.0), "gamma_M must be > 0, got 0.0"),
        (lambda: final_deflection(1e-3, 0.0, -0.8, 0.0), "k_def must be >= 0, got -0.8"),
    ],
)
def test_bad_classes_and_factors_are_refused_with_the_value(call, message):
    with pytest.raises(FEError, match=message):
        call()


BASE = {
    "crease": {"profile": "arc", "span": 2.0, "rise": 0.6},
    "rulings": {"type": "orthogonal"},
    "deployment": {"alpha": 30.0},
    "layout": {"width": 0.3},
}


def test_the_design_file_names_the_bad_duration():
    d = Design({**BASE, "loads": {"snow": 800.0, "snow_duration": "medium-term"}})
    assert d.loads.to_dict()["snow_duration"] == "medium-term"
    assert d.loads.to_dict()["wind_duration"] == "instantaneous"  # the default
    with pytest.raises(
        DesignError,
        match=r"loads\.snow_duration: must be one of 'medium-term', 'short-term'"
        r", got 'medium'",
    ):
        Design({**BASE, "loads": {"snow_duration": "medium"}})


def test_creep_takes_psi2_of_the_action_with_the_largest_stress_over_strength():
    """EN 1995-1-1 2.3.2.2(2): ψ2 = 1 when the permanent action (the active bending) governs."""
    assert creep_psi2(17.3 / 15.0, 0.9 / 22.5, 0.0) == 1.0  # the vault: the prestress governs
    assert creep_psi2(0.1, 0.5, 0.0) == 0.0
    basis = StiffnessBasis("plywood", 1.2, 0.8, 1.0, "permanent")
    assert basis.instantaneous == pytest.approx(1.0 / 1.2, rel=1e-15)
    assert basis.final == pytest.approx(1.0 / (1.2 * 1.8), rel=1e-15)
    text = basis.text()
    for clause in ("E_d", "gamma_M", "E_fin", "k_def", "u_fin"):
        assert CLAUSES[clause] in text
    alu = StiffnessBasis("aluminium", 1.1, 0.0, 1.0)
    assert alu.final == alu.instantaneous == pytest.approx(1.0 / 1.1, rel=1e-15)
    assert "EN 1999-1-1 6.1.3" in alu.text() and "no creep" in alu.text()
    unknown = StiffnessBasis("gfrp", 1.3, None)
    assert unknown.final is None and "creep not included" in unknown.text()
    assert unknown.to_dict()["E_d_fin_over_E_mean"] is None
