"""The key figures and checks as rows of text: one wording of every number a user reads.

``ccu info`` prints these rows as lines (label padded to :data:`LABEL_WIDTH`), the HTML and PDF
report (:mod:`compas_ccu.viz.report`) as table rows: the same strings, so the terminal and the
report cannot disagree. A row is ``(label, text)``; a row that continues the one above has an
empty label; a failed check is marked ``** ... **`` in its text (:func:`row_failed`).

The numbers come from the library: :class:`compas_ccu.key_figures.KeyFigures`,
:meth:`compas_ccu.thickness.ThickModel.summary`, :func:`compas_ccu.fea.record.last_validation`
(a record: plain data) and :class:`compas_ccu.materials.Material` /
:class:`compas_ccu.materials.DesignFactors`.

Every wording is importable from here; each is written in the module of its subject: the rows
and the wordings they share (:mod:`.rows`), the key figures of a design (:mod:`.figure_text`),
the thick plates and their material (:mod:`.thickness_text`), the FE validation
(:mod:`.validation_text`) and the workshop (:mod:`.workshop_text`).
"""

from __future__ import annotations

from compas_ccu.key_figures.figure_text import figure_rows, size_figures
from compas_ccu.key_figures.rows import (
    LABEL_WIDTH,
    basis_text,
    row_failed,
    rows_lines,
    utilisation_text,
    value_text,
)
from compas_ccu.key_figures.thickness_text import kink_note, material_rows, thickness_rows
from compas_ccu.key_figures.validation_text import (
    LOAD_CASE_COLUMNS,
    deployment_utilisation_text,
    design_values_text,
    load_case_lines,
    load_case_table,
    validation_rows,
)
from compas_ccu.key_figures.workshop_text import workshop_rows

__all__ = [
    "LABEL_WIDTH",
    "figure_rows",
    "thickness_rows",
    "validation_rows",
    "material_rows",
    "basis_text",
    "load_case_lines",
    "load_case_table",
    "design_values_text",
    "workshop_rows",
    "LOAD_CASE_COLUMNS",
    "value_text",
    "rows_lines",
    "row_failed",
    "size_figures",
    "utilisation_text",
    "deployment_utilisation_text",
    "kink_note",
]
