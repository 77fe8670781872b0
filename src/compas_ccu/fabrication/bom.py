"""The bill of materials: areas, masses, sheets, textile, glue line, fasteners and cost, and its
``bom.csv``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from compas_ccu.fabrication.plan import WorkshopOptions, WorkshopPlan

__all__ = [
    "anchors",
    "bill_of_materials",
    "BOM_COLUMNS",
    "write_bom_csv",
]


def bill_of_materials(data, parts, sheets, roll, options: WorkshopOptions, density: float) -> dict:
    """Rows and totals of the bill of materials (strict-JSON values)."""
    rows = []
    for p in parts:
        rows.append(
            {
                "item": p.name,
                "kind": p.kind,
                "plate": p.plate,
                "sheet": p.sheet + 1,
                "area_m2": p.area,
                "thickness_m": p.thickness,
                "mass_kg": p.area * p.thickness * density,
                "quantity": 1,
            }
        )
    hinge_lengths = roll.strips
    glue_hinges = 2.0 * sum(hinge_lengths.values())  # each strip glued to both plates
    splices = [p for p in parts if p.kind == "splice"]
    glue_splices = sum(
        float(np.linalg.norm(np.diff(np.r_[p.outline, p.outline[:1]], axis=0), axis=1).sum())
        for p in splices
    )
    fasteners = len(splices) * options.fasteners_per_splice
    mass = sum(r["mass_kg"] for r in rows)
    textile = float(roll.length)
    glue = glue_hinges + glue_splices
    costs = {
        "sheets": len(sheets) * options.sheet_price,
        "textile": textile * options.textile_price,
        "glue": glue * options.glue_price,
        "fasteners": fasteners * options.fastener_price,
    }
    for c, length in sorted(hinge_lengths.items(), key=lambda kv: int(kv[0][1:])):
        rows.append(
            {
                "item": f"hinge {c}",
                "kind": "hinge",
                "plate": None,
                "sheet": None,
                "area_m2": length * data.hinge_width,
                "thickness_m": None,
                "mass_kg": None,
                "quantity": 1,
            }
        )
    return {
        "rows": rows,
        "plates": sum(1 for p in parts if p.kind == "plate"),
        "splices": len(splices),
        "sheets": len(sheets),
        "sheet_area_m2": sum(s["size"][0] * s["size"][1] for s in sheets),
        "parts_area_m2": sum(p.area for p in parts),
        "mass_kg": mass,
        "density_kg_m3": density,
        "textile_roll_width_m": float(roll.width),
        "textile_length_m": textile,
        "hinge_length_m": sum(hinge_lengths.values()),
        "glue_line_m": glue,
        "glue_line_hinges_m": glue_hinges,
        "glue_line_splices_m": glue_splices,
        "fasteners": fasteners,
        "currency": options.currency,
        "cost": costs,
        "cost_total": sum(costs.values()),
        "anchors": anchors(data),
    }


def anchors(data) -> list:
    """Per plate: the feet (mid-points of the end rulings) where the actuators or the tie of the
    deployment are fixed, in the cut pattern (m) and in the world at the design state (m), and
    the tie length between them at the design state (m)."""
    n = data.segments
    out = []
    for i, pid in enumerate(data.plate_ids):
        flat = np.asarray(data.flat[i], dtype=float)
        xyz = np.asarray(data.deployed_mid[i], dtype=float)
        ends = [(0, n + 1), (n, 2 * n + 1)]
        f = [0.5 * (flat[a] + flat[b]) for a, b in ends]
        w = [0.5 * (xyz[a] + xyz[b]) for a, b in ends]
        out.append(
            {
                "plate": int(pid),
                "flat": [v.tolist() for v in f],
                "world": [v.tolist() for v in w],
                "tie_length": float(np.linalg.norm(w[1] - w[0])),
            }
        )
    return out


BOM_COLUMNS = ("item", "kind", "plate", "sheet", "area_m2", "thickness_m", "mass_kg", "quantity")


def write_bom_csv(plan: WorkshopPlan, path) -> Path:
    """The bill of materials as CSV: one row per part and hinge strip, then the totals."""
    import csv

    b = plan.bom
    path = Path(path)
    with path.open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(BOM_COLUMNS)
        for r in b["rows"]:
            w.writerow(
                [
                    "" if r[c] is None else (f"{r[c]:.6g}" if isinstance(r[c], float) else r[c])
                    for c in BOM_COLUMNS
                ]
            )
        cur = b["currency"]
        totals = [
            ("sheets", b["sheets"], "", b["cost"]["sheets"]),
            ("parts area", f"{b['parts_area_m2']:.4f}", "m2", ""),
            ("mass", f"{b['mass_kg']:.2f}", "kg", ""),
            (
                f"textile (roll {b['textile_roll_width_m']:g} m)",
                f"{b['textile_length_m']:.3f}",
                "m",
                b["cost"]["textile"],
            ),
            ("glue line", f"{b['glue_line_m']:.3f}", "m", b["cost"]["glue"]),
            ("fasteners", b["fasteners"], "", b["cost"]["fasteners"]),
            ("total", "", "", b["cost_total"]),
        ]
        w.writerow([])
        w.writerow(["total", "quantity", "unit", f"cost {cur}"])
        for label, q, unit, cost in totals:
            w.writerow([label, q, unit, "" if cost == "" else f"{cost:.2f}"])
    return path
