"""The offline viewer page (compas_ccu.viz.viewer), checked in a real headless Chromium.

One page (the vault, 12 steps) is written and opened once for the module; the tests drive it
with the mouse like a user (slider, buttons) and look at screenshots of the 3D scene. They need
Debian's chromium (``make browser``; or set ``CCU_CHROMIUM`` to an executable). Without one the
browser tests fail, unless ``CCU_SKIP_BROWSER=1`` says to skip them.

Pixel statistics are taken on the 3D scene only (the WebGL scene area, ~1095 x 602 px, with the
legend drawn over it masked out). Measured on the vault at 1280 x 800 (SwiftShader WebGL), and
the thresholds used below:

- design state: 10 % of the pixels "coloured" (chroma max(rgb) - min(rgb) > 20, i.e. not the
  white / grey page, panes, grid and labels; threshold 3 %; an empty scene gives 0 %), ~2400
  distinct colours (threshold 200), ~5900 / ~570 pixels within 60 of the synclastic /
  anticlastic crease colour (threshold 40 each);
- slider to α = 0: mean absolute difference 5.9 grey levels against the design picture
  (threshold 3; neighbouring states differ by 2.1), plates coplanar to 0.0 (float32; threshold
  1e-5, the design state 0.2); back to the design: 0.0 (threshold 0.5);
- creases hidden: 0 kind-coloured pixels (threshold < 10), shown again: difference 0.0;
- cut patterns shown: difference 11.9 (threshold 3), anticlastic pixels 570 -> 2580 (threshold:
  more than doubled); hidden again: 0.0 (threshold 0.5).

The module takes ~12 s (one browser, one page load of the 5.9 MB file).
"""

from __future__ import annotations

import base64
import io
import json
import os
import re
from types import SimpleNamespace

import numpy as np
import pytest

from browser import CHROMIUM_ARGS, chromium
from compas_ccu.design.presets import preset_text
from compas_ccu.errors import OptionError
from compas_ccu.fabrication import fabrication_data
from compas_ccu.fabrication.hinges import hinge_strips
from compas_ccu.fabrication.workshop import WorkshopOptions, plan_workshop
from compas_ccu.key_figures import state_figures
from compas_ccu.model import load_model
from compas_ccu.viz.colors import KIND_COLORS
from compas_ccu.viz.viewer import (
    VIEWER_DIV_ID,
    cut_pattern_layout,
    sheet_document,
    sheet_grid_layout,
    viewer_figure,
    write_viewer,
)
from conftest import EXAMPLES

STEPS = 12
VIEWPORT = {"width": 1280, "height": 800}
SHOTS = os.environ.get("CCU_VIEWER_SHOTS")  # folder to keep the screenshots in, if set

# thresholds (see the module docstring for the measured values)
COLOURED_CHROMA = 20  # max(r, g, b) - min(r, g, b) above this: not page / pane / grid / text
MIN_COLOURED = 0.03
MIN_COLOURS = 200
KIND_TOLERANCE = 60.0  # Euclidean RGB distance to a crease kind colour
MIN_KIND_PIXELS = 40
MAX_KIND_PIXELS_HIDDEN = 10
MIN_CHANGE = 3.0  # mean absolute difference (0-255) of a picture that changed
MAX_RETURN = 0.5  # ... and of a picture that came back

GD = f"document.getElementById('{VIEWER_DIV_ID}')"
READY = f"""() => {{
    const gd = {GD};
    return !!(gd && gd._fullLayout && gd._fullLayout.scene && gd._fullLayout.scene._scene
        && gd._transitionData && gd._transitionData._frames.length === {STEPS + 1}
        && document.querySelector('#{VIEWER_DIV_ID} .slider-grip-rect')
        && document.querySelector('#{VIEWER_DIV_ID} #scene canvas'));
}}"""
PLATES_Z = f"JSON.stringify({GD}.data[0].z)"  # the plotted plate z (a typed-array spec)
GROUP_VISIBLE = f"""(group) => {GD}.data
    .filter(t => t.legendgroup === group).map(t => t.visible === undefined || t.visible)"""


# -- fixtures ---------------------------------------------------------------------------------
NO_CHROMIUM = (
    "no chromium found for the viewer browser tests: run `make browser` (installs Debian's "
    "chromium), or set CCU_CHROMIUM to a Chromium executable, or set CCU_SKIP_BROWSER=1 to skip "
    "these tests"
)


class _NoBrowser:
    """Stands in for the open page when there is no chromium: every test using it FAILS."""

    def __getattr__(self, name):
        pytest.fail(NO_CHROMIUM)


def _chromium():
    """The Chromium executable, or None (:func:`browser.chromium`)."""
    return chromium()


