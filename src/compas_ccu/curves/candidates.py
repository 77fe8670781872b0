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

    Examples
    --------
    >>> import numpy as np
    >>> line = Candidate("LINE #1F on layer CREASE", "CREASE", "1F", lambda tol: np.eye(2, 3))
    >>> line.layer, line.sample(None).shape, line.layers
    ('CREASE', (2, 3), ())
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

    Examples
    --------
    A quarter of the unit circle, sampled to a chord tolerance of 1 mm:

    >>> import numpy as np
    >>> def circle(t):
    ...     return np.c_[np.cos(t), np.sin(t), np.zeros_like(t)]
    >>> points = adaptive(circle, 0.0, np.pi / 2, 1e-3)
    >>> len(points), bool(np.allclose(np.linalg.norm(points, axis=1), 1.0))
    (33, True)
    >>> len(adaptive(circle, 0.0, np.pi / 2, None, start=4))  # no tolerance: the start samples
    5
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

    Examples
    --------
    >>> need_module("json", "fab", "JSON files").dumps([1, 2])
    '[1, 2]'
    """
    require(module, extra, what=f"reading {what}")
    return importlib.import_module(module)
