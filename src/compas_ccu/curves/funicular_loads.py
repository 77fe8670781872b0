"""The loads of a funicular arch (:class:`~compas_ccu.curves.funicular.FunicularProfile`):
point and distributed load lists checked, and load positions a round-off apart snapped together.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.curves.base import require_real, short_repr
from compas_ccu.errors import ProfileError
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = ["KINK_TOLERANCE", "require_point_loads", "require_distributed_loads", "snap_positions"]

#: Kinks closer than this fraction of the length (to each other or to an end) share a sample;
#: load positions closer than this fraction of the span are snapped together.
KINK_TOLERANCE = ZERO_LENGTH


def require_point_loads(loads: object, half: float) -> np.ndarray:
    """Check a list of point loads ``[x, P]`` inside the span ``(-half, half)``.

    Returns
    -------
    (n, 2) float

    Raises
    ------
    ProfileError
        A row that is not two real finite numbers, a position outside the span or a load
        that is not > 0 (named by its index).

    Examples
    --------
    >>> require_point_loads([[0.0, 10.0]], 2.0).tolist()
    [[0.0, 10.0]]
    >>> require_point_loads([[3.0, 10.0]], 2.0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    compas_ccu.errors.ProfileError: point_loads[0]: x must lie inside the span, ... got 3.0
    """
    rows = _require_rows(loads, "point_loads", ("x", "P"), "[x, P]")
    for index, (x, load) in enumerate(rows):
        if not -half < x < half:
            raise ProfileError(
                f"point_loads[{index}]: x must lie inside the span, {-half!r} < x < {half!r} m, "
                f"got {x!r}"
            )
        if not load > 0.0:
            raise ProfileError(f"point_loads[{index}]: P must be > 0, got {load!r}")
    return np.array(rows, dtype=float).reshape(len(rows), 2)


def require_distributed_loads(loads: object, half: float) -> np.ndarray:
    """Check a list of distributed loads ``[x0, x1, q0, q1]`` on the span ``[-half, half]``.

    Returns
    -------
    (n, 4) float

    Raises
    ------
    ProfileError
        A row that is not four real finite numbers, an interval outside the span or empty, a
        negative intensity or both intensities 0 (named by its index).

    Examples
    --------
    >>> require_distributed_loads([[-2.0, 0.0, 1.0, 0.5]], 2.0).tolist()
    [[-2.0, 0.0, 1.0, 0.5]]
    >>> require_distributed_loads([[-2.0, 0.0, 0.0, 0.0]], 2.0)
    Traceback (most recent call last):
    ...
    compas_ccu.errors.ProfileError: distributed_loads[0]: q0 and q1 are both 0 (no load)
    """
    rows = _require_rows(loads, "distributed_loads", ("x0", "x1", "q0", "q1"), "[x0, x1, q0, q1]")
    for index, (x0, x1, q0, q1) in enumerate(rows):
        if not -half <= x0 < x1 <= half:
            raise ProfileError(
                f"distributed_loads[{index}]: need {-half!r} <= x0 < x1 <= {half!r} m, "
                f"got x0 = {x0!r}, x1 = {x1!r}"
            )
        for key, value in (("q0", q0), ("q1", q1)):
            if not value >= 0.0:
                raise ProfileError(f"distributed_loads[{index}]: {key} must be >= 0, got {value!r}")
        if q0 == 0.0 and q1 == 0.0:
            raise ProfileError(f"distributed_loads[{index}]: q0 and q1 are both 0 (no load)")
    return np.array(rows, dtype=float).reshape(len(rows), 4)


def _require_rows(loads: object, name: str, keys: tuple, form: str) -> list:
    """Check a list of equal-length rows of real finite numbers; return lists of floats."""
    if isinstance(loads, np.ndarray):
        loads = loads.tolist() if loads.ndim == 2 else loads
    if not isinstance(loads, (list, tuple)):
        raise ProfileError(f"{name} must be a list of {form} lists, got {short_repr(loads)}")
    rows = []
    for index, row in enumerate(loads):
        if not isinstance(row, (list, tuple, np.ndarray)) or len(row) != len(keys):
            raise ProfileError(f"{name}[{index}] must be a list {form}, got {short_repr(row)}")
        units = ["m" if key.startswith("x") else "load units" for key in keys]
        rows.append(
            [
                require_real(f"{name}[{index}] {key}", value, unit=unit)
                for key, value, unit in zip(keys, row, units)
            ]
        )
    return rows


def snap_positions(points: np.ndarray, distributed: np.ndarray, half: float):
    """Load positions closer than round-off to each other, to the supports or to mid-span
    made equal.

    Positions within :data:`KINK_TOLERANCE` of the span of each other take the value of the
    first of their cluster (the supports and mid-span first), so that no piece of the thrust
    line has a length of round-off (a degenerate piece would put several crease vertices on one
    point).

    Parameters
    ----------
    points : (n, 2) float
        Point loads ``[x, P]``.
    distributed : (m, 4) float
        Distributed loads ``[x0, x1, q0, q1]``.
    half : float
        Half the span, m.

    Returns
    -------
    points : (n, 2) float
    distributed : (m, 4) float
        Copies with the positions snapped.

    Examples
    --------
    A point load 1e-15 m from mid-span and a load end 1e-15 m past a point load:

    >>> import numpy as np
    >>> points = np.array([[1e-15, 10.0], [1.0, 5.0]])
    >>> distributed = np.array([[-2.0, 1.0 + 1e-15, 1.0, 1.0]])
    >>> points, distributed = snap_positions(points, distributed, 2.0)
    >>> points[:, 0].tolist(), distributed[0, :2].tolist()
    ([0.0, 1.0], [-2.0, 1.0])
    """
    tolerance = KINK_TOLERANCE * 2.0 * half
    points, distributed = points.copy(), distributed.copy()
    xs = np.concatenate([points[:, 0], distributed[:, :2].ravel()])
    if not xs.size:
        return points, distributed
    anchors = [-half, 0.0, half]
    snapped = np.empty_like(xs)
    for i in np.argsort(xs, kind="stable"):
        near = [a for a in anchors if abs(a - xs[i]) <= tolerance]
        if near:
            snapped[i] = near[0]
        else:
            snapped[i] = xs[i]
            anchors.append(xs[i])
    points[:, 0] = snapped[: len(points)]
    distributed[:, :2] = snapped[len(points) :].reshape(-1, 2)
    return points, distributed
