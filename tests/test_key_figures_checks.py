"""The check sheet (``compas_ccu.key_figures.checks``, ``ccu check``): every check with value,
limit and clause; the examples pass their own design checks as shipped, the teaching example
fails on purpose; a failed check exits 3 with every failure listed."""

from __future__ import annotations

import json

import pytest

from compas_ccu.cli import main
from compas_ccu.key_figures.checks import (
    Check,
    check_lines,
    design_checks,
    fabrication_checks,
    failed,
    fe_checks,
)
from conftest import EXAMPLES


def test_check_relations_and_verdict_line():
    ok = Check("design", "plate bending utilisation", 0.922, 1.0, "<=", "EN 1995-1-1 6.1.6")
    low = Check("FE a", "design buckling factor", 0.878, 1.0, ">=", "EN 1995-1-1 2.4.1")
    over = Check("FE b", "ULS utilisation", 1.0004, 1.0, "<=", "EN 1995-1-1 6.1")
    assert ok.ok and not low.ok and not over.ok
    # exactly at the limit passes, on either relation
    assert Check("x", "y", 1.0, 1.0, "<=", "").ok and Check("x", "y", 1.0, 1.0, ">=", "").ok
    with pytest.raises(ValueError, match="not '<'"):
        _ = Check("x", "y", 1.0, 1.0, "<", "").ok
    lines = check_lines([ok, low, over])
    assert len(lines) == 5
    # every failure in the verdict, 3 digits near 1 (1.0004 is not printed as "1")
    assert lines[-1] == (
        "3 checks: 1 passed, 2 FAILED: FE a design buckling factor 0.878 >= 1; "
        "FE b ULS utilisation 1.0004 <= 1"
    )
    assert [c.name for c in failed([ok, low, over])] == [
        "design buckling factor",
        "ULS utilisation",
    ]
    assert ok.to_dict()["ok"] is True and low.to_dict()["value"] == 0.878


def _figures(**kw):
    f = {
        "alpha_design": 30.0,
        "alpha_limit": 88.95,
        "invariant_max_relative": 8.6e-16,
        "overlap_alpha": 68.15,
        "collision_free_alpha": 68.15,
    }
    return {**f, **kw}


def _thickness(utilisation=0.922, depth=0.0, clear=68.15):
    return {
        "collision_free_alpha": clear,
        "collisions": {"max_penetration": depth, "tolerance": 1e-6},
        "bending": {
            "max_utilisation": utilisation,
            "max_utilisation_characteristic": utilisation / 2,
            "worst": {"plate": 9},
            "basis": {"code": "EC5", "basis": "EC5 SC1 permanent"},
        },
    }


def test_design_checks_fail_on_each_limit():
    names = lambda checks: [c.name for c in failed(checks)]  # noqa: E731
    assert names(design_checks(_figures(), _thickness())) == []
    assert names(design_checks(_figures(invariant_max_relative=2e-9), _thickness())) == [
        "kinematic invariants"
    ]
    assert names(design_checks(_figures(alpha_limit=29.0), _thickness())) == [
        "design angle in the deployment"
    ]
    assert names(design_checks(_figures(), _thickness(utilisation=1.229))) == [
        "plate bending utilisation"
    ]
    assert names(design_checks(_figures(), _thickness(depth=1e-3, clear=20.0))) == [
        "thick plates clear to the design",
        "thick plates' penetration, m",
    ]
    # no thick model: a failed check of its own, never a pass for want of a number
    assert names(design_checks(_figures(), None)) == ["thick model"]


