"""The robust fit of an as-built check (docs/fit.md, ``ccu asbuilt`` step 3):
``scipy.optimize.least_squares`` over the reflection angle α and the pose, the residual the
exact point-to-plates distance of the deployed state (:class:`PlateStates`: one model's plate
surfaces by α), loss ``soft_l1`` with ``f_scale`` twice the noise, the noise a robust spread of
the residuals (:func:`robust_sigma`)."""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares

from compas_ccu.fit.distance import PlateSurface
from compas_ccu.fit.rigid import apply, matrix, rotation

__all__ = ["PlateStates", "fit_state", "mad_sigma", "robust_sigma"]


class PlateStates:
    """Plate surfaces of one model by α, the last one cached (the pose columns of a
    finite-difference Jacobian share it); every state sampled on the first one's lattice plan
    (the samples move continuously with α).

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    spacing : float
        Sample spacing of the surfaces, m.
    """

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


def mad_sigma(signed) -> float:
    """1.4826 times the median absolute value of ``signed`` (n,): the standard deviation of
    normal noise; 0 without values."""
    return float(1.4826 * np.median(np.abs(signed))) if len(signed) else 0.0


def robust_sigma(signed, start: float) -> float:
    """Noise of signed distances: 1.4826 MAD, twice restricted to within 5 sigma."""
    sigma = max(start, 1e-6)
    for _ in range(3):
        sel = np.abs(signed) <= 5.0 * sigma
        if sel.sum() < 10:
            break
        sigma = max(mad_sigma(signed[sel]), 1e-6)
    return sigma


def fit_state(states, scan, alpha0, m0, lo, hi, noise, max_evaluations):
    """Two robust least-squares passes over (alpha, rotation vector, translation).

    Parameters
    ----------
    states : PlateStates
        The plates sampled finely, by α.
    scan : (n, 3) float
        The fit's scan points.
    alpha0 : float
        Start α, degrees.
    m0 : (4, 4) float
        Start motion from scan to design coordinates.
    lo, hi : float
        Bounds of α, degrees.
    noise : float or None
        Fixed noise, m; None: estimated from the residuals.
    max_evaluations : int
        Residual evaluations of each pass.

    Returns
    -------
    (cost, alpha, motion, sigma), evaluations
        ``cost`` the mean squared residual capped at 5 sigma (m²), ``motion`` (4, 4),
        ``sigma`` the noise (m); ``evaluations`` the residual evaluations of both passes.
    """
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
    sigma = noise if noise is not None else robust_sigma(r, mad_sigma(r))
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
            sigma = robust_sigma(res.fun, sigma)
    cost = float(np.mean(np.minimum(res.fun**2, (5.0 * sigma) ** 2)))
    return (cost, float(x[0]), motion(x), sigma), count
