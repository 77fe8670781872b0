"""Where the viewer lays the cut patterns and the sheets on the ground beside the structure.

:func:`cut_pattern_layout` packs the cut patterns in columns (arcs nest in arcs);
:func:`sheet_grid_layout` sets the fabrication's sheets in a grid around the structure's plan;
:func:`sheet_document` checks the nesting document (``sheets.json``) the sheets come from.
Plain numpy: the plotly figure is :mod:`compas_ccu.viz.viewer_plot`.
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["cut_pattern_layout", "sheet_grid_layout", "sheet_document", "outline_index"]


def outline_index(n: int) -> np.ndarray:
    """(2n + 3,) vertex order of a closed plate outline: near 0..n, far 2n+1..n+1, back to 0.

    Examples
    --------
    >>> outline_index(2).tolist()
    [0, 1, 2, 5, 4, 3, 0]
    """
    return np.r_[np.arange(n + 1), np.arange(2 * n + 1, n, -1), 0]


def _envelopes(outline: np.ndarray, xs: np.ndarray):
    """Lowest and highest ``y`` of a closed 2D polygon along vertical lines ``x = xs``.

    Parameters
    ----------
    outline : (m, 2) float
        Closed polygon (first point repeated last).
    xs : (g,) float

    Returns
    -------
    lower, upper : (g,) float
        NaN where the line misses the polygon.
    """
    a, b = outline[:-1], outline[1:]
    x0, x1 = a[:, 0:1], b[:, 0:1]
    lo, hi = np.minimum(x0, x1), np.maximum(x0, x1)
    hit = (xs >= lo) & (xs <= hi) & (hi > lo)  # (m - 1, g)
    t = np.where(hit, (xs - x0) / np.where(hi > lo, x1 - x0, 1.0), 0.0)
    y = a[:, 1:2] + t * (b[:, 1:2] - a[:, 1:2])
    with np.errstate(invalid="ignore"):
        lower = np.where(hit, y, np.inf).min(axis=0)
        upper = np.where(hit, y, -np.inf).max(axis=0)
    miss = ~hit.any(axis=0)
    lower[miss] = np.nan
    upper[miss] = np.nan
    return lower, upper


def _pattern_offsets(flat: np.ndarray, n: int, gap: float) -> np.ndarray:
    """(p,) downward shifts (−y) that lay the cut patterns one below the other without overlap.

    Each plate drops (in −y) until it is ``gap`` below everything placed before it, measured
    along vertical lines, so nesting shapes (arcs in arcs) pack closely and others stack.

    Parameters
    ----------
    flat : (p, v, 3) float
        Cut patterns (z = 0), all in the same plane coordinates.
    n : int
        Segments per plate.
    gap : float
        Clearance between patterns, metres.
    """
    outlines = flat[:, outline_index(n), :2]
    xs = np.linspace(outlines[..., 0].min(), outlines[..., 0].max(), 512)
    floor = np.full(xs.shape, np.inf)  # lowest placed point along each vertical line
    offsets = np.zeros(len(flat))
    for i, outline in enumerate(outlines):
        lower, upper = _envelopes(outline, xs)
        both = np.isfinite(upper) & np.isfinite(floor)
        if i > 0:
            if both.any():
                offsets[i] = float(np.min(floor[both] - upper[both])) - gap
            else:
                offsets[i] = float(np.nanmin(floor)) - float(np.nanmax(upper)) - gap
        inside = np.isfinite(lower)
        floor[inside] = np.minimum(floor[inside], lower[inside] + offsets[i])
    return offsets


def cut_pattern_layout(flat: np.ndarray, n: int, *, gap: float, beside=None) -> np.ndarray:
    """(p, 2) translations that lay the cut patterns out compactly, without overlap.

    The plates are split into columns of consecutive plates; in every column each plate
    drops (−y) until it is ``gap`` below the plates above it (:func:`_pattern_offsets`: arcs
    nest in arcs), and the columns stand side by side, ``gap`` apart. The number of columns is
    the one that makes the whole picture (the structure's plan ``beside`` and the block in
    front of it) most nearly square, the smallest larger side: many plates neither make one
    long row nor one long column, and the structure beside them stays large on the screen.

    This is the viewer's own layout; it is kept apart from the figure so that the sheet
    nesting of the fabrication output can replace it (``viewer_figure(pattern_offsets=...)``).

    Parameters
    ----------
    flat : (p, v, 3) float
        Cut patterns (z = 0), all in the same plane coordinates (the flat-folded stack).
    n : int
        Segments per plate.
    gap : float
        Clearance between patterns, metres.
    beside : (float, float), optional
        Plan width (x) and depth (y) of the structure the block lies beside (behind it, +y, in
        the viewer); default: none (the block alone is made square).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> s = load_model("examples/vault.toml").deploy()
    >>> off = cut_pattern_layout(np.asarray(s.flat), 64, gap=0.1)
    >>> off.shape
    (10, 2)
    """
    flat = np.asarray(flat, dtype=float)
    p = len(flat)
    best = None
    for columns in range(1, p + 1):
        rows = math.ceil(p / columns)
        if columns > 1 and math.ceil(p / (columns - 1)) == rows:
            continue  # same rows as fewer columns
        offsets = np.zeros((p, 2))
        x = 0.0
        for start in range(0, p, rows):
            part = slice(start, min(p, start + rows))
            offsets[part, 1] = _pattern_offsets(flat[part], n, gap)
            lo = float(flat[part, :, 0].min())
            offsets[part, 0] = x - lo
            x += float(flat[part, :, 0].max()) - lo + gap
        moved = flat[..., :2] + offsets[:, None, :]
        width, depth = np.ptp(moved.reshape(-1, 2), axis=0)
        if beside is not None:
            width, depth = max(width, beside[0]), depth + beside[1] + 2.0 * gap
        side = float(max(width, depth))
        if best is None or side < best[0] - EXACT_RELATIVE:
            best = (side, offsets)
    return best[1]


def sheet_grid_layout(sizes, *, gap: float, structure=None) -> np.ndarray:
    """(s, 2) corners that lay the sheets out in a grid around the structure's plan.

    The sheets go into cells of one size (the largest sheet plus ``gap``), in rows from the
    front of the structure (its lowest y) backwards and, in every row, from left to right; a
    cell that would overlap the structure's plan (widened by half a gap) is skipped, so the
    sheets fill the ground beside and behind the structure. The grid is centred on the
    structure in x, and its number of columns is the one that makes the whole picture (the
    structure and the sheets) most nearly square, the smallest larger side: the structure stays
    large on the screen and the sheets neither make one long row nor one long column.

    Parameters
    ----------
    sizes : (s, 2) float
        Sheet length (x) and width (y), m, in sheet order.
    gap : float
        Clearance between sheets (and between the sheets and the structure), m.
    structure : (float, float, float, float), optional
        The structure's plan box ``(x0, y0, x1, y1)``; default none (a grid alone, from the
        origin).

    Returns
    -------
    (s, 2) float
        Where each sheet's corner (its origin, the sheet DXF's (0, 0)) lies.

    Examples
    --------
    >>> corners = sheet_grid_layout([[2.5, 1.25]] * 8, gap=0.1, structure=(0, 0, 2.7, 2.6))
    >>> corners.shape, np.ptp(corners, axis=0).round(2).tolist()
    ((8, 2), [5.2, 2.7])
    """
    sizes = np.asarray(sizes, dtype=float).reshape(-1, 2)
    count = len(sizes)
    if count == 0:
        return np.zeros((0, 2))
    gap = float(gap)
    cell = sizes.max(axis=0) + gap
    if structure is None:
        box = None
        cx, y0 = 0.0, 0.0
    else:
        box = np.asarray(structure, dtype=float)
        cx, y0 = 0.5 * (box[0] + box[2]), float(box[1])
        wide = box + np.array([-0.5, -0.5, 0.5, 0.5]) * gap
    span = 0 if box is None else int(math.ceil((box[2] - box[0]) / cell[0])) + 2
    best = None
    for columns in range(1, count + span + 1):
        x0 = 0.0 if box is None else cx - 0.5 * columns * cell[0]
        corners, row = [], 0
        while len(corners) < count:
            ys = y0 + row * cell[1]
            for c in range(columns):
                xs = x0 + c * cell[0]
                if box is not None and (
                    xs < wide[2]
                    and xs + cell[0] > wide[0]
                    and ys < wide[3]
                    and ys + cell[1] > wide[1]
                ):
                    continue  # the structure stands there
                corners.append((xs + 0.5 * gap, ys + 0.5 * gap))
                if len(corners) == count:
                    break
            row += 1
            if row > count + span + 64:  # pragma: no cover - every row beyond the plan is free
                break
        corners = np.asarray(corners)
        lo, hi = corners.min(axis=0), (corners + sizes).max(axis=0)
        if box is not None:
            lo, hi = np.minimum(lo, box[:2]), np.maximum(hi, box[2:])
        side = float(max(hi - lo))
        if best is None or side < best[0] - EXACT_RELATIVE:
            best = (side, corners)
    return best[1]


def sheet_document(sheets, plate_ids=None, *, design=None) -> dict:
    """The nesting to show: a workshop plan's :meth:`layout` or a ``sheets.json`` document,
    checked.

    Parameters
    ----------
    sheets : dict or object with a ``layout()`` method
        ``compas_ccu.fabrication.workshop.WorkshopPlan`` or its ``layout()`` (the
        ``sheets.json`` that ``ccu fabricate`` writes, parsed).
    plate_ids : sequence of int, optional
        The model's plate ids: the document's ``model_plate_ids`` must be the same plates.
    design : str, optional
        The model's design name: a document of another design is refused.

    Returns
    -------
    dict
        The document, with ``tone_index`` added to every part (the index of its plate in
        ``plate_ids``, for its colour).

    Raises
    ------
    compas_ccu.errors.OptionError
        Not a nesting document (no ``sheets`` / ``parts`` lists), another design, other
        plates, or a part on a sheet that does not exist (the message names it).

    Examples
    --------
    >>> doc = {"sheets": [{"size": [2.0, 1.0], "utilisation": 0.5, "parts": ["P0"]}],
    ...        "parts": [{"name": "P0", "plate": 0, "sheet": 0,
    ...                   "outline": [[0.1, 0.1], [1.0, 0.1], [1.0, 0.9], [0.1, 0.9]]}]}
    >>> sheet_document(doc, [0])["parts"][0]["tone_index"]
    0
    """
    if hasattr(sheets, "layout") and callable(sheets.layout):
        sheets = sheets.layout()
    if not isinstance(sheets, dict):
        raise OptionError(
            f"sheets must be a workshop plan or its layout (sheets.json), got "
            f"{type(sheets).__name__}"
        )
    missing = [k for k in ("sheets", "parts") if not isinstance(sheets.get(k), list)]
    if missing:
        raise OptionError(
            f"sheets: the nesting document has no {' and no '.join(missing)} list (is it the "
            "sheets.json that ccu fabricate writes?)"
        )
    name = sheets.get("design")
    if design is not None and name is not None and name != design:
        raise OptionError(f"sheets: the nesting is of design {name!r}, not of {design!r}")
    count = len(sheets["sheets"])
    model = sheets.get("model_plate_ids")
    if plate_ids is not None:
        plate_ids = [int(v) for v in plate_ids]
        if model is not None and sorted(int(v) for v in model) != sorted(plate_ids):
            raise OptionError(
                f"sheets: the nesting is of {len(model)} plates {sorted(model)}, the model has "
                f"{len(plate_ids)} plates {sorted(plate_ids)}"
            )
    tones = _part_tone(model, plate_ids)
    parts = [
        {**part, "tone_index": _checked_part(part, count, model, tones)} for part in sheets["parts"]
    ]
    return {**sheets, "parts": parts}


def _part_tone(model, plate_ids):
    """The tone index of a part's plate: through the nesting's plate ids when both are known."""
    if model is None or plate_ids is None:
        return None
    index = {pid: i for i, pid in enumerate(plate_ids)}
    return [index.get(int(pid)) for pid in model]


def _checked_part(part: dict, count: int, model, tones) -> int:
    """The tone index of one part of a nesting, after checking its sheet and outline.

    Parameters
    ----------
    part : dict
        One of the document's ``parts``.
    count : int
        The number of sheets.
    model : list of int or None
        The document's ``model_plate_ids``.
    tones : list of int or None
        :func:`_part_tone`: the tone of each of the nesting's plates, or None (the part's
        ``plate`` is its tone).

    Raises
    ------
    compas_ccu.errors.OptionError
        The part is on a sheet that does not exist, has no outline, or is of a plate the
        nesting does not have.
    """
    k = part.get("sheet")
    if not isinstance(k, int) or not 0 <= k < count:
        raise OptionError(
            f"sheets: part {part.get('name')!r} is on sheet {k!r}, but there are {count} sheets"
        )
    outline = np.asarray(part.get("outline", []), dtype=float)
    if outline.ndim != 2 or outline.shape[0] < 3 or outline.shape[1] != 2:
        raise OptionError(
            f"sheets: part {part.get('name')!r} has no outline of at least 3 points (x, y)"
        )
    plate = int(part.get("plate", 0))
    if tones is None:
        return plate
    if not 0 <= plate < len(model):
        raise OptionError(
            f"sheets: part {part.get('name')!r} is of plate {plate}, but the nesting "
            f"has {len(model)} plates"
        )
    return tones[plate]