@pytest.fixture(scope="module")
def viewer_html(tmp_path_factory, vault_model):
    return write_viewer(vault_model, tmp_path_factory.mktemp("viewer") / "vault.html", steps=STEPS)


@pytest.fixture(scope="module")
def chromium_browser():
    """One headless Chromium for the module (playwright's sync API allows one at a time)."""
    exe = _chromium()
    if not exe:
        yield _NoBrowser()
        return
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS, headless=True)
        try:
            yield browser
        finally:
            browser.close()


@pytest.fixture(scope="module")
def viewer(viewer_html, chromium_browser):
    """The vault viewer open in one headless Chromium page, with its console / request log."""
    if isinstance(chromium_browser, _NoBrowser):
        yield chromium_browser
        return
    log = SimpleNamespace(console=[], errors=[], requests=[])
    page = chromium_browser.new_page(viewport=VIEWPORT, device_scale_factor=1)
    try:
        page.on("console", lambda m: log.console.append((m.type, m.text)))
        page.on("pageerror", lambda e: log.errors.append(str(e)))
        page.on("request", lambda r: log.requests.append(r.url))
        # recorded above; never let the page reach the network
        page.route(re.compile(r"^(https?|wss?|ftp):"), lambda route: route.abort())
        page.goto(viewer_html.as_uri())
        page.wait_for_function(READY, timeout=30_000)
        _settle(page)
        yield SimpleNamespace(page=page, log=log, path=viewer_html)
    finally:
        page.close()


