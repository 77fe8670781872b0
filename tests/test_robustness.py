"""A bounded slice of the robustness campaign (``make fuzz`` runs 5,000 designs): generated and
malformed designs across the whole schema either give a model whose written structure file
holds its invariants to 1e-9 of its size, or a one-line CCUError — never anything else."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from hypothesis import HealthCheck, given, settings

import strategies
from compas_ccu.cli import main

ROOT = Path(__file__).resolve().parents[1]
SLICE = settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))


@SLICE
@given(document=strategies.designs())
def test_a_design_is_exact_in_its_file_or_refused_in_one_line(document):
    kind, detail = strategies.outcome(document)
    assert kind in ("ok", "refused"), detail


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
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
