"""The Python side of a studio edit, without a browser: what the checks panel waits for.

Run from the repository root::

    .venv/bin/python benchmarks/bench_studio_checks.py               # 20 edits of each kind
    .venv/bin/python benchmarks/bench_studio_checks.py --edits 40 --out checks.json

A :class:`~compas_ccu.studio.StudioSession` on the vault takes edits as the page's fields send
them; after each, the work the studio's workers do for it is timed in the studio's order (one
thread, so the numbers add up; in the studio the view and the checks are threads of one process
that share the GIL, so the checks panel waits for the view's Python as well):

- **build**: the edit validated and the new model built (``StudioSession.edit``; with the
  recovery copy where the studio writes it there);
- **view**: the thick plates built for the view and the first frame of the new model
  (:func:`compas_ccu.studio.view.view_state` at the design angle with them; before
  2026-12-06 it asked for the overlap and collision-free angles, which the checks measure now);
- **checks**: :func:`compas_ccu.studio.checks.design_checks` (key figures, thick plates' first
  collision, bending; with the view's thick plates where the studio shares them) and whatever
  the studio does before it sends the checks panel (the cut patterns, where it draws them
  first);
- **total**: from the edit until the checks panel's content is ready;
- **after**: what the studio does for the edit after it sent the panel (the cut patterns and
  the recovery copy, where they come after it).

With ``--studio`` the same edits are also made in a :class:`~compas_ccu.studio.app.Studio` (a
viser server on a free port, no browser) through its own callback, and timed until the checks
panel's content is the new model's: the studio's threads, its order of work and its GIL.

The script runs on older versions of the studio too (it follows what the code it imports
does), so before and after are measured by the same script.

Two kinds of edit: the **rise** (a new geometry: every limit is measured again) and the
**material** (the same geometry: the limits of the last model are kept, where the code has that
cache). Median and p95 in ms, with the 1-minute load before and after; **CPU** is the process's
CPU time of the whole edit (build, view, checks and after), which a loaded machine inflates less
than the wall-clock time.
"""

from __future__ import annotations

import argparse
import inspect
import json
import os
import platform
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

from compas_ccu.design.schema import design_sheet  # noqa: E402
from compas_ccu.studio import StudioSession  # noqa: E402
from compas_ccu.studio.checks import design_checks  # noqa: E402
from compas_ccu.studio.view import cut_patterns_svg, view_state  # noqa: E402
from compas_ccu.thickness import ThickModel  # noqa: E402

#: The studio sends the checks panel before it draws the cut patterns and writes the recovery
#: copy after it (versions whose session has ``write_recovery``).
DEFERRED = hasattr(StudioSession, "write_recovery")
#: The checks take the thick plates the view built (versions whose ``design_checks`` has
#: ``thick``).
SHARED = "thick" in inspect.signature(design_checks).parameters

EDITS = {
    "rise": ("crease", "rise", lambda i: round(0.9 + 0.2 * (i % 2) + 0.001 * i, 4)),
    "material": ("plates", "material", lambda i: ("plywood", "birch-plywood")[i % 2]),
}


def _patterns(model) -> None:
    cut_patterns_svg(model, sheet=design_sheet(model.design.values))


def measure(session, kind: str, count: int) -> dict:
    section, key, value = EDITS[kind]
    names = ("build", "view", "checks", "total", "after", "cpu")
    times = {name: [] for name in names}
    for i in range(count + 2):  # two warm-up edits
        c0, t0 = time.process_time(), time.perf_counter()
        problem = session.edit(section, key, value(i))
        assert problem is None, problem
        model = session.model
        t1 = time.perf_counter()
        thick = ThickModel(model)  # the view worker's (the vault has thick plates)
        view_state(model, model.alpha_design, thick=thick)
        t2 = time.perf_counter()
        design_checks(model, **({"thick": thick} if SHARED else {}))
        if not DEFERRED:
            _patterns(model)
        t3 = time.perf_counter()  # the checks panel's content is ready
        if DEFERRED:
            _patterns(model)
            session.write_recovery()
        t4, c4 = time.perf_counter(), time.process_time()
        if i >= 2:
            for name, seconds in zip(names, (t1 - t0, t2 - t1, t3 - t2, t3 - t0, t4 - t3, c4 - c0)):
                times[name].append(1000 * seconds)
    return {
        name: {
            "median_ms": statistics.median(v),
            "p95_ms": float(np.percentile(v, 95)),
        }
        for name, v in times.items()
    }


