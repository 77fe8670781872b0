"""The rule catalog of global shape control (paper §5.4-5.5, Fig. 9-12), regenerated and measured.

Every entry of :data:`FAMILIES` is a design document; :func:`catalog_metrics` builds, deploys and
measures it (the global curvature class from the deployed geometry, not assumed), and
:func:`write_catalog` writes for every design its design file and structure file plus one
metrics table (CSV, Markdown, JSON) and, with the ``viz`` extra, one contact sheet per figure.
``examples/catalog/`` holds the same designs as TOML files (a test keeps them equal).

Plate parity in the vault families: the leading plate (index 5 of 10) lies on the inside of the
leading crease, so plates 0, 2, 4, 5, 7, 9 run from a ridge crease inwards (*inward* plates)
and plates 1, 3, 6, 8 from a valley crease outwards (*outward* plates).
"""

from __future__ import annotations

import copy
import csv
import json
from pathlib import Path

import numpy as np

__all__ = [
    "FAMILIES",
    "family",
    "catalog_design",
    "catalog_metrics",
    "write_catalog",
    "write_examples",
]

_ARC = {"profile": "arc", "span": 2.5, "rise": 1.0, "segments": 48}
_BASE = {
    "crease": _ARC,
    "rulings": {"type": "orthogonal", "side": "inside"},
    "deployment": {"alpha": 30.0},
    "layout": {"type": "parallel", "plates": 10, "spacing": 0.12},
}
_INWARD = (0, 2, 4, 5, 7, 9)


def _by_parity(inward, outward) -> list:
    """Per-plate values for the 10-plate vaults: dicts plate -> value, or one number each."""
    out = []
    for k in range(10):
        table = inward if k in _INWARD else outward
        out.append(float(table[k] if isinstance(table, dict) else table))
    return out


def _entry(name, figure, title, expected, **sections) -> dict:
    doc = copy.deepcopy(_BASE)
    for key, value in sections.items():
        doc[key] = value
    doc["design"] = {"name": name, "description": f"Fig. {figure}: {title}"}
    return {"name": name, "figure": figure, "title": title, "expected": expected, "document": doc}


