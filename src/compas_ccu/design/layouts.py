"""Plane layouts of multi-crease structures: where the crease planes lie at the design state.

Paper §5.5 and Fig. 10-12. Every layout is a sequence of ``m + 1`` crease planes ``O_0 .. O_m``
for ``m`` plates; plate ``k`` lies between ``O_k`` and ``O_{k+1}``. Planes are returned in the
local frame of the leading crease plane (profile ``x``, ``y`` in ``z = 0``; the leading plate
rises towards ``+z``), as unit normals ``n_k`` oriented towards ``+z`` and offsets ``h_k`` with
``n_k . p = h_k``. The leading plane ``O_{k0}`` is ``z = 0``.

* ``parallel`` -- planes ``z = z_k``: constant distances give a monoclastic vault; distances
  that vary from plate to plate give synclastic or anticlastic vaults (Fig. 10).
* ``inclined`` -- plane ``O_{k+1}`` lies at the distances ``d_start``, ``d`` and ``d_end`` from
  ``O_k`` (measured along ``z``) above the crease's start vertex, reference vertex and end
  vertex. ``d_start = d_end != d`` inclines the plane about the actuation rotation axis (the
  chord direction, Fig. 11); ``d_start != d_end`` inclines it perpendicular to that axis
  (Fig. 12a).
* ``radial`` -- planes through one axis parallel to the profile's ``y`` axis at ``x = axis``,
  rotated by the given angles: corrugated domes and funnel columns (Fig. 12b, c).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import DesignError
from compas_ccu.tolerances import EXACT_RELATIVE, ZERO_LENGTH

__all__ = [
    "PlaneLayout",
    "plane_layout",
    "per_plate",
    "inclined_increments",
    "increments_through",
    "planes_from_heights",
    "check_plane_gaps",
    "check_straight_creases",
    "STRAIGHT_CREASE",
]

#: A crease between two plates whose vertices lie within this fraction of its length of a
#: straight line has no plane to speak of: the mechanism mirrors the next plate in the plane
#: fitted to the crease, and round-off turns that plane by about 1e-16 over this fraction
#: (measured: a 10-plate ring misses its design by 2e-10 of its size at 9e-8, 3e-9 at 9e-9).
STRAIGHT_CREASE = 1e-7


@dataclass(frozen=True)
class PlaneLayout:
    """Crease planes of a multi-crease structure at the design state (leading local frame).

    Attributes
    ----------
    normals : (m + 1, 3) float
        Unit normals, ``normal[2] > 0``.
    offsets : (m + 1,) float
        ``normal . p = offset`` for points ``p`` on the plane.
    leading : int
        Index of the leading plane (``z = 0``).
    """

    normals: np.ndarray
    offsets: np.ndarray
    leading: int

    @property
    def plates(self) -> int:
        return len(self.offsets) - 1

    def height(self, k: int, xy: np.ndarray) -> np.ndarray:
        """``z`` of plane ``k`` above the points ``xy`` ``(..., 2)`` of the leading plane."""
        n = self.normals[k]
        return (self.offsets[k] - xy[..., 0] * n[0] - xy[..., 1] * n[1]) / n[2]

    def inclinations(self) -> np.ndarray:
        """(m, 2) angles (degrees) of plane ``k + 1`` against plane ``k``.

        Column 0: inclination about the actuation rotation axis (the profile ``x`` direction),
        the change of the plane's slope ``dz/dy`` as an angle, ``atan(delta(-n_y / n_z))``.
        Column 1: rotation perpendicular to it (about the profile ``y`` direction), the change
        of the angle ``atan2(-n_x, n_z)``, exact for radial layouts at any angle.
        """
        n = self.normals
        with np.errstate(divide="ignore", invalid="ignore"):
            slope_y = np.where(np.abs(n[:, 2]) > ZERO_LENGTH, -n[:, 1] / n[:, 2], 0.0)
        about_x = np.degrees(np.arctan(np.diff(slope_y)))
        about_y = np.degrees(np.diff(np.arctan2(-n[:, 0], n[:, 2])))
        return np.c_[about_x, about_y]


def per_plate(value, m: int, key: str) -> np.ndarray:
    """One value per plate from a number or a list of ``m`` numbers."""
    if value is None:
        raise DesignError("required for this layout type", key=key)
    if isinstance(value, (int, float)):
        return np.full(m, float(value))
    if len(value) != m:
        raise DesignError(f"needs one value per plate ({m}), got {len(value)}", key=key)
    return np.asarray(value, dtype=float)


def _leading_index(layout: dict, m: int) -> int:
    k0 = m // 2 if layout["leading"] is None else layout["leading"]
    if k0 >= m:
        raise DesignError(
            f"must be a plane with a plate on its positive side, 0 ... {m - 1}, got {k0}",
            key="layout.leading",
        )
    return k0


def _parallel(layout: dict, m: int, k0: int) -> PlaneLayout:
    spacing = per_plate(layout["spacing"], m, "layout.spacing")
    z = np.r_[0.0, np.cumsum(spacing)]
    normals = np.tile([0.0, 0.0, 1.0], (m + 1, 1))
    return PlaneLayout(normals, z - z[k0], k0)


def inclined_increments(layout: dict, local: np.ndarray, reference: int) -> np.ndarray:
    """(m, 3) affine height increments ``(c0, c1, c2)`` from plane ``k`` to plane ``k + 1``.

    Plane ``k + 1`` lies ``c0 + c1 x + c2 y`` above plane ``k`` (along the leading normal),
    through the given distances above the crease's start, reference and end vertex.
    """
    m = layout["plates"]
    apex = per_plate(layout["spacing"], m, "layout.spacing")
    start = apex
    if layout.get("spacing_start") is not None:
        start = per_plate(layout["spacing_start"], m, "layout.spacing_start")
    end = start
    if layout.get("spacing_end") is not None:
        end = per_plate(layout["spacing_end"], m, "layout.spacing_end")
    return increments_through(local, reference, np.c_[start, apex, end])


def increments_through(local: np.ndarray, reference: int, distances: np.ndarray) -> np.ndarray:
    """Affine heights ``(c0, c1, c2)`` ``(m, 3)`` through distances ``(m, 3)`` above the crease's
    start, reference and end vertex."""
    controls = local[[0, reference, -1]]
    design = np.c_[np.ones(3), controls]  # z = c0 + c1 x + c2 y through three points
    if abs(np.linalg.det(design)) < ZERO_LENGTH * float(np.ptp(local, axis=0).max()) ** 2:
        raise DesignError(
            "the crease's start, reference and end vertices are collinear, so distances at "
            "them do not define a plane; use layout type 'parallel' or move crease.reference",
            key="layout.type",
        )
    return np.linalg.solve(design, np.asarray(distances, dtype=float).T).T


def planes_from_heights(coeffs: np.ndarray, k0: int) -> PlaneLayout:
    """Planes ``z = c0 + c1 x + c2 y`` from ``(m + 1, 3)`` coefficients (plane ``k0``: z = 0)."""
    normals = np.c_[-coeffs[:, 1], -coeffs[:, 2], np.ones(len(coeffs))]
    scale = np.linalg.norm(normals, axis=1)
    return PlaneLayout(normals / scale[:, None], coeffs[:, 0] / scale, k0)


def check_plane_gaps(coeffs: np.ndarray, local: np.ndarray) -> None:
    """Refuse consecutive planes that meet above the crease."""
    heights = coeffs[:, :1] + coeffs[:, 1:] @ local.T  # (m + 1, n + 1)
    gaps = np.diff(heights, axis=0)
    bad = np.argwhere(gaps <= 0.0)
    if bad.size:
        k, i = (int(v) for v in bad[0])
        raise DesignError(
            f"crease planes {k} and {k + 1} cross at crease vertex {i} (distance "
            f"{gaps[k, i]:.6g} m): the distances at start, reference and end must keep the "
            "planes apart along the whole crease",
            key="layout.spacing_start",
        )


def _inclined(layout: dict, m: int, k0: int, local: np.ndarray, reference: int) -> PlaneLayout:
    increments = inclined_increments(layout, local, reference)
    coeffs = np.vstack([np.zeros(3), np.cumsum(increments, axis=0)])
    coeffs -= coeffs[k0]
    check_plane_gaps(coeffs, local)
    return planes_from_heights(coeffs, k0)


def _radial(layout: dict, m: int, k0: int, local: np.ndarray) -> PlaneLayout:
    angles = np.radians(per_plate(layout["angle"], m, "layout.angle"))
    if layout["axis"] is None:
        raise DesignError("required for layout type 'radial'", key="layout.axis")
    axis = float(layout["axis"])
    theta = np.r_[0.0, np.cumsum(angles)]
    theta -= theta[k0]
    if theta[-1] - theta[0] >= 2.0 * math.pi * (1.0 - EXACT_RELATIVE):
        given = layout["angle"]
        each = f"{given:g} deg" if isinstance(given, (int, float)) else "the given angles"
        raise DesignError(
            f"the planes turn by {math.degrees(theta[-1] - theta[0]):.6g} deg in total ({m} "
            f"plates x {each}); a radial layout is an open ring of less than 360 deg: a closed "
            "ring cannot deploy, because the angle between neighbouring planes changes along "
            "the deployment (docs/shape-control.md); use fewer plates or a smaller angle",
            key="layout.angle",
        )
    side = np.sign(local[:, 0] - axis)
    if np.any(side == 0.0) or np.any(side != side[0]):
        i = int(np.flatnonzero(side != side[0])[0]) if np.any(side != side[0]) else 0
        raise DesignError(
            f"the axis x = {axis:.6g} m must lie beside the crease, but crease vertex {i} is at "
            f"x = {local[i, 0]:.6g} m (the planes would cross the crease)",
            key="layout.axis",
        )
    # plane k contains the axis (x = axis, z = 0, any y) and is turned by theta_k about it,
    # so that the crease side (sign s of x - axis) moves towards +z
    s = side[0]
    normals = np.c_[-s * np.sin(theta), np.zeros(m + 1), np.cos(theta)]
    return PlaneLayout(normals, normals[:, 0] * axis, k0)


def plane_layout(layout: dict, local: np.ndarray, reference: int) -> PlaneLayout:
    """The crease planes of a validated ``[layout]`` table (types parallel, inclined, radial).

    Parameters
    ----------
    layout : dict
        The validated ``[layout]`` values.
    local : (n + 1, 2) float
        The leading crease in its plane's local coordinates.
    reference : int
        Reference crease vertex.

    Returns
    -------
    PlaneLayout

    Examples
    --------
    >>> import numpy as np
    >>> local = np.c_[np.linspace(-1, 1, 5), 1 - np.linspace(-1, 1, 5) ** 2]
    >>> lay = plane_layout(
    ...     {"type": "inclined", "plates": 2, "leading": 0, "spacing": 0.2,
    ...      "spacing_start": 0.1, "spacing_end": None},
    ...     local, 2)
    >>> np.round(lay.height(1, local[[0, 2, 4]]), 12)
    array([0.1, 0.2, 0.1])
    """
    m = layout["plates"]
    if m is None:
        raise DesignError(f"required for layout type '{layout['type']}'", key="layout.plates")
    k0 = _leading_index(layout, m)
    kind = layout["type"]
    if kind == "parallel":
        return _parallel(layout, m, k0)
    if kind == "inclined":
        return _inclined(layout, m, k0, local, reference)
    if kind == "radial":
        return _radial(layout, m, k0, local)
    raise DesignError(f"not a multi-crease layout: {kind!r}", key="layout.type")


def check_straight_creases(nears, fars, creases, plate_ids) -> None:
    """Refuse a multi-crease design with an (almost) straight crease between two plates.

    Parameters
    ----------
    nears, fars : (p, n + 1, 3) float
        The plates at the design state (mechanism order).
    creases : list of CreaseLink
        The creases; the fixed leading crease plane needs no fit and is not checked.
    plate_ids : list of int
        Output id of every mechanism plate.

    Raises
    ------
    DesignError
        Names the plates, the straightness and the key (``[crease]``).
    """
    for link in creases:
        if link.fixed:
            continue
        row = (nears if link.boundary_a == "near" else fars)[link.plate_a]
        centred = row - row.mean(axis=0)
        _, _, vt = np.linalg.svd(centred, full_matrices=True)
        along = centred @ vt[0]
        off = np.linalg.norm(centred - along[:, None] * vt[0], axis=1).max()
        length = float(np.ptp(along))
        if not off > STRAIGHT_CREASE * length:
            a, b = plate_ids[link.plate_a], plate_ids[link.plate_b]
            raise DesignError(
                f"the crease between plates {a} and {b} is straight to {off / length:.2g} of its "
                f"{length:.3g} m length at the design state (its vertices lie within "
                f"{off:.3g} m of a line, less than {STRAIGHT_CREASE:g} of it): the plane that "
                "holds it, in which the next plate is mirrored, is undetermined; curve the "
                "crease more (a larger rise) or use layout type 'single'",
                key="[crease]",
            )
