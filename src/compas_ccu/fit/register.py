"""As-built check: register a scan to the one-degree-of-freedom model (``ccu asbuilt``,
docs/fit.md).

The unknowns are the reflection angle α and the rigid pose of the structure in the scan (6
parameters). :func:`register` finds them in two steps:

1. **Global start.** The scan's principal axes are matched to the model's at a coarse grid of α
   from the flat stack to the first collision, trying all 24 signed axis permutations (the
   ambiguities of principal axes), each followed by a few trimmed ICP iterations against a
   sampling of the plates; the best candidates by trimmed mean distance go on.
2. **Robust fit.** ``scipy.optimize.least_squares`` over α and the pose, the residual the
   exact signed point-to-plates distance (:class:`~compas_ccu.fit.distance.PlateSurface`), loss
   ``soft_l1`` with ``f_scale`` twice the noise (estimated from the residuals unless given),
   twice (the second pass with the noise re-estimated).

Then every scan point is measured once more: inliers (within the outlier distance), their RMS
and largest distance, the share of every plate's area covered by scan points, and optionally
(``per_plate``) each plate's own small rigid deviation, which finds a plate that slipped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial import cKDTree

from compas_ccu.errors import FitError, GeometryError, OptionError
from compas_ccu.fit.distance import Distances, PlateSurface
from compas_ccu.fit.rigid import apply, axis_rotations, invert, matrix, rotation, rotations
from compas_ccu.key_figures import state_figures
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["AsBuilt", "PlateDeviation", "register", "MIN_COVERAGE", "MIN_INLIER_SHARE"]

#: Below this share of the plate area covered by scan points, ``ccu asbuilt`` exits 3.
MIN_COVERAGE = 0.2
#: A scan with fewer of its points within the outlier distance of the fitted state fits no
#: state (FitError).
MIN_INLIER_SHARE = 0.5
#: Scan points below this count cannot be registered.
MIN_POINTS = 50
#: Points a plate needs for its own rigid deviation (``per_plate``).
MIN_PLATE_POINTS = 30
#: The most points of a plate its own deviation is fitted to (an even subset; all are measured).
PLATE_SAMPLE = 2000
#: The global start's ICP pairs a point with a sample at most (1 + START_EPS) times as far as
#: its nearest (cKDTree's approximate search: the rough search of many poor starts, most of
#: whose points lie far from the plates, is over 2 times faster).
START_EPS = 1.0


@dataclass(frozen=True)
class PlateDeviation:
    """One plate of an as-built check.

    Attributes
    ----------
    id : int
        Plate id.
    points : int
        Inlier scan points nearest to this plate.
    rms, max : float or None
        RMS and largest distance of those points, m (None without points).
    coverage : float
        Share of the plate's area with a scan inlier within the coverage radius.
    slip : float or None
        With ``per_plate``: the largest displacement of a plate vertex under the plate's own
        rigid deviation from the fitted state, m (None: not fitted or too few points).
    translation : (3,) float or None
        That deviation's translation at the plate's centroid, m (design frame).
    rotation : float or None
        Its rotation angle, degrees.
    rms_after : float or None
        RMS of the plate's points after its own deviation, m.
    slipped : bool
        ``slip`` beyond the tolerance.
    """

    id: int
    points: int
    rms: float | None
    max: float | None
    coverage: float
    slip: float | None = None
    translation: tuple | None = None
    rotation: float | None = None
    rms_after: float | None = None
    slipped: bool = False

    def to_dict(self) -> dict:
        return {
            "id": self.id,
            "points": self.points,
            "rms": self.rms,
            "max": self.max,
            "coverage": self.coverage,
            "slip": self.slip,
            "translation": None if self.translation is None else list(self.translation),
            "rotation": self.rotation,
            "rms_after": self.rms_after,
            "slipped": self.slipped,
        }


@dataclass(frozen=True)
class AsBuilt:
    """The result of :func:`register`.

    Attributes
    ----------
    alpha : float
        Fitted reference reflection angle, degrees.
    pose : (4, 4) float
        Rigid motion from the design's world frame to the scan's coordinates.
    rms, max : float
        RMS and largest distance of the inliers to the fitted state, m.
    points, inliers, outliers, beyond_tolerance : int
        Scan points; those within the outlier distance; those beyond it; inliers farther than
        the tolerance.
    tolerance, outlier_distance, noise : float
        m; ``noise`` the robust standard deviation of the inliers' signed distances (1.4826
        MAD) unless given.
    coverage : float
        Share of the whole plate area covered (see :class:`PlateDeviation`).
    coverage_radius : float
        m: the larger of the tolerance and 2.5 times the scan's median point spacing.
    plates : tuple of PlateDeviation
    figures, design_figures : dict
        ``alpha`` (deg), ``crease_span``, ``crease_rise`` (m) as built and as designed.
    evaluations : int
        Distance evaluations of the robust fit.
    signed : (n,) float
        Signed distance of every scan point to the fitted state, m.
    plate_row : (n,) int
        Row of its nearest plate.
    design_points : (n, 3) float
        The scan points in the design frame.
    """

    alpha: float
    pose: np.ndarray
    rms: float
    max: float
    points: int
    inliers: int
    outliers: int
    beyond_tolerance: int
    tolerance: float
    outlier_distance: float
    noise: float
    coverage: float
    coverage_radius: float
    plates: tuple
    figures: dict
    design_figures: dict
    evaluations: int
    per_plate: bool
    signed: np.ndarray = field(repr=False)
    plate_row: np.ndarray = field(repr=False)
    design_points: np.ndarray = field(repr=False)

    @property
    def coverage_ok(self) -> bool:
        """The scan covers at least :data:`MIN_COVERAGE` of the plate area."""
        return self.coverage >= MIN_COVERAGE

    @property
    def slipped(self) -> list:
        """Ids of the plates whose own deviation exceeds the tolerance."""
        return [p.id for p in self.plates if p.slipped]

    def to_dict(self) -> dict:
        """The ``ccu.asbuilt`` record (docs/fit.md): lengths m, angles degrees."""
        return {
            "format": "ccu.asbuilt",
            "version": 1,
            "units": "m",
            "alpha": self.alpha,
            "pose": self.pose.tolist(),
            "pose_maps": "design world coordinates to scan coordinates",
            "rms": self.rms,
            "max": self.max,
            "points": self.points,
            "inliers": self.inliers,
            "outliers": self.outliers,
            "beyond_tolerance": self.beyond_tolerance,
            "tolerance": self.tolerance,
            "outlier_distance": self.outlier_distance,
            "noise": self.noise,
            "coverage": self.coverage,
            "coverage_radius": self.coverage_radius,
            "min_coverage": MIN_COVERAGE,
            "coverage_ok": self.coverage_ok,
            "evaluations": self.evaluations,
            "per_plate": self.per_plate,
            "slipped": self.slipped,
            "key_figures": {"as_built": self.figures, "design": self.design_figures},
            "plates": [p.to_dict() for p in self.plates],
        }


class _States:
    """Plate surfaces of one model by α, the last one cached (the pose columns of a
    finite-difference Jacobian share it)."""

    def __init__(self, model, spacing: float):
        self.model = model
        self.spacing = spacing
        self.faces = model.faces
        self._key = None
        self._surface = None
        self._plan = None

    def __call__(self, alpha: float) -> PlateSurface:
        if alpha != self._key:
            vertices = self.model.vertices([alpha])[0]
            self._surface = PlateSurface.from_vertices(
                vertices, self.faces, spacing=self.spacing, plan=self._plan
            )
            self._plan = self._surface.plan
            self._key = alpha
        return self._surface


def _pca(points, weights=None):
    w = np.ones(len(points)) if weights is None else weights
    w = w / w.sum()
    c = w @ points
    cov = (points - c).T @ ((points - c) * w[:, None])
    _, vec = np.linalg.eigh(cov)
    axes = vec[:, ::-1].copy()
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1.0
    return c, axes


def _icp(start, scan, surf: PlateSurface, iterations: int, keep: float, cap: float):
    """Trimmed point-to-plane ICP against the samples of ``surf`` (the share ``keep`` of
    nearest pairs); returns the motion and its score, the mean point-to-plane distance capped
    at ``cap`` over all points (a partial fit of few points scores badly)."""
    m, score = _icp_many(start[None], scan, surf, iterations, keep, cap)
    return m[0], float(score[0])


def _icp_many(
    starts, scan, surf: PlateSurface, iterations: int, keep: float, cap: float, eps: float = 0.0
):
    """:func:`_icp` from every motion of ``starts`` (b, 4, 4) at once (one tree query per
    iteration for all of them); returns the motions (b, 4, 4) and scores (b,)."""
    m = np.array(starts, dtype=np.float64)
    b, n = len(m), len(scan)
    normals = surf.normals[surf.sample_triangle]
    for _ in range(iterations):
        x = np.einsum("bij,nj->bni", m[:, :3, :3], scan) + m[:, None, :3, 3]
        d, i = surf.tree.query(x.reshape(-1, 3), eps=eps)
        d, i = d.reshape(b, n), i.reshape(b, n)
        w = (d <= np.quantile(d, keep, axis=1)[:, None]).astype(np.float64)
        nrm = normals[i]
        a = np.concatenate([np.cross(x, nrm), nrm], axis=2)  # (b, n, 6)
        rhs = ((surf.samples[i] - x) * nrm).sum(axis=2)
        lhs = np.einsum("bni,bn,bnj->bij", a, w, a) + EXACT_RELATIVE * np.eye(6)
        step = _lstsq_many(lhs, np.einsum("bni,bn->bi", a, w * rhs))
        move = np.tile(np.eye(4), (b, 1, 1))
        move[:, :3, :3] = rotations(step[:, :3])
        move[:, :3, 3] = step[:, 3:]
        m = move @ m
    x = np.einsum("bij,nj->bni", m[:, :3, :3], scan) + m[:, None, :3, 3]
    _, i = surf.tree.query(x.reshape(-1, 3), eps=eps)
    i = i.reshape(b, n)
    d = np.abs(((x - surf.samples[i]) * normals[i]).sum(axis=2))
    return m, np.minimum(d, cap).mean(axis=1)


def _lstsq_many(lhs, rhs):
    """``numpy.linalg.lstsq`` of every system ``lhs`` (b, k, k), ``rhs`` (b, k): the
    minimum-norm solution, singular values below ``k`` eps of the largest dropped (a singular
    system, such as a diverged start's, does not raise)."""
    u, sv, vt = np.linalg.svd(lhs)
    keep = sv > np.finfo(np.float64).eps * lhs.shape[-1] * sv[:, :1]
    inv = np.where(keep, 1.0 / np.where(keep, sv, 1.0), 0.0)
    return np.einsum("bji,bj->bi", vt, inv * np.einsum("bji,bj->bi", u, rhs))


def _mad_sigma(signed) -> float:
    return float(1.4826 * np.median(np.abs(signed))) if len(signed) else 0.0


def _robust_sigma(signed, start: float) -> float:
    """Noise of signed distances: 1.4826 MAD, twice restricted to within 5 sigma."""
    sigma = max(start, 1e-6)
    for _ in range(3):
        sel = np.abs(signed) <= 5.0 * sigma
        if sel.sum() < 10:
            break
        sigma = max(_mad_sigma(signed[sel]), 1e-6)
    return sigma


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
    rng = np.random.default_rng(seed)
    fit_idx = np.sort(rng.choice(len(p), size=min(int(sample), len(p)), replace=False))
    few = np.sort(rng.choice(len(fit_idx), size=min(500, len(fit_idx)), replace=False))
    start_idx = fit_idx[few]
    scan_fit, scan_start = p[fit_idx], p[start_idx]
    scan_few = scan_start[:200]

    lo = 0.5
    hi = min(model.alpha_limit, model.collision_free_alpha) - 1e-3
    coarse = _States(model, model.size / 60.0)
    fine = _States(model, model.size / 150.0)

    starts = _starts(model, scan_start, scan_few, coarse, lo, hi, alpha_grid, refine)
    cap = model.size / 60.0  # the ICP's trimming distance, as in the starts
    best = None
    evaluations = 0
    for _, alpha0, m0 in starts[: int(candidates)]:
        surf = coarse(alpha0)
        m0, _ = _icp(m0, scan_fit[:2000], surf, 15, 0.6, cap)
        result, count = _fit_state(fine, scan_fit, alpha0, m0, lo, hi, noise, max_evaluations)
        evaluations += count
        if best is None or result[0] < best[0]:
            best = result
    _, alpha, m, sigma_fit = best

    # 4. every point, measured at the fitted state
    design_points = apply(m, p)
    surf = fine(alpha)
    # exact near the plates; a point certainly beyond the largest possible outlier distance
    # is an outlier whatever its distance, which is then exact to the lattice's cover only
    widest = max(5.0 * (noise if noise is not None else tolerance), 3.0 * tolerance)
    reach = outlier_distance if outlier_distance is not None else widest
    d = surf.query(design_points, candidates=16, max_candidates=64, beyond=reach)
    # the noise, estimated unless given; at most the tolerance (a scan noisier than the
    # tolerance cannot check it, and a scan of something else must not widen its own gate)
    sigma = noise if noise is not None else min(_robust_sigma(d.signed, sigma_fit), tolerance)
    gate = outlier_distance if outlier_distance is not None else max(5.0 * sigma, 3.0 * tolerance)
    inlier = d.distance <= gate
    if inlier.mean() < MIN_INLIER_SHARE:
        raise FitError(
            f"the scan fits no state of {model.design.name}: at the best state (alpha "
            f"{alpha:.2f} deg) only {100 * inlier.mean():.0f} % of its {len(p)} points lie within "
            f"{gate * 1000:.1f} mm of the plates (at least {100 * MIN_INLIER_SHARE:.0f} % needed)"
        )
    plates = _plate_records(model, surf, d, inlier, design_points, tolerance, sigma, per_plate)
    coverage, radius, per = _coverage(surf, design_points[inlier], tolerance)
    plates = tuple(
        PlateDeviation(**{**rec.__dict__, "coverage": float(per[i])})
        for i, rec in enumerate(plates)
    )
    deployed = model.deploy(alpha)
    as_built = state_figures(deployed)
    design = state_figures(model.deploy())
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
        figures={
            "alpha": float(alpha),
            "crease_span": as_built["crease_span"],
            "crease_rise": as_built["crease_rise"],
        },
        design_figures={
            "alpha": float(model.alpha_design),
            "crease_span": design["crease_span"],
            "crease_rise": design["crease_rise"],
        },
        evaluations=int(evaluations),
        per_plate=bool(per_plate),
        signed=d.signed,
        plate_row=d.plate,
        design_points=design_points,
    )


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


