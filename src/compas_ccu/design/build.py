"""Build the design-state geometry and the mechanism of a validated design.

Everything here works in the local frame of the leading crease plane (see
:mod:`compas_ccu.kinematics.leading`): crease in ``z = 0``, leading plate on the left of the
crease, rising towards ``+z``. A plate on the right of the profile is handled by mirroring the
profile's y coordinate (``flip = -1``) in and out of the local frame.

Multi-crease construction (docs/kinematics.md, paper §5.1): the rulings of a plate are trimmed at
the next crease plane, and the next plate is the mirror image of those ruling lines across that
plane, trimmed at the plane after it. At the design state every crease is planar by construction.

Layout ``patterns`` (:mod:`compas_ccu.design.patterns`) gives every plate by its cut pattern:
the mechanism attaches them as above, and the design state is the flat-folded stack it places.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.curves import profile_from_dict
from compas_ccu.design.crease_rulings import (
    check_crease,
    check_ruling_sides,
    design_rulings,
    explicit_side,
    pattern_rulings,
    side_flip,
)
from compas_ccu.design.layouts import (
    PlaneLayout,
    check_plane_gaps,
    check_straight_creases,
    inclined_increments,
    plane_layout,
    planes_from_heights,
)
from compas_ccu.design.patterns import check_patterns, pattern_chain
from compas_ccu.design.targets import TargetFit, solve_plane, targets_from_values
from compas_ccu.errors import DesignError, GeometryError, ProfileError
from compas_ccu.geometry import reflect
from compas_ccu.kinematics.leading import LeadingStrip
from compas_ccu.kinematics.mechanism import CreaseLink, Mechanism, PlateLink
from compas_ccu.strips.frames import crease_frames
from compas_ccu.strips.intrinsics import strip_intrinsics

__all__ = ["DesignGeometry", "build", "PROFILE_KEYS"]

#: [crease] keys passed to the profile factory.
PROFILE_KEYS = (
    "profile",
    "span",
    "rise",
    "radius",
    "angle",
    "points",
    "point_loads",
    "distributed_loads",
)


@dataclass
class DesignGeometry:
    """The geometry of a design at its design state, and the mechanism that deploys it.

    Attributes
    ----------
    mechanism : Mechanism
    plate_ids : list of int
        Output id of mechanism plate ``i``.
    design_near, design_far : (p, n + 1, 3) float
        Plates at the design state (local frame, mechanism order): the 3D target for
        ``state = "deployed"``, the cut pattern for ``state = "flat"``. They are the reference of
        the isometry check and independent of the kinematics.
    design_alpha : float
        Radians.
    reference : int
        Reference crease vertex.
    flip : float
        +1 if the leading plate lies left of the profile, -1 if right.
    profile_points : (n + 1, 2) float
        The sampled profile in plane coordinates.
    state : str
        ``"deployed"`` or ``"flat"``.
    planes : PlaneLayout or None
        Crease planes of a multi-crease layout (local frame, design state).
    target_fit : TargetFit or None
        The planes solved for ``[target]`` curves and the remaining fit error.
    kinks : tuple of int
        Crease vertices at a kink of the profile (a funicular's point loads: the slope jumps
        there), in profile order; empty for smooth profiles.
    """

    mechanism: Mechanism
    plate_ids: list
    design_near: np.ndarray
    design_far: np.ndarray
    design_alpha: float
    reference: int
    flip: float
    profile_points: np.ndarray
    state: str
    planes: PlaneLayout | None = None
    target_fit: TargetFit | None = None
    kinks: tuple = ()


def _trim(near, direction, normal, offset, plane: int, plate: int):
    """Ruling points where the lines ``near + t direction`` meet crease plane ``plane``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (offset - near @ normal) / (direction @ normal)
    bad = np.flatnonzero(~np.isfinite(t) | (t <= 0.0))
    if bad.size:
        raise DesignError(
            f"the rulings of plate {plate} do not reach crease plane {plane} at crease vertex "
            f"{int(bad[0])} (they run parallel to it or away from it)",
            key="layout",
        )
    return near + t[:, None] * direction


def _reflect_z(v: np.ndarray) -> np.ndarray:
    return v * np.array([1.0, 1.0, -1.0])