def _free_port() -> int:
    import socket

    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def measure_studio(session, kind: str, count: int) -> dict:
    """The edit in the studio itself (its threads, no browser): from the edit's callback until
    the checks panel's content is the new model's (``total``), and the process's CPU time until
    every worker is idle (``cpu``)."""
    from compas_ccu.studio.app import Studio

    section, key, value = EDITS[kind]
    app = Studio(session, port=_free_port())
    times = {"total": [], "cpu": []}
    try:
        assert app.wait_idle(120)
        for i in range(count + 2):
            c0, t0 = time.process_time(), time.perf_counter()
            app.apply_action(lambda i=i: session.edit(section, key, value(i)))
            while "measuring" in app.checks_panel.content:  # set by the edit, then the panel
                time.sleep(0.0005)
            t1 = time.perf_counter()
            assert app.wait_idle(120)
            if i >= 2:
                times["total"].append(1000 * (t1 - t0))
                times["cpu"].append(1000 * (time.process_time() - c0))
    finally:
        app.stop()
    return {
        name: {"median_ms": statistics.median(v), "p95_ms": float(np.percentile(v, 95))}
        for name, v in times.items()
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--edits", type=int, default=20, help="edits of each kind")
    parser.add_argument("--out", default=None, help="also write the results as JSON")
    parser.add_argument(
        "--studio",
        action="store_true",
        help="also time the edit in the studio's threads (a viser server, no browser)",
    )
    args = parser.parse_args(argv)
    load = [os.getloadavg()[0]]
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        design = Path(tmp) / "vault.toml"
        shutil.copy(ROOT / "examples" / "vault.toml", design)
        session = StudioSession.start(design, out=Path(tmp) / "out")
        session.defer_recovery = DEFERRED  # as the studio sets it
        for kind in EDITS:
            rows[kind] = measure(session, kind, args.edits)
            load.append(os.getloadavg()[0])
        studio = {}
        if args.studio:
            fresh = StudioSession.start(design, out=Path(tmp) / "out-studio")
            for kind in EDITS:
                studio[kind] = measure_studio(fresh, kind, args.edits)
                load.append(os.getloadavg()[0])
    print(f"{platform.platform()}, {os.cpu_count()} cores, load (1 min) {min(load):.1f}-"
          f"{max(load):.1f}, {args.edits} edits each, ms (median / p95)")  # fmt: skip
    heads = ("build", "view", "checks", "total", "after", "CPU")
    print(f"{'edit':<10} " + " ".join(f"{h:>15}" for h in heads))
    for kind, row in rows.items():
        cells = " ".join(
            f"{row[n]['median_ms']:>7.1f} /{row[n]['p95_ms']:>6.1f}"
            for n in ("build", "view", "checks", "total", "after", "cpu")
        )
        print(f"{kind:<10} {cells}")
    for kind, row in studio.items():
        print(
            f"{kind:<10} in the studio: until the checks panel {row['total']['median_ms']:.1f} /"
            f" {row['total']['p95_ms']:.1f}, CPU {row['cpu']['median_ms']:.1f} /"
            f" {row['cpu']['p95_ms']:.1f}"
        )
    if args.out:
        Path(args.out).write_text(
            json.dumps(
                {
                    "machine": platform.platform(),
                    "load": load,
                    "deferred": DEFERRED,
                    "shared": SHARED,
                    "edits": rows,
                    "studio": studio,
                },
                indent=1,
            )
            + "\n"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
