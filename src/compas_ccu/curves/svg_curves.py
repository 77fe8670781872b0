"""The shapes of an SVG file (``svgelements``), as candidate curves in SVG user units.

Every ``<path>``, ``<polyline>``, ``<polygon>`` and ``<line>``, with the transforms and viewBox
applied by svgelements. SVG user units are CSS pixels (96 per inch), so a file whose ``width`` /
``height`` carry a unit (``mm``) is read in that unit. SVG's y axis points down: the y
coordinate is negated so that a drawing reads upright. A candidate's layers are the ids and
Inkscape labels of its enclosing groups.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from compas_ccu.curves.candidates import UNITS, Candidate, adaptive, need_module
from compas_ccu.errors import ProfileError

__all__ = ["svg_candidates"]


_INKSCAPE_LABEL = "{http://www.inkscape.org/namespaces/inkscape}label"


def svg_candidates(path: Path):
    """The shapes of an SVG file, its units (``px``) and the metres per user unit.

    Returns
    -------
    candidates : list of Candidate
        Every ``<path>``, ``<polyline>``, ``<polygon>`` and ``<line>`` in document order (the
        first subpath of each), y negated.
    units : str
        ``"px"``.
    factor : float
        Metres per user unit as svgelements scaled them (:func:`_svg_metres_per_px`).

    Raises
    ------
    ProfileError
        The file is not SVG that svgelements parses.
    MissingExtraError
        svgelements is not installed.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> path = Path(tempfile.mkdtemp()) / "crease.svg"
    >>> _ = path.write_text(
    ...     '<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
    ...     '<polyline id="crease" points="0,0 48,48 96,0"/></svg>'
    ... )
    >>> candidates, units, factor = svg_candidates(path)
    >>> len(candidates), candidates[0].name, units, round(factor * 96, 6)  # 96 px per inch
    (1, 'crease', 'px', 0.0254)
    >>> (candidates[0].sample(None)[[0, -1]] + 0.0).tolist()  # y negated
    [[0.0, 0.0, 0.0], [96.0, 0.0, 0.0]]
    """
    svgelements = need_module("svgelements", "fab", "SVG files")
    try:
        svg = svgelements.SVG.parse(str(path), reify=True, ppi=96.0)
    except Exception as exc:  # XML or SVG syntax errors of any kind
        raise ProfileError(f"cannot read SVG file {str(path)!r}: {exc}") from exc
    candidates = []

    def walk(group, layers):
        for element in group:
            if isinstance(element, svgelements.Group):
                names = [element.id, element.values.get(_INKSCAPE_LABEL)]
                walk(element, layers + [n for n in names if n])
            elif isinstance(element, (svgelements.Path, svgelements.SimpleLine)) or (
                type(element).__name__ in ("Polyline", "Polygon")
            ):
                candidate = _svg_candidate(svgelements, element, layers)
                if candidate is not None:
                    candidates.append(candidate)

    walk(svg, [])
    return candidates, "px", _svg_metres_per_px(svgelements, svg.values.get("width"))


def _svg_candidate(svgelements, element, layers):
    """The first subpath of an SVG shape as a candidate curve (y negated: upright)."""
    segments, moves = [], 0
    for seg in svgelements.Path(element).segments():
        if isinstance(seg, svgelements.Move):
            moves += 1
            if moves > 1:
                break
        elif not isinstance(seg, svgelements.Close):
            segments.append(seg)
    if not segments:
        return None
    tag = type(element).__name__.lower()
    label = f"<{tag}> id={element.id!r}" + (f" in group {'/'.join(layers)!r}" if layers else "")

    def sample(tol):
        pieces = []
        for seg in segments:
            if isinstance(seg, svgelements.Line):
                pieces.append(np.array([[seg.start.x, seg.start.y], [seg.end.x, seg.end.y]]))
            else:
                pieces.append(adaptive(_pad(seg.npoint), 0.0, 1.0, tol)[:, :2])
        pts = np.concatenate(pieces)
        return np.c_[pts[:, 0], -pts[:, 1], np.zeros(len(pts))]

    return Candidate(
        label, layers[-1] if layers else None, element.id, sample, tuple(n.lower() for n in layers)
    )


def _svg_metres_per_px(svgelements, width) -> float:
    """Metres per user unit as svgelements scaled them: it converts a root ``width`` in mm or cm
    to pixels with a rounded factor (3.7795296 px/mm instead of 96 / 25.4, 5e-7 too large), so
    the exact factor is the unit's length over svgelements' pixels per unit."""
    unit = re.sub(r"^[-+0-9.eE]+", "", str(width or "")).strip().lower()
    exact = {"mm": 0.001, "cm": 0.01, "in": 0.0254, "pt": 0.0254 / 72.0, "pc": 0.0254 / 6.0}
    if unit not in exact:
        return UNITS["px"]
    return exact[unit] / svgelements.Length(f"1{unit}").value(ppi=96.0)


def _pad(evaluate):
    """An evaluator of (m, 2) points as one of (m, 3) points with z = 0."""

    def padded(ts):
        pts = np.asarray(evaluate(ts), dtype=float)
        return np.c_[pts[:, :2], np.zeros(len(pts))]

    return padded