def test_fabrication_checks_read_the_manifest():
    manifest = {
        "bending": {"basis": {"code": "EC5", "basis": "EC5 SC1 permanent"}},
        "collisions": {"max_penetration": 0.0, "tolerance": 1e-6},
        "splices": {
            "collisions": {
                "splices": [{"name": "S0.1D"}],
                "clearance_design": -2e-3,
                "tolerance": 1e-6,
                "clear_from_alpha": None,
            }
        },
        "bom": {"rows": [{"item": "P0", "sheet": 1}, {"item": "S0.1D", "sheet": 2}]},
        "workshop": {
            "sheets_in_stock": [[2.5, 1.25]],
            "sheets": [{"parts": ["P0"]}],
            "splice_bending": {"cuts": [{"utilisation": 3.687, "plate": 9, "ruling": 12}]},
        },
    }
    checks = fabrication_checks(manifest)
    by = {c.name: c for c in checks}
    assert by["splice plate bending utilisation"].value == 3.687
    assert not by["splice plate bending utilisation"].ok
    assert not by["splice plates' clearance, m"].ok  # 2 mm inside its neighbour
    assert by["BOM parts not on a sheet"].value == 1  # S0.1D is on no sheet
    assert by["written plates' penetration, m"].ok


def test_fe_checks_per_case_with_buckling():
    case = {
        "name": "construction",
        "basis": {"code": "EC5", "k_mod": 0.9, "basis": "EC5 SC1 short-term"},
        "utilisation_max": 0.614,
        "utilisation_plate": 1,
        "stress_max_MPa": 13.8,
        "strength_MPa": 22.5,
        "deflection_ratio": 0.226,
        "deflection_max_m": 1.18e-3,
        "deflection_limit_m": 5.24e-3,
        "deflection_final_ratio": 0.41,
        "buckling_factor": 0.878,
        "buckling_factor_mean": 1.9,
    }
    checks = fe_checks(
        {"checks": {"cases": [case, {**case, "name": "b", "buckling_factor": None}]}}
    )
    assert [c.name for c in checks[:4]] == [
        "ULS utilisation",
        "SLS deflection / limit",
        "final deflection / limit",
        "design buckling factor",
    ]
    assert len(checks) == 7  # case b without a buckling analysis: no buckling row
    assert [c.source for c in failed(checks)] == ["FE construction"]
    assert fe_checks({"checks": None}) == []


def test_examples_pass_their_design_checks(capsys):
    for name in ("vault", "cone"):
        assert main(["check", str(EXAMPLES / f"{name}.toml")]) == 0
        out = capsys.readouterr().out
        assert out.splitlines()[-1] == "7 checks: 7 passed, none failed"


def test_teaching_example_fails_and_says_why(capsys):
    assert main(["check", str(EXAMPLES / "overbent.toml")]) == 3
    cap = capsys.readouterr()
    last = cap.out.splitlines()[-1]
    assert last.startswith("7 checks: 6 passed, 1 FAILED: design plate bending utilisation 1.2")
    assert "EN 1995-1-1 6.1.6" in cap.err
    text = (EXAMPLES / "overbent.toml").read_text()
    assert "fails" in text and "sigma = E t kappa / 2 (1 - nu^2)" in text


def test_check_json_and_bad_folders(tmp_path, capsys):
    assert main(["check", str(EXAMPLES / "overbent.toml"), "--json"]) == 3
    doc = json.loads(capsys.readouterr().out)
    assert doc["format"] == "ccu.checks" and doc["failed"] == 1 and doc["ok"] is False
    worst = next(c for c in doc["checks"] if not c["ok"])
    assert worst["name"] == "plate bending utilisation" and worst["value"] == pytest.approx(
        1.229, rel=1e-3
    )
    # a folder without the record, a record of another command: one line, exit 2
    assert main(["check", str(EXAMPLES / "vault.toml"), "--fe", str(tmp_path)]) == 2
    assert "validation.json: no such file" in capsys.readouterr().err
    (tmp_path / "validation.json").write_text('{"format": "ccu.fabrication"}')
    assert main(["check", str(EXAMPLES / "vault.toml"), "--fe", str(tmp_path)]) == 2
    assert "format 'ccu.fabrication', expected 'ccu.validation'" in capsys.readouterr().err
