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
   and shown: the step ends with the checks panel's update; target p95 <= 300 ms (the frame
   that first draws the new geometry, when the read-out's rise changes, is recorded too: the
   view of an edit does not wait for its checks);
3. **slider step, 10 plates x 200 segments**: as 1 on the vault with 200 segments; target p95 <=
   150 ms;
4. **continuous drag, vault**: a real pointer drag over the α slider, one pointer move every
   1/60 s for ``--drag-seconds`` (default 3 s) from 8 % to 60 % of the track, the pointer's
   position a function of time as a hand drags it.
   Recorded in the page: every pointer move (time, x), every animation frame, every change of
   the read-out (its α) and the frame after it. An update's latency is that frame minus the
   moment the pointer passed the α it shows (interpolated between the recorded moves); the
   frame intervals during the drag say how smoothly the page redraws; target latency p95 <= 50
   ms.

``--gpu`` runs the slider cases (1, 3, 4) in a chromium allowed to use the GPU (hardware WebGL)
and says "no GPU found" (exit 3) when the page's WebGL renderer is a software one (SwiftShader,
llvmpipe) or no GPU device is present: on a machine with a GPU that checks the 50 ms slider goal
(``make bench-studio-gpu``).

The Python side of each step (redeploy and draw; the checks) is timed too (``python``), and so is
the time from the input to the read-out's (or checks panel's) change in the page (``arrived``:
the update has crossed the websocket and React has put it on the page); the rest, up to the next
animation frame, is the browser drawing it.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import tempfile
import time
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
  c.riseFrame = 0;
  addEventListener('pointermove', () => { c.inputAt = performance.now(); }, true);
  addEventListener('input', () => { c.inputAt = performance.now(); c.riseFrame = 0; }, true);
  const seen = {readout: '', checks: '', rise: ''};
  new MutationObserver(() => {
    const r = document.getElementById('ccu-readout');
    const k = document.getElementById('ccu-checks');
    const rt = r ? r.textContent : '', kt = k ? k.textContent : '';
    // the frame after a change draws it: its time ends the step
    if (rt !== seen.readout) { seen.readout = rt; c.readoutAt = performance.now();
      requestAnimationFrame(() => { c.readoutFrame = performance.now(); }); }
    // the read-out's rise changes with the first view of an edited design: its geometry
    const rise = (rt.match(/rise ([0-9.]+) m/) || ['', ''])[1];
    if (rise !== seen.rise) { seen.rise = rise;
      requestAnimationFrame(() => { if (!c.riseFrame) c.riseFrame = performance.now(); }); }
    if (k && kt !== seen.checks) { seen.checks = kt; c.checksAt = performance.now();
      requestAnimationFrame(() => { c.checksFrame = performance.now(); }); }
  }).observe(document.body, {subtree: true, childList: true, characterData: true});
}
"""

#: The continuous drag's recorder: pointer moves, animation frames, read-out changes.
DRAG_WATCH = """
() => {
  const d = window.__ccuDrag = {on: false, moves: [], frames: [], readouts: [], shown: []};
  addEventListener('pointermove', (e) => {
    if (d.on) d.moves.push([performance.now(), e.clientX]); }, true);
  const tick = (t) => { if (d.on) d.frames.push(t); requestAnimationFrame(tick); };
  requestAnimationFrame(tick);
  let last = '';
  new MutationObserver(() => {
    const r = document.getElementById('ccu-readout');
    const text = r ? r.textContent : '';
    if (!d.on || text === last) return;
    last = text;
    const i = d.readouts.length;
    d.readouts.push([performance.now(), text]);
    requestAnimationFrame(() => { d.shown[i] = performance.now(); });
  }).observe(document.body, {subtree: true, childList: true, characterData: true});
}
"""

#: Chromium allowed to use the GPU (hardware WebGL) for ``--gpu``.
GPU_ARGS = [a for a in CHROMIUM_ARGS if a != "--disable-gpu"] + [
    "--ignore-gpu-blocklist",
    "--enable-gpu-rasterization",
    "--use-angle=default",
]
SOFTWARE_RENDERERS = ("swiftshader", "llvmpipe", "softpipe", "software")
RENDERER = """
() => {
  const gl = document.createElement('canvas').getContext('webgl2')
    || document.createElement('canvas').getContext('webgl');
  if (!gl) return 'no webgl';
  const ext = gl.getExtension('WEBGL_debug_renderer_info');
  return ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}
