"""Stresses from shell forces: surface stresses, principal values, the active-bending sign.

Shell forces are ``[n11, n22, n12, m11, m22, m12]`` per element in the element frame (see
:mod:`compas_ccu.fea.problem`). Everything returned here is independent of the in-plane
orientation of that frame, so two engines with different local axes compare directly.

>>> import numpy as np
>>> f = np.array([[0.0, 0.0, 0.0, -10.0, 0.0, 0.0]])       # pure bending, 10 N m/m
>>> s = surface_stresses(f, thickness=0.01)
>>> s["top"][0] / 1e6, s["bottom"][0] / 1e6                # sigma11 = -/+ 6 m / t^2
(array([-0.6,  0. ,  0. ]), array([0.6, 0. , 0. ]))
>>> float(signed_bending_stress(f, thickness=0.01)[0] / 1e6)  # the top surface is compressed
-0.6
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "surface_stresses",
    "principal",
    "von_mises",
    "signed_bending_stress",
    "stress_summary",
]


def surface_stresses(forces: np.ndarray, *, thickness: float) -> dict:
    """Plane stress ``[s11, s22, s12]`` on the top and bottom surfaces and the mid-plane.

    Parameters
    ----------
    forces : (..., 6) float
    thickness : float

    Returns
    -------
    dict of (..., 3) float
        ``top`` (+t/2 along the element normal), ``bottom`` and ``membrane``, Pa.
    """
    f = np.asarray(forces, dtype=float)
    membrane = f[..., :3] / thickness
    bending = 6.0 * f[..., 3:] / thickness**2
    return {"top": membrane + bending, "bottom": membrane - bending, "membrane": membrane}


def principal(s: np.ndarray) -> np.ndarray:
    """(..., 2) principal values (largest first) of plane tensors ``[s11, s22, s12]``."""
    s = np.asarray(s, dtype=float)
    mean = 0.5 * (s[..., 0] + s[..., 1])
    radius = np.hypot(0.5 * (s[..., 0] - s[..., 1]), s[..., 2])
    return np.stack([mean + radius, mean - radius], axis=-1)


def von_mises(s: np.ndarray) -> np.ndarray:
    """(...) von Mises stress of plane tensors."""
    a, b, c = s[..., 0], s[..., 1], s[..., 2]
    return np.sqrt(a * a - a * b + b * b + 3.0 * c * c)


def signed_bending_stress(forces: np.ndarray, *, thickness: float) -> np.ndarray:
    """(...) the top-surface bending stress of largest magnitude, with its sign, Pa.

    Positive: the top surface is in tension (the plate bends away from its normal); this is the
    quantity the paper's Fig. 7 colours (tension / compression from active bending).
    """
    p = principal(6.0 * np.asarray(forces, dtype=float)[..., 3:] / thickness**2)
    return np.where(np.abs(p[..., 0]) >= np.abs(p[..., 1]), p[..., 0], p[..., 1])


def stress_summary(forces: np.ndarray, *, thickness: float) -> dict:
    """Peak values over elements of one state (forces (E, 6)): MPa and N m/m."""
    s = surface_stresses(forces, thickness=thickness)
    top, bottom = principal(s["top"]), principal(s["bottom"])
    bending = signed_bending_stress(forces, thickness=thickness)
    membrane = principal(s["membrane"])
    moments = principal(np.asarray(forces)[..., 3:])
    return {
        "max_tension_MPa": float(max(top.max(), bottom.max()) / 1e6),
        "max_compression_MPa": float(min(top.min(), bottom.min()) / 1e6),
        "max_von_mises_MPa": float(max(von_mises(s["top"]).max(), von_mises(s["bottom"]).max()))
        / 1e6,
        "max_bending_MPa": float(np.abs(bending).max() / 1e6),
        "max_membrane_MPa": float(np.abs(membrane).max() / 1e6),
        "max_moment_Nm_per_m": float(np.abs(moments).max()),
    }