# -- helpers ----------------------------------------------------------------------------------
def _settle(page) -> None:
    """Let plotly finish and WebGL draw: two animation frames and a short pause."""
    page.evaluate("() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    page.wait_for_timeout(150)


def _shot(page, name: str) -> np.ndarray:
    """(h, w, 3) uint8 screenshot of the 3D scene, the legend (drawn over it) set to white."""
    from PIL import Image

    box = page.locator(f"#{VIEWER_DIV_ID} #scene").bounding_box()
    png = page.screenshot(clip=box)
    if SHOTS:
        os.makedirs(SHOTS, exist_ok=True)
        with open(os.path.join(SHOTS, f"viewer-{name}.png"), "wb") as f:
            f.write(png)
    img = np.array(Image.open(io.BytesIO(png)).convert("RGB"))
    legend = page.locator(f"#{VIEWER_DIV_ID} g.legend")
    if legend.count():
        lb = legend.bounding_box()
        x0, y0 = int(lb["x"] - box["x"]) - 2, int(lb["y"] - box["y"]) - 2
        x1, y1 = (
            int(lb["x"] + lb["width"] - box["x"]) + 2,
            int(lb["y"] + lb["height"] - box["y"]) + 2,
        )
        img[max(y0, 0) : max(y1, 0), max(x0, 0) : max(x1, 0)] = 255
    return img


def _coloured(img: np.ndarray) -> float:
    """Fraction of pixels with chroma above COLOURED_CHROMA (plates, creases, rulings)."""
    chroma = img.max(axis=2).astype(int) - img.min(axis=2).astype(int)
    return float(np.mean(chroma > COLOURED_CHROMA))


def _kind_pixels(img: np.ndarray, kind: str) -> int:
    rgb = np.array([int(KIND_COLORS[kind][i : i + 2], 16) for i in (1, 3, 5)], dtype=float)
    return int(np.sum(np.linalg.norm(img.astype(float) - rgb, axis=2) < KIND_TOLERANCE))


def _difference(a: np.ndarray, b: np.ndarray) -> float:
    assert a.shape == b.shape
    return float(np.mean(np.abs(a.astype(float) - b.astype(float))))


def _array(value) -> np.ndarray:
    """A plotly data array as read from ``gd.data``: a list or a ``{dtype, bdata}`` spec."""
    if isinstance(value, dict):
        return np.frombuffer(base64.b64decode(value["bdata"]), dtype=value["dtype"]).astype(float)
    return np.asarray(value, dtype=float)


def _plates(page) -> np.ndarray:
    """(m, 3) plate vertices currently plotted (trace 0, the Mesh3d)."""
    xyz = page.evaluate(f"() => ['x', 'y', 'z'].map(k => {GD}.data[0][k])")
    return np.stack([_array(a) for a in xyz], axis=1)


def _flatness(points: np.ndarray) -> float:
    """Largest distance of the points from their best-fit plane, relative to their extent."""
    centred = points - points.mean(axis=0)
    normal = np.linalg.svd(centred, full_matrices=False)[2][-1]
    return float(np.abs(centred @ normal).max() / np.linalg.norm(np.ptp(points, axis=0)))


def _slider_active(page) -> int:
    return page.evaluate(f"() => {GD}._fullLayout.sliders[0].active")


def _click_button(page, label: str) -> None:
    page.locator(f"#{VIEWER_DIV_ID} g.updatemenu-button", has_text=label).click()


def _structure_pixels(page, name: str) -> int:
    """Pixels that change when the structure (plates, creases, rulings) is hidden."""
    shown = _shot(page, name)
    for label in ("Plates", "Creases", "Rulings"):
        _click_button(page, label)
    page.wait_for_function(f"() => ({GROUP_VISIBLE})('plates').every(v => v !== true)")
    _settle(page)
    hidden = _shot(page, name + "-hidden")
    for label in ("Plates", "Creases", "Rulings"):
        _click_button(page, label)
    page.wait_for_function(f"() => ({GROUP_VISIBLE})('plates').every(v => v === true)")
    _settle(page)
    return int((np.abs(shown.astype(int) - hidden.astype(int)).max(axis=2) > 24).sum())


# -- the written file (no browser) ------------------------------------------------------------
def test_html_is_self_contained(viewer_html):
    html = viewer_html.read_text(encoding="utf-8")
    assert f'<div id="{VIEWER_DIV_ID}"' in html
    # the page outside the inline scripts: no external script, stylesheet, frame or image
    outside = re.sub(r"(<script\b[^>]*>).*?</script>", r"\1</script>", html, flags=re.S)
    tags = re.findall(r"<(script|link|iframe|img)\b([^>]*)>", outside, flags=re.I)
    assert [t for t in tags if t[0].lower() != "script"] == []
    assert all("src" not in attrs.lower() for _, attrs in tags)
    assert not re.search(r"(src|href)\s*=\s*[\"']?(https?:)?//", outside, flags=re.I)
    assert "cdn.plot.ly/plotly" not in html and "mathjax" not in outside.lower()
    # the figure script (the last one) names no URL at all; ':' is not in base64 data
    figure = html[html.rindex("<script") :]
    assert "Plotly.newPlot" in figure and "://" not in figure
    # one frame per state, named 0 .. STEPS
    start = figure.index("[", figure.index(f"Plotly.addFrames('{VIEWER_DIV_ID}',"))
    frames, _ = json.JSONDecoder().raw_decode(figure, start)
    assert [f["name"] for f in frames] == [str(k) for k in range(STEPS + 1)]
    assert 4e6 < viewer_html.stat().st_size < 8e6


def test_figure_states_and_arguments(vault_model):
    from compas_ccu.errors import DeploymentLimitError

    fig = viewer_figure(vault_model, steps=3, alpha=20.0, title="my vault")
    assert len(fig.frames) == 4
    slider = fig.layout.sliders[0]
    assert slider.active == 3 and [s.label for s in slider.steps][::3] == ["0°", "20°"]
    # the page opens on the last state: the initial traces are those of the last frame
    last = fig.frames[-1]
    for k, trace in zip(last.traces, last.data):
        for axis in "xyz":
            np.testing.assert_array_equal(fig.data[k][axis], trace[axis])
    assert "my vault" in fig.layout.title.text
    assert "88.95°" in fig.layout.title.subtitle.text  # the deployment limit
    cut = [t for t in fig.data if t.legendgroup == "cut"]
    assert cut and all(t.visible is False for t in cut)
    # the cut patterns lie on the ground, clear of the structure (all states)
    zs = np.concatenate([np.asarray(t.z, float) for t in cut if t.type == "scatter3d"])
    assert np.nanmax(np.abs(zs)) == 0.0
    structure_y = np.concatenate([np.asarray(f.data[0].y, float) for f in fig.frames])
    cut_y = np.asarray(cut[0].y, float)
    assert cut_y.min() > structure_y.max()  # behind the structure (+y), seen past it

    with pytest.raises(ValueError, match=r"steps.*\b0\b"):
        viewer_figure(vault_model, steps=0)
    with pytest.raises(ValueError, match="-5"):
        viewer_figure(vault_model, alpha=-5)
    with pytest.raises(ValueError, match="nan"):
        viewer_figure(vault_model, alpha=float("nan"))
    with pytest.raises(DeploymentLimitError):
        viewer_figure(vault_model, alpha=95.0, steps=1)


def test_read_out_per_state_and_readable_slider(vault_model):
    fig = viewer_figure(vault_model, steps=24)
    # one read-out per state, from the state's key figures (the slider's own value is hidden)
    states = vault_model.path(np.linspace(0.0, 30.0, 25))
    for frame, s in zip(fig.frames, states):
        (note,) = frame.layout.annotations
        f = state_figures(s)
        assert note.text == (
            f"α = {s.alpha:.4g}° · span {f['crease_span']:.2f} m · rise {f['crease_rise']:.2f} m"
            f" · plate length {f['plate_length']:.2f} m"
        )
    assert fig.layout.annotations[0].text == fig.frames[-1].layout.annotations[0].text
    assert fig.layout.sliders[0].currentvalue.visible is False
    # 25 steps: 7 labels (every 5 deg), not 25 crowding ones; axes readable
    labels = [st.label for st in fig.layout.sliders[0].steps]
    assert [x for x in labels if x] == ["0°", "5°", "10°", "15°", "20°", "25°", "30°"]
    assert fig.layout.scene.xaxis.tickfont.size >= 12 and fig.layout.scene.xaxis.nticks == 6
    assert fig.layout.scene.zaxis.title.font.size >= 14
    # a named camera: orthographic from the front (-y)
    cam = viewer_figure(vault_model, steps=1, view="front").layout.scene.camera
    assert cam.projection.type == "orthographic" and cam.eye.y < 0 and abs(cam.eye.x) < 1e-12


def _outlines(pattern: np.ndarray, n: int) -> list:
    from shapely.geometry import Polygon

    order = np.r_[np.arange(n + 1), np.arange(2 * n + 1, n, -1)]
    return [Polygon(p[order, :2]) for p in pattern]


def _overlap(polys) -> float:
    return max(
        (polys[i].intersection(polys[j]).area for i in range(len(polys)) for j in range(i)),
        default=0.0,
    )


@pytest.fixture(scope="module")
def vault22(tmp_path_factory):
    """The vault with 22 plates (the issue's case: one long row of cut patterns)."""
    text = (
        (EXAMPLES / "vault.toml").read_text(encoding="utf-8").replace("plates = 10", "plates = 22")
    )
    path = tmp_path_factory.mktemp("vault22") / "vault22.toml"
    path.write_text(text.replace('name = "vault"', 'name = "vault22"'), encoding="utf-8")
    return load_model(path)


def test_cut_pattern_layout_is_compact_and_without_overlap(vault_model, vault22):
    for model in (vault_model, vault22):
        s = model.deploy()
        flat, n = np.asarray(s.flat), model.segments
        pts = np.asarray(s.deployed).reshape(-1, 3)
        size = float(np.linalg.norm(np.ptp(pts, axis=0)))
        plan = np.ptp(pts[:, :2], axis=0)
        offsets = cut_pattern_layout(flat, n, gap=0.02 * size, beside=plan)
        moved = flat.copy()
        moved[..., :2] += offsets[:, None, :]
        polys = _outlines(moved, n)
        assert all(p.is_valid for p in polys) and _overlap(polys) == 0.0
        # measured: the vault's block 5.5 x 3.0 m, the 22-plate vault's 8.3 x 4.7 m (size 3.8 m);
        # one nested column (the layout before) was 13.7 m deep for 22 plates
        block = np.ptp(moved[..., :2].reshape(-1, 2), axis=0)
        assert block.max() < 2.5 * size, (block, size)
    with pytest.raises(ValueError, match=r"pattern_offsets must have shape \(22, 2\)"):
        viewer_figure(vault22, steps=1, pattern_offsets=np.zeros((3, 2)))


# -- in the browser ---------------------------------------------------------------------------
@pytest.mark.slow
def test_page_loads_offline_without_errors(viewer):
    errors = [text for kind, text in viewer.log.console if kind == "error"]
    assert errors == [] and viewer.log.errors == []
    assert viewer.log.requests, "no request recorded at all: the listener is not working"
    assert viewer.log.requests[0] == viewer.path.as_uri()
    external = [u for u in viewer.log.requests if not u.startswith(("file:", "data:", "blob:"))]
    assert external == []


@pytest.mark.slow
def test_scene_is_drawn_in_kind_colours(viewer):
    img = _shot(viewer.page, "design")
    assert img.shape[0] > 300 and img.shape[1] > 500
    assert _coloured(img) > MIN_COLOURED
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > MIN_COLOURS
    for kind in ("synclastic", "anticlastic"):
        assert _kind_pixels(img, kind) > MIN_KIND_PIXELS, kind


@pytest.mark.slow
def test_slider_moves_through_the_states(viewer):
    page = viewer.page
    assert _slider_active(page) == STEPS
    before_img, before_xyz, z_before = (
        _shot(page, "design"),
        _plates(page),
        page.evaluate(f"() => {PLATES_Z}"),
    )
    assert _flatness(before_xyz) > 1e-2  # deployed: far from one plane

    # click the left end of the rail: the first state, the flat-folded stack
    rail = page.locator(f"#{VIEWER_DIV_ID} .slider-rail-rect").bounding_box()
    page.mouse.click(rail["x"] + 2, rail["y"] + rail["height"] / 2)
    page.wait_for_function(f"() => {GD}._fullLayout.sliders[0].active === 0")
    page.wait_for_function(f"(before) => {PLATES_Z} !== before", arg=z_before)
    _settle(page)
    # the read-out of the state (α, span, rise, plate length) follows the slider
    current = page.locator(f"#{VIEWER_DIV_ID} g.annotation-text-g").first.text_content()
    assert current == "α = 0° · span 2.72 m · rise 0.90 m · plate length 2.72 m", current
    folded_xyz = _plates(page)
    assert _flatness(folded_xyz) < 1e-5  # α = 0: all plates in one plane (float32 data)
    folded_img = _shot(page, "folded")
    assert _difference(folded_img, before_img) > MIN_CHANGE

    # drag the grip back to the right end: the design state again
    grip = page.locator(f"#{VIEWER_DIV_ID} .slider-grip-rect").bounding_box()
    page.mouse.move(grip["x"] + grip["width"] / 2, grip["y"] + grip["height"] / 2)
    page.mouse.down()
    page.mouse.move(rail["x"] + rail["width"] + 20, grip["y"] + grip["height"] / 2, steps=12)
    page.mouse.up()
    page.wait_for_function(f"() => {GD}._fullLayout.sliders[0].active === {STEPS}")
    page.wait_for_function(f"(before) => {PLATES_Z} === before", arg=z_before)
    _settle(page)
    np.testing.assert_array_equal(_plates(page), before_xyz)
    assert _difference(_shot(page, "returned"), before_img) < MAX_RETURN


@pytest.mark.slow
def test_creases_toggle(viewer):
    page = viewer.page
    shown = _shot(page, "design")
    assert page.evaluate(GROUP_VISIBLE, "creases") == [True, True]

    _click_button(page, "Creases")
    page.wait_for_function(f"() => ({GROUP_VISIBLE})('creases').every(v => v !== true)")
    _settle(page)
    hidden = _shot(page, "no-creases")
    assert page.evaluate(GROUP_VISIBLE, "creases") == ["legendonly", "legendonly"]
    for kind in ("synclastic", "anticlastic"):
        assert _kind_pixels(hidden, kind) < MAX_KIND_PIXELS_HIDDEN, kind
    assert "☐ Creases" in page.locator(f"#{VIEWER_DIV_ID} g.updatemenu-button").all_text_contents()

    _click_button(page, "Creases")
    page.wait_for_function(f"() => ({GROUP_VISIBLE})('creases').every(v => v === true)")
    _settle(page)
    again = _shot(page, "creases-again")
    for kind in ("synclastic", "anticlastic"):
        assert _kind_pixels(again, kind) > MIN_KIND_PIXELS, kind
    assert _difference(again, shown) < MAX_RETURN


@pytest.mark.slow
def test_cut_patterns_toggle(viewer):
    page = viewer.page
    start = _shot(page, "design")
    assert set(page.evaluate(GROUP_VISIBLE, "cut")) == {False}
    y_range = page.evaluate(f"() => {GD}._fullLayout.scene.yaxis.range.slice()")

    _click_button(page, "Cut patterns")
    page.wait_for_function(f"() => ({GROUP_VISIBLE})('cut').every(v => v === true)")
    _settle(page)
    shown = _shot(page, "cut-patterns")
    assert _difference(shown, start) > MIN_CHANGE
    # every crease appears on both of its plates' patterns: many more anticlastic pixels
    assert _kind_pixels(shown, "anticlastic") > 2 * _kind_pixels(start, "anticlastic")
    assert _kind_pixels(shown, "synclastic") > MIN_KIND_PIXELS
    # the box grew to hold the patterns, which lie on the ground behind the structure (+y)
    cut_y = _array(page.evaluate(f"() => {GD}.data.find(t => t.legendgroup === 'cut').y"))
    wide = page.evaluate(f"() => {GD}._fullLayout.scene.yaxis.range.slice()")
    assert wide[1] > y_range[1] and wide[1] >= cut_y.max() and cut_y.min() > y_range[1]

    _click_button(page, "Cut patterns")
    page.wait_for_function(f"() => ({GROUP_VISIBLE})('cut').every(v => v === false)")
    _settle(page)
    assert page.evaluate(f"() => {GD}._fullLayout.scene.yaxis.range.slice()") == y_range
    assert _difference(_shot(page, "cut-hidden"), start) < MAX_RETURN


@pytest.mark.slow
def test_play_deploys_from_the_folded_stack(viewer):
    page = viewer.page
    assert _slider_active(page) == STEPS
    _click_button(page, "Play")
    # the animation starts at the flat-folded stack and stops at the design state; it plays
    # STEPS frames of 140 ms and every frame redraws the plates and the read-out, which takes
    # up to a second per frame with software WebGL on a busy machine: allow for the slowest
    slow = 120_000
    page.wait_for_function(f"() => {GD}._fullLayout.sliders[0].active < {STEPS // 2}")
    page.wait_for_function(f"() => {GD}._fullLayout.sliders[0].active === {STEPS}", timeout=slow)
    page.wait_for_function(f"() => !{GD}._transitionData._animationRaf", timeout=slow)
    _settle(page)
    assert _flatness(_plates(page)) > 1e-2


def _open_and_show_cut_patterns(browser, path, name: str, shots: dict):
    """Open a 2-step viewer page, count the structure's pixels, show the cut patterns and
    count them again: the page (still open), pixels alone, pixels with the cut patterns;
    ``shots`` gets the screenshots before and after ("start", "shown")."""
    ready = READY.replace(f"=== {STEPS + 1}", "=== 3")
    page = browser.new_page(viewport=VIEWPORT, device_scale_factor=1)
    page.goto(path.as_uri())
    page.wait_for_function(ready, timeout=30_000)
    _settle(page)
    alone = _structure_pixels(page, f"{name}-alone")
    shots["start"] = _shot(page, f"{name}-start")
    _click_button(page, "Cut patterns")
    page.wait_for_function(f"() => ({GROUP_VISIBLE})('cut').every(v => v === true)")
    _settle(page)
    shots["shown"] = _shot(page, f"{name}-shown")
    return page, alone, _structure_pixels(page, f"{name}-cut")


@pytest.mark.slow
def test_cut_patterns_leave_the_structure_visible(vault22, tmp_path, chromium_browser):
    """22 plates: with the cut patterns shown the structure keeps a good part of its screen area
    and the patterns plotted in the page do not overlap."""
    path = write_viewer(vault22, tmp_path / "vault22.html", steps=2)
    page, alone, with_cut = _open_and_show_cut_patterns(chromium_browser, path, "22", {})
    try:
        # the patterns as plotted: x, y of the cut Mesh3d, one plate after the other
        xy = page.evaluate(
            f"() => {{const t = {GD}.data.find(t => t.legendgroup === 'cut'); return [t.x, t.y];}}"
        )
    finally:
        page.close()
    # measured: 140 000 px alone, 20 100 px with the patterns (14 %); the layout before (one
    # nested column in front, an 18 m deep box) left 2 200 px (1.5 %)
    assert alone > 50_000
    assert with_cut > 0.08 * alone, (with_cut, alone)
    x, y = (_array(a) for a in xy)
    n = vault22.segments
    pattern = np.stack([x, y], axis=1).reshape(22, 2 * n + 2, 2)
    assert _overlap(_outlines(pattern, n)) < 1e-9


# -- the fabrication's sheets as the cut patterns -----------------------------------------------
def _plan(model, **options):
    """The workshop plan of a model, nested by shelves (fast: the tests are not about spyrrow)."""
    data = fabrication_data(model)
    opts = WorkshopOptions.from_section(model.design.fabrication, nesting="shelf", **options)
    return plan_workshop(data, hinge_strips(data), opts, density=500.0)


@pytest.fixture(scope="module")
def dome22(tmp_path_factory):
    """The dome preset with 22 plates (docs/fabrication.md's many-plate case)."""
    text = preset_text("dome", name="dome22").replace("plates = 12 ", "plates = 22 ")
    path = tmp_path_factory.mktemp("dome22") / "dome22.toml"
    path.write_text(text, encoding="utf-8")
    return load_model(path)


@pytest.fixture(scope="module")
def plans(vault_model, overbent_model, vault22, dome22):
    """model name -> (model, plan): the design's sheets (the vault's 3.05 x 1.525 m take its
    plates whole; the 8 mm overbent vault is spliced on the default 2.5 x 1.25 m), by shelves."""
    models = (vault_model, overbent_model, vault22, dome22)
    return _Plans({m.design.name: m for m in models})


class _Plans(dict):
    """model name -> (model, plan), each plan made when a test first asks for it (a process
    of a parallel run makes only its tests' plans)."""

    def __init__(self, models):
        super().__init__()
        self.models = models

    def __missing__(self, name):
        model = self.models[name]
        value = self[name] = (model, _plan(model))
        return value


def _split(trace) -> list:
    """The polylines of a line trace (NaN rows separate them), as (k, 3) float64 arrays."""
    xyz = np.stack([np.asarray(trace[a], dtype=float) for a in "xyz"], axis=1)
    gaps = np.flatnonzero(np.isnan(xyz[:, 0]))
    chunks = [c[~np.isnan(c[:, 0])] for c in np.split(xyz, gaps)]
    return [c for c in chunks if len(c)]


def _figure_sheets(fig, plan):
    """(sheet corners (s, 2), sheet sizes (s, 2), per part its (m, 3) points) as plotted."""
    cut = [t for t in fig.data if t.legendgroup == "cut"]
    edges = next(t for t in cut if t.name == "sheet edges")
    rects = _split(edges)
    corners = np.array([r[0, :2] for r in rects])
    sizes = np.array([np.ptp(r[:, :2], axis=0) for r in rects])
    mesh = cut[0]  # the parts' fill, the first cut trace
    xyz = np.stack([np.asarray(mesh[a], dtype=float) for a in "xyz"], axis=1)
    bounds = np.cumsum([0] + [len(p.outline) for p in plan.parts])
    return corners, sizes, [xyz[a:b] for a, b in zip(bounds, bounds[1:])]


@pytest.mark.parametrize(
    ("name", "counts"),
    [("vault", (10, 10)), ("overbent", (15, 40)), ("vault22", (22, 22)), ("dome22", (30, 88))],
)
def test_sheets_show_every_part_at_its_nested_place(plans, name, counts):
    from shapely.geometry import Polygon, box

    model, plan = plans[name]
    assert (len(plan.sheets), len(plan.parts)) == counts
    fig = viewer_figure(model, steps=1, sheets=plan)
    cut = [t for t in fig.data if t.legendgroup == "cut"]
    assert all(t.visible is False for t in cut)
    assert cut[0].name == f"cut patterns: {counts[0]} sheets, {counts[1]} parts"
    corners, sizes, parts = _figure_sheets(fig, plan)
    assert len(corners) == len(plan.sheets) and len(parts) == len(plan.parts)
    np.testing.assert_allclose(sizes, [s["size"] for s in plan.sheets], rtol=0, atol=1e-12)
    inset = plan.options.inset
    polys = []
    for part, pts in zip(plan.parts, parts):
        local = pts[:, :2] - corners[part.sheet]
        # exactly the sheet DXF's placement (float64 in the page), inside the usable sheet
        assert np.abs(local - part.placed(part.outline)).max() < 1e-12, part.name
        length, width = plan.sheets[part.sheet]["size"]
        assert local.min() >= inset - 1e-9, part.name
        assert (local <= np.array([length, width]) - inset + 1e-9).all(), part.name
        polys.append(Polygon(pts[:, :2]))
    assert all(p.is_valid and p.area > 0 for p in polys)
    # no two parts overlap: on one sheet they keep kerf + bridge apart, sheets are disjoint
    for i in range(len(polys)):
        for j in range(i):
            gap = polys[i].distance(polys[j])
            assert gap >= plan.options.spacing - 1e-9, (plan.parts[i].name, plan.parts[j].name)
    rects = [box(*c, *(c + s)) for c, s in zip(corners, sizes)]
    assert (
        max(rects[i].intersection(rects[j]).area for i in range(len(rects)) for j in range(i)) == 0
    )
    # the sheets lie around the structure's plan (all states), never under it
    plates = np.concatenate([np.stack([f.data[0].x, f.data[0].y], 1) for f in fig.frames])
    plan_box = box(*plates.min(axis=0), *plates.max(axis=0))
    assert all(not r.intersects(plan_box) for r in rects)
    # compact: a grid about as deep as wide, not one long row
    everything = np.r_[corners, corners + sizes, plates]
    extent = np.ptp(everything, axis=0)
    assert extent.max() < 1.6 * extent.min(), extent
    # every crease edge of every part, in its kind's trace, on the part's outline
    for kind in ("synclastic", "anticlastic"):
        lines = _split(next(t for t in cut if t.name == f"sheets: {kind}"))
        expected = [(p, c) for p in plan.parts for c in p.creases if c["kind"] == kind]
        assert len(lines) == len(expected) > 0
        for line, (part, c) in zip(lines, expected):
            local = line[:, :2] - corners[part.sheet]
            assert np.abs(local - part.placed(c["points"])).max() < 1e-12
    # the plate parts carry their plates' creases, the splice plates none
    assert all(not p.creases for p in plan.parts if p.kind == "splice")
    workshop = {m: k for k, m in enumerate(plan.model_plate_ids)}
    on_parts = sum(
        len(plan.splits[workshop[pid]]) + 1 for c in model.deploy().creases for pid in c["plates"]
    )  # every crease runs along its two plates, so it is on every part of both
    assert sum(len(p.creases) for p in plan.parts) == on_parts
    labels = next(t for t in cut if t.name == "sheet numbers")
    assert list(labels.text)[0].startswith("sheet 1 · ")
    assert sorted(next(t for t in cut if t.name == "part names").text) == sorted(
        p.name for p in plan.parts
    )


def test_sheets_are_refused_for_another_design_or_other_plates(plans, vault_model, vault22):
    _, vault_plan = plans["vault"]
    with pytest.raises(OptionError, match="the nesting is of design 'vault', not of 'vault22'"):
        viewer_figure(vault22, steps=1, sheets=vault_plan)
    doc = vault_plan.layout()
    doc["design"] = None  # a nesting without its design's name: the plates still must match
    with pytest.raises(OptionError, match=r"the nesting is of 10 plates .*the model has 22"):
        viewer_figure(vault22, steps=1, sheets=doc)
    with pytest.raises(OptionError, match="give sheets or pattern_offsets, not both"):
        viewer_figure(vault_model, steps=1, sheets=doc, pattern_offsets=np.zeros((10, 2)))
    with pytest.raises(OptionError, match="has no parts list"):
        sheet_document({"sheets": []})
    with pytest.raises(OptionError, match="a workshop plan or its layout"):
        sheet_document([1, 2])
    bad = {**doc, "parts": [{**doc["parts"][0], "sheet": 99}]}
    with pytest.raises(OptionError, match="part 'P0' is on sheet 99, but there are 10 sheets"):
        sheet_document(bad, vault_model.plate_ids)
    # the plan and its JSON document (sheets.json) draw the same figure
    a = viewer_figure(vault_model, steps=1, sheets=vault_plan)
    b = viewer_figure(vault_model, steps=1, sheets=json.loads(json.dumps(vault_plan.layout())))
    for ta, tb in zip(a.data, b.data):
        for axis in "xyz":
            np.testing.assert_array_equal(np.asarray(ta[axis]), np.asarray(tb[axis]))


def test_sheet_grid_layout_is_compact_and_clear_of_the_structure():
    plan = (-1.4, -1.3, 1.4, 1.3)  # the structure's plan box, 2.8 x 2.6 m
    for count, columns, beside, extent in ((12, 3, 0, (7.7, 8.05)), (20, 4, 4, (10.3, 8.05))):
        sizes = np.array([[2.5, 1.25]] * count)
        corners = sheet_grid_layout(sizes, gap=0.1, structure=plan)
        # cells of 2.6 x 1.35 m from the structure's front (y = -1.3) backwards, centred on it
        np.testing.assert_allclose(
            np.ptp(corners, axis=0), [2.6 * (columns - 1), np.ptp(corners[:, 1])], atol=1e-12
        )
        assert np.allclose((corners[:, 1] + 1.3 - 0.05) / 1.35 % 1.0, 0.0, atol=1e-9)
        lo = np.minimum(corners.min(axis=0), plan[:2])
        hi = np.maximum((corners + sizes).max(axis=0), plan[2:])
        np.testing.assert_allclose(hi - lo, extent, atol=1e-12)
        # 20 sheets: four in the structure's rows, beside it (clear of its plan by a gap / 2)
        side = corners[:, 1] < plan[3]
        assert side.sum() == beside
        assert ((corners[side, 0] >= 1.45) | (corners[side, 0] + 2.5 <= -1.45)).all()
        assert (corners[~side, 1] >= plan[3] + 0.05 - 1e-12).all()
    # without a structure: the grid alone from the origin, as square as the sheets allow
    alone = sheet_grid_layout(np.array([[2.5, 1.25]] * 12), gap=0.1)
    np.testing.assert_allclose(alone.min(axis=0), [0.05, 0.05], atol=1e-12)
    np.testing.assert_allclose(np.ptp(alone, axis=0), [5.2, 4.05], atol=1e-12)


@pytest.mark.slow
def test_sheets_toggle_shows_the_nesting_and_keeps_the_structure_visible(
    vault22, tmp_path, chromium_browser
):
    """The 22-plate vault with its sheets (2.8 x 2.1 m: 11 sheets, 22 whole plates): the cut
    patterns toggle shows the sheets, and the structure keeps a good part of its screen area."""
    plan = _plan(vault22, sheets=((2.8, 2.1),))
    path = write_viewer(vault22, tmp_path / "vault22-sheets.html", steps=2, sheets=plan)
    shots = {}
    page, alone, with_sheets = _open_and_show_cut_patterns(
        chromium_browser, path, "22-sheets", shots
    )
    start, shown = shots["start"], shots["shown"]
    try:
        plotted = page.evaluate(
            f"""() => {GD}.data.filter(t => t.legendgroup === 'cut')
                .map(t => [t.name, t.x, t.y, t.text || null])"""
        )
    finally:
        page.close()
    assert _difference(shown, start) > MIN_CHANGE
    assert alone > 50_000
    assert with_sheets > 0.08 * alone, (with_sheets, alone)
    by_name = {name: (x, y, text) for name, x, y, text in plotted}
    x, y, _ = by_name["sheet edges"]
    rects = _split({"x": _array(x), "y": _array(y), "z": np.zeros(len(_array(x)))})
    assert len(rects) == len(plan.sheets) == 11
    labels = by_name["sheet numbers"][2]
    assert [t.split(" · ")[0] for t in labels] == [f"sheet {k + 1}" for k in range(11)]
    assert sorted(by_name["part names"][2]) == sorted(p.name for p in plan.parts)
