"""The candidate curves of a curve file, shared by the format readers of :mod:`.readers`.

* :class:`Candidate`: one curve of a file, with its label, layer, name and sampler;
* :func:`adaptive`: a parametric curve sampled until every chord lies within a tolerance;
* :func:`need_module`: an optional reader (ezdxf, svgelements, rhino3dm), imported by name;
* :data:`UNITS`: the length units a file may be read in.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

import numpy as np

from compas_ccu import limits
from compas_ccu.errors import require

__all__ = ["UNITS", "Candidate", "adaptive", "need_module"]

#: Length units a file may be read in, metres per unit (``px``: SVG user units, 96 per inch).
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "ft": 0.3048, "px": 0.0254 / 96.0}


@dataclass
class Candidate:
    """One curve of a file, before it is chosen and sampled.

    Attributes
    ----------
    label : str
        What the messages name it, e.g. ``"LWPOLYLINE #1F on layer CREASE"``.
    layer, name : str or None
        The layer (DXF, 3dm; SVG: the innermost group) and the name (DXF handle, 3dm object
        name, SVG element id) it is chosen by.
    sample : callable
        ``tolerance (file units) or None -> (n, 3) points`` in file units; None gives a rough
        sample (for the curve's size).
    layers : tuple of str
        SVG: the ids and labels of every enclosing group, lower case.
    """

    label: str
    layer: str | None
    name: str | None
    sample: object
    layers: tuple = ()


def adaptive(evaluate, t0: float, t1: float, tolerance, *, start: int = 16, breaks=()):
    """Sample a parametric curve until every chord's midpoint lies within ``tolerance`` of the
    curve's midpoint.

    Parameters
    ----------
    evaluate : callable
        Maps an (m,) array of parameters to (m, 3) points.
    t0, t1 : float
        The parameter interval.
    tolerance : float or None
        Largest distance of a chord's midpoint from the curve (file units); None: the
        ``start + 1`` equally spaced samples and the breaks only.
    start : int
        Equal parameter steps to start from.
    breaks : sequence of float
        Parameters sampled exactly (knots: possible kinks).

    Returns
    -------
    (n, 3) float
    """
    ts = np.unique(np.r_[np.linspace(t0, t1, start + 1), [b for b in breaks if t0 < b < t1]])
    if tolerance is None:
        return evaluate(ts)
    pts = evaluate(ts)
    for _ in range(40):
        mids = 0.5 * (ts[:-1] + ts[1:])
        pm = evaluate(mids)
        error = np.linalg.norm(pm - 0.5 * (pts[:-1] + pts[1:]), axis=1)
        bad = error > tolerance
        if not bad.any():
            return pts
        if len(ts) + int(bad.sum()) > limits.LIMITS.points:
            limits.check("points", len(ts) + int(bad.sum()), what="points (the curve's sampling)")
        ts = np.sort(np.r_[ts, mids[bad]])
        pts = evaluate(ts)
    return pts  # pragma: no cover - 2^40 refinements


def need_module(module: str, extra: str, what: str):
    """The optional module ``module`` of the extra ``extra``, imported to read ``what``.

    Raises
    ------
    MissingExtraError
        The module is not installed (the message names the extra, as every such message).
    """
    require(module, extra, what=f"reading {what}")
    return importlib.import_module(module)