def _starts(model, scan_start, scan_few, coarse, lo, hi, alpha_grid, refine) -> list:
    """The starts of the robust fit, best first: ``(score, alpha, pose)`` (steps 1 and 2)."""
    # 1. global start: principal axes, 24 axis rotations, a coarse alpha grid, the scan's
    # centroid or its ends put on the model's (a partial scan), scored, the best refined by ICP
    cs, es = _pca(scan_start)
    cap = model.size / 60.0
    scored = []
    for alpha in np.linspace(lo + 0.5, hi - 0.5, int(alpha_grid)):
        surf = coarse(float(alpha))
        cm, em = _pca(surf.samples, surf.sample_weight)
        model_proj = (surf.samples - cm) @ em
        m_lo, m_hi = model_proj.min(axis=0), model_proj.max(axis=0)
        tried = []
        for q in axis_rotations():
            rot = em @ q @ es.T
            x = (scan_start - cs) @ rot.T
            proj = x @ em
            shifts = [np.zeros(3)]
            for k in range(3):
                shifts += [(m_lo[k] - proj[:, k].min()) * em[:, k]]
                shifts += [(m_hi[k] - proj[:, k].max()) * em[:, k]]
            tried += [matrix(rot, cm + shift - rot @ cs) for shift in shifts]
        motions, scores = _icp_many(np.array(tried), scan_few, surf, 5, 0.6, cap, eps=START_EPS)
        scored += [(float(s), float(alpha), m) for s, m in zip(scores, motions)]
    scored.sort(key=lambda s: s[0])
    # 2. the best starts followed along a fine alpha grid (continuation: each alpha starts from
    # the pose of its neighbour), a few ICP iterations at each
    fine_grid = np.linspace(lo + 0.5, hi - 0.5, max(2, int(round((hi - lo) / 2.0))))
    starts = []
    for _, alpha0, m0 in scored[: int(refine)]:
        at = int(np.argmin(np.abs(fine_grid - alpha0)))
        m_at, _ = _icp(m0, scan_start, coarse(float(fine_grid[at])), 10, 0.6, cap)
        for direction in (range(at, len(fine_grid)), range(at, -1, -1)):
            m = m_at
            for j in direction:
                alpha = float(fine_grid[j])
                m, score = _icp(m, scan_start, coarse(alpha), 4, 0.6, cap)
                starts.append((score, alpha, m))
    starts.sort(key=lambda s: s[0])
    return starts


