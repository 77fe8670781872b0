"""The viewer's plotly figure: the structure along its deployment path, the cut patterns or the
fabrication's sheets, the animation frames, the slider and the toggles, put together.

The arrays come from :mod:`compas_ccu.viz.viewer_data`, the traces from
:mod:`compas_ccu.viz.viewer_traces`, the slider, menus and layout from
:mod:`compas_ccu.viz.viewer_controls`; the page that holds the figure is
:mod:`compas_ccu.viz.viewer`. Plotly is imported only when a figure is built.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.viz.viewer_controls import (
    axis_ranges,
    figure_layout,
    figure_title,
    play_buttons,
    readout_annotation,
    readouts,
    scene_layout,
    toggle_menus,
)
from compas_ccu.viz.viewer_data import ViewerData, cut_pattern_places, path_data, sheet_places
from compas_ccu.viz.viewer_ground import sheet_document
from compas_ccu.viz.viewer_traces import (
    cut_pattern_traces,
    frame_traces,
    sheet_traces,
    structure_traces,
)

if TYPE_CHECKING:  # plotly is imported when a figure is built, not with this module
    import plotly.graph_objects as go

__all__ = ["viewer_figure"]


def viewer_figure(
    model,
    *,
    steps: int = 24,
    alpha: float | None = None,
    title: str | None = None,
    view=None,
    pattern_offsets=None,
    sheets=None,
) -> go.Figure:
    """Interactive 3D figure of a model along its deployment path, with slider and toggles.

    The states are ``numpy.linspace(0, alpha, steps + 1)``: from the flat-folded stack to the
    target; the figure opens on the last one. Every state is grounded (lowest point on
    ``z = 0``) and the axis ranges are fixed over all states, so the view does not jump. The cut
    patterns (hidden at first) lie on the ground behind the structure (+y, so that the
    structure stands in front of them, large), in the compact columns of
    :func:`cut_pattern_layout` (or at ``pattern_offsets``), none overlapping another; or, with
    ``sheets``, the fabrication's sheets with every part at its nested place, beside and behind
    the structure. Showing them widens the box to include them. A read-out under the scene
    gives α, span, rise and plate length of the state shown
    (:func:`compas_ccu.key_figures.state_figures`).

    Traces, in order: plates (Mesh3d, two triangles per quad, alternating plate tones), plate
    edges (free boundaries and plate ends, thin dark lines), one crease trace per kind present
    (wide, coloured and labelled by kind), rulings (at most 32 per plate), then the cut patterns
    (fill, outlines, creases by kind, rulings, plate ids; with ``sheets``: the parts' fill,
    boards, sheet edges, part outlines, creases by kind, score lines and splice marks if any,
    part names, sheet numbers). Every trace carries ``legendgroup``
    ``"plates"``, ``"creases"``, ``"rulings"`` or ``"cut"``; the animation frames update the
    coordinates of the structure's traces only. *Play* runs the whole path from α = 0.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    steps : int
        Number of steps of the path (``steps + 1`` states, ``steps >= 1``).
    alpha : float, optional
        Target reference reflection angle, degrees (``> 0``); default the design angle.
    title : str, optional
        Replaces the headline (the design name); the key figures stay below it.
    view : str, optional
        The opening camera: a view name of :func:`compas_ccu.viz.render.camera` (``iso``,
        ``front``, ``side``, ``top``, ...) or ``"azimuth,elevation"``; default a perspective
        from the front right.
    pattern_offsets : (p, 2) float, optional
        Where the cut patterns lie (translations of the flat-folded stack's plates); default
        :func:`cut_pattern_layout`.
    sheets : WorkshopPlan or dict, optional
        The fabrication's nesting: a ``compas_ccu.fabrication.workshop.WorkshopPlan`` or its
        ``layout()`` (the ``sheets.json`` of a ``ccu fabricate`` folder:
        :func:`compas_ccu.viz.record.read_sheets`). The cut patterns are then the sheets: every
        sheet (its board and edge, "sheet k · utilisation") in a grid around the structure
        (:func:`sheet_grid_layout`), every part at exactly its nested place (float64, the
        placement of the sheet DXFs), filled in its plate's tone, with its crease edges by
        kind, its score lines and splice marks if any, and its name.

    Returns
    -------
    plotly.graph_objects.Figure
        With ``steps + 1`` frames named ``"0" .. str(steps)``, one slider, Play / Pause buttons
        and one toggle menu per group.

    Raises
    ------
    compas_ccu.errors.OptionError
        ``steps`` is not an integer >= 1 or ``alpha`` is not a finite angle > 0 (the message
        names the value); ``sheets`` is no nesting, or one of another design or other plates
        (:func:`sheet_document`), or is given with ``pattern_offsets``.
    compas_ccu.errors.DeploymentLimitError, compas_ccu.errors.SelfIntersectionError
        ``alpha`` is beyond the deployment limit, or a crease overlaps itself on the way.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> fig = viewer_figure(model, steps=4)
    >>> len(fig.frames), fig.layout.sliders[0].active, fig.layout.sliders[0].steps[-1].label
    (5, 4, '40°')
    """
    import plotly.graph_objects as go

    target = _check_arguments(model, steps, alpha)
    doc = _nesting(model, sheets, pattern_offsets)  # checked before the path is computed
    alphas = np.linspace(0.0, target, int(steps) + 1)
    data = path_data(model, alphas)
    # the cut patterns (static, hidden at first): the compact layout, or the sheets
    if doc is None:
        pattern = cut_pattern_places(data, pattern_offsets)
        cut = cut_pattern_traces(data, pattern)
        extent = pattern.reshape(-1, 3)
    else:
        sizes, corners = sheet_places(data, doc)
        cut = sheet_traces(doc, corners, 0.0, _sheet_kinds(doc, data.kinds), data.tones)
        ends = np.concatenate([corners, corners + sizes]) if len(sizes) else np.zeros((0, 2))
        extent = np.c_[ends, np.zeros(len(ends))]
    structure_box, whole_box = _boxes(data, extent)
    moving = structure_traces(data)
    for trace in cut:
        trace.visible = False
    traces = moving + cut
    texts = readouts(data.structures)
    menus = toggle_menus([t.legendgroup for t in traces], structure_box, whole_box)
    layout = figure_layout(
        figure_title(model, data.kinds, data.counts, alphas),
        view,
        alphas,
        texts[-1],
        [play_buttons(), *menus],
    )
    fig = go.Figure(data=traces, layout=layout, frames=_frames(data, len(moving), texts))
    fig.update_layout(scene_layout(*structure_box))
    if title is not None:
        fig.layout.title.text = title
    return fig


def _check_arguments(model, steps, alpha) -> float:
    """The target angle, degrees, after checking ``steps`` and ``alpha``."""
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
        raise OptionError(f"steps must be an integer >= 1, got {steps!r}")
    if alpha is None:
        return float(model.alpha_design)
    try:
        value = float(alpha)
    except (TypeError, ValueError):
        raise OptionError(f"alpha must be a number of degrees > 0, got {alpha!r}") from None
    if not math.isfinite(value) or value <= 0.0:
        raise OptionError(f"alpha must be a finite angle > 0 degrees, got {alpha!r}")
    return value


def _nesting(model, sheets, pattern_offsets):
    """The checked nesting document of ``sheets`` (:func:`sheet_document`), or None."""
    if sheets is None:
        return None
    if pattern_offsets is not None:
        raise OptionError("give sheets or pattern_offsets, not both")
    name = getattr(model.design, "name", None)
    return sheet_document(sheets, model.plate_ids, design=name)


def _sheet_kinds(doc: dict, kinds: list) -> list:
    """The crease kinds of the sheets' traces: the structure's, then any other on a part."""
    sheet_kinds = {c.get("kind") for part in doc["parts"] for c in part.get("creases", [])}
    return kinds + sorted(k for k in sheet_kinds if k and k not in kinds)


def _boxes(data: ViewerData, extent: np.ndarray) -> tuple:
    """:func:`axis_ranges` of the structure's box over all states, and of the box that also
    holds ``extent`` (m, 3), the cut patterns or the sheets."""
    lo, hi = data.lo, data.hi
    plo = np.minimum(lo, extent.min(axis=0)) if len(extent) else lo
    phi = np.maximum(hi, extent.max(axis=0)) if len(extent) else hi
    return axis_ranges(lo, hi), axis_ranges(plo, phi)


def _frames(data: ViewerData, moving: int, texts: list) -> list:
    """One animation frame per state: the coordinates of the first ``moving`` traces (the
    structure's) and the state's read-out."""
    import plotly.graph_objects as go

    return [
        go.Frame(
            name=str(k),
            data=frame_traces(data, k),
            traces=list(range(moving)),
            layout={"annotations": [readout_annotation(texts[k])]},
        )
        for k in range(len(data.states))
    ]
