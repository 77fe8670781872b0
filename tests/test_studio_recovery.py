"""The recovery copy written after the checks panel (studio/recovery.py, studio/jobs.py): every
valid change reaches the copy, none is lost."""

from __future__ import annotations

import shutil

import pytest

from compas_ccu.studio import StudioSession
from conftest import EXAMPLES

pytest.importorskip("tomlkit")


def _copy(session) -> str | None:
    path = session.files.recovery_of(session.path) / "recovery.toml"
    return path.read_text("utf-8") if path.exists() else None


@pytest.fixture
def design(tmp_path):
    shutil.copy(EXAMPLES / "vault.toml", tmp_path / "vault.toml")
    shutil.copy(EXAMPLES / "cone.toml", tmp_path / "cone.toml")
    return tmp_path / "vault.toml"


def test_a_deferred_recovery_copy_is_written_when_asked(design, tmp_path):
    session = StudioSession.start(design, out=tmp_path / "out")
    session.defer_recovery = True
    assert session.edit("crease", "rise", 0.85) is None
    assert _copy(session) is None  # not on the way to the checks panel
    assert session.write_recovery() and "rise = 0.85" in _copy(session)
    assert not session.write_recovery()  # nothing new
    assert session.edit("crease", "rise", 0.9) is None
    assert session.edit("crease", "rise", 0.95) is None  # two changes, one write
    assert session.write_recovery() and "rise = 0.95" in _copy(session)
    # a change not written yet goes to its file's copy before another file is opened
    assert session.edit("crease", "rise", 0.8) is None
    vault = session.files.recovery_of(session.path) / "recovery.toml"
    session.open_file("cone.toml")
    assert "rise = 0.8" in vault.read_text("utf-8")
    # a save leaves nothing to write
    assert session.edit("plates", "material", "birch-plywood") is None
    session.save()
    assert not session.write_recovery()
    again = StudioSession.start(tmp_path / "vault.toml", out=tmp_path / "out")
    assert again.model.design.crease.rise == 0.8  # the copy of the unsaved change
    assert "restored unsaved edits" in again.notice


def test_the_studio_writes_every_change_to_the_recovery_copy(design, tmp_path):
    pytest.importorskip("viser")
    from compas_ccu.studio.app import Studio
    from studio_page import free_port

    session = StudioSession.start(design, out=tmp_path / "out")
    app = Studio(session, port=free_port())
    try:
        assert app.wait_idle(120) and session.defer_recovery
        for rise in (0.85, 0.9):
            shown = app.checks_shown
            assert app.apply_action(lambda r=rise: session.edit("crease", "rise", r))
            assert app.wait_idle(120)
            assert app.checks_shown == shown + 1
            assert f"rise = {rise}" in _copy(session)
            assert "measuring" not in app.checks_panel.content
        # an invalid value has no model and never reaches the copy
        assert app.apply_action(lambda: session.edit("crease", "rise", -1.0), panel="design")
        assert session.problem is not None
        assert "rise = 0.9" in _copy(session)
        # a change whose checks have not run yet is written when the studio stops
        assert app.apply_action(lambda: session.edit("crease", "rise", 0.95))
    finally:
        app.stop()
    assert "rise = 0.95" in _copy(session)
    assert not session.defer_recovery  # without the studio, every change at once
    assert session.edit("crease", "rise", 0.75) is None and "rise = 0.75" in _copy(session)
    assert session.edit("crease", "rise", 0.95) is None
    again = StudioSession.start(design, out=tmp_path / "out")
    assert again.model.design.crease.rise == 0.95