#: The catalog: name, paper figure, title, the class the paper's rule predicts (None where the
#: paper states none) and the design document.
FAMILIES = [
    # Fig. 9: crease profiles, parallel planes at constant distance
    _entry("fig09a-arc", "9a", "arc profile", "monoclastic"),
    _entry(
        "fig09b-elastica",
        "9b",
        "Euler elastica profile",
        "monoclastic",
        crease={"profile": "elastica", "span": 2.5, "rise": 1.0, "segments": 48},
    ),
    _entry(
        "fig09c-catenary",
        "9c",
        "catenary profile",
        "monoclastic",
        crease={"profile": "catenary", "span": 2.5, "rise": 1.0, "segments": 48},
    ),
    _entry(
        "fig09d-funicular",
        "9d",
        "funicular of asymmetric loads (uniform + left half + point load)",
        None,
        crease={
            "profile": "funicular",
            "span": 2.5,
            "rise": 1.0,
            "segments": 48,
            "distributed_loads": [[-1.25, 1.25, 1.0, 1.0], [-1.25, 0.0, 1.0, 1.0]],
            "point_loads": [[0.5, 0.6]],
        },
    ),
    _entry(
        "fig09e-freeform",
        "9e",
        "freeform spline with inflection points (crease kind changes along it)",
        None,
        crease={
            "profile": "spline",
            "points": [
                [-1.25, 0.0],
                [-1.0, 0.8],
                [-0.45, 0.75],
                [0.0, 1.0],
                [0.45, 0.75],
                [1.0, 0.8],
                [1.25, 0.0],
            ],
            "segments": 64,
        },
        layout={"type": "parallel", "plates": 10, "spacing": 0.1},
    ),
    # Fig. 10: plane distance only
    _entry("fig10a-monoclastic", "10a", "constant plane distance", "monoclastic"),
    _entry(
        "fig10b-synclastic",
        "10b",
        "outward plates' distance decreasing away from the centre",
        "synclastic",
        layout={
            "type": "parallel",
            "plates": 10,
            "spacing": _by_parity(0.12, {1: 0.08, 3: 0.11, 6: 0.11, 8: 0.08}),
        },
    ),
    _entry(
        "fig10c-anticlastic",
        "10c",
        "inward plates' distance decreasing away from the centre",
        "anticlastic",
        layout={
            "type": "parallel",
            "plates": 10,
            "spacing": _by_parity({0: 0.06, 2: 0.09, 4: 0.11, 5: 0.11, 7: 0.09, 9: 0.06}, 0.12),
        },
    ),
    # Fig. 11: inclination about the actuation rotation axis
    _entry(
        "fig11a-constant-apex",
        "11a",
        "constant apex height, support distance varying",
        None,
        layout={
            "type": "inclined",
            "plates": 10,
            "spacing": 0.12,
            "spacing_start": _by_parity(0.08, 0.16),
        },
    ),
    _entry(
        "fig11b-constant-support",
        "11b",
        "constant support line, apex height varying",
        None,
        layout={
            "type": "inclined",
            "plates": 10,
            "spacing": _by_parity(0.08, 0.16),
            "spacing_start": 0.12,
        },
    ),
    _entry(
        "fig11c-alternating",
        "11c",
        "ridge and valley creases articulated alternately at apex and supports",
        None,
        layout={
            "type": "inclined",
            "plates": 10,
            "spacing": _by_parity(0.16, 0.08),
            "spacing_start": _by_parity(0.08, 0.16),
        },
    ),
    _entry(
        "fig11d-target-curves",
        "11d",
        "inverse design: apex line level, support lines widening (target curves)",
        None,
        layout={
            "type": "inclined",
            "plates": 10,
            "spacing": 0.12,
            "spacing_start": 0.12,
        },
        target={
            "apex": [[-1.5, 1.0], [1.5, 1.0]],
            "support": [[-1.5, -1.45], [0.0, -1.25], [1.5, -1.45]],
        },
    ),
    # Fig. 12: inclination perpendicular to the actuation rotation axis
    _entry(
        "fig12a-asymmetric",
        "12a",
        "non-axisymmetric vault: planes tilted alternately to the sides",
        None,
        layout={
            "type": "inclined",
            "plates": 10,
            "spacing": 0.12,
            "spacing_start": _by_parity(0.08, 0.16),
            "spacing_end": _by_parity(0.16, 0.08),
        },
    ),
    _entry(
        "fig12b-dome",
        "12b",
        "radial dome: planes through the vertical axis",
        "synclastic",
        crease={
            "profile": "spline",
            "points": [[0.25, 1.2], [1.0, 1.0], [1.6, 0.5], [1.9, 0.0]],
            "segments": 48,
        },
        layout={"type": "radial", "plates": 12, "angle": 8.0, "axis": 0.0},
    ),
    _entry(
        "fig12c-funnel",
        "12c",
        "funnel column: radial planes, profile rising outwards",
        "anticlastic",
        crease={
            "profile": "spline",
            "points": [[0.25, 0.0], [0.45, 0.8], [1.0, 1.4], [1.8, 1.7]],
            "segments": 48,
        },
        rulings={"type": "orthogonal", "side": "left"},
        layout={"type": "radial", "plates": 12, "angle": 8.0, "axis": 0.0},
    ),
]


def family(name: str) -> dict:
    """The catalog entry ``name`` (see :data:`FAMILIES`); ValueError names the others."""
    for entry in FAMILIES:
        if entry["name"] == name:
            return entry
    names = ", ".join(e["name"] for e in FAMILIES)
    raise ValueError(f"no catalog design {name!r}; the catalog has: {names}")


def catalog_design(name: str):
    """The :class:`compas_ccu.design.Design` of catalog entry ``name``."""
    from compas_ccu.design import Design

    return Design(copy.deepcopy(family(name)["document"]))


