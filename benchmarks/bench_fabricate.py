"""Time of ``ccu fabricate`` and ``ccu report``: where the seconds go, for the vault, the cone,
the dome preset and the 22-plate dome, nested by compas_nest, by spyrrow and by shelves.

Run: ``.venv/bin/python benchmarks/bench_fabricate.py`` (``make bench-fabricate``; about 25 min
on 2 cores, spyrrow's dome taking most of it; ``--nestings compas_nest shelf`` in about 2 min);
results are recorded in ``docs/benchmarks.md``. Wall-clock and CPU seconds of one run each:
every nesting is bounded by a count (compas_nest's generations, spyrrow's steps), never by
seconds, so a repeat only repeats the same layout; the CPU seconds are this process's and its
ended children's (spyrrow runs in child processes, compas_nest on a thread of this one).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from compas_ccu.design.presets import preset_text
from compas_ccu.fabrication import fabrication_data
from compas_ccu.fabrication.fabricate import fabricate
from compas_ccu.fabrication.hinges import hinge_strips
from compas_ccu.fabrication.workshop import WorkshopOptions, plan_workshop
from compas_ccu.model import load_model
from compas_ccu.thickness import ThickModel
from compas_ccu.viz.report import write_report

ROOT = Path(__file__).resolve().parents[1]


def _cpu() -> float:
    """CPU seconds of this process and of its ended children (spyrrow's packings run in child
    processes, compas_ccu.fabrication.packing)."""
    import resource

    own, children = (
        resource.getrusage(resource.RUSAGE_SELF),
        resource.getrusage(resource.RUSAGE_CHILDREN),
    )
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _timed(fn):
    w, c = time.perf_counter(), _cpu()
    out = fn()
    return out, time.perf_counter() - w, _cpu() - c


def dome22(folder: Path) -> Path:
    """The dome preset with 22 plates (15 deg apart, 330 deg in all)."""
    text = preset_text("dome").replace("plates = 12 ", "plates = 22 ")
    path = folder / "dome22.toml"
    path.write_text(text, encoding="utf-8")
    return path


def dome(folder: Path) -> Path:
    """The dome preset (``ccu new --preset dome``: 12 plates)."""
    path = folder / "dome.toml"
    path.write_text(preset_text("dome"), encoding="utf-8")
    return path


def bench(name: str, path: Path, nesting: str, out: Path, *, files: bool) -> dict:
    """The nesting alone (``plan_workshop``: split, nest, roll, BOM) and, with ``files``, the
    whole ``fabricate`` (thick model, checks, nesting, every file)."""
    model = load_model(path)
    thick, w_thick, _ = _timed(lambda: ThickModel(model))
    data, w_data, _ = _timed(lambda: fabrication_data(model, thick=thick))
    options = WorkshopOptions.from_section(model.design.fabrication, nesting=nesting)
    strips = hinge_strips(data)
    bend = thick.bending()
    plan, w_plan, c_plan = _timed(
        lambda: plan_workshop(
            data,
            strips,
            options,
            density=float(thick.material.density),
            utilisation=bend.utilisation.max(axis=0),
        )
    )
    row = {
        "design": name,
        "nesting": nesting,
        "plates": len(model.plate_ids),
        "parts": len(plan.parts),
        "sheets": len(plan.sheets),
        "utilisation": plan.utilisation,
        "roll_m": plan.roll.length,
        "thick_s": w_thick + w_data,
        "plan_s": w_plan,
        "plan_cpu_s": c_plan,
        "fabricate_s": None,
        "fabricate_cpu_s": None,
    }
    if files:
        manifest, w_all, c_all = _timed(lambda: fabricate(model, out / name, workshop=options))
        assert manifest["workshop"]["sheet_count"] == row["sheets"]
        row["fabricate_s"], row["fabricate_cpu_s"] = w_all, c_all
    return row


def cli_vault(out: Path) -> tuple:
    """``ccu fabricate examples/vault.toml --out DIR`` as a user runs it (a fresh process:
    imports included), its default nesting: wall and CPU seconds, and the sheets."""
    import json

    folder = out / "cli-vault"
    cmd = [sys.executable, "-m", "compas_ccu", "fabricate", str(ROOT / "examples" / "vault.toml")]
    before = os.times()
    w = time.perf_counter()
    subprocess.run([*cmd, "--out", str(folder), "--quiet"], check=True)
    wall = time.perf_counter() - w
    after = os.times()
    cpu = (after.children_user - before.children_user) + (
        after.children_system - before.children_system
    )
    manifest = json.loads((folder / "fabrication.json").read_text())
    return wall, cpu, manifest["workshop"]["sheet_count"], manifest["workshop"]["nesting"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--nestings", nargs="+", default=["compas_nest", "spyrrow", "shelf"],
        help="the nestings to compare (default: compas_nest spyrrow shelf)",
    )  # fmt: skip
    parser.add_argument(
        "--designs", nargs="+", default=["vault", "cone", "dome", "dome22"],
        help="vault, cone (examples/), dome (the preset), dome22 (the preset with 22 plates)",
    )  # fmt: skip
    parser.add_argument("--no-files", action="store_true", help="the nesting only")
    args = parser.parse_args()
    out = Path(tempfile.mkdtemp(prefix="bench_fabricate_"))
    paths = {
        "vault": ROOT / "examples" / "vault.toml",
        "cone": ROOT / "examples" / "cone.toml",
        "dome": dome(out),
        "dome22": dome22(out),
    }
    load = os.getloadavg()[0]
    rows = [
        bench(f"{n}-{k}", paths[n], k, out, files=not args.no_files)
        for n in args.designs
        for k in args.nestings
    ]
    print(
        f"load average before: {load:.2f}, after: {os.getloadavg()[0]:.2f} ({os.cpu_count()} cores)"
    )
    print(
        "| design | nesting | plates | parts | sheets | utilisation | roll m | thick model + data "
        "s | split + nest + BOM s (CPU) | ccu fabricate s (CPU) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        fab = (
            "—"
            if r["fabricate_s"] is None
            else f"{r['fabricate_s']:.1f} ({r['fabricate_cpu_s']:.1f})"
        )
        print(
            f"| {r['design']} | {r['nesting']} | {r['plates']} | {r['parts']} | {r['sheets']} | "
            f"{100 * r['utilisation']:.1f} % | {r['roll_m']:.2f} | {r['thick_s']:.2f} | "
            f"{r['plan_s']:.1f} ({r['plan_cpu_s']:.1f}) | {fab} |"
        )
    if args.no_files:
        return 0
    wall, cpu, sheets, nesting = cli_vault(out)
    print(
        f"\nccu fabricate examples/vault.toml --out DIR (a fresh process): {wall:.1f} s wall, "
        f"{cpu:.1f} s CPU, {sheets} sheets ({nesting}); load average {os.getloadavg()[0]:.2f}"
    )
    if (out / "vault-shelf").is_dir():
        model = load_model(paths["vault"])
        _, w_rep, c_rep = _timed(
            lambda: write_report(model, out / "report", fabrication=out / "vault-shelf")
        )
        print(
            f"ccu report of the vault with its fabrication folder: {w_rep:.1f} s ({c_rep:.1f} s "
            "CPU)"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
