"""A target or a scan uploaded from the studio's page (docs/studio.md, "Target and scan"): written
only into the design folder's ``targets/`` under a checked name, never over a file, at most
200 MB, read in the background process and shown like a loaded target; a file that does not
read is refused in one line and removed. The upload event is simulated with a fake handle."""

from __future__ import annotations

import html
import os
import shutil
import time
from types import SimpleNamespace

import numpy as np
import pytest

from compas_ccu.errors import LimitError, OptionError
from compas_ccu.studio import StudioSession
from compas_ccu.studio.target import TARGET_COLORING, load_target
from compas_ccu.studio.target_upload import (
    UPLOAD_BYTES,
    read_upload,
    save_upload,
    upload_name,
)
from conftest import EXAMPLES

pytest.importorskip("trimesh")


def grid_obj(n: int = 12, size: float = 2.0) -> bytes:
    """A flat square mesh of (n - 1)² quads (two triangles each), as OBJ bytes."""
    t = np.linspace(0.0, size, n)
    x, y = np.meshgrid(t, t, indexing="ij")
    lines = [f"v {a:.6f} {b:.6f} 1.0" for a, b in zip(x.ravel(), y.ravel())]
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j + 1, (i + 1) * n + j + 1, (i + 1) * n + j + 2, i * n + j + 2
            lines += [f"f {a} {b} {c}", f"f {a} {c} {d}"]
    return ("\n".join(lines) + "\n").encode()


def cloud_xyz(count: int = 400) -> bytes:
    p = np.random.default_rng(1).random((count, 3)) * [3.0, 2.0, 0.01]
    return "".join(f"{x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in p).encode()


def tree(root) -> dict:
    """Every file under ``root`` (relative path -> bytes)."""
    out = {}
    for folder, _, names in os.walk(root):
        for n in names:
            path = os.path.join(folder, n)
            with open(path, "rb") as f:
                out[os.path.relpath(path, root)] = f.read()
    return out


@pytest.fixture
def session(tmp_path):
    design = tmp_path / "designs"
    design.mkdir()
    shutil.copy(EXAMPLES / "vault.toml", design / "vault.toml")
    return StudioSession.start(design / "vault.toml", out=tmp_path / "out")


def upload_event(name, content):
    """What viser gives the callback: ``event.target.value`` is the uploaded file."""
    return SimpleNamespace(
        target=SimpleNamespace(value=SimpleNamespace(name=name, content=content))
    )


class Huge:
    """Content that says it is ``size`` bytes (refused on its length, never read)."""

    def __init__(self, size: int):
        self.size = size

    def __len__(self) -> int:
        return self.size


# -- the file written ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("name", "content", "kind"),
    [("roof.obj", grid_obj(), "mesh"), ("scan.xyz", cloud_xyz(), "points")],
)
def test_an_upload_is_written_into_targets_and_reads(session, tmp_path, name, content, kind):
    before = tree(tmp_path)
    rel = save_upload(session.files, name, content)
    assert rel == f"targets/{name}"
    after = tree(tmp_path)
    assert set(after) - set(before) == {f"designs/targets/{name}"}  # nothing else, no temp file
    assert after[f"designs/targets/{name}"] == content
    outcome = read_upload(session.files, rel)
    target = outcome["target"]
    assert target.name == rel and target.target.kind == kind
    assert len(target.target) == (50_000 if kind == "mesh" else 400)
    assert len(load_target(session.files, rel).target) == len(target.target)  # Load takes it too


