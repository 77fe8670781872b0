"""The workshop of a ``fabrication.json`` as rows of text (``ccu fabricate``, the report)."""

from __future__ import annotations

from compas_ccu.key_figures.rows import utilisation_text

__all__ = [
    "workshop_rows",
]


def workshop_rows(manifest: dict) -> list:
    """Rows on the workshop of a ``fabrication.json`` (``ccu fabricate``; the report).

    Sheets and their utilisation, the split plates, the nesting and its warnings (a nester
    missing: marked ``** ... **``), the splice plates in the stack (stack height with them,
    highest pile, mass, from which angle they clear the neighbouring plates), the splices'
    bending check (marked as failed above 1), the bill of materials' totals, the
    cost estimate and the assembly.

    Examples
    --------
    >>> work = {"sheets_in_stock": [[2.5, 1.25]], "sheet_count": 1, "utilisation": 0.5,
    ...     "kerf": 0.006, "bridge": 0.01, "grain": "along", "splits": {"0": []},
    ...     "sheets": [{"thickness": 0.008}]}
    >>> bom = {"plates": 2, "splices": 0, "parts_area_m2": 1.0, "mass_kg": 4.0,
    ...     "textile_length_m": 1.5, "textile_roll_width_m": 1.4, "glue_line_m": 6.0,
    ...     "fasteners": 0, "cost_total": 100.0, "currency": "EUR", "cost": {"sheets": 60.0}}
    >>> rows = workshop_rows({"workshop": work, "bom": bom, "assembly": [1, 2]})
    >>> rows[0][1]
    '1 of 2500 x 1250 mm, 8 mm thick; utilisation 50.0 % (kerf 6 mm, bridge 10 mm, grain along)'
    >>> rows[1]
    ('split plates', 'none: every plate fits a sheet')
    """
    w, b = manifest["workshop"], manifest["bom"]
    split = {k: v for k, v in w["splits"].items() if v}
    rows = [
        ("sheets", _sheets_text(w)),
        (
            "split plates",
            ", ".join(f"P{k} at rulings {v}" for k, v in split.items())
            + f"; {b['splices']} splice plates"
            if split
            else "none: every plate fits a sheet",
        ),
    ]
    rows += _nesting_rows(w.get("nesting_search"))
    rows += [("warning", f"** {text} **") for text in w.get("warnings") or []]
    rows += _splice_rows(manifest.get("splices") or {}, w.get("splice_bending"))
    rows += _bom_rows(b, manifest["assembly"])
    return rows


def _sheets_text(w: dict) -> str:
    """The sheets of the workshop: their count, sizes, thicknesses and utilisation."""
    sizes = ", ".join(f"{x * 1e3:g} x {y * 1e3:g}" for x, y in w["sheets_in_stock"])
    counts: dict = {}
    for sheet in w.get("sheets", []):
        t = sheet.get("thickness")
        counts[t] = counts.get(t, 0) + 1
    if len(counts) == 1 and None not in counts:
        thick = f", {next(iter(counts)) * 1e3:g} mm thick"
    elif counts:
        thick = (
            " ("
            + ", ".join(
                f"{n} of {t * 1e3:g} mm"
                for t, n in sorted(counts.items(), key=lambda kv: -(kv[0] or 0))
            )
            + ")"
        )
    else:
        thick = ""
    return (
        f"{w['sheet_count']} of {sizes} mm{thick}; utilisation {100 * w['utilisation']:.1f} % "
        f"(kerf {w['kerf'] * 1e3:g} mm, bridge {w['bridge'] * 1e3:g} mm, grain {w['grain']})"
    )


def _nesting_rows(search) -> list:
    """The nesting search: solver, seed and generations (compas_nest) or steps (spyrrow), or
    the rows of bounding boxes."""
    if search and search.get("generations") is not None:  # compas_nest
        return [
            (
                "nesting",
                f"{search['solver']} {search['version']}, seed {search['seed']}, "
                f"{search['generations']} generations of {search['population']} layouts per "
                f"packing ({search['packings']} packings; the same seed and generations give "
                "the same sheets)",
            )
        ]
    if search and search.get("seed") is not None:
        return [
            (
                "nesting",
                f"{search['solver']} {search['version']}, seed {search['seed']}, "
                f"{search['steps']} steps per packing ({search['packings']} packings, "
                f"{search['steps_searched']} steps; the same seed and steps give the same sheets)",
            )
        ]
    if search:
        return [("nesting", f"{search['solver']}: bounding boxes in rows (no search)")]
    return []


def _splice_rows(spliced: dict, check) -> list:
    """The splice plates in the stack and their bending check (marked as failed above 1)."""
    rows = []
    if spliced.get("count"):
        clear = (spliced.get("collisions") or {}).get("clear_from_alpha")
        rows.append(
            (
                "splice plates",
                f"stack {spliced['stack_height'] * 1e3:.4g} mm with them (plates "
                f"{spliced['stack_height_plates'] * 1e3:.4g} mm); highest pile "
                f"{spliced['max_pile'] * 1e3:.4g} mm (cuts staggered; "
                f"{spliced['max_pile_unstaggered'] * 1e3:.4g} mm at the same rulings); "
                f"{spliced['mass']:.3f} kg; "
                + (
                    f"clear of the neighbouring plates from alpha {clear:.3g} deg"
                    if clear is not None
                    else "** inside a neighbouring plate at the design state **"
                ),
            )
        )
    if check and check.get("cuts"):
        worst = max(check["cuts"], key=lambda c: c["utilisation"])
        text = (
            f"utilisation {utilisation_text(worst['utilisation'])} (characteristic "
            f"{utilisation_text(worst['utilisation_characteristic'])}) at P{worst['plate']} ruling "
            f"{worst['ruling']}: the plate's {utilisation_text(worst['plate_utilisation'])} x "
            f"{check['factor']:.3g} (splices {check['splice_thickness'] * 1e3:g} mm glued on "
            f"both faces of {check['thickness'] * 1e3:g} mm)"
        )
        rows.append(("splice bending", f"** {text} **" if check["exceeded"] else text))
    return rows


def _bom_rows(b: dict, assembly) -> list:
    """The bill of materials' totals, the cost estimate and the assembly."""
    return [
        (
            "bill of materials",
            f"{b['plates']} plate parts + {b['splices']} splices, {b['parts_area_m2']:.2f} m², "
            f"{b['mass_kg']:.1f} kg; textile {b['textile_length_m']:.2f} m of a "
            f"{b['textile_roll_width_m']:g} m roll; glue line {b['glue_line_m']:.1f} m; "
            f"{b['fasteners']} fasteners",
        ),
        (
            "cost estimate",
            f"{b['cost_total']:.0f} {b['currency']} ("
            + ", ".join(f"{k} {v:.0f}" for k, v in b["cost"].items())
            + ")",
        ),
        (
            "assembly",
            f"{len(assembly)} steps in stack order (fabrication.json assembly, assembly.pdf)",
        ),
    ]
