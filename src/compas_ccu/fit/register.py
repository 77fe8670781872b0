"""As-built check: register a scan to the one-degree-of-freedom model (``ccu asbuilt``,
docs/fit.md).

The unknowns are the reflection angle α and the rigid pose of the structure in the scan (6
parameters). :func:`register` finds them in two steps:

1. **Global start** (:mod:`compas_ccu.fit.global_start`). The scan's principal axes are matched
   to the model's at a coarse grid of α from the flat stack to the first collision, trying all
   24 signed axis permutations (the ambiguities of principal axes), each followed by a few
   trimmed ICP iterations against a sampling of the plates; the best candidates by trimmed mean
   distance go on, followed along a fine grid of α.
2. **Robust fit** (:mod:`compas_ccu.fit.robust_fit`). ``scipy.optimize.least_squares`` over α
   and the pose, the residual the exact point-to-plates distance
   (:class:`~compas_ccu.fit.distance.PlateSurface`), loss ``soft_l1`` with ``f_scale`` twice
   the noise (estimated from the residuals unless given), twice (the second pass with the noise
   re-estimated).

Then every scan point is measured once more (:mod:`compas_ccu.fit.measure`): inliers (within
the outlier distance), their RMS and largest distance, the share of every plate's area covered
by scan points, and optionally (``per_plate``) each plate's own small rigid deviation, which
finds a plate that slipped. The result is an :class:`~compas_ccu.fit.asbuilt.AsBuilt`.
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.errors import FitError, GeometryError, OptionError
from compas_ccu.fit.asbuilt import MIN_COVERAGE, AsBuilt, PlateDeviation
from compas_ccu.fit.global_start import global_starts, icp
from compas_ccu.fit.measure import plate_coverage, plate_records
from compas_ccu.fit.rigid import apply, invert
from compas_ccu.fit.robust_fit import PlateStates, fit_state, robust_sigma
from compas_ccu.key_figures import state_figures

__all__ = ["AsBuilt", "PlateDeviation", "register", "MIN_COVERAGE", "MIN_INLIER_SHARE"]

#: A scan with fewer of its points within the outlier distance of the fitted state fits no
#: state (FitError).
MIN_INLIER_SHARE = 0.5
#: Scan points below this count cannot be registered.
MIN_POINTS = 50


def register(
    model,
    points,
    *,
    per_plate: bool = False,
    tolerance: float = 0.01,
    outlier_distance: float | None = None,
    noise: float | None = None,
    sample: int = 3000,
    seed: int = 0,
    max_evaluations: int = 200,
    alpha_grid: int = 7,
    candidates: int = 2,
    refine: int = 4,
) -> AsBuilt:
    """Register a scan to the model's one-degree-of-freedom deployment (module docstring).

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    points : (n, 3) float
        Scan points, m (any coordinates: the pose is found).
    per_plate : bool
        Also fit each plate's own rigid deviation from the fitted state (a slipped plate).
    tolerance : float
        m: points beyond it count as ``beyond_tolerance``, plates whose deviation moves a
        vertex further are ``slipped``.
    outlier_distance : float, optional
        m; default the larger of 5 noise and 3 tolerances (the estimated noise is at most the
        tolerance).
    noise : float, optional
        Standard deviation of the scan's noise, m; default estimated.
    sample : int
        Scan points the fit uses (a seeded random subset; every point is measured at the end).
    seed : int
        Seed of that subset (the result is reproducible: no clock decides it).
    max_evaluations : int
        Distance evaluations of each least-squares pass.
    alpha_grid : int
        α values of the global start.
    refine : int
        Best starts of the global search refined by ICP.
    candidates : int
        Of those, the best refined by the robust fit.

    Returns
    -------
    AsBuilt

    Raises
    ------
    GeometryError
        Fewer than 50 points, or non-finite ones.
    OptionError
        A tolerance, outlier distance, noise or count out of range.
    FitError
        The scan fits no state: fewer than half of its points within the outlier distance of
        the best state.
    """
    p = _checked_scan(points, tolerance, outlier_distance, noise, sample, max_evaluations)
    scan_fit, scan_start, scan_few = _subsets(p, sample, seed)
    lo = 0.5
    hi = min(model.alpha_limit, model.collision_free_alpha) - 1e-3
    coarse = PlateStates(model, model.size / 60.0)
    fine = PlateStates(model, model.size / 150.0)
    starts = global_starts(model, scan_start, scan_few, coarse, lo, hi, alpha_grid, refine)
    (_, alpha, m, sigma_fit), evaluations = _best_state(
        starts[: int(candidates)], scan_fit, coarse, fine, lo, hi, noise, max_evaluations
    )
    # 4. every point, measured at the fitted state
    design_points = apply(m, p)
    surf = fine(alpha)
    d, sigma, gate, inlier = _measured(
        model, surf, design_points, alpha, sigma_fit, tolerance, outlier_distance, noise
    )
    plates = plate_records(model, surf, d, inlier, design_points, tolerance, sigma, per_plate)
    coverage, radius, per = plate_coverage(surf, design_points[inlier], tolerance)
    plates = tuple(
        PlateDeviation(**{**rec.__dict__, "coverage": float(per[i])})
        for i, rec in enumerate(plates)
    )
    dist_in = d.distance[inlier]
    return AsBuilt(
        alpha=float(alpha),
        pose=invert(m),
        rms=float(np.sqrt(np.mean(dist_in**2))),
        max=float(dist_in.max()),
        points=int(len(p)),
        inliers=int(inlier.sum()),
        outliers=int((~inlier).sum()),
        beyond_tolerance=int((inlier & (d.distance > tolerance)).sum()),
        tolerance=float(tolerance),
        outlier_distance=float(gate),
        noise=float(sigma),
        coverage=float(coverage),
        coverage_radius=float(radius),
        plates=plates,
        figures=_figures(model, alpha),
        design_figures=_figures(model, model.alpha_design),
        evaluations=int(evaluations),
        per_plate=bool(per_plate),
        signed=d.signed,
        plate_row=d.plate,
        design_points=design_points,
    )


def _subsets(p, sample: int, seed: int):
    """The seeded subsets of the scan: the robust fit's (``sample`` points), the
    continuation's (500 of those) and the global start's (the first 200 of those)."""
    rng = np.random.default_rng(seed)
    fit_idx = np.sort(rng.choice(len(p), size=min(int(sample), len(p)), replace=False))
    few = np.sort(rng.choice(len(fit_idx), size=min(500, len(fit_idx)), replace=False))
    scan_start = p[fit_idx[few]]
    return p[fit_idx], scan_start, scan_start[:200]


def _best_state(starts, scan_fit, coarse, fine, lo, hi, noise, max_evaluations):
    """Step 3: each start refined by ICP on up to 2,000 points, then fitted robustly
    (:func:`~compas_ccu.fit.robust_fit.fit_state`); returns the best ``(cost, alpha, motion,
    sigma)`` and the distance evaluations of all."""
    cap = coarse.model.size / 60.0  # the ICP's trimming distance, as in the starts
    best = None
    evaluations = 0
    for _, alpha0, m0 in starts:
        m0, _ = icp(m0, scan_fit[:2000], coarse(alpha0), 15, 0.6, cap)
        result, count = fit_state(fine, scan_fit, alpha0, m0, lo, hi, noise, max_evaluations)
        evaluations += count
        if best is None or result[0] < best[0]:
            best = result
    return best, evaluations


def _measured(model, surf, design_points, alpha, sigma_fit, tolerance, outlier_distance, noise):
    """Every scan point's distance to the fitted state, the noise, the outlier distance and the
    inliers; FitError if fewer than :data:`MIN_INLIER_SHARE` of the points are inliers."""
    # exact near the plates; a point certainly beyond the largest possible outlier distance
    # is an outlier whatever its distance, which is then exact to the lattice's cover only
    widest = max(5.0 * (noise if noise is not None else tolerance), 3.0 * tolerance)
    reach = outlier_distance if outlier_distance is not None else widest
    d = surf.query(design_points, candidates=16, max_candidates=64, beyond=reach)
    # the noise, estimated unless given; at most the tolerance (a scan noisier than the
    # tolerance cannot check it, and a scan of something else must not widen its own gate)
    sigma = noise if noise is not None else min(robust_sigma(d.signed, sigma_fit), tolerance)
    gate = outlier_distance if outlier_distance is not None else max(5.0 * sigma, 3.0 * tolerance)
    inlier = d.distance <= gate
    if inlier.mean() < MIN_INLIER_SHARE:
        raise FitError(
            f"the scan fits no state of {model.design.name}: at the best state (alpha "
            f"{alpha:.2f} deg) only {100 * inlier.mean():.0f} % of its {len(design_points)} "
            f"points lie within {gate * 1000:.1f} mm of the plates (at least "
            f"{100 * MIN_INLIER_SHARE:.0f} % needed)"
        )
    return d, sigma, gate, inlier


def _figures(model, alpha: float) -> dict:
    """``alpha`` (deg), ``crease_span``, ``crease_rise`` (m) of the model deployed to ``alpha``."""
    figures = state_figures(model.deploy(alpha))
    return {
        "alpha": float(alpha),
        "crease_span": figures["crease_span"],
        "crease_rise": figures["crease_rise"],
    }


def _checked_scan(points, tolerance, outlier_distance, noise, sample, max_evaluations):
    """The scan as (n, 3) float64, its options checked (:func:`register`'s Raises)."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if len(p) < MIN_POINTS:
        raise GeometryError(f"a scan needs at least {MIN_POINTS} points, got {len(p)}")
    if not np.isfinite(p).all():
        raise GeometryError("the scan holds non-finite coordinates")
    for name, value in (("tolerance", tolerance), ("outlier distance", outlier_distance)):
        if value is not None and not (value > 0.0 and math.isfinite(value)):
            raise OptionError(f"the {name} must be a positive length in m, got {value!r}")
    if noise is not None and not (noise > 0.0 and math.isfinite(noise)):
        raise OptionError(f"the noise must be a positive length in m, got {noise!r}")
    for name, value, low in (("sample", sample, 100), ("max_evaluations", max_evaluations, 4)):
        if int(value) < low:
            raise OptionError(f"{name} must be at least {low}, got {value!r}")
    return p
