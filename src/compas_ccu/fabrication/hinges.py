"""Textile hinge strips: one developable strip of constant width centred on every crease.

In the flat-folded stack every crease is a planar curve shared by its two plates; the hinge of
the Unfold Form demonstrator is a textile strip glued across it. :func:`hinge_strips` returns
the strip of every crease as a closed outline in the plane of the stack (plate ``a``'s flat
coordinates, m): the crease polyline offset by ``+-width / 2``, with flat ends perpendicular to
the crease's end segments.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import GeometryError
from compas_ccu.tolerances import EXACT_RELATIVE, ZERO_LENGTH

__all__ = ["HingeStrip", "hinge_strips", "check_hinge_width", "offset_strip"]


@dataclass
class HingeStrip:
    """The textile hinge of one crease, flat, in the plane of the flat-folded stack.

    Attributes
    ----------
    crease_id : int
        Crease id (``FabricationData.creases[...]["id"]``).
    plates : tuple of int
        Plate ids ``(a, b)`` the crease joins.
    centre : (k, 2) float
        The crease polyline, m: plate ``a``'s flat coordinates of the crease vertices.
    outline : (2k, 2) float
        Closed outline of the strip (first vertex not repeated), m: the left offset of
        ``centre`` from its first to its last vertex, then the right offset back.
    width : float
        Strip width, m.
    """

    crease_id: int
    plates: tuple
    centre: np.ndarray
    outline: np.ndarray
    width: float


def check_hinge_width(width) -> float:
    """``width`` as a float, or :class:`~compas_ccu.errors.GeometryError` if not finite and > 0."""
    try:
        value = float(width)
    except (TypeError, ValueError):
        raise GeometryError(f"hinge width must be a finite number > 0 (m), got {width!r}") from None
    if not math.isfinite(value) or value <= 0.0:
        raise GeometryError(f"hinge width must be a finite number > 0 (m), got {width!r}")
    return value


def _radii(centre: np.ndarray) -> np.ndarray:
    """(k - 2,) radius of the circle through every three consecutive vertices (inf if straight)."""
    a = centre[1:-1] - centre[:-2]
    b = centre[2:] - centre[1:-1]
    c = centre[2:] - centre[:-2]
    cross = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    num = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1) * np.linalg.norm(c, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(cross > 0.0, num / (2.0 * cross), np.inf)


def offset_strip(centre, width: float, *, name: str = "polyline") -> np.ndarray:
    """Closed outline of the strip of ``width`` centred on an open polyline.

    Every interior vertex moves by ``width / 2`` along the bisector of its two edge normals;
    on the inside of the turn the move is scaled by ``1 / cos(turn / 2)`` (miter: the vertex
    where the two offset edges meet). So every outline vertex lies exactly ``width / 2`` from
    the centre polyline (the outside vertices sample the round join). The end vertices move
    along their edge's normal: flat ends, perpendicular to the end edges.

    Parameters
    ----------
    centre : (k, 2) float
        Open polyline, k >= 2, no zero-length edge.
    width : float
        Strip width, > 0, same units as ``centre``.
    name : str
        What ``centre`` is, for error messages.

    Returns
    -------
    (2k, 2) float
        Left offset from vertex 0 to k - 1, then the right offset back (first vertex not
        repeated). A simple polygon.

    Raises
    ------
    GeometryError
        If the width is not finite and > 0, the polyline is degenerate (fewer than 2 vertices,
        a zero-length edge, a U-turn), or the width is too large for the polyline's curvature
        (an offset side would reverse or the outline would cross itself).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, np.pi / 2, 9)
    >>> arc = np.c_[np.cos(t), np.sin(t)]
    >>> ring = offset_strip(arc, 0.2)
    >>> ring.shape
    (18, 2)
    >>> r = np.linalg.norm(ring, axis=1)
    >>> bool(r.max() < 1.11 and r.min() > 0.89)
    True
    """
    from shapely import Polygon

    width = check_hinge_width(width)
    centre = np.asarray(centre, dtype=float)
    if centre.ndim != 2 or centre.shape[1] != 2 or len(centre) < 2:
        raise GeometryError(f"{name}: expected a (k >= 2, 2) polyline, got shape {centre.shape}")
    if not np.isfinite(centre).all():
        raise GeometryError(f"{name}: the polyline has non-finite coordinates")
    d = np.diff(centre, axis=0)
    length = np.linalg.norm(d, axis=1)
    scale = float(np.ptp(centre, axis=0).max()) or 1.0
    if (length <= ZERO_LENGTH * scale).any():
        j = int(np.argmin(length))
        raise GeometryError(f"{name}: edge {j} has zero length ({length[j]:.3g})")
    t = d / length[:, None]
    normal = np.c_[-t[:, 1], t[:, 0]]
    left_shift = np.empty_like(centre)
    left_shift[0], left_shift[-1] = normal[0], normal[-1]
    right_shift = left_shift.copy()
    bisector = normal[:-1] + normal[1:]
    blen = np.linalg.norm(bisector, axis=1)
    if (blen < EXACT_RELATIVE).any():
        j = int(np.argmin(blen)) + 1
        raise GeometryError(f"{name}: the polyline turns back on itself at vertex {j}")
    bisector /= blen[:, None]
    cos_half = np.einsum("ij,ij->i", bisector, normal[1:])
    # miter (1 / cos) on the inside of every turn, plain bisector on the outside: every offset
    # vertex lies exactly width / 2 from the centre polyline
    turn = t[:-1, 0] * t[1:, 1] - t[:-1, 1] * t[1:, 0]  # > 0: left turn, left side inside
    left_shift[1:-1] = bisector / np.where(turn > 0.0, cos_half, 1.0)[:, None]
    right_shift[1:-1] = bisector / np.where(turn < 0.0, cos_half, 1.0)[:, None]
    half = 0.5 * width
    left = centre + half * left_shift
    right = centre - half * right_shift
    forward = np.minimum(
        np.einsum("ij,ij->i", np.diff(left, axis=0), d),
        np.einsum("ij,ij->i", np.diff(right, axis=0), d),
    )
    outline = np.concatenate([left, right[::-1]])
    if (forward <= 0.0).any() or not Polygon(outline).is_valid:
        radii = _radii(centre)
        where = ""
        if len(radii) and np.isfinite(radii).any():
            j = int(np.argmin(radii))
            where = (
                f"; its smallest radius of curvature is {radii[j]:.4g} at vertex {j + 1}, "
                f"so the width must stay below about 2 * {radii[j]:.4g} = {2 * radii[j]:.4g}"
            )
        raise GeometryError(
            f"{name}: hinge width {width!r} is too large for the curvature of the crease "
            f"(the strip outline would cross itself){where}"
        )
    return outline


def hinge_strips(data, *, width: float | None = None) -> list:
    """The hinge strip of every crease of a design, flat, in the plane of the stack.

    Parameters
    ----------
    data : compas_ccu.fabrication.data.FabricationData
    width : float, optional
        Strip width, m (default: ``data.hinge_width``).

    Returns
    -------
    list of HingeStrip
        One per crease, in the order of ``data.creases``; ``centre`` is plate ``a``'s flat
        coordinates of the crease vertices, ``outline`` its offset by ``+-width / 2``.

    Raises
    ------
    GeometryError
        If the width is not finite and > 0, or too large for a crease's curvature (the message
        names the crease, the width and the smallest radius of curvature).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> from compas_ccu.fabrication import fabrication_data
    >>> data = fabrication_data(load_model("examples/vault.toml"), hinge_width=0.05)
    >>> strips = hinge_strips(data)
    >>> [(s.crease_id, s.plates) for s in strips][:2]
    [(0, (1, 0)), (1, (2, 1))]
    >>> strips[0].centre.shape, strips[0].outline.shape
    ((65, 2), (130, 2))
    """
    width = check_hinge_width(data.hinge_width if width is None else width)
    strips = []
    for c in data.creases:
        a, b = (int(v) for v in c["plates"])
        centre = np.array(data.flat[data.index(a)][list(c["vertices"][0])], dtype=float)
        outline = offset_strip(centre, width, name=f"crease {c['id']} (plates {a}, {b})")
        strips.append(HingeStrip(int(c["id"]), (a, b), centre, outline, width))
    return strips
