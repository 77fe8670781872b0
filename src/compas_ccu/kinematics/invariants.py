"""Invariant errors and validity of placed mechanism states (docs/kinematics.md, quality bars).

An exact deployment keeps every quad congruent to its cut pattern (isometry) and planar, the two
plates of a crease joined (hinge gap) and mirror images of each other across the crease plane
(mirror error); the leading crease stays in its plane. :func:`invariant_errors` measures all of
them on ``k`` placed states at once; :func:`overlapping_creases` finds creases that overlap
themselves in their plane (the plates would pass through each other).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from compas_ccu.geometry import dot, unit
from compas_ccu.kinematics.checks import planar_overlaps, self_intersecting, total_turning
from compas_ccu.kinematics.plates import boundary_rows
from compas_ccu.strips.intrinsics import quad_lengths

__all__ = [
    "InvariantErrors",
    "invariant_errors",
    "overlapping_creases",
    "crease_polylines",
    "bisection_tree",
    "overlap_limit",
    "OVERLAP_LEVELS",
    "INVARIANT_KEYS",
    "EXACT_KEYS",
]

#: The scalar invariant errors of a state, metres (each also reported relative to the size).
INVARIANT_KEYS = ("isometry", "quad_planarity", "hinge_gap", "mirror_error", "leading_in_plane")

#: The invariants that are exact (round-off) in every state of every design.
EXACT_KEYS = ("isometry", "quad_planarity", "hinge_gap", "mirror_error", "leading_in_plane")


@dataclass(frozen=True)
class InvariantErrors:
    """The invariant errors of ``k`` placed states, metres (:func:`invariant_errors`).

    Attributes
    ----------
    isometry : (k,) float
        The largest change of a quad side or diagonal length from the cut pattern.
    quad_planarity : (k,) float
        The largest distance of a quad's fourth corner from the plane of the other three.
    hinge_gap : (k,) float
        The largest distance between the two plates' vertices of a crease.
    mirror_error : (k,) float
        The largest distance between a ruling point of plate b reflected in the crease plane
        and plate a's ruling.
    leading_in_plane : (k,) float
        The largest distance of the leading crease from its plane.
    crease_planarity : (k, c) float
        Every crease's largest distance from its plane.

    Examples
    --------
    >>> import numpy as np
    >>> zeros, mirror = np.zeros(2), np.array([0.0, 3e-16])
    >>> errors = InvariantErrors(zeros, zeros, zeros, mirror, zeros, np.zeros((2, 1)))
    >>> errors.worst(EXACT_KEYS).tolist()
    [0.0, 3e-16]
    >>> sorted(errors.as_dict())[:2]
    ['crease_planarity', 'hinge_gap']
    """

    isometry: np.ndarray
    quad_planarity: np.ndarray
    hinge_gap: np.ndarray
    mirror_error: np.ndarray
    leading_in_plane: np.ndarray
    crease_planarity: np.ndarray

    def worst(self, names=INVARIANT_KEYS) -> np.ndarray:
        """(k,) float: the largest of the scalar errors ``names`` in each state."""
        return np.max([getattr(self, name) for name in names], axis=0)

    def as_dict(self) -> dict:
        """``{name: array}`` of every field (for JSON writers and tables)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


