"""The rule catalog of global shape control (paper §5.4-5.5, Fig. 9-12), regenerated and measured.

The catalog's designs are the design files in ``compas_ccu/data/catalog/``, shipped with the
package (:data:`CATALOG_DIR`; :func:`catalog_path` finds one by name, and ``ccu info`` or
``ccu deploy`` take it like any design file). Their ``[design]`` section names the paper figure
(``figure``) and the global curvature class the paper's rule predicts (``expected``, absent where
the paper states none). :func:`catalog_metrics` builds, deploys and measures a design: its key
figures (:mod:`compas_ccu.key_figures`), with the global curvature class measured from the
deployed geometry, not assumed. :func:`write_catalog` writes for every design its design file
and structure file plus one table (CSV, Markdown, JSON) and, with the ``viz`` extra, one contact
sheet per figure.

Plate parity in the vault families: the leading plate (index 5 of 10) lies on the inside of the
leading crease, so plates 0, 2, 4, 5, 7, 9 run from a ridge crease inwards (*inward* plates)
and plates 1, 3, 6, 8 from a valley crease outwards (*outward* plates); the per-plate spacings
of Fig. 10-12 alternate accordingly.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from compas_ccu.design import Design, load_design
from compas_ccu.design.document import read_toml
from compas_ccu.design.inverse import write_design
from compas_ccu.errors import OptionError
from compas_ccu.io import write_structure_json
from compas_ccu.key_figures import key_figures
from compas_ccu.model import CCUModel
from compas_ccu.outputs import write_json
from compas_ccu.viz.export import save_figure
from compas_ccu.viz.sheet import plot_contact_sheet

__all__ = [
    "CATALOG_DIR",
    "CatalogEntry",
    "COLUMNS",
    "catalog_entries",
    "catalog_entry",
    "catalog_path",
    "catalog_design",
    "catalog_metrics",
    "write_catalog",
]

#: Folder of the catalog's design files (package data).
CATALOG_DIR = Path(__file__).resolve().parent / "data" / "catalog"


@dataclass(frozen=True)
class CatalogEntry:
    """One design of the catalog.

    Attributes
    ----------
    name : str
        Design name (the file name without ``.toml``).
    figure : str
        Paper figure, e.g. ``"9a"``.
    title : str
        What the design shows (its description without the ``Fig. 9a:`` prefix).
    expected : str or None
        Global curvature class the paper's rule predicts (None where it states none).
    path : Path
        The design file.
    """

    name: str
    figure: str
    title: str
    expected: str | None
    path: Path

    @property
    def document(self) -> dict:
        """The parsed design file (a fresh copy)."""
        return read_toml(self.path)

    def design(self) -> Design:
        """The validated design."""
        return load_design(self.path)


@cache
def catalog_entries() -> tuple:
    """Every catalog design, ordered by file name (Fig. 9a ... 12c)."""
    entries = []
    for path in sorted(CATALOG_DIR.glob("*.toml")):
        meta = load_design(path).document["design"]
        figure = meta["figure"]
        prefix = f"Fig. {figure}: "
        title = meta["description"]
        title = title[len(prefix) :] if title.startswith(prefix) else title
        entries.append(CatalogEntry(path.stem, figure, title, meta.get("expected"), path))
    return tuple(entries)


def catalog_entry(name: str) -> CatalogEntry:
    """The catalog design ``name``; OptionError names the others."""
    for entry in catalog_entries():
        if entry.name == name:
            return entry
    names = ", ".join(e.name for e in catalog_entries())
    raise OptionError(f"no catalog design {name!r}; the catalog has: {names}")


def catalog_path(name: str) -> Path:
    """The design file of catalog design ``name``."""
    return catalog_entry(name).path


def catalog_design(name: str) -> Design:
    """The :class:`compas_ccu.design.Design` of catalog design ``name``."""
    return catalog_entry(name).design()


def catalog_metrics(model, *, steps: int = 24, relax: bool = True) -> dict:
    """Measure a built design for the catalog table: its key figures.

    Returns :meth:`compas_ccu.key_figures.KeyFigures.to_dict` with the path figures measured
    over ``steps`` states (crease planarity along the path) and, where a crease leaves its
    plane and ``relax`` is set, the residuals of the least-squares relaxation of the worst state.
    """
    return key_figures(model, path=steps, relax=relax).to_dict()


#: Columns of the catalog table, in order: the entry, then key figures (missing values are
#: left empty).
COLUMNS = (
    "name",
    "figure",
    "expected",
    "global_curvature",
    "gaussian_curvature",
    "plates",
    "crease_kinds",
    "crease_span",
    "crease_rise",
    "height",
    "plan_x",
    "plan_y",
    "stack_x",
    "stack_y",
    "alpha_design",
    "alpha_max",
    "alpha_limit",
    "overlap_alpha",
    "collision_free_alpha",
    "crease_planarity_path",
    "crease_planarity_exact",
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
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    entries = catalog_entries() if names is None else [catalog_entry(n) for n in names]
    rows, files, structures = [], [], {}
    for entry in entries:
        if progress is not None:
            progress(entry.name)
        design = entry.design()
        model = CCUModel(design)
        structure = model.deploy()
        measured = key_figures(model, structure, path=steps, relax=relax)
        row = {"name": entry.name, "figure": entry.figure, "expected": entry.expected}
        row.update(measured.to_dict())
        row["title"] = entry.title
        rows.append(row)
        folder = out / entry.name
        folder.mkdir(exist_ok=True)
        write_design(design, folder / "design.toml")
        structure.metrics["catalog"] = {k: v for k, v in row.items() if k != "title"}
        write_structure_json(structure, folder / "structure.json")
        files += [folder / "design.toml", folder / "structure.json"]
        structures[entry.name] = (entry, structure)
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
    write_json(out / "catalog.json", rows, default=float)
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
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover - viz extra missing
        return []

    files = []
    groups: dict = {}
    for entry, structure in structures.values():
        fig_no = "".join(ch for ch in entry.figure if ch.isdigit())
        groups.setdefault(fig_no, []).append((entry, structure))
    for fig_no, items in groups.items():
        captions = [
            f"{e.title}\nmeasured: {s.metrics['catalog']['global_curvature']}" for e, s in items
        ]
        fig = plot_contact_sheet(
            [s for _, s in items],
            titles=[f"Fig. {e.figure}" for e, _ in items],
            captions=captions,
            columns=min(3, len(items)),
            title=f"Rule catalog, paper Fig. {fig_no}",
        )
        files += save_figure(fig, out / f"fig{int(fig_no):02d}", formats=("png",))
        plt.close(fig)
    return files
