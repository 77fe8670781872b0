"""Inverse design of a plane layout from target curves along the apex and the supports.

Paper §5.5: "The shape is generated to fit target curves along the apex and supports". Given the
leading crease and the ruling field, the plates are built outwards from the leading plane by
trimming and reflecting (docs/geometry.md §2). The planes of the leading crease's parity (``k0 +-
2``, ``k0 +- 4``, ...) are *solved*: each must pass through three points, one on each of three
ruling lines of the plate that reaches it,

* the reference (apex) ruling meets the apex target ``y = A(d)``,
* the start ruling meets the support target ``x = S(d)``,
* the end ruling meets the end-support target ``x = S_end(d)`` (default: ``-S(d)``),

with ``d`` the distance from the leading plane along its normal and ``x, y`` the profile
coordinates (local frame of the leading plane). A ruling line is straight and a target is a
polyline, so each point is an exact line-polyline intersection: the fit is exact whenever the
rulings reach the targets. Where a ruling misses its target, the closest point is taken and the
remaining distance is reported. The other planes keep the layout's distances to the previous
plane.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compas_ccu.errors import DesignError
from compas_ccu.tolerances import EXACT_RELATIVE, ZERO_LENGTH

__all__ = ["TargetCurves", "TargetFit", "targets_from_values", "intersect_ray_polyline"]


@dataclass(frozen=True)
class TargetCurves:
    """Target polylines in (d, value) coordinates of the leading plane's local frame.

    Attributes
    ----------
    apex : (a, 2) float or None
        ``(d, y)``: height of the reference (apex) vertex of the solved creases.
    support, support_end : (b, 2) float or None
        ``(d, x)``: profile x of the crease's start / end vertex.
    """

    apex: np.ndarray | None = None
    support: np.ndarray | None = None
    support_end: np.ndarray | None = None

    def __bool__(self) -> bool:
        return any(v is not None for v in (self.apex, self.support, self.support_end))


@dataclass
class TargetFit:
    """Result of fitting the plane layout to the target curves.

    Attributes
    ----------
    planes : list of int
        The solved planes.
    residuals : dict
        Plane index -> (3,) distances (m) of the start, apex and end points from their targets
        (0 where the ruling meets the target; NaN where the control has no target).
    distances : (m, 3) float
        Distances of plane ``k + 1`` above plane ``k`` at the crease's start, reference and end
        vertex, as a ``layout.spacing_start / spacing / spacing_end`` design would give them.
    """

    planes: list = field(default_factory=list)
    residuals: dict = field(default_factory=dict)
    distances: np.ndarray | None = None

    @property
    def max_residual(self) -> float:
        vals = [np.nanmax(np.abs(r)) for r in self.residuals.values() if np.isfinite(r).any()]
        return float(max(vals)) if vals else 0.0

    def summary(self) -> dict:
        return {
            "target_planes": list(self.planes),
            "target_fit_max": self.max_residual,
            "target_residuals": {
                str(q): [None if not np.isfinite(v) else float(v) for v in r]
                for q, r in self.residuals.items()
            },
        }


def targets_from_values(section: dict | None, *, flip: float = 1.0) -> TargetCurves:
    """TargetCurves from the validated ``[target]`` table; checks the curves run along d.

    ``flip = -1`` when the leading plate lies right of the profile: the construction's local
    frame then has ``y = -profile y`` (see :mod:`compas_ccu.design.build`).
    """
    if not section:
        return TargetCurves()
    out = {}
    for name in ("apex", "support", "support_end"):
        pts = section.get(name)
        if pts is None:
            out[name] = None
            continue
        arr = np.asarray(pts, dtype=float)
        if np.any(np.diff(arr[:, 0]) <= 0.0):
            raise DesignError(
                f"the distances d (first column) must increase strictly, got {arr[:, 0].tolist()}",
                key=f"target.{name}",
            )
        out[name] = arr
    if out["support_end"] is not None and out["support"] is None:
        raise DesignError("needs target.support as well", key="target.support_end")
    if out["support"] is not None and out["support_end"] is None:
        out["support_end"] = out["support"] * np.array([1.0, -1.0])
    if out["apex"] is not None:
        out["apex"] = out["apex"] * np.array([1.0, flip])
    return TargetCurves(**out)


def intersect_ray_polyline(origin: np.ndarray, direction: np.ndarray, polyline: np.ndarray):
    """First intersection of the ray ``origin + t direction`` (t > 0) with a 2D polyline.

    Parameters
    ----------
    origin, direction : (2,) float
    polyline : (q, 2) float

    Returns
    -------
    t : float
        Ray parameter of the intersection, or of the closest approach if they do not meet.
    miss : float
        0 at an intersection, else the distance of the closest approach.

    Examples
    --------
    >>> import numpy as np
    >>> intersect_ray_polyline(np.zeros(2), np.array([1.0, 1.0]), np.array([[0, 2], [4, -2]]))
    (1.0, 0.0)
    """
    a, b = polyline[:-1], polyline[1:]
    e = b - a
    denom = direction[0] * e[:, 1] - direction[1] * e[:, 0]
    w = a - origin
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / denom
        u = (w[:, 0] * direction[1] - w[:, 1] * direction[0]) / denom
    hit = np.isfinite(t) & (t > ZERO_LENGTH) & (u >= -ZERO_LENGTH) & (u <= 1.0 + ZERO_LENGTH)
    if hit.any():
        return float(t[hit].min()), 0.0
    # closest approach: target vertices projected on the ray, ray points on the segments
    dd = float(direction @ direction)
    ts = np.clip((polyline - origin) @ direction / dd, EXACT_RELATIVE, None)
    pts = origin + ts[:, None] * direction
    rel = pts[:, None, :] - a[None]
    s = np.clip(np.einsum("pqi,qi->pq", rel, e) / np.einsum("qi,qi->q", e, e), 0.0, 1.0)
    dist = np.linalg.norm(rel - s[..., None] * e[None], axis=-1).min(axis=1)
    i = int(np.argmin(dist))
    return float(ts[i]), float(dist[i])


def solve_plane(near, direction, controls, targets: TargetCurves, base_heights):
    """Heights ``(c0, c1, c2)`` of a solved plane and the residuals at its three controls.

    Parameters
    ----------
    near, direction : (n + 1, 3) float
        Ruling lines of the plate that reaches the plane (local frame).
    controls : (3,) int
        Start, reference and end crease vertex.
    base_heights : (3,) float
        The layout's plane ``z = c0 + c1 x + c2 y``, used at controls without a target.
    """
    points = np.empty((3, 3))
    residual = np.full(3, np.nan)
    curves = (targets.support, targets.apex, targets.support_end)
    for slot, (i, curve) in enumerate(zip(controls, curves)):
        p, d = near[i], direction[i]
        if curve is None:
            c0, c1, c2 = base_heights
            t = (c0 + c1 * p[0] + c2 * p[1] - p[2]) / (d[2] - c1 * d[0] - c2 * d[1])
            miss = np.nan
        else:
            col = 1 if slot == 1 else 0  # apex: y(d); supports: x(d)
            t, miss = intersect_ray_polyline(
                np.array([p[2], p[col]]), np.array([d[2], d[col]]), curve
            )
        points[slot] = p + t * d
        residual[slot] = miss
    design = np.c_[np.ones(3), points[:, :2]]
    return np.linalg.solve(design, points[:, 2]), residual
