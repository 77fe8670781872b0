"""Driving the studio page in Debian's chromium with playwright (the browser tests and
``benchmarks/bench_studio.py``): find a control by its label, drag the slider, read the canvas."""

from __future__ import annotations

import io
import os
import re
import socket

import numpy as np

from browser import CHROMIUM_ARGS, chromium  # noqa: F401 - the page tests' browser

VIEWPORT = {"width": 1400, "height": 900}
SHOTS = os.environ.get("CCU_STUDIO_SHOTS")  # folder to keep screenshots in, if set

#: Installed before the page's scripts: the time of the last websocket message and of every
#: animation frame, so a test can tell when an update arrived and was drawn.
PROBE = """
(() => {
  window.__ccu = {messages: 0, lastMessage: 0, frames: 0, lastFrame: 0};
  const Native = window.WebSocket;
  window.WebSocket = function (...args) {
    const ws = new Native(...args);
    ws.addEventListener('message', () => {
      window.__ccu.messages += 1; window.__ccu.lastMessage = performance.now();
    });
    return ws;
  };
  window.WebSocket.prototype = Native.prototype;
  Object.assign(window.WebSocket, Native);
  const tick = (t) => { window.__ccu.frames += 1; window.__ccu.lastFrame = t;
                        requestAnimationFrame(tick); };
  requestAnimationFrame(tick);
})();
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def open_page(browser, url: str, *, log=None):
    """A new page on the studio at ``url``, ready (the scene canvas and the panel are there)."""
    page = browser.new_page(viewport=VIEWPORT, device_scale_factor=1)
    page.add_init_script(PROBE)
    if log is not None:
        page.on("pageerror", lambda e: log.append(str(e)))
    # the studio works offline: any request off this machine fails the page
    page.route(re.compile(r"^(https?|wss?)://(?!127\.0\.0\.1[:/])"), lambda route: route.abort())
    page.goto(url)
    page.wait_for_selector("canvas", timeout=30_000)
    page.wait_for_selector("#ccu-readout", timeout=30_000)
    settle(page)
    return page


def settle(page, ms: int = 300) -> None:
    """Two animation frames and a pause: the last update is drawn."""
    page.evaluate("() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    page.wait_for_timeout(ms)


def field(page, label: str):
    """The input of the control labelled ``label`` (viser's labels are not bound to inputs)."""
    row = page.locator(
        "div.mantine-Flex-root",
        has=page.locator("label", has_text=re.compile(f"^{re.escape(label)}$")),
    )
    return row.last.locator("input").first


def tab(page, name: str) -> None:
    page.get_by_role("tab", name=name).click()
    page.wait_for_timeout(150)


def slider_thumb(page):
    row = page.locator("div.mantine-Flex-root", has=page.locator("label", has_text="α [deg]"))
    return row.last.locator("[role=slider]").first


def drag_slider(page, fraction: float, *, steps: int = 12) -> None:
    """Drag the α slider's thumb to ``fraction`` of the track (0 .. 1)."""
    thumb = slider_thumb(page)
    track = page.locator(".mantine-Slider-track").first.bounding_box()
    box = thumb.bounding_box()
    x0, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x0, y)
    page.mouse.down()
    page.mouse.move(track["x"] + fraction * track["width"], y, steps=steps)
    page.mouse.up()


def canvas(page, name: str = "") -> np.ndarray:
    """(h, w, 3) uint8 screenshot of the 3D view left of the panel."""
    from PIL import Image

    png = page.screenshot(clip={"x": 0, "y": 150, "width": 960, "height": 700})
    if SHOTS and name:
        os.makedirs(SHOTS, exist_ok=True)
        with open(os.path.join(SHOTS, f"studio-{name}.png"), "wb") as f:
            f.write(png)
    return np.array(Image.open(io.BytesIO(png)).convert("RGB"))


def changed(a: np.ndarray, b: np.ndarray) -> float:
    """Mean absolute difference of two pictures (0-255)."""
    return float(np.abs(a.astype(int) - b.astype(int)).mean())


def coloured(img: np.ndarray) -> float:
    """Fraction of coloured pixels (plates, creases): chroma above 20."""
    chroma = img.max(axis=2).astype(int) - img.min(axis=2).astype(int)
    return float((chroma > 20).mean())
