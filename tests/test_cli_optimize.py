"""``ccu optimize``: the console summary, the files, no feasible design (exit 3), bad input
(exit 2), continuing a study, another study in the folder."""

from __future__ import annotations

import json

import pytest

from compas_ccu.cli import build_parser, main
from compas_ccu.cli.optimize import NO_FEASIBLE
from compas_ccu.explore.results import read_table
from test_explore_optimize import write_study

pytest.importorskip("optuna")
pytest.importorskip("pyarrow")


@pytest.mark.slow  # a whole study through the CLI (2-4 s)
def test_ccu_optimize_prints_the_best_design_and_writes_the_files(tmp_path, capsys):
    write_study(tmp_path)
    out = tmp_path / "out"
    code = main(["optimize", str(tmp_path / "study.toml"), "--out", str(out), "--in-process",
                 "--trials", "20", "--quiet"])  # fmt: skip
    assert code == 0 and capsys.readouterr().out == ""  # --quiet
    code = main(["optimize", str(tmp_path / "study.toml"), "--out", str(out), "--in-process",
                 "--trials", "24"])  # fmt: skip
    text = capsys.readouterr().out
    assert code == 0
    assert "study small: 24 trials (tpe, seed 2) of base.toml over plates.thickness" in text
    assert "20 trials were already in" in text and "ran 4 trials in" in text
    summary = json.loads((out / "summary.json").read_text())
    best = summary["best"][0]
    assert f"best 1: trial {best['trial']}: mass {best['objectives']['mass']:.4g}; " in text
    assert summary["trials"] == 24 and f"; {summary['feasible']} feasible" in text
    rows = read_table(out / "results.parquet")
    assert len(rows) == 24 and [r["run"] for r in rows] == [1] * 20 + [2] * 4
    folder = out / "best" / f"1-{best['variant']}"
    assert main(["info", str(folder / "design.toml")]) == 0  # a design file ccu takes
    info = capsys.readouterr().out
    assert f"vault-{best['variant']}" in info
    assert f"thickness         {best['parameters']['plates.thickness'] * 1000:.3f} mm" in info
    for name in ("convergence", "design_space"):
        assert (out / "plots" / f"{name}.png").stat().st_size > 10_000
    assert not (out / "plots" / "pareto.png").exists()  # one objective
    assert {p.name for p in out.iterdir()} >= {"study.json", "journal.jsonl", "optuna.journal"}


@pytest.mark.slow  # a whole study through the CLI (2-4 s)
def test_no_feasible_design_exits_3_and_lists_the_least_violating(tmp_path, capsys):
    write_study(tmp_path, replace={"rise = {min = 0.9}": "rise = {min = 2.0}"})
    code = main(["optimize", str(tmp_path / "study.toml"), "--out", str(tmp_path / "out"),
                 "--in-process", "--trials", "6"])  # fmt: skip
    captured = capsys.readouterr()
    assert code == NO_FEASIBLE == 3
    assert "; 0 feasible" in captured.out
    err = captured.err.splitlines()  # after the progress bar
    head = err.index(
        "ccu optimize: no feasible design in 6 trials: none meets every constraint. "
        "The least violating:"
    )
    err = err[head:]
    listed = [line for line in err if line.startswith("  trial ")]
    assert len(listed) == 5
    assert all("< min 2" in line and "plates.thickness = " in line for line in listed)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    first = summary["least_violating"][0]
    assert listed[0].startswith(f"  trial {first['trial']} (violation {first['violation']:.3g}): ")
    assert "Relax the constraints" in err[-1]
    # --quiet hides the summary, never the error
    code = main(["optimize", str(tmp_path / "study.toml"), "--out", str(tmp_path / "out"),
                 "--in-process", "--trials", "6", "--quiet"])  # fmt: skip
    captured = capsys.readouterr()
    assert code == 3 and captured.out == "" and "no feasible design" in captured.err


def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys):
    write_study(tmp_path)
    study = tmp_path / "study.toml"
    study.write_text(
        study.read_text().replace("{min = 0.04, max = 0.1}", "{min = 0.1, max = 0.04}")
    )
    out = str(tmp_path / "out")
    assert main(["optimize", str(tmp_path / "study.toml"), "--out", out, "--in-process"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ccu: error: ") and len(err.strip().splitlines()) == 1
    assert "study.toml: parameters.layout.spacing: max 0.04 is below min 0.1" in err
    write_study(tmp_path)
    study = str(tmp_path / "study.toml")
    for argv, message in (
        (["--in-process", "--workers", "2"], "--in-process runs without Dask"),
        (["--trials", "0"], "--trials must be >= 1, got 0"),
        (["--seed", "-1"], "--seed must be >= 0, got -1"),
    ):
        assert main(["optimize", study, "--out", out, *argv]) == 2
        assert message in capsys.readouterr().err
    assert main(["optimize", str(tmp_path / "nope.toml"), "--out", out]) == 2
    assert "cannot read study file" in capsys.readouterr().err


@pytest.mark.slow  # a whole study through the CLI (2-4 s)
def test_another_study_in_the_folder_is_refused_and_seed_is_another_study(tmp_path, capsys):
    write_study(tmp_path)
    study, out = str(tmp_path / "study.toml"), str(tmp_path / "out")
    # two random startup trials of seed 2: neither is feasible (exit 3), the folder is the study's
    assert main(["optimize", study, "--out", out, "--in-process", "--trials", "2", "--quiet"]) == 3
    code = main(["optimize", study, "--out", out, "--in-process", "--seed", "5"])
    err = capsys.readouterr().err
    assert code == 2 and "holds results of a different study" in err and "fingerprint" in err
    assert main(["optimize", study, "--out", str(tmp_path / "o5"), "--in-process", "--seed",
                 "5", "--trials", "12"]) == 0  # fmt: skip
    assert "study small: 12 trials (tpe, seed 5)" in capsys.readouterr().out


def test_the_command_is_declared():
    """(Building the parser, with compas_ccu.explore.optimize imported, imports no optuna:
    tests/test_cli.py::test_the_commands_are_declared_once_and_help_needs_no_extra, in a fresh
    process.)"""
    parser = build_parser()
    args = parser.parse_args(["optimize", "s.toml", "--out", "o", "--trials", "5"])
    assert (args.trials, args.workers, args.scheduler, args.spec.staged) == (5, None, None, False)