@pytest.mark.parametrize(
    ("name", "words"),
    [
        ("../x.xyz", "an uploaded file name has no folders"),
        ("a/b.xyz", "an uploaded file name has no folders"),
        ("a\\b.xyz", "an uploaded file name has no folders"),
        ("/etc/x.xyz", "an uploaded file name has no folders"),
        ("..", "an uploaded file name has no folders"),
        (".hidden.xyz", "a hidden file name"),
        ("..xyz", "a hidden file name"),
        ("scan.exe", "a target is one of .obj, .stl, .ply, .off, .xyz"),
        ("vault.toml", "a target is one of"),
        ("scan", "a target is one of"),
        ("a:b.xyz", "give the file a plain name"),
        ("a\nb.xyz", "give the file a plain name"),
        ("x" * 101 + ".xyz", "give the file a plain name"),
        ("  ", "the uploaded file has no name"),
    ],
)
def test_a_bad_name_is_refused_in_one_line_and_nothing_is_written(session, tmp_path, name, words):
    before = tree(tmp_path)
    with pytest.raises(OptionError) as info:
        save_upload(session.files, name, cloud_xyz(10))
    assert words in str(info.value) and "\n" not in str(info.value)
    assert tree(tmp_path) == before
    assert not (session.files.design_folder / "targets").exists()


def test_a_name_is_kept_as_sent_when_it_is_plain():
    assert upload_name(" Scan 2026 (east).XYZ ") == "Scan 2026 (east).XYZ"
    assert upload_name("dome.3dm") == "dome.3dm"


def test_a_file_too_large_or_empty_is_refused_naming_its_size(session, tmp_path):
    before = tree(tmp_path)
    with pytest.raises(LimitError) as info:
        save_upload(session.files, "big.xyz", Huge(250_000_000))
    assert str(info.value) == (
        "'big.xyz' is 250.0 MB; an uploaded target may have at most 200 MB (copy a larger one "
        "into the design folder and Load it)"
    )
    assert UPLOAD_BYTES == 200_000_000
    with pytest.raises(LimitError, match="'big.xyz' is 1.5 MB; .* at most 1 MB"):
        save_upload(session.files, "big.xyz", b"0" * 1_500_000, limit=1_000_000)
    with pytest.raises(LimitError, match=r"'none.xyz' is empty \(0 bytes\)"):
        save_upload(session.files, "none.xyz", b"")
    assert tree(tmp_path) == before


def test_a_clash_gets_a_number_and_never_overwrites(session, tmp_path):
    targets = session.files.design_folder / "targets"
    targets.mkdir()
    (targets / "scan.xyz").write_bytes(b"0 0 0\n1 0 0\n")  # the user's own file
    first, second = cloud_xyz(20), cloud_xyz(30)
    assert save_upload(session.files, "scan.xyz", first) == "targets/scan-2.xyz"
    assert save_upload(session.files, "scan.xyz", second) == "targets/scan-3.xyz"
    assert (targets / "scan.xyz").read_bytes() == b"0 0 0\n1 0 0\n"
    assert (targets / "scan-2.xyz").read_bytes() == first
    assert (targets / "scan-3.xyz").read_bytes() == second
    assert sorted(p.name for p in targets.iterdir()) == ["scan-2.xyz", "scan-3.xyz", "scan.xyz"]


def test_targets_leading_out_of_the_design_folder_is_refused(session, tmp_path):
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    os.symlink(outside, session.files.design_folder / "targets")
    with pytest.raises(OptionError, match="leads outside the design folder"):
        save_upload(session.files, "scan.xyz", cloud_xyz(10))
    assert list(outside.iterdir()) == []


@pytest.mark.parametrize(
    ("name", "content", "words"),
    [
        ("bad.xyz", b"hello world\nnot numbers here\n", "not x y z rows of numbers"),
        ("bad.xyz", b"1 2 nan\n3 4 5\n", "non-finite coordinate"),
        ("bad.obj", b"this is not a mesh\n", "no points"),
        ("bad.ply", b"\x00\x01binary garbage" * 20, "cannot read it as .ply"),
    ],
)
def test_a_file_that_does_not_read_is_refused_and_removed(session, tmp_path, name, content,
                                                         words):  # fmt: skip
    before = tree(tmp_path)
    rel = save_upload(session.files, name, content)
    outcome = read_upload(session.files, rel)
    error = outcome["error"]
    assert error.startswith(f"'targets/{name}' is not a target and was removed: ")
    assert words in error and "\n" not in error
    assert set(tree(tmp_path)) == set(before)  # the copy is gone (the empty targets/ stays)


