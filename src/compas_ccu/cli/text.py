"""Text of the ``ccu`` commands: the lines of ``ccu info`` and of the thickness summary.

Only layout: the rows (the wording of every number) are :mod:`compas_ccu.key_figures.text`,
shared with the report; the numbers come from the library (:mod:`compas_ccu.key_figures`,
:meth:`compas_ccu.thickness.ThickModel.summary`, :func:`compas_ccu.fea.record.last_validation`).
"""

from __future__ import annotations

from compas_ccu.key_figures.text import (
    basis_text,
    figure_rows,
    load_case_lines,
    rows_lines,
    thickness_rows,
    validation_rows,
)

__all__ = ["info_lines", "thickness_lines", "validation_lines", "basis_text", "load_case_lines"]


def info_lines(k) -> list:
    """``ccu info`` lines of the key figures ``k`` (:class:`compas_ccu.key_figures.KeyFigures`
    with the path figures): design, limits, shape, stack, invariants, layout, planarity."""
    return rows_lines(figure_rows(k))


def thickness_lines(summary: dict) -> list:
    """Text lines of a :meth:`compas_ccu.thickness.ThickModel.summary` (info, fabricate)."""
    return rows_lines(thickness_rows(summary))


def validation_lines(record: dict | None) -> list:
    """``ccu info`` lines on the last FE validation record of a design file, if any."""
    return rows_lines(validation_rows(record))