def build(design) -> DesignGeometry:
    """Build the design state and the mechanism of a validated design.

    Parameters
    ----------
    design : compas_ccu.design.Design
        A validated design (its schema rules, :data:`compas_ccu.design.rules.RULES`, hold).

    Raises
    ------
    DesignError
        The profile cannot be built, the rulings do not point into the plate, a layout is
        impossible for this crease (the message names the key).
    """
    crease, rulings, layout = design.crease, design.rulings, design.layout
    spec = {k: getattr(crease, k) for k in PROFILE_KEYS if getattr(crease, k) is not None}
    n = crease.segments
    try:
        profile = profile_from_dict(spec)
        if crease.profile == "polyline" and len(crease.points) == n + 1:
            points = np.asarray(crease.points, dtype=float)  # the vertices as given
        else:
            points = np.asarray(profile.sample(n), dtype=float)
        kinks = _kink_vertices(profile, n) if len(points) == n + 1 else ()
    except ProfileError as exc:
        raise DesignError(str(exc), key="[crease]") from exc
    except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
        # the profile solvers (elliptic integrals, root finding, eigenvalues) fail only for
        # extreme values; say which section, not the solver's words alone
        raise DesignError(
            f"the {crease.profile} profile cannot be computed for these values ({exc})",
            key="[crease]",
        ) from exc
    check_crease(points)
    reference = int(round(crease.reference * n))
    state = crease.state
    if rulings.type == "explicit":
        flip = explicit_side(rulings, points)
    else:
        flip = side_flip(points, rulings.side, reference)
    local = points * np.array([1.0, flip])
    alpha = math.radians(design.alpha)
    near0 = np.c_[local, np.zeros(len(local))]

    planes, fit = None, None
    if layout.type == "single":
        if rulings.type == "explicit":
            ends = np.asarray(rulings.points) * np.array([1.0, flip])
            width = np.linalg.norm(ends - local, axis=1)[:, None]
            r = pattern_rulings(rulings, local, flip)
        elif state == "deployed":
            width = layout.width
            r = design_rulings(rulings, local, alpha, reference, flip)
        else:
            width = layout.width
            r = pattern_rulings(rulings, local, flip)
        deployed = state == "deployed" and rulings.type != "explicit"
        check_ruling_sides(rulings, local, r, "deployed" if deployed else "flat")
        ccf_width = layout.ccf_width or width
        nears = [near0, near0]
        fars = [near0 + width * r, _reflect_z(near0 + width * r)]
        links = [(None, "near", "ccu", None), (0, "near", "ccu", 0)]
        creases = [CreaseLink(0, "near", 1, "ccu", True, (0.0, 0.0, 1.0))]
        if layout.quadrants:
            cont = -_reflect_z(r)  # collinear with the leading rulings in the pattern
            nears += [near0, near0]
            fars += [near0 + ccf_width * cont, _reflect_z(near0 + ccf_width * cont)]
            links += [(0, "near", "ccf", 1), (2, "near", "ccu", 2)]
            creases += [
                CreaseLink(0, "near", 2, "ccf", True, (0.0, 0.0, 1.0)),
                CreaseLink(2, "near", 3, "ccu", True, (0.0, 0.0, 1.0)),
                CreaseLink(1, "near", 3, "ccf", True, (0.0, 0.0, 1.0)),
            ]
        plate_ids = list(range(len(nears)))
    elif layout.type == "patterns":
        ends = np.asarray(rulings.points) * np.array([1.0, flip])
        far0 = near0 + np.linalg.norm(ends - local, axis=1)[:, None] * pattern_rulings(
            rulings, local, flip
        )
        chain = pattern_chain(layout.patterns, near0, far0, layout.leading)
        nears, fars, links, creases, plate_ids = chain
    else:
        layout_values = layout.to_dict()
        r = design_rulings(rulings, local, alpha, reference, flip)
        check_ruling_sides(rulings, local, r, "deployed")
        targets = targets_from_values(design.target.to_dict(), flip=flip)
        if targets:
            chain, planes, fit = _fit_targets(layout_values, targets, local, reference, near0, r)
        else:
            planes = plane_layout(layout_values, local, reference)
            chain = _plate_chain(
                near0,
                r,
                planes.plates,
                planes.leading,
                lambda q, near, direction: (planes.normals[q], planes.offsets[q]),
            )
        nears, fars, links, creases, plate_ids = chain
        check_straight_creases(np.asarray(nears), np.asarray(fars), creases, plate_ids)

    design_near = np.asarray(nears)
    design_far = np.asarray(fars)
    intrinsics = [strip_intrinsics(a, b) for a, b in zip(design_near, design_far)]
    anchor_angle = math.atan2(*crease_frames(local).tangents[reference][::-1])
    leading = LeadingStrip(
        intrinsics[0],
        reference=reference,
        anchor_point=local[reference],
        anchor_angle=anchor_angle,
    )
    plates = [
        PlateLink(intr, parent=p, boundary=b, relation=rel, crease=c)
        for intr, (p, b, rel, c) in zip(intrinsics, links)
    ]
    mechanism = Mechanism(leading, plates, creases)
    if layout.type == "patterns":
        # the design state is the flat-folded stack the mechanism places (every plate's
        # pattern checked against the plate attached)
        st = mechanism.place(0.0)
        check_patterns(chain, st.near[0], st.far[0])
        design_near, design_far = st.near[0], st.far[0]
    if state == "deployed" and alpha > mechanism.alpha_limit:  # pragma: no cover - guard
        raise GeometryError("design alpha beyond the deployment limit of its own pattern")
    return DesignGeometry(
        mechanism,
        plate_ids,
        design_near,
        design_far,
        alpha,
        reference,
        flip,
        points,
        state,
        planes,
        fit,
        kinks,
    )


