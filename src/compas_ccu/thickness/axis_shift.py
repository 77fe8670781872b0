"""Plate thickness by the axis-shift approach (Shimoda, Tachi & Sato 2020; paper §5.3, Fig. 8c).

Every plate is a solid of uniform thickness ``t`` around its **mid-surface**, the neutral fibre
(ε₀ = 0), which is the planar-quad strip of the zero-thickness kinematics: it stays an exact
isometry of the plate's cut pattern. The faces at ``±t/2`` are exact face offsets of the planar
quads: at ruling ``j`` the offset vector is

    ν_j = (n_{j-1} + n_j) / (1 + n_{j-1} · n_j)          (ν_0 = n_0, ν_n = n_{n-1})

with ``n`` the unit quad normals, so ``mid ± (t/2) ν`` lies on both neighbouring offset planes
and the offset faces are planar-quad strips with the same rulings.

**Axis shift.** The hinge of a crease does not lie on the mid-surfaces but on the two faces that
face each other (the *facing faces*): plate a's face towards plate b and plate b's face towards
plate a. Plate b's mid-surface is the mirror image of plate a's mid-surface across the **hinge
plane** P, the plane of the hinge curve on plate a's facing face. Mirror images share every point
of P, so the facing faces meet exactly along the hinge and the two solids lie on opposite sides
of it: the structure folds completely closed at α = 0 (every plate on top of its neighbour, a
stack of height Σt) and opens along the one-degree-of-freedom path of the leading strip.

**Offset crease planarity (paper §5.3).** The facing face's crease, ``m + σ (t/2) ν`` (``m`` the
mid-surface crease, ``σ = ±1`` the side towards the partner), lies at distance
``(t/2) ν·B ≈ (t/2) cos α`` from the mid crease's plane. It is planar exactly when α is constant
along the crease, i.e. for rulings orthogonal to the crease (the ultra-special case); otherwise
the paper corrects it by *intersecting the rulings with an offset plane by cos_mean*: P is the
mid crease's plane (the fixed leading plane O for the leading crease, else its least-squares
plane) moved by the mean offset, the facing face's rulings are intersected with P, and the solid's
crease edge is moved along its rulings by that distance (the *correction*, reported per crease).
The solids are fabricated with the correction of the design state; at other states the remaining
difference is reported as the hinge gap.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.errors import GeometryError
from compas_ccu.geometry import cross3, dot, unit, unit3
from compas_ccu.kinematics.mechanism import CreasePlanes, Mechanism, MechanismStates
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "vertex_offsets",
    "crease_sides",
    "ThickStates",
    "HingePlanes",
    "place_thick",
    "solid_faces",
    "offset_faces",
]


def quad_normals(near: np.ndarray, far: np.ndarray) -> np.ndarray:
    """(..., n, 3) unit normals of the quads of planar-quad strips.

    Oriented as ``(far_{j+1} - near_j) x (far_j - near_{j+1})`` (the orientation of
    :func:`compas_ccu.strips.curvature.plate_curvature`).
    """
    a, b, c, d = near[..., :-1, :], near[..., 1:, :], far[..., 1:, :], far[..., :-1, :]
    return unit3(cross3(c - a, d - b))


def vertex_offsets(near: np.ndarray, far: np.ndarray) -> np.ndarray:
    """Exact face-offset vectors ν of planar-quad strips, one per ruling.

    Parameters
    ----------
    near, far : (..., n + 1, 3) float
        The two boundaries; ruling ``j`` joins ``near[j]`` and ``far[j]``.

    Returns
    -------
    (..., n + 1, 3) float
        ``ν_j``, perpendicular to ruling ``j``: ``x + d ν_j`` lies at distance ``d`` from the
        planes of both quads next to the ruling for every point ``x`` of the ruling line.

    Examples
    --------
    >>> import numpy as np
    >>> near = np.array([[1.0, 0, 0], [0, 1.0, 0], [-1.0, 0, 0]])   # a roof of two quads
    >>> far = near + [0.0, 0.0, 1.0]
    >>> nu = vertex_offsets(near, far)
    >>> np.round(np.abs(nu[1]), 6).tolist()   # |ν| = 1 / cos(45°) at the 90° ridge
    [0.0, 1.414214, 0.0]
    """
    normals = quad_normals(near, far)
    if normals.shape[-2] == 1:
        return np.concatenate([normals, normals], axis=-2)
    ruling = unit3(far - near)
    n0, n1 = normals[..., :-1, :], normals[..., 1:, :]
    interior = (n0 + n1) / (1.0 + dot(n0, n1))[..., None]
    # end rulings: continue the strip past its end with the fold angle of the neighbouring
    # ruling (exact for the uniform cone, so its offset creases stay planar to round-off)
    fold = np.arctan2(dot(cross3(n0, n1), ruling[..., 1:-1, :]), dot(n0, n1))
    ends = []
    for quad, r, angle in (
        (normals[..., 0, :], ruling[..., 0, :], -fold[..., 0]),
        (normals[..., -1, :], ruling[..., -1, :], fold[..., -1]),
    ):
        beyond = quad * np.cos(angle)[..., None] + cross3(r, quad) * np.sin(angle)[..., None]
        ends.append(((quad + beyond) / (1.0 + np.cos(angle))[..., None])[..., None, :])
    return np.concatenate([ends[0], interior, ends[1]], axis=-2)


def crease_sides(mechanism: Mechanism, probe: MechanismStates) -> np.ndarray:
    """(c, 2) sides σ of plates a and b at every crease: the facing face is ``mid + σ t/2 ν``.

    Measured on a deployed zero-thickness state (the sides do not change along the path): plate
    a's facing side is the one towards plate b's rulings, ``σ_a = sign(ν_a · r_b)``; plate b's is
    the mirror image of plate a's.

    Raises
    ------
    GeometryError
        A crease that is not a CCU (mirror) crease, or a probe state that is not deployed.
    """
    near, far = probe.near, probe.far
    sides = np.zeros((len(mechanism.creases), 2))
    for ci, crease in enumerate(mechanism.creases):
        if crease.relation != "ccu":
            raise GeometryError(
                f"crease {ci} is a curved-crease-folding (CCF) continuation: the axis-shift "
                "thickness model of CCU (paper Fig. 8c) needs mirror (CCU) creases only"
            )
        nu_a = vertex_offsets(near[:, crease.plate_a], far[:, crease.plate_a])
        away_b = unit(far[:, crease.plate_b] - near[:, crease.plate_b])
        nu_b = vertex_offsets(near[:, crease.plate_b], far[:, crease.plate_b])
        towards = dot(nu_a, away_b)[0]
        sa = np.sign(np.sum(towards))
        if sa == 0.0:
            raise GeometryError(f"crease {ci}: the probe state is flat, its sides are undefined")
        facing_a = sa * nu_a[0]
        normal = probe.plane_normals[0, ci]
        mirrored = facing_a - 2.0 * dot(facing_a, normal)[:, None] * normal
        sb = np.sign(np.sum(dot(nu_b[0], mirrored)))
        sides[ci] = sa, sb
    return sides


class ThickStates(NamedTuple):
    """Placed thick plates for ``k`` states, local frame of the leading crease plane.

    Attributes
    ----------
    near, far : (k, p, n + 1, 3) float
        Mid-surface boundaries (exact isometries of the cut patterns).
    offsets : (k, p, n + 1, 3) float
        Face-offset vectors ν of every ruling.
    hinge_origins, hinge_normals : (k, c, 3) float
        Hinge planes P.
    offset_planarity : (k, c) float
        Largest distance of the uncorrected offset crease ``m + σ t/2 ν`` from P, m.
    corrections : (k, c, n + 1) float
        Distance along the rulings from the uncorrected offset crease to P (the paper's
        correction), m, signed along the ruling of plate a away from the crease.
    mid_planarity : (k, c) float
        Largest distance of the mid-surface crease of plate a from its fitted plane.
    tilts : (k, n) float
    """

    near: np.ndarray
    far: np.ndarray
    offsets: np.ndarray
    hinge_origins: np.ndarray
    hinge_normals: np.ndarray
    offset_planarity: np.ndarray
    corrections: np.ndarray
    mid_planarity: np.ndarray
    tilts: np.ndarray


class HingePlanes(CreasePlanes):
    """The crease-plane strategy of thick plates: mirror across the hinge plane P.

    For :meth:`Mechanism.place <compas_ccu.kinematics.mechanism.Mechanism.place>`: the plane of
    a crease is the hinge plane P of its facing face (module docstring), and a child plate's
    crease row is the mirror image of its parent's mid-surface row. While placing, it records per
    crease the mid-surface planarity, the offset-crease planarity and the corrections.

    Parameters
    ----------
    thickness : float
        Plate thickness t, m.
    sides : (c, 2) float
        From :func:`crease_sides`.
    """

    mirror_rows = True

    def __init__(self, thickness: float, sides: np.ndarray):
        self.half = 0.5 * float(thickness)
        self.sides = np.asarray(sides, dtype=float)
        self.mid_planarity = None
        self.offset_planarity = None
        self.corrections = None
        self.offsets = {}

    def begin(self, states: int, creases: int, vertices: int) -> None:
        self.mid_planarity = np.zeros((states, creases))
        self.offset_planarity = np.zeros((states, creases))
        self.corrections = np.zeros((states, creases, vertices))
        self.offsets = {}  # plate -> its face offsets (k, n + 1, 3), once placed

    def planes(self, mechanism: Mechanism, creases: np.ndarray, near: np.ndarray, far: np.ndarray):
        """Hinge planes P of ``creases`` (g,): origins, normals (k, g, 3) and the largest
        distance (k, g) of the uncorrected offset creases from them (see
        :meth:`CreasePlanes.planes <compas_ccu.kinematics.mechanism.CreasePlanes.planes>`)."""
        creases = np.asarray(creases, dtype=np.intp)
        row, other = mechanism.crease_boundaries(creases, near, far)  # (k, g, n + 1, 3)
        away = unit3(other - row)
        a = mechanism.crease_plate_a[creases]
        side = self.sides[creases, 0] * self.half  # (g,)
        offsets = vertex_offsets(near[:, a], far[:, a])
        self.offsets.update((int(plate), offsets[:, i]) for i, plate in enumerate(a))
        facing = row + side[None, :, None, None] * offsets
        origin, normal, self.mid_planarity[:, creases] = super().planes(
            mechanism, creases, near, far
        )
        # the offset plane by the mean offset (paper: "offset plane by cos_mean")
        shift = dot(facing - origin[:, :, None], normal[:, :, None]).mean(axis=-1)
        origin = origin + shift[..., None] * normal
        dist = dot(facing - origin[:, :, None], normal[:, :, None])
        self.offset_planarity[:, creases] = np.abs(dist).max(axis=-1)
        slope = dot(away, normal[:, :, None])
        with np.errstate(divide="ignore", invalid="ignore"):
            along = -dist / slope
        # rulings in the plane (the flat stack): the offset crease lies in P, nothing to correct
        self.corrections[:, creases] = np.where(np.abs(slope) > EXACT_RELATIVE, along, 0.0)
        return origin, normal, self.offset_planarity[:, creases]


def place_thick(mechanism: Mechanism, s0, thickness: float, sides: np.ndarray) -> ThickStates:
    """Place the thick plates of ``mechanism`` for values of its degree of freedom ``s0``.

    The leading plate follows the exact closed form (its mid crease stays in O); every other
    plate is the mirror image of its parent's mid-surface ruling lines across the hinge plane of
    the shared crease (module docstring, :class:`HingePlanes`), with the ruling lengths of its
    own cut pattern.

    Parameters
    ----------
    mechanism : Mechanism
    s0 : float or (k,) float
        Degree of freedom (see :class:`compas_ccu.kinematics.leading.LeadingStrip`).
    thickness : float
        Plate thickness t, m.
    sides : (c, 2) float
        From :func:`crease_sides`.

    Returns
    -------
    ThickStates
    """
    planes = HingePlanes(thickness, sides)
    st = mechanism.place(s0, planes=planes)
    return ThickStates(
        st.near,
        st.far,
        _all_offsets(st.near, st.far, planes.offsets),
        st.plane_origins,
        st.plane_normals,
        planes.offset_planarity,
        planes.corrections,
        planes.mid_planarity,
        st.tilts,
    )


def _all_offsets(near: np.ndarray, far: np.ndarray, known: dict) -> np.ndarray:
    """:func:`vertex_offsets` (k, p, n + 1, 3) of every plate, those of the plates in ``known``
    (the parents of creases, computed while placing: the same operations on the same rows,
    the same values) taken from there."""
    offsets = np.empty(near.shape)
    rest = [plate for plate in range(near.shape[1]) if plate not in known]
    if rest:
        offsets[:, rest] = vertex_offsets(near[:, rest], far[:, rest])
    for plate, value in known.items():
        offsets[:, plate] = value
    return offsets


def solid_faces(
    near: np.ndarray,
    far: np.ndarray,
    offsets: np.ndarray,
    thickness: float,
    shifts_near: np.ndarray,
    shifts_far: np.ndarray,
) -> np.ndarray:
    """Lower and upper face vertices of thick plates.

    Parameters
    ----------
    near, far, offsets : (..., n + 1, 3) float
        Mid-surface boundaries and face-offset vectors.
    thickness : float
    shifts_near, shifts_far : (..., n + 1) float
        Distance by which each boundary's edge moves along its ruling, into the plate (the
        crease corrections; 0 at free boundaries).

    Returns
    -------
    (..., 2, 2n + 2, 3) float
        ``[..., 0]`` the face at ``-t/2 ν`` ("lower"), ``[..., 1]`` at ``+t/2 ν`` ("upper"), in
        the plate vertex order (near row, then far row).
    """
    ruling = unit3(far - near)
    mid_near = near + shifts_near[..., None] * ruling
    mid_far = far - shifts_far[..., None] * ruling
    return offset_faces(mid_near, mid_far, offsets, thickness)


def offset_faces(
    mid_near: np.ndarray, mid_far: np.ndarray, offsets: np.ndarray, thickness: float
) -> np.ndarray:
    """Lower and upper face vertices (..., 2, 2n + 2, 3) of thick plates from their mid-surface
    boundaries with the crease corrections (..., n + 1, 3) and face offsets: the mid-surface
    vertices ``∓ t/2 ν`` (:func:`solid_faces`), written in place."""
    m = mid_near.shape[-2]
    step = (0.5 * thickness) * offsets
    out = np.empty((*np.broadcast_shapes(mid_near.shape, offsets.shape)[:-2], 2, 2 * m, 3))
    np.subtract(mid_near, step, out=out[..., 0, :m, :])
    np.subtract(mid_far, step, out=out[..., 0, m:, :])
    np.add(mid_near, step, out=out[..., 1, :m, :])
    np.add(mid_far, step, out=out[..., 1, m:, :])
    return out