def _fit_state(states, scan, alpha0, m0, lo, hi, noise, max_evaluations):
    """Two robust least-squares passes over (alpha, rotation vector, translation); returns
    ((cost, alpha, motion, sigma), evaluations)."""
    centre = states(alpha0).samples.mean(axis=0)
    count = 0

    def motion(x):
        rot = rotation(x[1:4])
        return matrix(rot, centre + x[4:7] - rot @ centre) @ m0

    def residuals(x):
        nonlocal count
        count += 1
        surf = states(float(x[0]))  # 8 candidates: exact near the plates, fast
        d = surf.query(apply(motion(x), scan), candidates=8, max_candidates=8).distance
        # unsigned (a signed distance flips where the nearest plate changes side; for
        # Gauss-Newton |s| and s are the same), capped: far points constant, no jumps
        return np.minimum(d, clip)

    x = np.array([min(max(alpha0, lo), hi), 0, 0, 0, 0, 0, 0], dtype=float)
    bounds = ([lo, *[-np.inf] * 6], [hi, *[np.inf] * 6])
    scale = [1.0, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01]
    clip = np.inf
    r = residuals(x)
    sigma = noise if noise is not None else _robust_sigma(r, _mad_sigma(r))
    clip = max(20.0 * sigma, states.model.size / 100.0)
    for _ in range(2):
        res = least_squares(
            residuals,
            x,
            bounds=bounds,
            loss="soft_l1",
            f_scale=max(2.0 * sigma, 1e-4),
            x_scale=scale,
            max_nfev=int(max_evaluations),
            xtol=1e-8,
            ftol=1e-8,
        )
        x = res.x
        if noise is None:
            sigma = _robust_sigma(res.fun, sigma)
    cost = float(np.mean(np.minimum(res.fun**2, (5.0 * sigma) ** 2)))
    return (cost, float(x[0]), motion(x), sigma), count


def _plate_records(model, surf, d: Distances, inlier, pts, tolerance, sigma, per_plate):
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
            rec = _plate_deviation(rec, surf, i, pts[inlier & (d.plate == i)], tolerance, sigma)
        out.append(rec)
    return out


def _plate_deviation(rec, surf, row, pts, tolerance, sigma):
    """The plate's own small rigid deviation, fitted robustly to its points."""
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


def _coverage(surf: PlateSurface, inliers, tolerance):
    """Share of the area covered: samples with an inlier within the coverage radius."""
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