def _kink_vertices(profile, n: int) -> tuple:
    """The crease vertices on a kink of ``profile`` (its ``kinks``: arc lengths, which
    ``sample_s`` puts on samples exactly), ends excluded."""
    at = getattr(profile, "kinks", None)
    if at is None or not len(at):
        return ()
    s = np.asarray(profile.sample_s(n), dtype=float)
    found = {int(np.argmin(np.abs(s - k))) for k in np.asarray(at, dtype=float)}
    return tuple(sorted(i for i in found if 0 < i < n))


def _plate_chain(near0, r, m: int, k0: int, plane_at):
    """Trim-and-reflect construction of ``m`` plates from the leading plate (docs/kinematics.md).

    ``plane_at(q, near, direction)`` returns the unit normal and offset of crease plane ``q``
    when the ruling lines ``near + t direction`` of the plate that reaches it are known
    (planes ``k0 + 1 .. m``, then ``k0 - 1 .. 0``).

    Returns nears, fars, links, creases, plate_ids (mechanism order).
    """
    nears, fars, links, creases, plate_ids = [], [], [], [], []
    # the leading plate and the plates after it
    near, direction = near0, r
    parent, crease_index = None, None
    for k in range(k0, m):
        normal, offset = plane_at(k + 1, near, direction)
        far = _trim(near, direction, normal, offset, k + 1, k)
        nears.append(near)
        fars.append(far)
        plate_ids.append(k)
        links.append((parent, "far", "ccu", crease_index))
        if k + 1 < m:
            creases.append(
                CreaseLink(len(nears) - 1, "far", len(nears), "ccu", False, tuple(normal))
            )
            crease_index = len(creases) - 1
            parent = len(nears) - 1
            # the ruling lines themselves, mirrored: not the direction of far - near, which
            # round-off spoils where the planes almost meet (a ruling of 1e-9 m)
            direction = reflect(-direction, normal)
            near = far
    # the plates before the leading plane, mirrored across it
    parent, boundary = 0, "near"
    near, direction = near0, _reflect_z(r)
    upper = np.array([0.0, 0.0, 1.0])
    for k in range(k0 - 1, -1, -1):
        creases.append(CreaseLink(parent, boundary, len(nears), "ccu", k == k0 - 1, tuple(upper)))
        normal, offset = plane_at(k, near, direction)
        far = _trim(near, direction, normal, offset, k, k)
        nears.append(near)
        fars.append(far)
        plate_ids.append(k)
        links.append((parent, boundary, "ccu", len(creases) - 1))
        parent, boundary = len(nears) - 1, "far"
        direction = reflect(-direction, normal)
        near, upper = far, normal
    return nears, fars, links, creases, plate_ids


def _fit_targets(layout, targets, local, reference, near0, r):
    """Build the plate chain with the planes of the leading crease's parity solved for targets."""
    m = layout["plates"]
    if m is None:
        raise DesignError(f"required for layout type '{layout['type']}'", key="layout.plates")
    k0 = m // 2 if layout["leading"] is None else layout["leading"]
    if k0 >= m:
        raise DesignError(
            f"must be a plane with a plate on its positive side, 0 ... {m - 1}, got {k0}",
            key="layout.leading",
        )
    increments = inclined_increments(layout, local, reference)
    heights = np.full((m + 1, 3), np.nan)
    heights[k0] = 0.0
    controls = (0, reference, len(local) - 1)
    fit = TargetFit()

    def plane_at(q, near, direction):
        base = heights[q - 1] + increments[q - 1] if q > k0 else heights[q + 1] - increments[q]
        if (q - k0) % 2 == 0:
            heights[q], residual = solve_plane(near, direction, controls, targets, base)
            fit.planes.append(q)
            fit.residuals[q] = residual
        else:
            heights[q] = base
        normal = np.array([-heights[q, 1], -heights[q, 2], 1.0])
        scale = float(np.linalg.norm(normal))
        return normal / scale, heights[q, 0] / scale

    chain = _plate_chain(near0, r, m, k0, plane_at)
    check_plane_gaps(heights, local)
    fit.planes.sort()
    increments = np.diff(heights, axis=0)
    fit.distances = increments[:, :1] + increments[:, 1:] @ local[list(controls)].T
    return chain, planes_from_heights(heights, k0), fit
