"""The record of an as-built check (``ccu asbuilt``, docs/fit.md): every plate's deviation
(:class:`PlateDeviation`) and the whole check (:class:`AsBuilt`, the ``ccu.asbuilt`` record),
as :func:`compas_ccu.fit.register.register` returns them."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["AsBuilt", "PlateDeviation", "MIN_COVERAGE"]

#: Below this share of the plate area covered by scan points, ``ccu asbuilt`` exits 3.
MIN_COVERAGE = 0.2


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
