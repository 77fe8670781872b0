"""The leading crease and its rulings at the design state: checks of the sampled crease, the side
the leading plate lies on, and the ruling directions of every ruling type (3D at the deployed
design state, 2D in the cut pattern). Local frame of the leading crease plane, plate on the left
(docs/geometry.md §2)."""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.errors import DesignError
from compas_ccu.strips import rulings as ruling_fields
from compas_ccu.strips.frames import crease_frames
from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE, ZERO_ANGLE, ZERO_LENGTH

__all__ = [
    "check_crease",
    "side_flip",
    "explicit_side",
    "design_rulings",
    "pattern_rulings",
    "check_ruling_sides",
]

#: The key of a design file that sets the rulings of each ruling type.
RULING_KEYS = {
    "orthogonal": "rulings.type",
    "cylindrical": "rulings.direction",
    "conical": "rulings.apex",
    "angle": "rulings.gamma",
    "explicit": "rulings.points",
}


def check_crease(points: np.ndarray) -> None:
    """Refuse a sampled crease that is not finite, doubles back on itself or is closed."""
    if not np.all(np.isfinite(points)):
        i = int(np.flatnonzero(~np.isfinite(points).all(axis=1))[0])
        raise DesignError(
            f"the profile cannot be computed for these values: crease vertex {i} is "
            f"{points[i].tolist()}",
            key="[crease]",
        )
    edges = np.diff(points, axis=0)
    lengths = np.linalg.norm(edges, axis=1)
    total = float(lengths.sum())
    if np.any(lengths <= ZERO_LENGTH * total):
        i = int(np.flatnonzero(lengths <= ZERO_LENGTH * total)[0])
        raise DesignError(f"crease vertices {i} and {i + 1} coincide", key="[crease]")
    u = edges / lengths[:, None]
    back = np.einsum("ij,ij->i", u[:-1], u[1:]) <= -1.0 + EXACT_RELATIVE
    if back.any():
        i = int(np.flatnonzero(back)[0]) + 1
        raise DesignError(
            f"the crease doubles back on itself at vertex {i} (a 180 deg turn): a crease "
            "must run forward",
            key="[crease]",
        )
    if np.linalg.norm(points[-1] - points[0]) <= EXACT_RELATIVE * total:
        raise DesignError(
            "the crease is closed (its end points coincide); a CCU crease is an open curve",
            key="[crease]",
        )


def side_flip(points: np.ndarray, side: str, reference: int) -> float:
    """+1 if the leading plate lies left of the profile direction, -1 if right.

    ``side`` is ``rulings.side``: inside / outside (towards / away from the centre of curvature
    at the reference vertex, or of the crease as a whole where it is straight there), left or
    right.
    """
    if side == "left":
        return 1.0
    if side == "right":
        return -1.0
    turn = crease_frames(points).turns
    if reference in (0, len(points) - 1):
        reference = 1 if reference == 0 else len(points) - 2
    t = turn[reference]
    if abs(t) < ZERO_LENGTH:
        # straight at the reference vertex (a straight stretch of a polyline): the side the
        # crease turns to as a whole
        t = float(turn.sum())
        if abs(t) < EXACT_RELATIVE:
            left = math.degrees(turn[turn > 0.0].sum())
            right = -math.degrees(turn[turn < 0.0].sum())
            how = (
                "the crease is straight"
                if max(left, right) < math.degrees(EXACT_RELATIVE)
                else f"the crease is straight at the reference vertex {reference} and turns as "
                f"much to the left ({left:.4g} deg) as to the right ({right:.4g} deg)"
            )
            raise DesignError(
                f"'{side}' is undefined: {how}; use side = 'left' or 'right' (of the profile "
                "direction)",
                key="rulings.side",
            )
    centre_left = t > 0.0
    return 1.0 if centre_left == (side == "inside") else -1.0