"""


def _p(values, q):
    return float(np.percentile(values, q)) if values else float("nan")


def _summary(name, latencies, server, arrived, target, geometry=None):
    """The row of a step-at-a-time case (an edit's with the frames of its new geometry)."""
    row = {} if not geometry else {
        "geometry_median_ms": statistics.median(geometry),
        "geometry_p95_ms": _p(geometry, 95),
        "geometry_max_ms": max(geometry),
    }  # fmt: skip
    return row | {
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
    """Type rise values; the step ends when the checks panel shows the new design's checks.
    The frame that first draws the new geometry (the read-out's rise changed) is recorded too
    (``geometry``)."""
    latencies, server, arrived, geometry = [], [], [], []
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
        page.wait_for_function("() => window.__ccu.riseFrame > window.__ccu.inputAt")
        geometry.append(page.evaluate("() => window.__ccu.riseFrame - window.__ccu.inputAt"))
        studio.wait_idle(60)
        server.append(1000 * studio.checks.seconds)
    return latencies, server, arrived, geometry


def continuous_drag(page, studio, seconds: float, rate: float = 60.0):
    """Drag the α thumb over the track with one pointer move every ``1 / rate`` s.

    Returns
    -------
    dict
        ``latencies`` (ms, per read-out update: its frame minus the moment the pointer passed
        the α it shows), ``intervals`` (ms between animation frames during the drag),
        ``moves`` (pointer moves the page received), ``updates`` (read-out changes),
        ``seconds`` (the drag's length in the page), ``python`` (ms per view update).
    """
    page.evaluate(DRAG_WATCH)
    thumb = page.locator("[role=slider]").first
    track = page.locator(".mantine-Slider-track").first.bounding_box()
    box = thumb.bounding_box()
    y = box["y"] + box["height"] / 2
    page.mouse.move(box["x"] + box["width"] / 2, y)
    page.mouse.down()
    x0, x1 = track["x"] + 0.08 * track["width"], track["x"] + 0.6 * track["width"]
    frames, t_render = studio.frames, studio.render_seconds
    page.evaluate("() => { window.__ccuDrag.on = true; }")
    # as a hand: the pointer's position is a function of time; a move is sent every 1 / rate
    # s (playwright waits until the page took the last one, so a busy page gets fewer moves,
    # as chromium coalesces a real pointer's moves into the frames it draws)
    start = time.perf_counter()
    tick = 0
    while True:
        elapsed = time.perf_counter() - start
        fraction = min(elapsed / seconds, 1.0)
        page.mouse.move(x0 + fraction * (x1 - x0), y)
        if fraction >= 1.0:
            break
        tick = max(tick + 1, int(elapsed * rate))
        wait = start + tick / rate - time.perf_counter()
        if wait > 0:
            time.sleep(wait)
    page.mouse.up()
    studio.wait_idle(60)
    settle_ms = 1500
    page.wait_for_timeout(settle_ms)
    page.evaluate("() => { window.__ccuDrag.on = false; }")
    rec = page.evaluate("() => window.__ccuDrag")
    lo, hi = float(studio.slider.min), float(studio.slider.max)
    moves = np.array(rec["moves"], dtype=float).reshape(-1, 2)
    # α under the pointer at every move (Mantine maps the pointer's x along the track)
    alpha = lo + np.clip((moves[:, 1] - track["x"]) / track["width"], 0.0, 1.0) * (hi - lo)
    alpha = np.maximum.accumulate(alpha)
    latencies = []
    for i, (_, text) in enumerate(rec["readouts"]):
        shown = rec["shown"][i] if i < len(rec["shown"]) else None
        number = text.split("α =")[-1].split("°")[0].strip() if "α =" in text else ""
        if shown is None or not number or len(moves) < 2:
            continue
        a = float(number)
        if a < alpha[0] - 0.01 or a > alpha[-1] + 0.01:
            continue
        passed = float(np.interp(a, alpha, moves[:, 0]))
        latencies.append(shown - passed)
    frame_times = np.array(rec["frames"], dtype=float)
    during = frame_times[frame_times <= (moves[-1, 0] if len(moves) else np.inf)]
    intervals = np.diff(during).tolist()
    updates = studio.frames - frames
    return {
        "latencies": latencies,
        "intervals": intervals,
        "moves": len(moves),
        "updates": len(rec["readouts"]),
        "seconds": float((moves[-1, 0] - moves[0, 0]) / 1000) if len(moves) > 1 else 0.0,
        "python": 1000 * (studio.render_seconds - t_render) / updates if updates else None,
    }


def _drag_summary(name, drag, target):
    lat, iv = drag["latencies"], drag["intervals"]
    return {
        "case": name,
        "steps": len(lat),
        "median_ms": statistics.median(lat) if lat else float("nan"),
        "p95_ms": _p(lat, 95),
        "max_ms": max(lat) if lat else float("nan"),
        "server_median_ms": drag["python"] if drag["python"] is not None else float("nan"),
        "in_page_median_ms": float("nan"),
        "target_p95_ms": target,
        "ok": _p(lat, 95) <= target,
        "pointer_moves": drag["moves"],
        "pointer_rate_hz": drag["moves"] / drag["seconds"] if drag["seconds"] else None,
        "updates_shown": drag["updates"],
        "frame_interval_median_ms": statistics.median(iv) if iv else None,
        "frame_interval_p95_ms": _p(iv, 95),
        "frame_interval_max_ms": max(iv) if iv else None,
    }


def run(design: Path, out: Path, browser, *, what: str, steps: int, seconds: float = 3.0):
    app = Studio(StudioSession.start(design, out=out), port=free_port())
    try:
        app.wait_idle(60)
        page = open_page(browser, app.url)
        page.evaluate(WATCH)
        app.wait_idle(60)
        if what == "slider":
            slider_steps(page, app, 3)  # warm-up
            result = slider_steps(page, app, steps)
        elif what == "drag":
            slider_steps(page, app, 3)  # warm-up
            result = continuous_drag(page, app, seconds)
        else:
            edits(page, app, 2)
            result = edits(page, app, steps)
        page.close()
        return result
    finally:
        app.stop()


def gpu_renderer(browser) -> str | None:
    """The WebGL renderer of a page in ``browser`` if it is a GPU, else None."""
    page = browser.new_page()
    try:
        renderer = str(page.evaluate(RENDERER))
    finally:
        page.close()
    software = any(word in renderer.lower() for word in SOFTWARE_RENDERERS)
    return None if software or renderer == "no webgl" else renderer


def gpu_device() -> bool:
    """Whether this machine shows a GPU device (a DRM render node or an NVIDIA device)."""
    dri = Path("/dev/dri")
    nodes = list(dri.glob("renderD*")) if dri.is_dir() else []
    return bool(nodes) or Path("/dev/nvidia0").exists()


CASES = {
    "step": ("slider step, vault 64 segments", "vault", "slider", 50.0),
    "edit": ("parameter edit (rise), vault", "vault", "edit", 300.0),
    "step200": ("slider step, 10 plates x 200 segments", "big", "slider", 150.0),
    "drag": ("continuous drag (60 Hz), vault 64 segments", "vault", "drag", 50.0),
}


def _print(rows, machine) -> None:
    print(machine)
    print(
        f"{'case':<44} {'steps':>5} {'median':>8} {'p95':>8} {'max':>8} {'python':>8} "
        f"{'arrived':>8} target"
    )
    for r in rows:
        print(
            f"{r['case']:<44} {r['steps']:>5} {r['median_ms']:>6.1f}ms {r['p95_ms']:>6.1f}ms "
            f"{r['max_ms']:>6.1f}ms {r['server_median_ms']:>6.1f}ms "
            f"{r['in_page_median_ms']:>6.1f}ms "
            f"<= {r['target_p95_ms']:g} ms "
            f"{'ok' if r['ok'] else 'MISSED'}"
        )
        if "geometry_median_ms" in r:
            print(
                f"{'':<44} its new geometry drawn: median {r['geometry_median_ms']:.1f} ms, "
                f"p95 {r['geometry_p95_ms']:.1f} ms, max {r['geometry_max_ms']:.1f} ms"
            )
        if "pointer_moves" in r:
            print(
                f"{'':<44} {r['pointer_moves']} pointer moves at "
                f"{r['pointer_rate_hz'] or 0:.1f} Hz, {r['updates_shown']} updates shown, "
                f"frame interval median {r['frame_interval_median_ms'] or 0:.1f} ms, p95 "
                f"{r['frame_interval_p95_ms']:.1f} ms, max {r['frame_interval_max_ms'] or 0:.1f} ms"
            )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=40, help="slider steps / edits per case")
    parser.add_argument("--out", default=None, help="also write the results as JSON")
    parser.add_argument(
        "--cases", default=None, help=f"comma-separated, of {','.join(CASES)} (default: all)"
    )
    parser.add_argument("--drag-seconds", type=float, default=3.0, help="length of the drag")
    parser.add_argument(
        "--gpu", action="store_true", help="hardware WebGL; exit 3 with 'no GPU found' without"
    )
    args = parser.parse_args(argv)
    default = "step,step200,drag" if args.gpu else ",".join(CASES)
    names = (args.cases or default).split(",")
    unknown = [n for n in names if n not in CASES]
    if unknown:
        parser.error(f"unknown case {unknown[0]!r}: one of {', '.join(CASES)}")
    exe = chromium()
    if not exe:
        print("no chromium: run `make browser`", file=sys.stderr)
        return 2
    if args.gpu and not gpu_device():
        print("no GPU found: no /dev/dri/renderD* or /dev/nvidia0 device", file=sys.stderr)
        return 3
    from playwright.sync_api import sync_playwright

    rows = []
    load = [os.getloadavg()[0]]
    renderer = "software (SwiftShader)"
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as p:
        tmp = Path(tmp)
        vault = tmp / "vault.toml"
        vault.write_text((ROOT / "examples" / "vault.toml").read_text())
        fine = parse_toml(vault.read_text())
        fine["crease"]["segments"] = 200
        big = tmp / "vault200.toml"
        big.write_text(document_text(fine))
        designs = {"vault": vault, "big": big}
        flags = GPU_ARGS if args.gpu else CHROMIUM_ARGS
        browser = p.chromium.launch(executable_path=exe, args=flags, headless=True)
        try:
            if args.gpu:
                renderer = gpu_renderer(browser)
                if renderer is None:
                    print("no GPU found: chromium's WebGL renderer is a software one",
                          file=sys.stderr)  # fmt: skip
                    return 3
            for key in names:
                name, design, what, target = CASES[key]
                result = run(
                    designs[design], tmp / "out", browser, what=what, steps=args.steps,
                    seconds=args.drag_seconds,
                )  # fmt: skip
                if what == "drag":
                    rows.append(_drag_summary(name, result, target))
                else:
                    rows.append(_summary(name, *result[:3], target, *result[3:]))
                load.append(os.getloadavg()[0])
        finally:
            browser.close()
    machine = (
        f"{platform.platform()}, {os.cpu_count()} cores, WebGL: {renderer}, "
        f"load (1 min) {min(load):.1f}-{max(load):.1f}"
    )
    _print(rows, machine)
    if args.out:
        Path(args.out).write_text(
            json.dumps(
                {"machine": platform.platform(), "renderer": renderer, "load": load, "cases": rows},
                indent=1,
            )
            + "\n"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