def invariant_errors(
    mechanism, states, reference_lengths: np.ndarray, *, frame=None
) -> InvariantErrors:
    """Invariant errors of ``k`` placed states, metres.

    Parameters
    ----------
    mechanism : compas_ccu.kinematics.mechanism.Mechanism
    states : compas_ccu.kinematics.mechanism.MechanismStates
        In the local frame of the leading crease plane.
    reference_lengths : (p, n, 6) float
        Side and diagonal lengths of every quad at the design state
        (:func:`compas_ccu.strips.intrinsics.quad_lengths`).
    frame : compas_ccu.geometry.PlaneFrame, optional
        Measure on the world coordinates of this frame (what files hold) instead of the local
        ones: far from the origin the world coordinates round coarser than the local ones.

    Returns
    -------
    InvariantErrors
        ``isometry`` (largest quad side / diagonal length change), ``quad_planarity``,
        ``hinge_gap``, ``mirror_error``, ``leading_in_plane``, each (k,), and
        ``crease_planarity`` (k, c).

    Examples
    --------
    The cone pair of ``examples/cone.toml`` keeps every invariant to round-off:

    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> states = model.mechanism.deploy(np.radians([20.0, 40.0]))
    >>> errors = invariant_errors(model.mechanism, states, model.reference_lengths)
    >>> errors.isometry.shape, errors.crease_planarity.shape
    ((2,), (2, 1))
    >>> all(float(np.max(e)) < 1e-12 for e in errors.as_dict().values())
    True
    """
    near, far = states.near, states.far
    origins, normals = states.plane_origins, states.plane_normals
    lead_origin, lead_normal = np.zeros(3), np.array([0.0, 0.0, 1.0])
    if frame is not None:
        near, far = frame.to_world(near), frame.to_world(far)
        origins, normals = frame.to_world(origins), frame.vector_to_world(normals)
        lead_origin, lead_normal = frame.origin, frame.axes[2]
    lengths = quad_lengths(near, far)
    isometry = np.abs(lengths - reference_lengths[None]).max(axis=(1, 2, 3))
    a, b, c, d = near[..., :-1, :], near[..., 1:, :], far[..., 1:, :], far[..., :-1, :]
    normal = unit(np.cross(b - a, d - a))
    planarity = np.abs(dot(c - a, normal)).max(axis=(1, 2))
    gaps, mirror, crease_planarity = [], [], []
    for ci, crease in enumerate(mechanism.creases):
        pa, pb = crease.plate_a, crease.plate_b
        hinge_a, other_a = boundary_rows(near[:, pa], far[:, pa], crease.boundary_a)
        away_a = other_a - hinge_a
        away_b = far[:, pb] - near[:, pb]
        gaps.append(np.linalg.norm(near[:, pb] - hinge_a, axis=-1).max(axis=1))
        crease_planarity.append(
            np.abs(dot(hinge_a - origins[:, ci, None], normals[:, ci, None])).max(axis=1)
        )
        # mirror symmetry: plate b's ruling points reflected in the crease plane land on
        # plate a's ruling lines (CCF: on their continuation)
        nrm = normals[:, ci]
        ta = np.linalg.norm(away_a, axis=-1)
        tb = np.linalg.norm(away_b, axis=-1)
        t = np.minimum(ta, tb)
        pa_pts = hinge_a + away_a * (t / ta)[..., None]
        pb_pts = near[:, pb] + away_b * (t / tb)[..., None]
        if crease.relation == "ccf":
            pb_pts = 2.0 * near[:, pb] - pb_pts
        origin = origins[:, ci]
        dist = np.einsum("kmi,ki->km", pb_pts - origin[:, None], nrm)
        reflected = pb_pts - 2.0 * dist[..., None] * nrm[:, None, :]
        mirror.append(np.linalg.norm(reflected - pa_pts, axis=-1).max(axis=1))
    zeros = np.zeros(near.shape[0])
    return InvariantErrors(
        isometry=isometry,
        quad_planarity=planarity,
        hinge_gap=np.max(gaps, axis=0) if gaps else zeros,
        mirror_error=np.max(mirror, axis=0) if mirror else zeros,
        leading_in_plane=np.abs(dot(near[:, 0] - lead_origin, lead_normal)).max(axis=1),
        crease_planarity=(
            np.stack(crease_planarity, axis=1).reshape(len(zeros), -1)
            if frame is not None and crease_planarity
            else states.planarity
        ),
    )


#: Bisection levels of :func:`overlap_limit` placed in one vectorised deploy (2 ** L - 1 states).
#: Since one state's redeploy costs ~0.18 ms on the vault (its work arrays kept), 1 level (41
#: states, each the one the bisection visits) is the quickest: 3 placed 92 states in 14 deploys of
#: ~1.4 ms. The angle is the same at any level.
OVERLAP_LEVELS = 1


def crease_polylines(mechanism, states):
    """The leading crease, then every crease, of placed ``states`` as polylines in their planes.

    Parameters
    ----------
    mechanism : compas_ccu.kinematics.mechanism.Mechanism
    states : compas_ccu.kinematics.mechanism.MechanismStates

    Returns
    -------
    hinges : (k, 1 + c, n + 1, 3) float
    origins, normals : (k, 1 + c, 3) float
        The crease planes.
    turning : (k, 1 + c) float
        Total absolute turning of every polyline (:func:`total_turning`), radians.
    """
    near, far = states.near, states.far
    k = near.shape[0]
    creases = mechanism.creases
    a = np.array([c.plate_a for c in creases], dtype=int)
    on_far = np.array([c.boundary_a == "far" for c in creases], dtype=bool)[:, None, None]
    hinges = np.concatenate(
        [near[:, :1], np.where(on_far, far[:, a], near[:, a])], axis=1
    )  # (k, 1 + c, n + 1, 3)
    z = np.zeros((k, 1, 3))
    z[..., 2] = 1.0
    origins = np.concatenate([np.zeros((k, 1, 3)), states.plane_origins], axis=1)
    normals = np.concatenate([z, states.plane_normals], axis=1)
    shape = hinges.shape
    turning = total_turning(hinges.reshape((-1,) + shape[2:])).reshape(shape[:2])
    return hinges, origins, normals, turning


