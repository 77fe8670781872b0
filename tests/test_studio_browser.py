"""The studio in a real browser: Debian's chromium driven by playwright (``make browser``).

The studio runs in this process on a free port (one server per test module, restarted for the
recovery test); every test acts on the page as a designer would and checks the page *and* the
session behind it. Set ``CCU_STUDIO_SHOTS=DIR`` to keep the screenshots.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import time

import numpy as np
import pytest
from playwright.sync_api import expect

from compas_ccu.catalog import catalog_path
from compas_ccu.design.document import parse_toml
from compas_ccu.studio import StudioSession
from compas_ccu.viz.colors import KIND_COLORS
from conftest import EXAMPLES  # noqa: E402
from studio_page import (  # noqa: E402
    CHROMIUM_ARGS,
    canvas,
    changed,
    chromium,
    coloured,
    drag_slider,
    field,
    free_port,
    open_page,
    settle,
    tab,
)

pytestmark = [pytest.mark.slow, pytest.mark.in_order]  # they share one page: in file order
pytest.importorskip("viser")
Studio = pytest.importorskip("compas_ccu.studio.app").Studio

MIN_CHANGE = 2.0  # mean absolute difference (0-255) of a view that changed
SAME = 0.5  # ... and of one that did not


def _wait(predicate, timeout: float = 20.0, what: str = "condition") -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    root = tmp_path_factory.mktemp("studio")
    design = root / "designs"
    design.mkdir()
    shutil.copy(EXAMPLES / "vault.toml", design / "vault.toml")
    (root / "secret.toml").write_text("# outside the design folder\n")
    return design, root / "out"


@pytest.fixture(scope="module")
def browser():
    exe = chromium()
    if not exe:
        pytest.fail("no chromium for the studio browser tests: run `make browser`")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS, headless=True)
        try:
            yield b
        finally:
            b.close()


@pytest.fixture(scope="module")
def studio(folders):
    design, out = folders
    app = Studio(StudioSession.start(design / "vault.toml", out=out), port=free_port())
    assert app.wait_idle(60)
    try:
        yield app
    finally:
        app.stop()


@pytest.fixture(scope="module")
def page(browser, studio):
    errors = []
    page = open_page(browser, studio.url, log=errors)
    _wait(studio.wait_idle, what="the first frame")
    settle(page)
    yield page
    assert errors == []


def _idle(studio, page):
    assert studio.wait_idle(60)
    settle(page)


def _readout(page) -> str:
    return page.locator("#ccu-readout").inner_text()


# -- tests (in order: they share one page) -----------------------------------------------------
def test_the_page_shows_the_vault_offline(page, studio):
    img = canvas(page, "start")
    assert coloured(img) > 0.01, "no plates or creases drawn"
    text = _readout(page)
    assert "α = 30.00°" in text and "span 2.500 m" in text and "rise 1.000 m" in text
    assert page.locator("#ccu-state").inner_text() == "exact kinematics"


def _near(img, color: str, tol: int = 45) -> int:
    """Pixels within ``tol`` (per channel) of ``color``."""
    rgb = np.array([int(color[i : i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(img.astype(int) - rgb).max(axis=2) <= tol).sum())


def test_creases_are_drawn_in_their_legend_colours(page, studio):
    img = canvas(page, "kinds")
    legend = page.get_by_text("synclastic (CCU, Σβ < 2π): 5")
    assert legend.count() == 1 and page.get_by_text("anticlastic (CCU, Σβ > 2π): 4").count() == 1
    # the vault's 5 synclastic creases blue, 4 anticlastic pink: both colours on the canvas
    blue, pink = _near(img, KIND_COLORS["synclastic"]), _near(img, KIND_COLORS["anticlastic"])
    assert blue > 300 and pink > 100, (blue, pink)


def test_dragging_the_slider_redeploys_live(page, studio):
    before = canvas(page)
    frames = studio.frames
    drag_slider(page, 0.75)
    _idle(studio, page)
    after = canvas(page, "dragged")
    assert changed(before, after) > MIN_CHANGE
    assert studio.frames > frames + 1, "the drag drew only its end"
    alpha = float(studio.alpha)
    assert 55.0 < alpha < 75.0
    model = studio.session.model
    s = model.deploy(alpha, check=False)
    text = _readout(page)
    assert f"α = {alpha:.2f}°" in text
    assert f"span {s.metrics['span']:.3f} m" in text and f"rise {s.metrics['rise']:.3f} m" in text


def test_an_invalid_rise_shows_the_cli_message_and_keeps_the_model(page, studio):
    before = canvas(page)
    model = studio.session.model
    field(page, "rise [m]").fill("-1")
    _wait(lambda: studio.session.problem is not None, what="the edit")
    _idle(studio, page)
    message = "crease.rise: must be > 0 and <= 1e6, got -1.0"
    page.get_by_text(message).first.wait_for(timeout=10_000)
    assert studio.session.model is model
    assert changed(before, canvas(page, "invalid")) < SAME, "the last valid model must stay"
    field(page, "rise [m]").fill("1.0")
    _wait(lambda: studio.session.problem is None, what="the valid rise")
    _idle(studio, page)
    assert (
        page.get_by_text(message).count() == 0 or not page.get_by_text(message).first.is_visible()
    )


def test_plates_ten_to_six_updates_drawing_and_checks(page, studio):
    tab(page, "Checks")
    page.locator("#ccu-checks").wait_for()
    mass10 = studio.checks.figures.mass
    assert f"{mass10:.4g} kg" in page.locator("#ccu-checks").inner_text()
    before = canvas(page)
    tab(page, "Design")
    field(page, "plates").fill("6")
    _wait(lambda: studio.session.model.plates.count == 6, what="6 plates")
    _idle(studio, page)
    _wait(lambda: studio.checks.figures.plates == 6, what="the checks of 6 plates")
    _idle(studio, page)
    mass6 = studio.checks.figures.mass
    assert abs(mass6 - mass10 * 6 / 10) < 1e-9 * mass10
    assert changed(before, canvas(page, "six")) > MIN_CHANGE
    tab(page, "Checks")
    assert f"{mass6:.4g} kg" in page.locator("#ccu-checks").inner_text()


def test_save_writes_a_toml_that_ccu_info_reads(page, studio, folders):
    design, _ = folders
    tab(page, "File")
    page.get_by_role("button", name="Save", exact=True).click()
    _wait(lambda: studio.session.saved, what="the save")
    path = design / "vault.toml"
    values = parse_toml(path.read_text())
    assert values["layout"]["plates"] == 6 and values["crease"]["rise"] == 1.0
    run = subprocess.run(
        [sys.executable, "-m", "compas_ccu.cli", "info", str(path)], capture_output=True, text=True
    )
    assert run.returncode == 0 and "plates            6" in run.stdout, run.stdout + run.stderr
    page.get_by_text(f"saved {path}").wait_for(timeout=5_000)


def test_undo_restores_the_previous_design(page, studio):
    page.get_by_role("button", name="Undo", exact=True).click()
    _wait(lambda: studio.session.model.plates.count == 10, what="undo")
    _idle(studio, page)
    tab(page, "Design")
    expect(field(page, "plates")).to_have_value("10")  # the page follows the server
    tab(page, "File")
    page.get_by_role("button", name="Redo", exact=True).click()
    _wait(lambda: studio.session.model.plates.count == 6, what="redo")


def test_path_traversal_is_refused(page, studio, folders):
    design, _ = folders
    root = design.parent
    for name in ("../secret.toml", str(root / "secret.toml"), "/tmp/x.toml", "sub/../../x.toml"):
        said = studio.file_panel.content
        field(page, "save as").fill(name)
        # the click must reach the server after the name (viser throttles control updates)
        _wait(lambda n=name: studio.save_name.value == n, what="the name on the server")
        page.get_by_role("button", name="Save as", exact=True).click()
        _wait(lambda s=said: studio.file_panel.content != s, what="the answer to save as")
        assert "not saved:" in studio.file_panel.content, studio.file_panel.content
        page.get_by_text("not saved:").first.wait_for(timeout=10_000)
    assert (root / "secret.toml").read_text() == "# outside the design folder\n"
    assert not (root / "x.toml").exists()
    field(page, "save as").fill("vault.toml")


def test_a_failing_design_keeps_the_server_alive(page, studio):
    tab(page, "Design")
    page.get_by_role("tab", name="Design").click()
    model = studio.session.model
    field(page, "spacing [m]").fill("[0.1, 0.1]")  # 2 spacings for 6 plates
    _wait(lambda: studio.session.problem is not None, what="the failing edit")
    assert studio.session.model is model
    before = canvas(page)
    drag_slider(page, 0.2)
    _idle(studio, page)
    assert changed(before, canvas(page)) > MIN_CHANGE  # still live
    field(page, "spacing [m]").fill("0.12")
    _wait(lambda: studio.session.problem is None, what="the repair")


def test_a_binary_or_oversized_upload_is_refused_on_the_page(page, studio, tmp_path):
    tab(page, "Design")
    name = studio.session.name
    binary = tmp_path / "picture.toml"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00")
    page.locator("input[type=file]").first.set_input_files(str(binary))
    page.get_by_text("'picture.toml' is not a text file").first.wait_for(timeout=10_000)
    big = tmp_path / "big.toml"
    big.write_bytes(b"# " + b"x" * 1_100_000)
    page.locator("input[type=file]").first.set_input_files(str(big))
    page.get_by_text("a design file may have at most 1,000,000 bytes").first.wait_for(
        timeout=20_000
    )
    assert studio.session.name == name  # nothing changed


def test_two_tabs_show_the_same_design(browser, page, studio):
    other = open_page(browser, studio.url)
    try:
        field(page, "rise [m]").fill("0.9")
        _wait(lambda: studio.session.model.design.crease.rise == 0.9, what="the edit")
        _idle(studio, other)
        _wait(lambda: field(other, "rise [m]").input_value() == "0.9", 10, "the other tab")
        assert "rise 0.9" in _readout(other) or studio.alpha != studio.session.model.alpha_design
    finally:
        other.close()


def test_the_recovery_copy_survives_a_restart(browser, studio, folders):
    design, out = folders
    assert not studio.session.saved  # rise 0.9 is not saved
    studio.stop()
    again = Studio(StudioSession.start(design / "vault.toml", out=out), port=free_port())
    try:
        assert again.wait_idle(60)
        assert again.session.model.design.crease.rise == 0.9
        page = open_page(browser, again.url)
        try:
            page.get_by_text("restored unsaved edits of vault.toml").wait_for(timeout=10_000)
            expect(field(page, "rise [m]")).to_have_value("0.9")
        finally:
            page.close()
    finally:
        again.stop()


def test_a_stale_recovery_copy_is_offered_on_the_page(browser, tmp_path):
    """A recovery copy older than the file is not restored: the page says so and offers both."""
    path = tmp_path / "vault.toml"
    shutil.copy(EXAMPLES / "vault.toml", path)
    StudioSession.start(path, out=tmp_path / "out").edit("crease", "rise", 0.85)
    path.write_text(path.read_text() + "\n# changed by someone else\n")
    app = Studio(StudioSession.start(path, out=tmp_path / "out"), port=free_port())
    try:
        assert app.wait_idle(60)
        assert app.session.recovery is not None and app.session.model.design.crease.rise == 1.0
        page = open_page(browser, app.url)
        try:
            page.get_by_text("is older than the file (it changed since)").wait_for(timeout=10_000)
            tab(page, "File")
            page.get_by_role("button", name="Restore it", exact=True).click()
            _wait(lambda: app.session.model.design.crease.rise == 0.85, what="the restore")
            page.get_by_text("restored the recovery copy of vault.toml").first.wait_for(
                timeout=10_000
            )
            assert app.session.recovery is None and not app.session.saved
        finally:
            page.close()
    finally:
        app.stop()


def test_an_inclined_layout_shows_the_rigid_model_then_the_relaxed_one(browser, tmp_path):
    design = tmp_path / "fig12a.toml"
    design.write_text(catalog_path("fig12a-asymmetric").read_text())
    app = Studio(StudioSession.start(design, out=tmp_path / "out"), port=free_port())
    states = []
    render = app._render

    def recording():
        render()
        states.append((app.state, app.last_view.vertices.copy(), app.last_view.alpha))

    app._view._job = recording
    try:
        assert app.wait_idle(60)
        page = open_page(browser, app.url)
        try:
            assert page.locator("#ccu-state").inner_text() == "exact kinematics"  # design state
            drag_slider(page, 0.55)
            page.get_by_text("relaxed model").first.wait_for(timeout=20_000)
            _idle(app, page)
        finally:
            page.close()
        last = [s for s in states if s[2] == app.alpha]
        kinds = [s[0].split(" ")[0] for s in last]
        assert kinds[0] == "relaxing" and kinds[-1] == "relaxed", kinds
        model = app.session.model
        rigid = model.vertices([app.alpha])[0]
        moved = np.abs(last[-1][1] - rigid).max()
        assert np.array_equal(last[0][1], rigid) and 1e-6 < moved < 0.05 * model.size
    finally:
        app.stop()