def catalog_metrics(model, *, steps: int = 24, relax: bool = True) -> dict:
    """Measure a built design for the catalog table.

    Returns a flat dict: global curvature class and principal curvatures, span, rise, plan
    dimensions, flat stack footprint, reference and largest crease alpha, deployment and
    overlap limits, crease planarity along the path (and the relaxation's residuals where it is
    not exact), the largest invariant error of the design state and the target-curve fit.
    """
    from compas_ccu.analysis import global_curvature
    from compas_ccu.analysis.planarity import planarity_along_path
    from compas_ccu.io import flat_footprint

    structure = model.deploy()
    deployed = np.asarray(structure.deployed).reshape(-1, 3)
    axes = model.axes  # rows: profile x, profile y (up), plane normal
    rel = deployed - model.origin
    out = {
        "plates": len(structure.flat),
        "creases": len(structure.creases),
        "kinds": " ".join(f"{k}:{v}" for k, v in structure.crease_kind_counts().items()),
    }
    if model.planes is not None and model.planes.plates >= 4:
        states = model.mechanism.deploy(np.radians([model.alpha_design]))
        g = global_curvature(model.plane_curves(states)[0])
        out.update(g.summary())
    else:
        out.update({"global_curvature": "n/a"})
    stack = flat_footprint(structure)
    out.update(
        {
            "span": structure.metrics["span"],
            "rise": float(np.ptp(rel @ axes[1])),
            "plan_x": float(np.ptp(rel @ axes[0])),
            "plan_y": float(np.ptp(rel @ axes[2])),
            "stack_x": stack[0],
            "stack_y": stack[1],
            "alpha": model.alpha_design,
            "alpha_max": float(max(max(c["alpha"]) for c in structure.creases)),
            "alpha_limit": model.alpha_limit,
            "overlap_alpha": model.overlap_alpha,
            "invariant_max_relative": structure.max_invariant_error / model.size,
        }
    )
    report = planarity_along_path(model, steps=steps, relax=relax and steps > 0)
    summary = report.summary()
    out.update(
        {
            "planarity_max": summary["planarity_max"],
            "planarity_max_relative": summary["planarity_max_relative"],
            "planarity_alpha_at_max": summary["planarity_alpha_at_max"],
            "planarity_exact": summary["planarity_exact"],
        }
    )
    r = summary["relaxation"]
    if r is not None and not report.exact:
        out.update(
            {
                "relaxed_alpha": r["alpha"],
                "kinematic_isometry": r["kinematic_isometry"],
                "relaxed_strain": r["max_strain"],
                "relaxed_quad_planarity": r["quad_planarity"],
                "relaxed_displacement": r["displacement"],
            }
        )
    fit = model.built.target_fit
    if fit is not None:
        out["target_fit_max"] = fit.max_residual
    return out


#: Columns of the catalog table, in order (missing values are left empty).
COLUMNS = (
    "name",
    "figure",
    "expected",
    "global_curvature",
    "gaussian_curvature",
    "plates",
    "kinds",
    "span",
    "rise",
    "plan_x",
    "plan_y",
    "stack_x",
    "stack_y",
    "alpha",
    "alpha_max",
    "alpha_limit",
    "overlap_alpha",
    "planarity_max",
    "planarity_exact",
    "relaxed_strain",
    "relaxed_quad_planarity",
    "target_fit_max",
    "invariant_max_relative",
)


def _fmt(value) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        if value == 0.0:
            return "0"
        return f"{value:.4g}" if 1e-3 <= abs(value) < 1e4 else f"{value:.2e}"
    return str(value)


def write_examples(folder) -> list:
    """Write every catalog design as ``folder/<name>.toml`` (the ``examples/catalog`` files)."""
    from compas_ccu.design.inverse import write_design

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for entry in FAMILIES:
        path = folder / f"{entry['name']}.toml"
        write_design(catalog_design(entry["name"]), path)
        paths.append(path)
    return paths


