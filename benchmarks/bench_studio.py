"""Latency of the design studio, measured in a real browser (Debian's chromium via playwright).

Run from the repository root (``make bench-studio``)::

    .venv/bin/python benchmarks/bench_studio.py                # the three cases below
    .venv/bin/python benchmarks/bench_studio.py --steps 20     # fewer slider steps / edits
    .venv/bin/python benchmarks/bench_studio.py --out studio.json

The studio runs in this process on a free port; the page runs in headless chromium (software
WebGL). A probe installed before the page's scripts (``tests/studio_page.py``) records when the
pointer moved or a field was typed into, when the page's read-out changed (the server sends it
after the scene update of the same state, so the new geometry has arrived) and the next animation
frame after it (the frame that draws the new geometry). The latency of one step is that frame's
time minus the input's time, all in the page's clock (``performance.now``):

1. **slider step, vault (64 segments)**: the pointer drags the α thumb one step; the view worker
   redeploys, colours and sends the plates, creases and rulings; target p95 <= 50 ms;
2. **parameter edit, vault**: the rise field is typed; the design is validated and rebuilt, the
   view redrawn, and the checks (key figures, bending, collision scan along the path) measured
   and shown: the step ends with the checks panel's update; target p95 <= 300 ms;
3. **slider step, 10 plates x 200 segments**: as 1 on the vault with 200 segments; target p95 <=
   150 ms.

The Python side of each step (redeploy and draw; the checks) is timed too (``python``), and so is
the time from the input to the read-out's (or checks panel's) change in the page (``arrived``:
the update has crossed the websocket and React has put it on the page); the rest, up to the next
animation frame, is the browser drawing it.
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from compas_ccu.design.document import parse_toml  # noqa: E402
from compas_ccu.studio import StudioSession  # noqa: E402
from compas_ccu.studio.app import Studio  # noqa: E402
from compas_ccu.studio.session import document_text  # noqa: E402
from studio_page import CHROMIUM_ARGS, chromium, field, free_port, open_page, tab  # noqa: E402

WATCH = """
() => {
  const c = window.__ccu;
  c.inputAt = 0; c.readoutAt = 0; c.checksAt = 0; c.readoutFrame = 0; c.checksFrame = 0;
  addEventListener('pointermove', () => { c.inputAt = performance.now(); }, true);
  addEventListener('input', () => { c.inputAt = performance.now(); }, true);
  const seen = {readout: '', checks: ''};
  new MutationObserver(() => {
    const r = document.getElementById('ccu-readout');
    const k = document.getElementById('ccu-checks');
    const rt = r ? r.textContent : '', kt = k ? k.textContent : '';
    // the frame after a change draws it: its time ends the step
    if (rt !== seen.readout) { seen.readout = rt; c.readoutAt = performance.now();
      requestAnimationFrame(() => { c.readoutFrame = performance.now(); }); }
    if (k && kt !== seen.checks) { seen.checks = kt; c.checksAt = performance.now();
      requestAnimationFrame(() => { c.checksFrame = performance.now(); }); }
  }).observe(document.body, {subtree: true, childList: true, characterData: true});
}
"""


def _p(values, q):
    return float(np.percentile(values, q)) if values else float("nan")


def _summary(name, latencies, server, arrived, target):
    return {
        "in_page_median_ms": statistics.median(arrived),
        "case": name,
        "steps": len(latencies),
        "median_ms": statistics.median(latencies),
        "p95_ms": _p(latencies, 95),
        "max_ms": max(latencies),
        "server_median_ms": statistics.median(server) if server else None,
        "target_p95_ms": target,
        "ok": _p(latencies, 95) <= target,
    }


def slider_steps(page, studio, steps: int):
    """Drag the α thumb step by step across the track; latency and Python time per step."""
    thumb = page.locator("[role=slider]").first
    track = page.locator(".mantine-Slider-track").first.bounding_box()
    box = thumb.bounding_box()
    y = box["y"] + box["height"] / 2
    page.mouse.move(box["x"] + box["width"] / 2, y)
    page.mouse.down()
    latencies, server, arrived = [], [], []
    xs = track["x"] + track["width"] * np.linspace(0.08, 0.6, steps)
    for x in xs:
        frames = studio.frames
        t_render = studio.render_seconds
        page.mouse.move(float(x), y)
        page.wait_for_function(
            "() => window.__ccu.readoutFrame > window.__ccu.readoutAt"
            " && window.__ccu.readoutAt > window.__ccu.inputAt",
            timeout=30_000,
        )
        latencies.append(page.evaluate("() => window.__ccu.readoutFrame - window.__ccu.inputAt"))
        arrived.append(page.evaluate("() => window.__ccu.readoutAt - window.__ccu.inputAt"))
        if studio.frames > frames:
            server.append(1000 * (studio.render_seconds - t_render) / (studio.frames - frames))
    page.mouse.up()
    return latencies, server, arrived


def edits(page, studio, steps: int):
    """Type rise values; the step ends when the checks panel shows the new design's checks."""
    latencies, server, arrived = [], [], []
    tab(page, "Checks")
    tab(page, "Design")
    for i in range(steps):
        rise = 0.9 + 0.2 * (i % 2) + 0.001 * i
        page.evaluate("() => { window.__ccu.checksAt = 0; }")
        field(page, "rise [m]").fill(f"{rise:.3f}")
        page.wait_for_function(
            "() => window.__ccu.checksFrame > window.__ccu.checksAt"
            " && window.__ccu.checksAt > window.__ccu.inputAt",
            timeout=60_000,
        )
        latencies.append(page.evaluate("() => window.__ccu.checksFrame - window.__ccu.inputAt"))
        arrived.append(page.evaluate("() => window.__ccu.checksAt - window.__ccu.inputAt"))
        studio.wait_idle(60)
        server.append(1000 * studio.checks.seconds)
    return latencies, server, arrived