def explicit_side(rulings, points: np.ndarray) -> float:
    """+1 / -1: the side of the crease on which explicitly given ruling ends lie."""
    ends = np.asarray(rulings.points, dtype=float)
    if len(ends) != len(points):
        raise DesignError(
            f"needs one point per crease vertex ({len(points)}), got {len(ends)}",
            key="rulings.points",
        )
    f = crease_frames(points)
    side = np.einsum("ij,ij->i", ends - points, f.normals)
    if np.all(side > 0.0):
        return 1.0
    if np.all(side < 0.0):
        return -1.0
    i = int(np.flatnonzero(np.sign(side) != np.sign(side[0]))[0])
    raise DesignError(
        f"the ruling ends must all lie on one side of the crease; point {i} lies on the other side",
        key="rulings.points",
    )


def _gamma_field(value, s_fraction: np.ndarray) -> np.ndarray:
    if isinstance(value, float):
        return np.full(len(s_fraction), math.radians(value))
    table = np.asarray(value, dtype=float)
    return np.radians(np.interp(s_fraction, table[:, 0], table[:, 1]))


def design_rulings(rulings, local: np.ndarray, alpha: float, reference: int, flip: float):
    """(n + 1, 3) unit rulings of the leading plate at the deployed design state.

    ``rulings`` is the typed ``[rulings]`` section, ``local`` the crease (n + 1, 2) in the local
    frame, ``alpha`` the design reflection angle at vertex ``reference`` (radians).
    """
    kind = rulings.type
    flip2 = np.array([1.0, flip])
    if kind == "orthogonal":
        return ruling_fields.orthogonal_rulings(local, alpha=alpha, reference=reference)
    if kind == "cylindrical":
        return ruling_fields.cylindrical_rulings(
            local,
            direction=np.asarray(rulings.direction) * flip2,
            alpha=alpha,
            reference=reference,
        )
    if kind == "conical":
        return ruling_fields.conical_rulings(
            local, apex=np.asarray(rulings.apex) * flip2, alpha=alpha, reference=reference
        )
    f = crease_frames(local)
    s = np.r_[0.0, np.cumsum(f.lengths)]
    gamma = _gamma_field(rulings.gamma, s / s[-1])
    if rulings.alpha_field == "constant":
        ruling_fields.check_alpha_field(local, gamma, np.full(len(local), alpha))
    r, _ = ruling_fields.ruling_angle_rulings(local, gamma=gamma, alpha=alpha, reference=reference)
    return r


def pattern_rulings(rulings, local: np.ndarray, flip: float) -> np.ndarray:
    """Unit ruling directions in the cut pattern (flat state), plate on the left."""
    kind = rulings.type
    f = crease_frames(local)
    if kind == "orthogonal":
        r = f.normals.copy()
    elif kind == "cylindrical":
        d = np.asarray(rulings.direction) * [1.0, flip]
        if not np.hypot(*d) > 0.0:
            raise DesignError(
                f"must be a non-zero direction, got {rulings.direction}", key="rulings.direction"
            )
        d = d / np.hypot(*d)
        r = np.tile(d if f.normals[0] @ d > 0 else -d, (len(local), 1))
    elif kind == "explicit":
        to_end = np.asarray(rulings.points) * [1.0, flip] - local
        r = to_end / np.linalg.norm(to_end, axis=1)[:, None]
    elif kind == "conical":
        to_apex = np.asarray(rulings.apex) * [1.0, flip] - local
        r = to_apex / np.linalg.norm(to_apex, axis=1)[:, None]
        if np.einsum("ij,ij->i", r, f.normals)[0] < 0.0:
            r = -r
    else:
        s = np.r_[0.0, np.cumsum(f.lengths)]
        gamma = _gamma_field(rulings.gamma, s / s[-1])
        off = np.abs(gamma - np.pi / 2) > ZERO_ANGLE
        if rulings.alpha_field == "constant" and np.any(off):
            i = int(np.flatnonzero(off)[0])
            raise DesignError(
                "a constant reflection angle along a planar crease requires gamma = 90 deg "
                f"everywhere (docs/kinematics.md, ultra-special case); gamma = "
                f"{math.degrees(gamma[i]):.6g} deg at crease vertex {i} is not developable "
                "with a constant alpha (alpha' = cot(gamma) kappa_2D tan(alpha) != 0)",
                key="rulings.alpha_field",
            )
        r = np.cos(gamma)[:, None] * f.tangents + np.sin(gamma)[:, None] * f.normals
    into = np.einsum("ij,ij->i", r, f.normals)
    bad = np.flatnonzero(into <= EXACT_RELATIVE)
    if bad.size:
        raise DesignError(
            f"the {kind} rulings do not point into the plate at crease vertex {int(bad[0])}: "
            "the crease turns past the ruling direction there",
            key="rulings.type",
        )
    return np.c_[r, np.zeros(len(r))]


