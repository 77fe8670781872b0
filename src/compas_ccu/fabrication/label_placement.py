"""Where a block of text fits inside a plate outline, and which way it reads.

:func:`label_frame` places the label of a plate (its DXF cut file, a stock sheet's DXF, the
assembly sheet): at the plate's centroid of area if the block fits around it, else at the
nearest point inside the plate, along the nearest outline edge (crescent plates), its height
reduced until the block fits. :func:`upright` turns a direction to read left to right.
shapely is imported inside :func:`label_frame`.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.tolerances import ZERO_LENGTH

__all__ = ["label_frame", "upright"]


def upright(u: np.ndarray) -> np.ndarray:
    """Unit direction ``u`` flipped so text along it reads left to right (angle in (-90, 90])."""
    u = np.asarray(u, dtype=float)
    u = u / np.linalg.norm(u)
    if u[0] < -ZERO_LENGTH or (abs(u[0]) <= ZERO_LENGTH and u[1] < 0):
        u = -u
    return u


def label_frame(outline, *, lines: int = 5, chars: int = 30):
    """Where and how large a block of text fits inside a plate, near its centroid of area.

    Parameters
    ----------
    outline : (m, 2) float
        Closed plate outline (first vertex not repeated).
    lines : int
        Lines of text in the block.
    chars : int
        Characters of the longest line.

    Returns
    -------
    anchor : (2,) float
        Centre of the block: the centroid of area if the block fits around it, else the nearest
        point to it at which the block (height ``1.6 * lines * height``) stays inside.
    direction : (2,) float
        Unit reading direction of the text: x, or the direction of the nearest outline edge if
        the centroid lies outside (crescent plates), turned to read left to right.
    height : float
        Text height of one line, outline units: 3.5 % of the plate's bounding-box diagonal,
        reduced until the block fits the plate's inscribed circle and its length.
    """
    from shapely import Point, Polygon
    from shapely.ops import nearest_points, polylabel

    outline = np.asarray(outline, dtype=float)
    poly = Polygon(outline)
    if not poly.is_valid:
        poly = poly.buffer(0)
    size = float(np.linalg.norm(np.ptp(outline, axis=0)))
    pole = polylabel(poly, tolerance=1e-3 * size)
    r_in = float(poly.exterior.distance(pole))
    height = min(0.035 * size, 1.6 * r_in / (1.6 * lines))
    centroid = poly.centroid
    direction = np.array([1.0, 0.0])
    anchor = np.array([centroid.x, centroid.y])
    for _ in range(2):  # the second pass re-checks the block length along the new direction
        half_block = 0.8 * lines * height
        inset = poly.buffer(-min(half_block, 0.95 * r_in))
        if inset.is_empty:
            inset = pole
        if inset.contains(centroid):
            anchor, direction = np.array([centroid.x, centroid.y]), np.array([1.0, 0.0])
        else:
            q = nearest_points(inset, centroid)[0]
            anchor = np.array([q.x, q.y])
            ring = poly.exterior
            s = ring.project(Point(anchor))
            eps = 1e-3 * size
            p0, p1 = ring.interpolate(s - eps), ring.interpolate(s + eps)
            edge = np.array([p1.x - p0.x, p1.y - p0.y])
            if np.linalg.norm(edge) > 0:
                direction = upright(edge)
        # the block must also fit the plate's extent along the reading direction
        along = outline @ direction
        height = min(height, 0.8 * float(np.ptp(along)) / (0.65 * max(chars, 1)))
    return anchor, direction, height
