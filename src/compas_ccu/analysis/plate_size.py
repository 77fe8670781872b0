"""The size of every cut pattern: the smallest rectangle it fits in (for stock sheets)."""

from __future__ import annotations

import numpy as np

__all__ = ["plate_rectangles", "fits_sheet"]


def plate_rectangles(flat: np.ndarray) -> np.ndarray:
    """(p, 2) long and short side (m) of the minimum-area rectangle around every cut pattern.

    Parameters
    ----------
    flat : (p, v, 2 or 3) float
        Cut patterns in plane coordinates.

    Examples
    --------
    A 2 × 1 m plate turned by 30° still needs a 2 × 1 m rectangle:

    >>> import numpy as np
    >>> c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    >>> square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]) @ [[c, s], [-s, c]]
    >>> np.round(plate_rectangles(square[None]), 12).tolist()
    [[2.0, 1.0]]
    """
    import shapely

    out = np.zeros((len(flat), 2))
    for i, pattern in enumerate(np.asarray(flat, dtype=float)[..., :2]):
        box = shapely.minimum_rotated_rectangle(shapely.MultiPoint(pattern))
        xy = np.asarray(box.exterior.coords)[:4]
        sides = np.linalg.norm(np.diff(np.r_[xy, xy[:1]], axis=0), axis=1)[:2]
        out[i] = max(sides), min(sides)
    return out


def fits_sheet(rectangles: np.ndarray, sheet) -> np.ndarray:
    """(p,) bool: whether every plate's rectangle fits on a ``sheet`` (length, width) in m."""
    length, width = max(sheet), min(sheet)
    r = np.asarray(rectangles, dtype=float)
    return (r[:, 0] <= length) & (r[:, 1] <= width)