def overlapping_creases(mechanism, states) -> np.ndarray:
    """(k, 1 + c) bool: the leading crease, then every crease, overlapping itself in its plane.

    The turning test that settles almost every crease (:func:`self_intersecting`) runs on all
    creases of all states in one vectorised pass; the few suspects are tested together in one
    vectorised GEOS call.

    Parameters
    ----------
    mechanism : compas_ccu.kinematics.mechanism.Mechanism
    states : compas_ccu.kinematics.mechanism.MechanismStates

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> mechanism = load_model("examples/cone.toml").mechanism
    >>> overlapping_creases(mechanism, mechanism.deploy(np.radians([20.0, 40.0]))).tolist()
    [[False, False], [False, False]]
    """
    hinges, origins, normals, turning = crease_polylines(mechanism, states)
    out = np.zeros(turning.shape, dtype=bool)
    kk, ci = np.nonzero(turning > np.pi)
    if kk.size:
        out[kk, ci] = self_intersecting(hinges[kk, ci], origins[kk, ci], normals[kk, ci])
    return out


def bisection_tree(lo: float, hi: float, levels: int) -> np.ndarray:
    """(2 ** levels - 1,) float: every midpoint ``levels`` bisections of ``[lo, hi]`` can
    visit, in heap order (node ``i`` halves an interval; its children ``2 i + 1`` and
    ``2 i + 2`` halve the lower and upper half), computed as a sequential bisection would
    (``0.5 * (lo + hi)``), so a walk down the tree visits the same angles, bit for bit.

    >>> bisection_tree(0.0, 1.0, 2).tolist()
    [0.5, 0.25, 0.75]
    """
    nodes = np.empty(2**levels - 1)
    bounds = [(lo, hi)]
    for i in range(len(nodes)):
        a, b = bounds[i]
        mid = 0.5 * (a + b)
        nodes[i] = mid
        bounds += [(a, mid), (mid, b)]
    return nodes


def overlap_limit(mechanism, *, bisections: int = 40, levels: int = OVERLAP_LEVELS) -> float:
    """Largest reference alpha (radians) before a crease overlaps itself, or the limit.

    The ``bisections`` bisections on :func:`overlapping_creases` between the flat stack and the
    deployment limit, ``levels`` at a time: every angle those levels can visit
    (:func:`bisection_tree`) is placed in one vectorised deploy and turning test (one state at
    a time by default: :data:`OVERLAP_LEVELS`); the walk down the tree then tests only the
    suspect states it visits with GEOS: the crease found overlapping last first and alone (on
    the vault every crease overlaps at once, so one polyline instead of ten), then the other
    suspects in one call. The result is the sequential bisection's, to within
    ``alpha_limit / 2 ** bisections``, and never above it: every angle returned was tested clear.

    Examples
    --------
    The crease of ``examples/cone.toml`` (a 90 degree arc in the pattern) winds further as the
    cone deploys, until it overlaps itself:

    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> mechanism = load_model("examples/cone.toml").mechanism
    >>> round(float(np.degrees(overlap_limit(mechanism))), 4)
    75.5126
    """
    limit = mechanism.alpha_limit
    if not overlapping_creases(mechanism, mechanism.deploy(limit)).any():
        return limit
    lo, hi = 0.0, limit
    done = 0
    culprit = -1  # the crease found overlapping last: tested first, alone
    while done < bisections:
        depth = min(levels, bisections - done)
        nodes = bisection_tree(lo, hi, depth)
        hinges, origins, normals, turning = crease_polylines(mechanism, mechanism.deploy(nodes))
        i = 0
        for _ in range(depth):
            found = _overlapping(hinges[i], origins[i], normals[i], turning[i], culprit)
            if found >= 0:
                culprit, hi, i = found, nodes[i], 2 * i + 1
            else:
                lo, i = nodes[i], 2 * i + 2
        done += depth
    return float(lo)


def _overlapping(hinges, origins, normals, turning, first) -> int:
    """A crease of one state (``hinges`` (1 + c, n + 1, 3) and their planes, ``turning``
    (1 + c,)) that overlaps itself, or -1 if none does: the creases that turn by more than pi,
    crease ``first`` alone before the others (it is the likeliest: the last one found)."""
    suspects = np.flatnonzero(turning > np.pi)
    if first >= 0 and turning[first] > np.pi:
        if planar_overlaps(
            hinges[first : first + 1], origins[first : first + 1], normals[first : first + 1]
        )[0]:
            return first
        suspects = suspects[suspects != first]
    if not suspects.size:
        return -1
    found = planar_overlaps(hinges[suspects], origins[suspects], normals[suspects])
    return int(suspects[np.argmax(found)]) if found.any() else -1
