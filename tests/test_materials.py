"""The material library and the design factors (EN 1995-1-1 k_mod, gamma_M, k_def)."""

from __future__ import annotations

import pytest

from compas_ccu.materials import (
    GAMMA_M,
    K_DEF_PLYWOOD,
    LOAD_DURATIONS,
    MATERIALS,
    DesignFactors,
    Material,
    MaterialError,
    design_factors,
    k_mod_plywood,
    material,
)

#: EN 1995-1-1 Table 3.1, plywood EN 636 (docs/thickness.md, "Design values").
TABLE_3_1 = {
    1: [0.60, 0.70, 0.80, 0.90, 1.10],
    2: [0.60, 0.70, 0.80, 0.90, 1.10],
    3: [0.50, 0.55, 0.65, 0.70, 0.90],
}


@pytest.mark.parametrize("service_class", [1, 2, 3])
def test_k_mod_table_of_plywood(service_class):
    got = [k_mod_plywood(service_class, d) for d in LOAD_DURATIONS]
    assert got == TABLE_3_1[service_class]
    assert LOAD_DURATIONS == (
        "permanent",
        "long-term",
        "medium-term",
        "short-term",
        "instantaneous",
    )


@pytest.mark.parametrize(
    "args, message",
    [
        ((4, "permanent"), "service class must be 1, 2 or 3, got 4"),
        ((1, "weekly"), "load duration must be one of permanent, .*got 'weekly'"),
    ],
)
def test_k_mod_refuses_unknown_classes(args, message):
    with pytest.raises(MaterialError, match=message):
        k_mod_plywood(*args)


def test_library_kinds_and_default_factors():
    assert {n: m.kind for n, m in MATERIALS.items()} == {
        "plywood": "plywood",
        "birch-plywood": "plywood",
        "poplar-plywood": "plywood",
        "gfrp": "gfrp",
        "aluminium": "aluminium",
    }
    assert GAMMA_M == {"plywood": 1.2, "aluminium": 1.1, "gfrp": None, "other": None}
    assert K_DEF_PLYWOOD == {1: 0.8, 2: 1.0, 3: 2.5}


@pytest.mark.parametrize("service_class", [1, 2, 3])
@pytest.mark.parametrize("duration", LOAD_DURATIONS)
def test_plywood_design_factors(service_class, duration):
    f = design_factors("birch-plywood", "EC5", service_class, duration)
    k = TABLE_3_1[service_class][LOAD_DURATIONS.index(duration)]
    assert (f.k_mod, f.gamma_M, f.k_def) == (k, 1.2, K_DEF_PLYWOOD[service_class])
    assert f.strength_factor == k / 1.2
    assert f.label == f"EC5 SC{service_class} {duration}"
    assert "EN 1995-1-1 Table 3.1" in f.source and "Table 2.3" in f.source


def test_default_is_permanent_service_class_1():
    f = design_factors(material("plywood"))
    assert (f.code, f.service_class, f.load_duration) == ("EC5", 1, "permanent")
    assert (f.k_mod, f.gamma_M, f.strength_factor) == (0.6, 1.2, 0.5)
    assert f.to_dict()["basis"] == "EC5 SC1 permanent"
    assert f.text() == (
        "design strengths f_d = k_mod f_k / gamma_M, EC5 SC1 permanent: k_mod 0.6, "
        "gamma_M 1.2, k_def 0.8"
    )


def test_characteristic_basis_is_exactly_one():
    f = design_factors("plywood", "characteristic")
    assert (f.k_mod, f.gamma_M, f.strength_factor) == (1.0, 1.0, 1.0)
    assert f.is_characteristic and f.label == "characteristic"
    assert DesignFactors().strength_factor == 1.0 and DesignFactors().is_characteristic


def test_aluminium_takes_en_1999_gamma_and_no_duration_factor():
    f = design_factors("aluminium", service_class=3, load_duration="permanent")
    assert (f.k_mod, f.gamma_M, f.k_def) == (1.0, 1.1, 0.0)
    assert "EN 1999-1-1" in f.source


def test_overrides_win():
    f = design_factors("plywood", gamma_M=1.3, k_mod=0.5, k_def=0.6)
    assert (f.k_mod, f.gamma_M, f.k_def) == (0.5, 1.3, 0.6)
    assert f.source == "k_mod given; gamma_M given; k_def given"


@pytest.mark.parametrize(
    "spec, kw, message",
    [
        ("gfrp", {}, "material 'gfrp' \\(kind 'gfrp'\\) has no default k_mod"),
        ("gfrp", {"k_mod": 0.5}, "has no default gamma_M"),
        ("plywood", {"code": "EC9"}, "design_code.code must be one of EC5, characteristic"),
        ("plywood", {"gamma_M": 0.0}, "design_code.gamma_M must be > 0, got 0.0"),
        ("plywood", {"k_mod": float("nan")}, "design_code.k_mod must be > 0"),
        ("plywood", {"service_class": 0}, "service class must be 1, 2 or 3"),
    ],
)
def test_design_factor_errors(spec, kw, message):
    with pytest.raises(MaterialError, match=message):
        design_factors(spec, **kw)


def test_gfrp_with_given_factors():
    f = design_factors("gfrp", gamma_M=1.3, k_mod=0.5)
    assert f.strength_factor == 0.5 / 1.3 and f.k_def is None


def test_material_kind_is_checked_and_kept():
    with pytest.raises(MaterialError, match="kind must be one of plywood, gfrp, aluminium, other"):
        Material("x", 1e9, 1e9, 0.4e9, 0.2, 500.0, 1e6, 1e6, kind="wood")
    m = material({"base": "birch-plywood", "f1": 40e6})
    assert m.kind == "plywood" and m.isotropic_equivalent().kind == "plywood"
    assert material("gfrp").isotropic_equivalent().kind == "gfrp"
