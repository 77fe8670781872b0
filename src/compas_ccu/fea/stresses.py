"""Stresses from shell forces: surface stresses, principal values, the active-bending sign.

Shell forces are ``[n11, n22, n12, m11, m22, m12]`` per element in the element frame (see
:mod:`compas_ccu.fea.problem`). Everything returned here is independent of the in-plane
orientation of that frame, so two engines with different local axes compare directly.

>>> import numpy as np
>>> f = np.array([[0.0, 0.0, 0.0, -10.0, 0.0, 0.0]])       # pure bending, 10 N m/m
>>> s = surface_stresses(f, thickness=0.01)
>>> s.top[0] / 1e6, s.bottom[0] / 1e6                      # sigma11 = -/+ 6 m / t^2
(array([-0.6,  0. ,  0. ]), array([0.6, 0. , 0. ]))
>>> float(signed_bending_stress(f, thickness=0.01)[0] / 1e6)  # the top surface is compressed
-0.6
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

__all__ = [
    "SurfaceStresses",
    "StressSummary",
    "surface_stresses",
    "principal",
    "von_mises",
    "signed_bending_stress",
    "stress_summary",
]


@dataclass(frozen=True)
class SurfaceStresses:
    """Plane stress ``[s11, s22, s12]`` in the element frame (:func:`surface_stresses`).

    Attributes
    ----------
    top : (..., 3) float
        On the top surface (+t/2 along the element normal), Pa.
    bottom : (..., 3) float
        On the bottom surface (-t/2), Pa.
    membrane : (..., 3) float
        On the mid-plane (the membrane part alone), Pa.
    """

    top: np.ndarray
    bottom: np.ndarray
    membrane: np.ndarray


@dataclass(frozen=True)
class StressSummary:
    """Peak values over the elements of one state (:func:`stress_summary`).

    Attributes
    ----------
    max_tension_MPa : float
        The largest surface principal stress (top or bottom), MPa.
    max_compression_MPa : float
        The smallest (most compressive) surface principal stress, MPa.
    max_von_mises_MPa : float
        The largest surface von Mises stress, MPa.
    max_bending_MPa : float
        The largest absolute bending stress (:func:`signed_bending_stress`), MPa.
    max_membrane_MPa : float
        The largest absolute membrane principal stress, MPa.
    max_moment_Nm_per_m : float
        The largest absolute principal bending moment, N m/m.
    """

    max_tension_MPa: float
    max_compression_MPa: float
    max_von_mises_MPa: float
    max_bending_MPa: float
    max_membrane_MPa: float
    max_moment_Nm_per_m: float

    def to_dict(self) -> dict:
        """Plain data (``validation.json`` ``stresses``), the fields in order."""
        return asdict(self)


def surface_stresses(forces: np.ndarray, *, thickness: float) -> SurfaceStresses:
    """Plane stress ``[s11, s22, s12]`` on the top and bottom surfaces and the mid-plane.

    Parameters
    ----------
    forces : (..., 6) float
    thickness : float

    Returns
    -------
    SurfaceStresses
        ``top`` (+t/2 along the element normal), ``bottom`` and ``membrane``, (..., 3) Pa.
    """
    f = np.asarray(forces, dtype=float)
    membrane = f[..., :3] / thickness
    bending = 6.0 * f[..., 3:] / thickness**2
    return SurfaceStresses(top=membrane + bending, bottom=membrane - bending, membrane=membrane)


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


def stress_summary(forces: np.ndarray, *, thickness: float) -> StressSummary:
    """Peak values over the elements of one state, MPa and N m/m (:class:`StressSummary`).

    Parameters
    ----------
    forces : (E, 6) float
        The element forces of the state (:mod:`compas_ccu.fea.problem`).
    thickness : float
        The plates', m.
    """
    s = surface_stresses(forces, thickness=thickness)
    top, bottom = principal(s.top), principal(s.bottom)
    bending = signed_bending_stress(forces, thickness=thickness)
    membrane = principal(s.membrane)
    moments = principal(np.asarray(forces)[..., 3:])
    return StressSummary(
        max_tension_MPa=float(max(top.max(), bottom.max()) / 1e6),
        max_compression_MPa=float(min(top.min(), bottom.min()) / 1e6),
        max_von_mises_MPa=float(max(von_mises(s.top).max(), von_mises(s.bottom).max())) / 1e6,
        max_bending_MPa=float(np.abs(bending).max() / 1e6),
        max_membrane_MPa=float(np.abs(membrane).max() / 1e6),
        max_moment_Nm_per_m=float(np.abs(moments).max()),
    )
