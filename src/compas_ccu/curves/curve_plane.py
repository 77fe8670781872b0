"""The plane of a planar 3D curve and the curve's 2D coordinates in it (a crease profile).

:func:`plane_coordinates` takes a curve read from a file (:func:`.readers.read_curve`) to the
coordinates of its plane, in the frame the ``[plane]`` section of a design takes.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.errors import ProfileError
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["plane_coordinates"]


def plane_coordinates(points, *, source: str = "curve", planarity: float = 1e-6):
    """The 2D coordinates of a planar 3D polyline in its plane, and the plane.

    A curve in a plane ``z = const`` keeps its x, y coordinates. Any other planar curve is
    expressed in the frame of its chord: origin at the chord's midpoint, x from the first to the
    last point, y in the curve's plane towards the side the curve bulges to (an arch rises to
    +y), as the analytic profiles are.

    Parameters
    ----------
    points : (n, 3) float
        The curve, m.
    source : str
        What to name in an error (file and entity).
    planarity : float
        Largest distance from the best-fit plane allowed, relative to the curve's size.

    Returns
    -------
    points2 : (n, 2) float
        Plane coordinates, m.
    frame : dict
        ``origin``, ``xaxis``, ``yaxis`` (3 floats each) of the plane in the file's coordinates
        (m), as the ``[plane]`` section of a design takes them.
    deviation : float
        The largest distance of a point from the plane, m.

    Raises
    ------
    ProfileError
        The curve is not planar (the message gives its deviation) or is straight.

    Examples
    --------
    >>> pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [2.0, 0.0, 0.0]]
    >>> p2, frame, dev = plane_coordinates(pts)
    >>> (p2.round(12) + 0.0).tolist(), [v + 0.0 for v in frame["yaxis"]], dev
    ([[-1.0, 0.0], [0.0, 1.0], [1.0, 0.0]], [0.0, 0.0, 1.0], 0.0)
    """
    p = np.asarray(points, dtype=float)
    size = float(np.linalg.norm(np.ptp(p, axis=0)))
    if size == 0.0:
        raise ProfileError(f"{source}: all points coincide")
    if float(np.ptp(p[:, 2])) <= planarity * size:
        z = float(np.mean(p[:, 2]))
        frame = {"origin": [0.0, 0.0, z], "xaxis": [1.0, 0.0, 0.0], "yaxis": [0.0, 1.0, 0.0]}
        return p[:, :2].copy(), frame, float(np.max(np.abs(p[:, 2] - z)))
    centre = p.mean(axis=0)
    _, sv, vt = np.linalg.svd(p - centre)
    normal = vt[2]
    deviation = float(np.max(np.abs((p - centre) @ normal)))
    if deviation > planarity * size:
        raise ProfileError(
            f"{source}: the curve is not planar: its points lie up to {deviation:.6g} m from "
            f"their best-fit plane ({deviation / size:.3g} of its size; allowed "
            f"{planarity:g}); a crease profile is a plane curve"
        )
    chord = p[-1] - p[0]
    chord -= (chord @ normal) * normal
    if (
        np.linalg.norm(chord) <= EXACT_RELATIVE * size
    ):  # a closed curve: the first principal direction
        chord = vt[0]
    xaxis = chord / np.linalg.norm(chord)
    yaxis = np.cross(normal, xaxis)
    origin = 0.5 * (p[0] + p[-1])
    q = p - origin
    local = np.c_[q @ xaxis, q @ yaxis]
    if local[:, 1].mean() < 0.0:  # the curve bulges to +y
        yaxis = -yaxis
        local[:, 1] *= -1.0
    frame = {"origin": origin.tolist(), "xaxis": xaxis.tolist(), "yaxis": yaxis.tolist()}
    return local, frame, deviation
