"""The Python side of a studio edit, without a browser: what the checks panel waits for.

Run from the repository root::

    .venv/bin/python benchmarks/bench_studio_checks.py               # 20 edits of each kind
    .venv/bin/python benchmarks/bench_studio_checks.py --edits 40 --out checks.json

A :class:`~compas_ccu.studio.StudioSession` on the vault takes edits as the page's fields send
them; after each, the time of the work the studio's workers do for it is taken, in this order
(one thread, so the numbers add up):

- **build**: the edit validated and the new model built (``StudioSession.edit``);
- **view**: the first frame of the new model (:func:`compas_ccu.studio.view.view_state` at the
  design angle; it asks for the overlap and collision-free angles);
- **checks**: :func:`compas_ccu.studio.checks.design_checks` (key figures, thick plates' first
  collision, bending).

Two kinds of edit: the **rise** (a new geometry: every limit is measured again) and the
**material** (the same geometry: the limits of the last model are kept, where the code has that
cache). Median and p95 in ms, with the 1-minute load before and after; **CPU** is the process's
CPU time of the whole edit (build, view and checks), which a loaded machine inflates less than
the wall-clock time.
"""

from __future__ import annotations

import argparse
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

from compas_ccu.studio import StudioSession  # noqa: E402
from compas_ccu.studio.checks import design_checks  # noqa: E402
from compas_ccu.studio.view import view_state  # noqa: E402

EDITS = {
    "rise": ("crease", "rise", lambda i: round(0.9 + 0.2 * (i % 2) + 0.001 * i, 4)),
    "material": ("plates", "material", lambda i: ("plywood", "birch-plywood")[i % 2]),
}


def measure(session, kind: str, count: int) -> dict:
    section, key, value = EDITS[kind]
    times = {"build": [], "view": [], "checks": [], "total": [], "cpu": []}
    for i in range(count + 2):  # two warm-up edits
        c0, t0 = time.process_time(), time.perf_counter()
        problem = session.edit(section, key, value(i))
        assert problem is None, problem
        model = session.model
        t1 = time.perf_counter()
        view_state(model, model.alpha_design)
        t2 = time.perf_counter()
        design_checks(model)
        t3, c3 = time.perf_counter(), time.process_time()
        if i >= 2:
            for name, seconds in zip(times, (t1 - t0, t2 - t1, t3 - t2, t3 - t0, c3 - c0)):
                times[name].append(1000 * seconds)
    return {
        name: {
            "median_ms": statistics.median(v),
            "p95_ms": float(np.percentile(v, 95)),
        }
        for name, v in times.items()
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--edits", type=int, default=20, help="edits of each kind")
    parser.add_argument("--out", default=None, help="also write the results as JSON")
    args = parser.parse_args(argv)
    load = [os.getloadavg()[0]]
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        design = Path(tmp) / "vault.toml"
        shutil.copy(ROOT / "examples" / "vault.toml", design)
        session = StudioSession.start(design, out=Path(tmp) / "out")
        for kind in EDITS:
            rows[kind] = measure(session, kind, args.edits)
            load.append(os.getloadavg()[0])
    print(f"{platform.platform()}, {os.cpu_count()} cores, load (1 min) {min(load):.1f}-"
          f"{max(load):.1f}, {args.edits} edits each, ms (median / p95)")  # fmt: skip
    print(f"{'edit':<10} {'build':>15} {'view':>15} {'checks':>15} {'total':>15} {'CPU':>15}")
    for kind, row in rows.items():
        cells = " ".join(
            f"{row[n]['median_ms']:>7.1f} /{row[n]['p95_ms']:>6.1f}"
            for n in ("build", "view", "checks", "total", "cpu")
        )
        print(f"{kind:<10} {cells}")
    if args.out:
        Path(args.out).write_text(
            json.dumps({"machine": platform.platform(), "load": load, "edits": rows}, indent=1)
            + "\n"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
