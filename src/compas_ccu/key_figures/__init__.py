"""The key figures of a design: one definition of every number that describes it.

:data:`FIGURES` is the single source: the name, type, unit, group and meaning of every figure.
:func:`key_figures` measures a built model (and its deployed design state) and returns a
:class:`KeyFigures`; ``ccu info``, the HTML report (:mod:`compas_ccu.viz.report`), the results
columns of a sweep (:mod:`compas_ccu.explore.metrics`) and the rule catalog
(:mod:`compas_ccu.catalog`) all show these numbers, so they cannot disagree.
``docs/key-figures.md`` is generated from the table (:func:`figures_markdown`). The table is
:mod:`.table`, the measurement :mod:`.measure`.

The figures come in groups that can be measured one after the other (a sweep times them and
records which stage failed): :func:`design_state_figures` (design, deployment, shape, stack and
invariant groups), :func:`path_figures` (crease planarity along the deployment path) and
:func:`thickness_figures` (the thick plates). A figure that does not apply is None.
"""

from __future__ import annotations

from compas_ccu.key_figures.measure import (
    KeyFigures,
    design_state_figures,
    key_figures,
    path_figures,
    plate_area,
    state_figures,
    thickness_figures,
)
from compas_ccu.key_figures.table import FIGURES, GROUPS, Figure, figure, figures_markdown

__all__ = [
    "Figure",
    "FIGURES",
    "GROUPS",
    "KeyFigures",
    "key_figures",
    "design_state_figures",
    "path_figures",
    "state_figures",
    "thickness_figures",
    "plate_area",
    "figure",
    "figures_markdown",
]
