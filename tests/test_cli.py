"""The ccu command: deploy / path / info, the structure.json contract, errors, --help."""

from __future__ import annotations

import csv
import json
import subprocess
import sys

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.design import load_design
from compas_ccu.design.inverse import write_design
from compas_ccu.io import read_structure_json
from conftest import EXAMPLES

VAULT = str(EXAMPLES / "vault.toml")


def test_deploy_writes_the_spec_contract(tmp_path, capsys):
    assert main(["deploy", VAULT, "--alpha", "30", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "wrote" in out and "isometry" in out
    data = json.loads((tmp_path / "structure.json").read_text())
    assert data["format"] == "ccu.structure" and data["version"] == 1
    assert data["units"] == "m" and data["alpha"] == 30.0
    assert set(data) >= {"plates", "creases", "metrics"}
    n = data["metrics"]["segments"]
    size = data["metrics"]["size"]
    for plate in data["plates"]:
        assert set(plate) >= {"id", "faces", "flat", "deployed"}
        flat, dep = np.array(plate["flat"]), np.array(plate["deployed"])
        assert flat.shape == dep.shape == (2 * n + 2, 3)
        assert np.all(flat[:, 2] == 0.0)
        faces = np.array(plate["faces"])
        assert faces.shape == (n, 4)
        # every deployed quad is congruent to its cut quad (4 sides + 2 diagonals)
        for i, j in [(0, 1), (1, 2), (2, 3), (3, 0), (0, 2), (1, 3)]:
            d_flat = np.linalg.norm(flat[faces[:, i]] - flat[faces[:, j]], axis=1)
            d_dep = np.linalg.norm(dep[faces[:, i]] - dep[faces[:, j]], axis=1)
            assert np.abs(d_flat - d_dep).max() < 1e-9 * size
        # quads are planar and counter-clockwise in the cut pattern
        a, b, c, d = (dep[faces[:, k]] for k in range(4))
        nrm = np.cross(b - a, d - a)
        nrm /= np.linalg.norm(nrm, axis=1)[:, None]
        assert np.abs(np.einsum("ij,ij->i", c - a, nrm)).max() < 1e-9 * size
        fa, fb, fd = flat[faces[:, 0]], flat[faces[:, 1]], flat[faces[:, 3]]
        area = np.cross(fb - fa, fd - fa)[:, 2]
        assert np.all(area > 0.0)
    plates = {p["id"]: np.array(p["deployed"]) for p in data["plates"]}
    for crease in data["creases"]:
        assert set(crease) >= {"id", "plates", "vertices", "kind", "plane"}
        assert crease["kind"] in ("synclastic", "anticlastic", "ccf")
        a, b = crease["plates"]
        ia, ib = crease["vertices"]
        assert len(ia) == len(ib) == n + 1
        # hinge coincidence, and the crease lies in its plane
        assert np.abs(plates[a][ia] - plates[b][ib]).max() < 1e-9 * size
        o, nrm = np.array(crease["plane"]["origin"]), np.array(crease["plane"]["normal"])
        assert abs(np.linalg.norm(nrm) - 1.0) < 1e-12
        assert np.abs((plates[a][ia] - o) @ nrm).max() < 1e-9 * size
        # mirror symmetry: plate b's vertex rows near the crease reflected land on plate a's
        ra = plates[a][np.array(ia) + (n + 1 if ia[0] == 0 else -(n + 1))] - plates[a][ia]
        rb = plates[b][np.array(ib) + n + 1] - plates[b][ib]
        t = np.minimum(np.linalg.norm(ra, axis=1), np.linalg.norm(rb, axis=1))[:, None]
        pa = plates[a][ia] + ra / np.linalg.norm(ra, axis=1)[:, None] * t
        pb = plates[b][ib] + rb / np.linalg.norm(rb, axis=1)[:, None] * t
        mirrored = pb - 2 * ((pb - o) @ nrm)[:, None] * nrm
        assert np.abs(mirrored - pa).max() < 1e-9 * size
    # the round trip through the reader
    s = read_structure_json(tmp_path / "structure.json")
    assert s.alpha == 30.0 and len(s.plate_ids) == 10


def test_deploy_writes_obj_and_compas_json(tmp_path):
    import compas

    assert main(["deploy", VAULT, "--out", str(tmp_path), "--quiet"]) == 0
    lines = (tmp_path / "structure.obj").read_text().splitlines()
    assert sum(line.startswith("g plate_") for line in lines) == 10
    assert sum(line.startswith("v ") for line in lines) == 10 * 2 * 65
    assert sum(line.startswith("f ") for line in lines) == 10 * 64
    meshes = compas.json_load(str(tmp_path / "structure.compas.json"))
    assert len(meshes) == 10
    assert meshes[0].number_of_faces() == 64 and meshes[0].number_of_vertices() == 130
    assert [m.name for m in meshes] == [f"plate_{i}" for i in range(10)]
    assert len({str(m.guid) for m in meshes}) == 10  # name-based ids, one per plate
    # the same structure, the same file: no random COMPAS guid in it
    again = tmp_path / "again"
    assert main(["deploy", VAULT, "--out", str(again), "--quiet"]) == 0
    first = (tmp_path / "structure.compas.json").read_bytes()
    assert (again / "structure.compas.json").read_bytes() == first


def test_path_writes_states_and_table(tmp_path, capsys):
    assert main(["path", VAULT, "--steps", "4", "--out", str(tmp_path)]) == 0
    states = sorted((tmp_path / "states").glob("state_*.json"))
    assert len(states) == 5
    rows = list(csv.DictReader((tmp_path / "path.csv").open()))
    assert [float(r["alpha_deg"]) for r in rows] == [0.0, 7.5, 15.0, 22.5, 30.0]
    assert float(rows[-1]["span_m"]) == pytest.approx(2.5, abs=1e-9)
    assert float(rows[-1]["rise_m"]) == pytest.approx(1.0, abs=1e-9)
    assert all(float(r["crease_planarity_max_m"]) < 1e-12 for r in rows)
    assert "crease_8_planarity_m" in rows[0]
    spans = [float(r["span_m"]) for r in rows]
    assert all(a > b for a, b in zip(spans, spans[1:]))  # the vault closes as it deploys


def test_info_prints_key_figures(capsys):
    assert main(["info", VAULT]) == 0
    out = capsys.readouterr().out
    for text in (
        "plates            10",
        "creases           9 (4 anticlastic, 5 synclastic)",
        "design alpha      30 deg",
        "deployment limit  88.95",
        "span              2.5000",
        "rise              1.0000",
        "flat stack",
    ):
        assert text in out, text


def test_info_json_has_the_numbers_of_the_text(capsys):
    assert main(["info", VAULT]) == 0
    text = capsys.readouterr().out
    assert main(["info", "--json", VAULT]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["format"] == "ccu.info" and data["units"] == {"length": "m", "angle": "deg"}
    assert data["design_units"] == "m"
    k, units = data["key_figures"], data["figure_units"]
    assert units["crease_span"] == "m" and units["alpha_limit"] == "deg"
    assert k["plates"] == 10 and k["creases"] == 9 and k["segments"] == 64
    lines = {line[:18].strip(): line[18:] for line in text.splitlines()}
    assert lines["span"] == f"{k['crease_span']:.4f} m (leading crease chord)"
    assert lines["rise"] == f"{k['crease_rise']:.4f} m"
    assert lines["deployment limit"].startswith(f"{k['alpha_limit']:.4f} deg")
    assert lines["overlap limit"].startswith(f"{k['overlap_alpha']:.4f} deg")
    assert lines["bounding box"] == f"{k['plan_x']:.3f} x {k['plan_y']:.3f} x {k['height']:.3f} m"
    assert lines["flat stack"].startswith(f"{k['stack_x']:.3f} x {k['stack_y']:.3f} m")
    assert k["alpha_limit"] == pytest.approx(88.9537576330131, abs=1e-9)
    t = data["thickness"]
    assert lines["thickness"].startswith(f"{t['thickness'] * 1e3:.4g} mm {t['material']}")
    assert f"utilisation {t['bending']['max_utilisation']:.3f}" in lines["bending check"]
    assert data["thickness_error"] is None


def test_info_json_of_a_millimetre_design_is_in_metres(tmp_path, capsys):
    path = tmp_path / "vault-mm.toml"
    write_design(load_design(VAULT), path, units="mm")
    assert "span = 2500.0" in path.read_text()
    assert main(["info", str(path)]) == 0
    text = capsys.readouterr().out
    assert "units             the file's lengths are mm; below: m\n" in text
    assert "span              2.5000 m (leading crease chord)" in text
    assert main(["info", "--json", str(path)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["design_units"] == "mm"
    assert data["key_figures"]["crease_span"] == pytest.approx(2.5, rel=1e-12)
    assert data["thickness"]["thickness"] == pytest.approx(0.006, rel=1e-12)


@pytest.mark.parametrize(
    "argv,message",
    [
        (["deploy", VAULT, "--alpha", "95", "--out", "x"], "beyond the deployment limit"),
        (["deploy", VAULT, "--alpha", "80", "--out", "x"], "self-intersection at alpha = 80"),
        (["deploy", VAULT, "--alpha", "-3", "--out", "x"], "negative"),
        (["info", "missing.toml"], "cannot read design file"),
    ],
)
def test_errors_exit_2_with_the_cause(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("ccu: error:") and message in err


def test_bad_design_key_is_named(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text((EXAMPLES / "cone.toml").read_text().replace("radius = 2.0", "radius = -2.0"))
    assert main(["info", str(bad)]) == 2
    assert "crease.radius: must be > 0 and <= 1e6, got -2.0" in capsys.readouterr().err


@pytest.mark.parametrize(
    "sub",
    # a ccu process each (~0.8 s); every command's help in-process: tests/test_cli_startup.py
    [[]] + [pytest.param([name], marks=pytest.mark.slow) for name in ("deploy", "path", "info")],
)
def test_help_everywhere(sub):
    out = subprocess.run(
        [sys.executable, "-m", "compas_ccu.cli", *sub, "--help"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert "usage: ccu" in out


def test_import_is_cheap():
    code = (
        "import sys, compas_ccu; "
        "print(any(m.split('.')[0] in ('compas', 'scipy', 'shapely') for m in sys.modules))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert out.strip() == "False"


# -- the error policy: input errors are one line (exit 2), anything else is a bug (exit 1) ----


def _raising(error):
    def broken(*args, **kwargs):
        raise error

    return broken


@pytest.mark.parametrize(
    "error", [ZeroDivisionError("float division by zero"), ValueError("operands could not be")]
)
def test_a_bug_prints_its_traceback_and_exits_1(error, monkeypatch, capsys):
    from compas_ccu.cli import model_commands

    monkeypatch.setattr(model_commands, "key_figures", _raising(error))
    assert main(["info", VAULT]) == 1
    err = capsys.readouterr().err
    assert err.startswith("Traceback (most recent call last):")
    assert f"{type(error).__name__}: {error}" in err
    assert "this is a bug in compas_ccu" in err and "please report it" in err
    assert "ccu: error:" not in err


def test_a_ccu_error_is_one_line_and_exit_2(monkeypatch, capsys):
    from compas_ccu.cli import model_commands
    from compas_ccu.errors import GeometryError

    monkeypatch.setattr(model_commands, "key_figures", _raising(GeometryError("straight crease")))
    assert main(["info", VAULT]) == 2
    assert capsys.readouterr().err == "ccu: error: straight crease\n"


def test_an_os_error_on_the_users_path_is_one_line_and_exit_2(tmp_path, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    assert main(["deploy", VAULT, "--out", str(blocker / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ccu: error: ") and "a-file" in err and err.count("\n") == 1


def test_usage_errors_and_option_bounds_exit_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["deploy", VAULT])  # --out missing: argparse
    assert exit_.value.code == 2
    capsys.readouterr()
    assert main(["path", VAULT, "--steps", "0", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err == "ccu: error: --steps must be >= 1, got 0\n"


def test_a_missing_extra_is_named(monkeypatch, capsys, tmp_path):
    from compas_ccu import errors

    monkeypatch.setattr(errors, "missing_modules", lambda names: [n for n in names if n == "ezdxf"])
    assert main(["fabricate", VAULT, "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err == (
        "ccu: error: 'ccu fabricate' needs the fab extra (ezdxf not installed): "
        "pip install 'compas_ccu[fab]'\n"
    )


def test_every_error_class_pickles_with_its_attributes():
    """Dask workers send errors back pickled: every error class of the package survives it."""
    import pickle

    from compas_ccu.errors import (
        DeploymentLimitError,
        DesignError,
        LimitError,
        MissingExtraError,
        OptionError,
        SelfIntersectionError,
        SweepError,
    )
    from compas_ccu.fea.problem import ConvergenceError, FEError
    from compas_ccu.materials import MaterialError

    errors = [
        OptionError("--steps must be >= 1"),
        MissingExtraError("needs viz"),
        LimitError("too many"),
        DesignError("must be > 0", key="crease.span"),
        SweepError("bad", key="sweep.base"),
        FEError("no engine"),
        MaterialError("unknown"),
        DeploymentLimitError("beyond", alpha=95.0, alpha_limit=89.0, vertex=3),
        SelfIntersectionError("overlap", alpha=80.0, crease=2),
        ConvergenceError("step 3 did not converge", step=3, residual=0.5),
    ]
    for error in errors:
        again = pickle.loads(pickle.dumps(error))
        assert type(again) is type(error) and str(again) == str(error)
        assert again.__dict__ == error.__dict__


def test_the_commands_are_declared_once_and_help_needs_no_extra():
    import importlib

    from compas_ccu.cli import COMMANDS, thickness_lines  # noqa: F401 - still exported
    from compas_ccu.cli.table import TABLE

    names = [c.name for c in COMMANDS]
    assert len(names) == len(set(names)) == 21
    assert names == [e.name for e in TABLE]  # in the order of ccu --help
    # the table names every command of a module, and only there, where it is declared
    for module in {e.module for e in TABLE}:
        declared = sorted(c.name for c in importlib.import_module(module).COMMANDS)
        assert declared == sorted(e.name for e in TABLE if e.module == module), module
    # (with the explorer's and the optimiser's modules imported: they import optuna when a
    # study samples, not with themselves)
    code = (
        "import sys, compas_ccu.explore, compas_ccu.explore.optimize; "
        "from compas_ccu.cli import build_parser; build_parser(); "
        "print(sorted(m for m in ('matplotlib', 'plotly', 'distributed', 'pyarrow', 'optuna', "
        "'KratosMultiphysics', 'openseespy', 'ezdxf', 'rhino3dm', 'trimesh', 'viser', 'tomlkit') "
        "if m in sys.modules))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert out.strip() == "[]"