def check_ruling_sides(rulings, local: np.ndarray, r: np.ndarray, state: str) -> None:
    """Refuse rulings that leave the plate across a crease edge next to them.

    Every ruling lies in the quads on both sides of it, so it must point into the plate from
    both crease edges at its vertex (the end rulings: from the end edge): seen from above the
    crease plane, strictly to the left of the edges (the plate's side, local frame). A ruling to
    the right of an edge makes its quad fold through the crease; the sector angles of such a
    pattern describe another surface, so no deployment of the cut pattern reproduces the design
    (the end rulings of a ruling-angle field and the rulings towards a cone apex beside a sharp
    crease corner do this).

    Parameters
    ----------
    rulings : the typed ``[rulings]`` section
    local : (n + 1, 2) float
        The leading crease, local frame (plate on the left).
    r : (n + 1, 3) float
        Its rulings at the design state (3D for a deployed design, z = 0 in a cut pattern).
    state : str
        ``"deployed"`` or ``"flat"`` (named in the message).

    Raises
    ------
    DesignError
        Names the key of the ruling type, the vertex, the edge and the angle.
    """
    p = np.asarray(local, dtype=float)[:, :2]
    d = np.asarray(r, dtype=float)[:, :2]
    u = np.diff(p, axis=0)
    u /= np.linalg.norm(u, axis=1)[:, None]
    size = np.maximum(np.linalg.norm(d, axis=1), DIVISION_FLOOR)
    # ruling i against its forward edge i (i < n) and its backward edge i - 1 (i > 0)
    vertex = np.r_[np.arange(len(u)), np.arange(1, len(u) + 1)]
    edge = np.r_[np.arange(len(u)), np.arange(len(u))]
    ue, de = u[edge], d[vertex]
    sine = (ue[:, 0] * de[:, 1] - ue[:, 1] * de[:, 0]) / size[vertex]
    bad = np.flatnonzero(sine <= EXACT_RELATIVE)
    if not bad.size:
        return
    k = int(bad[np.argmin(sine[bad])])
    i, j = int(vertex[k]), int(edge[k])
    angle = math.degrees(math.atan2(-sine[k] * size[i], float(ue[k] @ de[k])))
    key = RULING_KEYS.get(rulings.type, "rulings.type")
    value = {
        "rulings.gamma": lambda: f"gamma = {rulings.gamma!r}",
        "rulings.apex": lambda: f"apex = {list(rulings.apex)!r}",
        "rulings.direction": lambda: f"direction = {list(rulings.direction)!r}",
    }.get(key, lambda: f"type = {rulings.type!r}")()
    end = " (an end of the crease)" if i in (0, len(p) - 1) else ""
    raise DesignError(
        f"{value}: the ruling at crease vertex {i}{end} points across crease edge {j}-{j + 1} "
        f"at the {state} design state ({angle:.4g} deg on the far side of it), so its quad folds "
        "through the crease and no deployment of the cut pattern reproduces the design; use "
        "more crease segments, rulings nearer perpendicular to the crease there, or a smoother "
        "crease",
        key=key,
    )
