"""What the report's page and its PDF both show, worded once.

The figures of the report and their captions (:data:`FIGURES`), the rows of the engineering
record (:func:`record_rows`), of the key figures and checks as ``ccu info`` words them
(:func:`check_rows`) and the tables of the fabrication folder (:func:`fabrication_tables`):
:mod:`compas_ccu.viz.report_page` puts them in HTML, :mod:`compas_ccu.viz.report_blocks` in
blocks of the PDF.
"""

from __future__ import annotations

from compas_ccu.key_figures import KeyFigures
from compas_ccu.key_figures.text import figure_rows, thickness_rows, validation_rows
from compas_ccu.viz.record import cell_text, table_columns

__all__ = ["FIGURES", "check_rows", "record_rows", "fabrication_tables"]

#: The figures of the report: (file stem, caption), in the order of the page.
FIGURES = (
    ("views-kind", "3D views, creases coloured by kind"),
    ("views-curvature", "3D views, plates coloured by their bending curvature |κ|"),
    ("views-alpha", "3D views, creases coloured by the reflection angle α"),
    ("cut-patterns", "Cut patterns of all plates: creases by kind, rulings as score lines"),
    ("sequence", "Deployment sequence from the flat-folded stack (paper Fig. 1)"),
    ("quadrants", "The four quadrants of the leading crease (paper Fig. 2)"),
    ("planarity", "Planarity of every crease along the deployment path (paper Fig. 6d)"),
)


def check_rows(k: KeyFigures, thickness, validation_record) -> list:
    """The key figures and checks, as ``ccu info`` words them (one definition)."""
    rows = figure_rows(k)
    if thickness:
        rows += thickness_rows(thickness)
    rows += validation_rows(validation_record)
    return rows


def record_rows(record: dict) -> list:
    """The rows of the engineering record: design file, hash, version, date and units."""
    rows = [
        ("design file", record["file"] or "not given (the model was built in Python)"),
    ]
    if record["sha256"]:
        rows.append(("sha256", record["sha256"]))
    rows += [
        ("compas_ccu", f"{record['version']} (Python {record['python']})"),
        ("date (UTC)", record["date"]),
    ]
    rows.append(("units", "; ".join(f"{k} {v}" for k, v in record["units"].items())))
    return rows


def fabrication_tables(fab: dict) -> list:
    """(title, columns, rows of cell strings) of the fabrication folder's tables."""
    out = []
    for key, title in (("sheets", "Sheets"), ("bom", "Bill of materials")):
        rows = fab.get(key)
        if rows:
            columns = table_columns(rows)
            out.append(
                (
                    f"{title} (fabrication.json: {key})",
                    columns,
                    [[cell_text(r.get(c)) for c in columns] for r in rows],
                )
            )
    return out