def write_catalog(
    out,
    *,
    names=None,
    steps: int = 24,
    relax: bool = True,
    figures: bool = True,
    progress=None,
) -> dict:
    """Build, measure and write the catalog.

    Parameters
    ----------
    out : path
        Output folder: ``catalog.csv``, ``catalog.md``, ``catalog.json``, one folder per design
        with ``design.toml`` and ``structure.json``, and ``fig09.png`` ... contact sheets.
    names : list of str, optional
        Only these designs.
    steps : int
        States along the path for the planarity measurement.
    relax : bool
        Relax the worst state of designs whose creases leave their planes.
    figures : bool
        Contact sheets (needs the ``viz`` extra).
    progress : callable, optional
        Called with each design name before it is measured.

    Returns
    -------
    dict
        ``rows`` (list of dicts), ``files`` (list of paths).
    """
    from compas_ccu.design.inverse import write_design
    from compas_ccu.io import write_structure_json

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    entries = FAMILIES if names is None else [family(n) for n in names]
    rows, files, structures = [], [], {}
    for entry in entries:
        if progress is not None:
            progress(entry["name"])
        design = catalog_design(entry["name"])
        model = design.build()
        metrics = catalog_metrics(model, steps=steps, relax=relax)
        row = {"name": entry["name"], "figure": entry["figure"], "expected": entry["expected"]}
        row.update(metrics)
        row["title"] = entry["title"]
        rows.append(row)
        folder = out / entry["name"]
        folder.mkdir(exist_ok=True)
        write_design(design, folder / "design.toml")
        structure = model.deploy()
        structure.metrics["catalog"] = {k: v for k, v in row.items() if k != "title"}
        write_structure_json(structure, folder / "structure.json")
        files += [folder / "design.toml", folder / "structure.json"]
        structures[entry["name"]] = (entry, structure)
    files += _write_tables(out, rows)
    if figures:
        files += _write_sheets(out, structures)
    return {"rows": rows, "files": files}


def _write_tables(out: Path, rows: list) -> list:
    with open(out / "catalog.csv", "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(COLUMNS + ("title",))
        for row in rows:
            writer.writerow([row.get(c, "") for c in COLUMNS] + [row["title"]])
    with open(out / "catalog.json", "w") as fh:
        json.dump(rows, fh, indent=1, default=float)
    lines = [
        "# CCU rule catalog",
        "",
        "Measured by `ccu catalog` (paper Fig. 9-12). Lengths m, angles degrees, curvature "
        "1/m^2. `expected`: the class the paper's rule predicts; `global_curvature`: measured "
        "from the deployed structure.",
        "",
        "| " + " | ".join(COLUMNS) + " |",
        "|" + "---|" * len(COLUMNS),
    ]
    for row in rows:
        lines.append("| " + " | ".join(_fmt(row.get(c)) for c in COLUMNS) + " |")
    (out / "catalog.md").write_text("\n".join(lines) + "\n")
    return [out / "catalog.csv", out / "catalog.json", out / "catalog.md"]


def _write_sheets(out: Path, structures: dict) -> list:
    try:
        from compas_ccu.viz.export import save_figure
        from compas_ccu.viz.sheet import plot_contact_sheet
    except ImportError:  # pragma: no cover - viz extra missing
        return []
    import matplotlib.pyplot as plt

    files = []
    groups: dict = {}
    for entry, structure in structures.values():
        fig_no = "".join(ch for ch in entry["figure"] if ch.isdigit())
        groups.setdefault(fig_no, []).append((entry, structure))
    for fig_no, items in groups.items():
        captions = [
            f"{e['title']}\nmeasured: {s.metrics['catalog']['global_curvature']}" for e, s in items
        ]
        fig = plot_contact_sheet(
            [s for _, s in items],
            titles=[f"Fig. {e['figure']}" for e, _ in items],
            captions=captions,
            columns=min(3, len(items)),
            title=f"Rule catalog, paper Fig. {fig_no}",
        )
        files += save_figure(fig, out / f"fig{int(fig_no):02d}", formats=("png",))
        plt.close(fig)
    return files
