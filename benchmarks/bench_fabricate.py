"""Time of ``ccu fabricate`` and ``ccu report``: where the seconds go, for the vault and the
22-plate dome, with spyrrow nesting and with shelves.

Run: ``.venv/bin/python benchmarks/bench_fabricate.py`` (``make bench-fabricate``; about 5 min
on 2 cores); results are recorded in ``docs/benchmarks.md``. Wall-clock and CPU seconds of one
run each (nesting is bounded by spyrrow's time budget per packing, ``nesting_time``, whole
seconds, so repeats would only repeat it).
"""

from __future__ import annotations

import argparse
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
    """CPU seconds of this process and of its ended children (the nesting runs in child
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


def bench(name: str, path: Path, nesting: str, out: Path) -> dict:
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
    manifest, w_all, c_all = _timed(lambda: fabricate(model, out / name, workshop=options))
    return {
        "design": name,
        "nesting": nesting,
        "plates": len(model.plate_ids),
        "sheets": manifest["workshop"]["sheet_count"],
        "utilisation": manifest["workshop"]["utilisation"],
        "thick_s": w_thick + w_data,
        "plan_s": w_plan,
        "plan_cpu_s": c_plan,
        "fabricate_s": w_all,
        "fabricate_cpu_s": c_all,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="shelf nesting only (~30 s)")
    args = parser.parse_args()
    out = Path(tempfile.mkdtemp(prefix="bench_fabricate_"))
    designs = [("vault", ROOT / "examples" / "vault.toml"), ("dome22", dome22(out))]
    nestings = ("shelf",) if args.quick else ("spyrrow", "shelf")
    rows = [bench(f"{n}-{k}", p, k, out) for n, p in designs for k in nestings]
    print(
        "| design | nesting | plates | sheets | utilisation | thick model + data s "
        "| split + nest + BOM s (CPU) | ccu fabricate s (CPU) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['design']} | {r['nesting']} | {r['plates']} | {r['sheets']} | "
            f"{100 * r['utilisation']:.1f} % | {r['thick_s']:.2f} | {r['plan_s']:.1f} "
            f"({r['plan_cpu_s']:.1f}) | {r['fabricate_s']:.1f} ({r['fabricate_cpu_s']:.1f}) |"
        )
    model = load_model(ROOT / "examples" / "vault.toml")
    _, w_rep, c_rep = _timed(
        lambda: write_report(model, out / "report", fabrication=out / "vault-shelf")
    )
    print(
        f"\nccu report of the vault with its fabrication folder: {w_rep:.1f} s ({c_rep:.1f} s CPU)"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
