"""A bounded slice of the robustness campaign (``make fuzz`` runs 5,000 designs): generated and
malformed designs across the whole schema either give a model whose written structure file
holds its invariants to 1e-9 of its size, or a one-line CCUError — never anything else."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

import strategies
from compas_ccu.cli import main
from compas_ccu.errors import GeometryError
from conftest import property_examples

ROOT = Path(__file__).resolve().parents[1]
SLICE = settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))


@pytest.mark.slow  # the fuzz campaign and its corpus (4-6 s)
@SLICE
@given(document=strategies.designs())
def test_a_design_is_exact_in_its_file_or_refused_in_one_line(document):
    kind, detail = strategies.outcome(document)
    assert kind in ("ok", "refused"), detail


@settings(
    max_examples=property_examples(40), deadline=None, suppress_health_check=list(HealthCheck)
)
@given(data=strategies.toml_texts())
def test_a_malformed_design_file_is_one_line_and_leaves_nothing(tmp_path_factory, data):
    folder = tmp_path_factory.mktemp("file")
    design = folder / "design.toml"
    design.write_bytes(data)
    out = folder / "out"
    code = main(["deploy", str(design), "--out", str(out), "--quiet"])
    assert code in (0, 2)
    if code == 2:
        assert not out.exists()


@pytest.mark.slow  # the fuzz campaign and its corpus (4-6 s)
def test_the_campaign_runs_and_finds_no_bug():
    """tools/fuzz.py end to end on a small campaign: the table and a clean exit status."""
    p = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "fuzz.py"), "--designs", "60", "--budget", "60"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    assert "| design |" in p.stdout and "Bugs and hangs: 0" in p.stdout


def _fuzz_module():
    spec = importlib.util.spec_from_file_location("fuzz", ROOT / "tools" / "fuzz.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize(
    "message",
    [
        "the mechanism misses its own design state by 1e-06 m; this is a bug in compas_ccu",
        "something odd happened, Please report it with the design file",
    ],
)
def test_a_refusal_that_asks_for_a_report_is_a_bug(monkeypatch, message):
    """A one-line CCUError is a refusal, unless it admits a defect of compas_ccu."""

    class Raising:
        def __init__(self, design):
            raise GeometryError(message)

    monkeypatch.setattr(strategies, "Design", lambda document: document)
    monkeypatch.setattr(strategies, "CCUModel", Raising)
    kind, detail = strategies.outcome({})
    assert kind == "bug" and detail == f"GeometryError asks for a report: {message}"

    class Refusing:
        def __init__(self, design):
            raise GeometryError("crease.span: must be > 0, got -1.0")

    monkeypatch.setattr(strategies, "CCUModel", Refusing)
    assert strategies.outcome({}) == ("refused", "GeometryError")


@pytest.mark.parametrize("stream", ["stderr", "stdout"])
@pytest.mark.parametrize("code", [0, 2])
def test_a_ccu_run_that_asks_for_a_report_is_a_bug(tmp_path, monkeypatch, stream, code):
    """tools/fuzz.py's ccu runs: one line and exit 2 is a refusal, unless it asks for a report
    (on either stream, whatever the exit code)."""
    fuzz = _fuzz_module()

    def fake(line):
        def run(argv):
            print(line, file=getattr(sys, stream))
            return code

        return run

    monkeypatch.setattr(fuzz, "ccu", fake("ccu: error: x: this is a bug in compas_ccu"))
    kind, detail = fuzz.cli_outcome(["info"], tmp_path / "out")
    assert kind == "bug"
    assert detail == f"exit {code}, asks for a report: ccu: error: x: this is a bug in compas_ccu"
    monkeypatch.setattr(fuzz, "ccu", fake("ccu: error: crease.span: must be > 0, got -1.0"))
    kind, detail = fuzz.cli_outcome(["info"], tmp_path / "out")
    expected = {
        (0, "stderr"): "ok",
        (0, "stdout"): "ok",
        (2, "stderr"): "refused",
        (2, "stdout"): "bug",  # exit 2 says nothing on stderr: not a one-line refusal
    }
    assert kind == expected[(code, stream)]
