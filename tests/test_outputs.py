"""Output folders are one transaction: exactly one complete run's files, checked before any work,
never touching files that compas_ccu did not write."""

from __future__ import annotations

import json
import os

import pytest

from compas_ccu.cli import main, model_commands
from compas_ccu.outputs import MANIFEST, manifest_files, staged_folder
from conftest import EXAMPLES

CONE = str(EXAMPLES / "cone.toml")


def files(folder):
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())


def test_a_shorter_path_leaves_no_stale_states(tmp_path):
    out = tmp_path / "path"
    assert main(["path", CONE, "--steps", "12", "--out", str(out), "--quiet"]) == 0
    long = files(out)
    assert main(["path", CONE, "--steps", "4", "--out", str(out), "--quiet"]) == 0
    short = files(out)
    assert len([f for f in long if f.startswith("states/")]) == 13
    assert len([f for f in short if f.startswith("states/")]) == 5
    assert sorted(manifest_files(out)) == [f for f in short if f != MANIFEST]
    assert not list(tmp_path.glob(".*ccu-staging*"))


def test_a_failed_run_leaves_the_previous_run(tmp_path, capsys):
    out = tmp_path / "deploy"
    assert main(["deploy", CONE, "--out", str(out), "--quiet"]) == 0
    before = {f: (out / f).read_bytes() for f in files(out)}
    assert main(["deploy", CONE, "--alpha", "89.5", "--out", str(out), "--quiet"]) == 2
    assert "beyond the deployment limit" in capsys.readouterr().err
    assert {f: (out / f).read_bytes() for f in files(out)} == before
    assert not list(tmp_path.glob(".*ccu-staging*"))


def test_a_failure_half_way_writes_nothing(tmp_path, monkeypatch):
    out = tmp_path / "new"

    def broken(*args, **kwargs):
        raise OSError(28, "No space left on device", "structure.obj")

    monkeypatch.setattr(model_commands, "write_obj", broken)
    assert main(["deploy", CONE, "--out", str(out), "--quiet"]) == 2
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_files_the_tool_did_not_write_are_kept(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("my notes")
    assert main(["deploy", CONE, "--out", str(out), "--quiet"]) == 0
    assert main(["deploy", CONE, "--alpha", "20", "--out", str(out), "--quiet"]) == 0
    assert (out / "notes.txt").read_text() == "my notes"
    assert "notes.txt" not in manifest_files(out)


@pytest.mark.parametrize("where", ["file", "under-file", "empty"])
def test_a_bad_out_is_one_line_before_any_work(tmp_path, monkeypatch, capsys, where):
    (tmp_path / "a-file").write_text("x")
    out = {"file": tmp_path / "a-file", "under-file": tmp_path / "a-file" / "x", "empty": ""}

    def never(*args, **kwargs):  # the design is not even loaded
        raise AssertionError("work started before --out was checked")

    monkeypatch.setattr(model_commands, "load_model", never)
    assert main(["deploy", CONE, "--out", str(out[where]), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ccu: error: --out") and err.count("\n") == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]


def test_an_unwritable_out_is_refused(tmp_path, monkeypatch, capsys):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    if os.geteuid() == 0:  # root may write anywhere: ask the check as a user would be answered
        real = os.access
        monkeypatch.setattr(os, "access", lambda p, m: False if p == locked else real(p, m))
    assert main(["deploy", CONE, "--out", str(locked / "x"), "--quiet"]) == 2
    assert f"cannot write into '{locked}'" in capsys.readouterr().err


def test_a_manifest_cannot_remove_files_outside_the_folder(tmp_path):
    outside = tmp_path / "precious.txt"
    outside.write_text("keep")
    out = tmp_path / "out"
    out.mkdir()
    manifest = {"format": "ccu.files", "version": 1, "files": ["../precious.txt", "/etc/hosts"]}
    (out / MANIFEST).write_text(json.dumps(manifest))
    with staged_folder(out) as stage:
        (stage / "a.txt").write_text("a")
    assert outside.read_text() == "keep"
    assert manifest_files(out) == ["a.txt"]