def run(design: Path, out: Path, browser, *, what: str, steps: int):
    app = Studio(StudioSession.start(design, out=out), port=free_port())
    try:
        app.wait_idle(60)
        page = open_page(browser, app.url)
        page.evaluate(WATCH)
        app.wait_idle(60)
        if what == "slider":
            slider_steps(page, app, 3)  # warm-up
            result = slider_steps(page, app, steps)
        else:
            edits(page, app, 2)
            result = edits(page, app, steps)
        page.close()
        return result
    finally:
        app.stop()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=40, help="slider steps / edits per case")
    parser.add_argument("--out", default=None, help="also write the results as JSON")
    args = parser.parse_args(argv)
    exe = chromium()
    if not exe:
        print("no chromium: run `make browser`", file=sys.stderr)
        return 2
    from playwright.sync_api import sync_playwright

    rows = []
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as p:
        tmp = Path(tmp)
        vault = tmp / "vault.toml"
        vault.write_text((ROOT / "examples" / "vault.toml").read_text())
        fine = parse_toml(vault.read_text())
        fine["crease"]["segments"] = 200
        big = tmp / "vault200.toml"
        big.write_text(document_text(fine))
        browser = p.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS, headless=True)
        try:
            cases = (
                ("slider step, vault 64 segments", vault, "slider", 50.0),
                ("parameter edit (rise), vault", vault, "edit", 300.0),
                ("slider step, 10 plates x 200 segments", big, "slider", 150.0),
            )
            for name, design, what, target in cases:
                lat, server, arrived = run(
                    design, tmp / "out", browser, what=what, steps=args.steps
                )
                rows.append(_summary(name, lat, server, arrived, target))
        finally:
            browser.close()
    print(
        f"{'case':<40} {'steps':>5} {'median':>8} {'p95':>8} {'max':>8} {'python':>8} "
        f"{'arrived':>8} target"
    )
    for r in rows:
        print(
            f"{r['case']:<40} {r['steps']:>5} {r['median_ms']:>6.1f}ms {r['p95_ms']:>6.1f}ms "
            f"{r['max_ms']:>6.1f}ms {r['server_median_ms']:>6.1f}ms "
            f"{r['in_page_median_ms']:>6.1f}ms "
            f"<= {r['target_p95_ms']:g} ms "
            f"{'ok' if r['ok'] else 'MISSED'}"
        )
    if args.out:
        Path(args.out).write_text(
            json.dumps({"machine": platform.platform(), "cases": rows}, indent=1) + "\n"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
