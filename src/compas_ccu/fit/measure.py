"""The measurement of an as-built check at the fitted state (docs/fit.md, ``ccu asbuilt``
steps 4 and 5): every plate's inliers, RMS and largest distance (:func:`plate_records`), with
``per_plate`` its own small rigid deviation (:func:`plate_deviation`, a slipped plate), and the
share of every plate's area the scan covers (:func:`plate_coverage`)."""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial import cKDTree

from compas_ccu.fit.asbuilt import PlateDeviation
from compas_ccu.fit.distance import Distances, PlateSurface
from compas_ccu.fit.rigid import apply, invert, matrix, rotation

__all__ = ["plate_records", "plate_deviation", "plate_coverage", "MIN_PLATE_POINTS"]
__all__ += ["PLATE_SAMPLE"]

#: Points a plate needs for its own rigid deviation (``per_plate``).
MIN_PLATE_POINTS = 30
#: The most points of a plate its own deviation is fitted to (an even subset; all are measured).
PLATE_SAMPLE = 2000


def plate_records(model, surf, d: Distances, inlier, pts, tolerance, sigma, per_plate):
    """Every plate's inliers, RMS and largest distance (and ``per_plate`` its own deviation).

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    surf : PlateSurface
        The fitted state.
    d : Distances
        Of every scan point ``pts`` (n, 3) (design coordinates) to ``surf``.
    inlier : (n,) bool
    tolerance, sigma : float
        m: the slip tolerance and the noise.
    per_plate : bool

    Returns
    -------
    list of PlateDeviation
        In the order of ``model.plate_ids``, ``coverage`` 0 (:func:`plate_coverage` fills it).
    """
    ids = model.plate_ids
    rows = d.plate[inlier]
    dist = d.distance[inlier]
    count = np.bincount(rows, minlength=len(ids))
    sq = np.bincount(rows, weights=dist**2, minlength=len(ids))
    top = np.zeros(len(ids))
    np.maximum.at(top, rows, dist)
    out = []
    for i, pid in enumerate(ids):
        rms = float(np.sqrt(sq[i] / count[i])) if count[i] else None
        rec = PlateDeviation(
            id=int(pid),
            points=int(count[i]),
            rms=rms,
            max=float(top[i]) if count[i] else None,
            coverage=0.0,
        )
        if per_plate:
            rec = plate_deviation(rec, surf, i, pts[inlier & (d.plate == i)], tolerance, sigma)
        out.append(rec)
    return out


def plate_deviation(rec, surf, row, pts, tolerance, sigma):
    """The plate's own small rigid deviation, fitted robustly to its points.

    Parameters
    ----------
    rec : PlateDeviation
        The plate's record so far.
    surf : PlateSurface
    row : int
        The plate's row in ``surf``.
    pts : (n, 3) float
        Its inliers, design coordinates.
    tolerance, sigma : float
        m.

    Returns
    -------
    PlateDeviation
        ``rec`` with ``slip``, ``translation``, ``rotation``, ``rms_after`` and ``slipped``
        (unchanged below :data:`MIN_PLATE_POINTS` points).
    """
    if len(pts) < MIN_PLATE_POINTS:
        return rec
    every = pts
    if len(pts) > PLATE_SAMPLE:  # an even, reproducible subset for the fit
        pts = pts[np.linspace(0, len(pts) - 1, PLATE_SAMPLE).astype(np.int64)]
    tri = surf.triangles[surf.plate == row]
    own = PlateSurface(tri, np.zeros(len(tri), dtype=np.int64), spacing=surf.spacing)
    corners = tri.reshape(-1, 3)
    centre = corners.mean(axis=0)
    size = float(np.linalg.norm(np.ptp(corners, axis=0)))
    weight = math.sqrt(len(pts)) * sigma / tolerance

    def inverse(x):  # moves the points onto the design plate
        rot = rotation(x[:3])
        return matrix(rot, centre + x[3:] - rot @ centre)

    def residuals(x):
        prior = weight * np.concatenate([x[:3] * size, x[3:]])
        moved = apply(inverse(x), pts)
        return np.concatenate([own.query(moved, candidates=8, max_candidates=8).signed, prior])

    res = least_squares(
        residuals,
        np.zeros(6),
        loss="soft_l1",
        f_scale=max(2.0 * sigma, 1e-4),
        x_scale=0.01,
        max_nfev=100,
    )
    deviation = invert(inverse(res.x))  # design plate -> as built
    moved = apply(deviation, corners)
    slip = float(np.linalg.norm(moved - corners, axis=1).max())
    after = own.query(apply(inverse(res.x), every), candidates=16, max_candidates=64).distance
    return PlateDeviation(
        **{
            **rec.__dict__,
            "slip": slip,
            "translation": tuple(float(v) for v in apply(deviation, centre[None])[0] - centre),
            "rotation": float(np.degrees(np.linalg.norm(res.x[:3]))),
            "rms_after": float(np.sqrt(np.mean(after**2))),
            "slipped": slip > tolerance,
        }
    )


def plate_coverage(surf: PlateSurface, inliers, tolerance):
    """Share of the area covered: samples with an inlier within the coverage radius.

    Parameters
    ----------
    surf : PlateSurface
    inliers : (n, 3) float
        Inlier scan points, design coordinates.
    tolerance : float
        m.

    Returns
    -------
    share : float
        Of the whole plate area.
    radius : float
        The coverage radius, m: the larger of the tolerance and 2.5 times the median point
        spacing.
    per_plate : (p,) float
        Share of every plate's area.
    """
    if len(inliers) < 2:
        return 0.0, tolerance, np.zeros(surf.count)
    tree = cKDTree(inliers)
    probe = inliers[:: max(1, len(inliers) // 20000)]
    spacing = float(np.median(tree.query(probe, k=2)[0][:, 1]))
    radius = max(tolerance, 2.5 * spacing)
    near, _ = tree.query(surf.samples, distance_upper_bound=radius)
    covered = np.isfinite(near)
    plate = surf.plate[surf.sample_triangle]
    area = np.bincount(plate, weights=surf.sample_weight, minlength=surf.count)
    hit = np.bincount(plate, weights=surf.sample_weight * covered, minlength=surf.count)
    return float(hit.sum() / area.sum()), radius, hit / np.where(area > 0, area, 1.0)
