"""The colour range of a value field and its colour bar.

:func:`colour_scale` gives the range a field is painted over (a constant field is not painted
as a gradient of rounding noise), :func:`value_mappable` the matplotlib mapping over it and
:func:`add_colorbar` the bar beside a picture that says what the colours mean.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE

__all__ = ["colour_scale", "value_range", "value_mappable", "add_colorbar"]


def value_mappable(values, vmin, vmax, cmap):
    """A ScalarMappable over :func:`colour_scale`; a constant field is marked ``constant``.

    Parameters
    ----------
    values : array_like of float
        The field (any shape).
    vmin, vmax : float or None
        Fixed ends of the range (None: the field's).
    cmap : str or matplotlib.colors.Colormap

    Returns
    -------
    matplotlib.cm.ScalarMappable
        With the attribute ``constant``: the value of a constant field, else None.
    """
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    lo, hi, constant = colour_scale(values, vmin, vmax)
    mappable = ScalarMappable(norm=Normalize(lo, hi), cmap=cmap)
    mappable.constant = constant
    return mappable


def colour_scale(values, vmin=None, vmax=None) -> tuple:
    """Colour range of ``values`` and, for a constant field, its value.

    A field that is constant (to rounding: a spread below 1e-9 of its size) is not painted
    as a gradient of rounding noise, nor in the middle of a degenerate scale (where a constant
    α of 30° would look like the anticlastic pink): its scale is widened to run from 0 to the
    value (a zero field: -1 to 1), and the colour bar says "constant".

    Parameters
    ----------
    values : array_like of float
    vmin, vmax : float, optional
        Fixed ends (kept as given).

    Returns
    -------
    lo, hi : float
    constant : float or None
        The value of a constant field, else None.

    Examples
    --------
    >>> colour_scale([30.0, 30.0, 30.0])
    (0.0, 30.0, 30.0)
    >>> colour_scale([0.390, 0.466])
    (0.39, 0.466, None)
    >>> colour_scale([30.0, 30.0], vmin=20.0)
    (20.0, 30.0, 30.0)
    """
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    dlo = float(finite.min()) if finite.size else 0.0
    dhi = float(finite.max()) if finite.size else 1.0
    constant = None
    if finite.size and dhi - dlo <= EXACT_RELATIVE * max(abs(dhi), abs(dlo), DIVISION_FLOOR):
        constant = 0.5 * (dlo + dhi)
    lo = vmin if vmin is not None else dlo
    hi = vmax if vmax is not None else dhi
    if hi < lo:
        raise OptionError(f"the colour range must have vmin < vmax, got {lo!r} to {hi!r}")
    if hi - lo <= EXACT_RELATIVE * max(abs(hi), abs(lo), DIVISION_FLOOR):
        mid = 0.5 * (lo + hi)
        lo, hi = (0.0, mid) if mid > 0.0 else (mid, 0.0) if mid < 0.0 else (-1.0, 1.0)
    return lo, hi, constant


def value_range(values, vmin=None, vmax=None) -> tuple:
    """``(lo, hi)`` of :func:`colour_scale`: a constant field runs from 0 to its value."""
    return colour_scale(values, vmin, vmax)[:2]


def add_colorbar(fig, mappable, ax, label: str):
    """A colour bar beside ``ax``, with plain tick labels (no offset notation); the label of a
    constant field (``mappable.constant``, see :func:`colour_scale`) ends with
    ``constant = <value>`` and a tick marks the value."""
    from matplotlib.ticker import ScalarFormatter

    bar = fig.colorbar(mappable, ax=ax, shrink=0.7, pad=0.02)
    fmt = ScalarFormatter(useOffset=False)
    bar.formatter = fmt
    bar.update_ticks()
    constant = getattr(mappable, "constant", None)
    if constant is not None:
        label = f"{label}: constant = {constant:.4g}"
        lo, hi = mappable.norm.vmin, mappable.norm.vmax
        bar.set_ticks(sorted({lo, constant, hi}))
    bar.set_label(label)
    return bar