# -- the page (the app on a free port, no browser; the upload event simulated) --------------------
@pytest.fixture
def studio(session):
    pytest.importorskip("viser")
    from compas_ccu.studio.app import Studio
    from studio_page import free_port

    app = Studio(session, port=free_port())
    try:
        assert app.wait_idle(120)
        yield app
    finally:
        app.stop()


def _read(panel, future):
    assert future is not None
    future.result(timeout=120)
    deadline = time.monotonic() + 30
    while panel._pending is not None and time.monotonic() < deadline:  # the done callback
        time.sleep(0.05)


@pytest.mark.slow  # the read in a spawned process (1-2 s alone, 6-12 s beside the quick loop)
def test_the_page_uploads_reads_and_refuses(studio, tmp_path):
    panel = studio.target_panel
    before = tree(tmp_path)
    # refused at once: nothing written, one line on the page
    for name, content, words in [
        ("../x.xyz", cloud_xyz(10), "has no folders"),
        ("big.xyz", Huge(250_000_000), "is 250.0 MB; an uploaded target may have at most 200 MB"),
    ]:
        assert panel._on_upload(upload_event(name, content)) is None
        assert words in html.unescape(panel.info.content) and panel.target is None
    assert tree(tmp_path) == before

    # a file that does not read: refused after the background read, and removed
    _read(panel, panel._on_upload(upload_event("bad.xyz", b"x y z\nnot numbers\n")))
    said = html.unescape(panel.info.content)
    assert "'targets/bad.xyz' is not a target and was removed" in said
    assert panel.target is None and not (studio.session.files.design_folder / "targets").is_file()
    assert list((studio.session.files.design_folder / "targets").iterdir()) == []

    # a good mesh: shown like a loaded target
    _read(panel, panel._on_upload(upload_event("roof.obj", grid_obj())))
    assert panel.target is not None and panel.target.name == "targets/roof.obj"
    said = html.unescape(panel.info.content)
    assert "uploaded as targets/roof.obj; targets/roof.obj: 50,000 points" in said
    assert panel.file.value == "targets/roof.obj"
    assert studio.coloring == TARGET_COLORING
    assert studio.wait_idle(60) and panel.state is not None
    added = set(tree(tmp_path)) - set(before)
    assert {p for p in added if not p.startswith("out/")} == {"designs/targets/roof.obj"}
    assert all(p.startswith(("designs/targets/", "out/")) for p in added)


# -- in a real browser (``make browser``; ~20 s) ------------------------------------------------
@pytest.mark.slow
def test_the_page_uploads_a_scan_from_the_file_dialog(session, tmp_path):
    pytest.importorskip("viser")
    pytest.importorskip("playwright")
    from playwright.sync_api import sync_playwright

    from browser import CHROMIUM_ARGS, chromium
    from compas_ccu.studio.app import Studio
    from studio_page import free_port, open_page, tab

    exe = chromium()
    if not exe:
        pytest.fail("no chromium for the studio browser tests: run `make browser`")
    mine = tmp_path / "mine"  # the user's computer
    mine.mkdir()
    (mine / "scan.xyz").write_bytes(cloud_xyz())
    (mine / ".hidden.xyz").write_bytes(cloud_xyz())
    app = Studio(session, port=free_port())
    errors = []
    try:
        assert app.wait_idle(60)
        with sync_playwright() as p:
            browser_ = p.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS, headless=True)
            page = open_page(browser_, app.url, log=errors)
            tab(page, "Target")
            upload = page.locator("input[type=file][accept*='.xyz']")
            upload.set_input_files(str(mine / ".hidden.xyz"))
            page.get_by_text("a hidden file name (starting with '.')").wait_for(timeout=20_000)
            upload.set_input_files(str(mine / "scan.xyz"))
            page.get_by_text("uploaded as targets/scan.xyz; targets/scan.xyz: 400 points").wait_for(
                timeout=60_000
            )
            browser_.close()
    finally:
        app.stop()
    assert errors == []
    assert (session.files.design_folder / "targets/scan.xyz").read_bytes() == cloud_xyz()
    assert sorted(p.name for p in (session.files.design_folder / "targets").iterdir()) == [
        "scan.xyz"
    ]
