"""The report as blocks of its PDF (:func:`compas_ccu.viz.pdf.write_pdf`).

:func:`pdf_blocks` gives what the page :mod:`compas_ccu.viz.report_page` shows (the record, the
key figures and checks, the structural checks, the fabrication, the figures, the design file and
what was not produced) as title, heading, rows, table, image, code and line blocks;
:func:`pdf_footer` is the footer of every page.
"""

from __future__ import annotations

from compas_ccu.key_figures import KeyFigures
from compas_ccu.key_figures.text import LOAD_CASE_COLUMNS, design_values_text, load_case_table
from compas_ccu.viz.report_content import FIGURES, fabrication_tables, record_rows

__all__ = ["pdf_blocks", "pdf_footer"]


def pdf_footer(k: KeyFigures, record: dict) -> str:
    """The footer of every PDF page: design, version, date and the design file's hash."""
    sha = f" · sha256 {record['sha256'][:12]}" if record.get("sha256") else ""
    return f"{k.name} · compas_ccu {record['version']} · {record['date']}{sha}"


def pdf_blocks(k: KeyFigures, report, checks, figures, validation, shown) -> list:
    """The report as blocks of :func:`compas_ccu.viz.pdf.write_pdf`.

    Parameters
    ----------
    k : KeyFigures
    report : compas_ccu.viz.report.Report
        What was written (the record, the fabrication, what was not produced).
    checks : list of (str, str)
        :func:`~compas_ccu.viz.report_content.check_rows`.
    figures : dict
        Figure name (:data:`~compas_ccu.viz.report_content.FIGURES`) to the paths written.
    validation : dict or None
        The ``validation.json`` of the design.
    shown : list of Path
        The pictures of the load cases.
    """
    r = report.record
    blocks = [
        (
            "title",
            k.name,
            (k.description + " · " if k.description else "")
            + f"compas_ccu {r['version']} · curved-crease unfolding report · {r['date']}",
        ),
        ("heading", "Engineering record"),
        ("rows", record_rows(r)),
        ("heading", "Key figures and checks"),
        ("rows", checks),
    ]
    if r["material"]:
        blocks += [("heading", "Material constants"), ("rows", r["material"])]
    blocks += _structural_blocks(validation, shown)
    if report.fabrication is not None:
        blocks += _fabrication_blocks(report.fabrication)
    for name, caption in FIGURES:
        if name in figures:
            png = next(p for p in figures[name] if p.suffix == ".png")
            blocks.append(("image", png, caption))
    if r["text"] is not None:
        blocks += [
            ("heading", f"Design inputs: {r['file']}"),
            ("paragraph", f"sha256 {r['sha256']}"),
            ("code", r["text"]),
        ]
    if report.skipped:
        blocks += [
            ("heading", "Not produced"),
            ("lines", [f"{a}: {b}" for a, b in sorted(report.skipped.items())]),
        ]
    return blocks


def _structural_blocks(validation, shown) -> list:
    """The structural checks of ``validation`` (its load cases) and their pictures ``shown``;
    none without load cases."""
    c = (validation or {}).get("checks")
    if not (c and "cases" in c):
        return []
    blocks = [
        ("heading", "Structural checks (FE, load cases)"),
        ("paragraph", f"{validation.get('engine', '')} {validation.get('mode', '')}"),
    ]
    heading, table, governing = load_case_table(c)
    blocks += [
        ("paragraph", heading),
        (
            "table",
            list(LOAD_CASE_COLUMNS),
            [cells if ok else [f"** {cells[0]} **", *cells[1:]] for cells, ok in table],
        ),
        *([("paragraph", design_values_text(c))] if design_values_text(c) else []),
        ("paragraph", f"governing: {governing}"),
    ]
    blocks += [
        ("image", p, "Deflection under the characteristic loads of every case") for p in shown
    ]
    return blocks


def _fabrication_blocks(fab: dict) -> list:
    """The fabrication folder ``fab`` (:func:`compas_ccu.viz.record.read_fabrication`): its
    problems, failed checks, workshop rows, utilisation, tables and files."""
    blocks = [("heading", "Fabrication"), ("paragraph", f"From {fab['folder']}")]
    blocks += [("paragraph", p) for p in fab["problems"]]
    if fab.get("failed_checks"):
        blocks.append(("rows", [("check failed", f"** {c} **") for c in fab["failed_checks"]]))
    if fab.get("workshop_rows"):
        blocks.append(("rows", fab["workshop_rows"]))
    if fab["utilisation"] is not None:
        blocks.append(("paragraph", f"Sheet utilisation {fab['utilisation']:.1%}"))
    for title, columns, rows in fabrication_tables(fab):
        blocks += [("paragraph", title), ("table", columns, rows)]

    blocks += [
        ("paragraph", "Files (in fabrication/ beside this report):"),
        ("lines", fab["files"]),
    ]
    return blocks
