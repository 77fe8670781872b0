"""Exact one-degree-of-freedom deployment of the leading strip of a planar crease.

The leading strip's crease stays in the fixed crease plane O (local ``z = 0``) while its planar
quads rotate about the ruling edges. docs/geometry.md §2 describes the sequential construction: tilt
quad 0 about its crease edge, then rotate every next quad about the shared ruling until its next
crease vertex returns to O (a circle-plane intersection). That march has a closed form, which is
what makes the kinematics vectorised and exact:

Local frame: the plate lies on the left of the crease (``+v`` side) and tilts towards ``+z``.
Quad ``j`` contains crease edge ``u_j`` (unit, in O) and is tilted by ``psi_j`` about it, i.e. it
is spanned by ``u_j`` and ``w_j = cos(psi_j) v_j + sin(psi_j) z``. ``psi_j`` is exactly the
reflection angle of crease segment ``j`` (angle between the surface tangent normal to the
crease and O). The ruling ``r_i`` at an interior crease vertex lies in quads ``i - 1`` and ``i``:

    r_i = cos(a_i) u_{i-1} + sin(a_i) w_{i-1} = cos(b_i) u_i + sin(b_i) w_i,

with ``a_i = pi - sector_back_i`` and ``b_i = sector_forward_i``. Its ``z`` component gives

    sin(psi_i) = sin(psi_{i-1}) * sin(sector_back_i) / sin(sector_forward_i)            (K1)

so ``sin(psi_j) = s0 * c_j`` with ``c`` a cumulative product fixed by the cut pattern and ``s0``
the one degree of freedom. The in-plane components give the crease turning angle in 3D

    turn_i = atan2(sin(a_i) cos(psi_{i-1}), cos(a_i)) - atan2(sin(b_i) cos(psi_i), cos(b_i))  (K2)

and the crease polyline follows by cumulative sums. (K1) has no solution once
``s0 * c_j > 1`` for some segment ``j``: that quad would have to stand beyond perpendicular to O,
which is the deployment limit. ``cos(psi_j) >= 0`` selects the root continuous with the flat
state. (K1)-(K2) are the discrete, exact form of alpha' = cot(gamma) kappa_2D tan(alpha) and
cos(alpha) = kappa_2D / kappa_3D (docs/geometry.md §1); they are exact for every planar-quad strip.

The actuation is named by the reflection angle alpha at a reference crease vertex, measured as
the angle between O and the surface tangent ``S_i`` at the vertex: the unit vector in the plane
spanned by the discrete tangent ``T_i`` (bisector of the crease edges, in O) and the ruling, normal
to ``T_i``. For orthogonal rulings ``S_i`` is the ruling itself; on the circular cone this makes
``r_3D = R cos(alpha)`` exact at any discretisation.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from compas_ccu.errors import DeploymentLimitError, GeometryError
from compas_ccu.strips.intrinsics import StripIntrinsics
from compas_ccu.tolerances import MACHINE, ZERO_LENGTH

__all__ = ["LeadingStrip", "LeadingPlacement", "LeadingWriter"]


class LeadingPlacement(NamedTuple):
    """The leading strip placed in the local crease-plane frame for ``k`` states.

    Attributes
    ----------
    near : (k, n + 1, 3) float
        Crease vertices (``z = 0``).
    rulings : (k, n + 1, 3) float
        Unit ruling directions from the crease into the plate.
    far : (k, n + 1, 3) float
        Far boundary vertices ``near + ruling_lengths * rulings``.
    tilts : (k, n) float
        Reflection angle ``psi_j`` of every crease segment, radians.

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> leading = load_model("examples/cone.toml").mechanism.leading
    >>> placed = leading.place_alpha(np.radians([20.0]))
    >>> placed.near.shape, placed.tilts.shape, float(np.abs(placed.near[..., 2]).max())
    ((1, 49, 3), (1, 48), 0.0)
    >>> np.degrees(placed.tilts).round(6).tolist() == [[20.002792] * 48]  # a cone: all alike
    True
    """

    near: np.ndarray
    rulings: np.ndarray
    far: np.ndarray
    tilts: np.ndarray


class LeadingStrip:
    """Closed-form kinematics of the strip whose crease stays in the fixed plane O.

    Parameters
    ----------
    intrinsics : StripIntrinsics
        Isometry invariants of the strip, plate on the left of the crease.
    reference : int
        Index of the reference crease vertex that names the actuation.
    anchor_point : (2,) float
        Where the reference vertex stays in the local plane coordinates, in every state.
    anchor_angle : float
        Direction (radians) that the crease tangent at the reference vertex keeps in every state.

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.strips.intrinsics import strip_intrinsics
    >>> t = np.linspace(0.0, np.pi / 2, 9)
    >>> near = np.c_[np.cos(t), np.sin(t)]
    >>> strip = LeadingStrip(strip_intrinsics(near, 0.8 * near), reference=4)
    >>> placed = strip.place_alpha([np.radians(30.0)])
    >>> a, b, c = placed.near[0, 3:6]  # circumradius of three crease vertices
    >>> r3d = (np.linalg.norm(b - a) * np.linalg.norm(c - b) * np.linalg.norm(c - a)
    ...        / (2 * np.linalg.norm(np.cross(b - a, c - a))))
    >>> round(float(r3d / np.cos(np.radians(30.0))), 12)  # the cone: r_3D = R cos(alpha)
    1.0
    """

    def __init__(
        self,
        intrinsics: StripIntrinsics,
        *,
        reference: int,
        anchor_point=(0.0, 0.0),
        anchor_angle: float | None = None,
    ):
        n = intrinsics.segments
        if not 0 <= reference <= n:
            raise GeometryError(f"reference vertex must be in [0, {n}], got {reference}")
        self.intrinsics = intrinsics
        self.reference = int(reference)
        self.n = n
        back, fwd = intrinsics.sector_back, intrinsics.sector_forward
        self._sin_back, self._cos_back = np.sin(back), np.cos(back)
        self._sin_fwd, self._cos_fwd = np.sin(fwd), np.cos(fwd)
        # (K1): sin(psi_j) = s0 * c_j
        ratio = self._sin_back[1:-1] / self._sin_fwd[1:-1]
        self.tilt_factors = np.concatenate([[1.0], np.cumprod(ratio)])
        # the (K2) constants, and those of the rulings: ruling i < n in quad i, ruling n in quad
        # n - 1 (the placement's extra column n repeats segment n - 1 for it)
        self._turn_terms = (
            self._sin_back[1:-1],
            -self._cos_back[1:-1],
            self._sin_fwd[1:-1],
            self._cos_fwd[1:-1],
        )
        self._ruling_cos = np.append(self._cos_fwd[:-1], -self._cos_back[-1])
        self._ruling_sin = np.append(self._sin_fwd[:-1], self._sin_back[-1])
        self._factors_ext = np.append(self.tilt_factors, self.tilt_factors[-1])
        self._ruling_xyz = np.repeat(intrinsics.ruling_lengths[:, None], 3, axis=1)
        j = int(np.argmax(self.tilt_factors))
        self.limit_segment = j
        self.s0_max = 1.0 / self.tilt_factors[j]
        self.anchor_point = np.asarray(anchor_point, dtype=float)
        if anchor_angle is None:
            # keep the flat pattern's own orientation (first edge along +x)
            flat = self._turns(np.zeros(1))[0]
            theta = np.concatenate([[0.0], np.cumsum(flat)])
            anchor_angle = float(self._tangent_angle(theta[None, :], flat[None, :])[0])
        self.anchor_angle = float(anchor_angle)
        self._alpha_limit = None
        self._one = _ScalarAlpha(self) if n > 1 else None

    # -- the closed form --------------------------------------------------------------------
    def tilts(self, s0) -> np.ndarray:
        """(k, n) reflection angles ``psi_j`` of the crease segments for ``s0 = sin(psi_0)``."""
        s0 = np.atleast_1d(np.asarray(s0, dtype=float))
        return np.arcsin(np.clip(s0[:, None] * self.tilt_factors[None, :], -1.0, 1.0))

    def _turns(self, s0: np.ndarray, sin_psi=None, cos_psi=None) -> np.ndarray:
        """(k, n - 1) crease turning angles in O at the interior vertices (K2)."""
        if sin_psi is None:
            sin_psi = np.clip(s0[:, None] * self.tilt_factors[None, :], -1.0, 1.0)
            cos_psi = np.sqrt(1.0 - sin_psi**2)
        sin_back, minus_cos_back, sin_fwd, cos_fwd = self._turn_terms
        left = np.arctan2(sin_back * cos_psi[:, :-1], minus_cos_back)
        right = np.arctan2(sin_fwd * cos_psi[:, 1:], cos_fwd)
        return left - right

    def _tangent_angle(self, theta: np.ndarray, turns: np.ndarray) -> np.ndarray:
        """(k,) direction of the discrete tangent (edge bisector) at the reference vertex."""
        k = self.reference
        if self.n == 1:
            return theta[:, 0]
        if k == 0:  # ends: the edge turned back by half the neighbouring turn (see frames)
            return theta[:, 0] - 0.5 * turns[:, 0]
        if k == self.n:
            return theta[:, -1] + 0.5 * turns[:, -1]
        return theta[:, k - 1] + 0.5 * turns[:, k - 1]

    def place(self, s0) -> LeadingPlacement:
        """Place the strip for one or more values of the degree of freedom ``s0``.

        Parameters
        ----------
        s0 : float or (k,) float
            ``sin(psi_0)``, in ``[0, s0_max]``.

        Returns
        -------
        LeadingPlacement
            New arrays (:class:`LeadingWriter` writes them).
        """
        if type(s0) is not np.ndarray or s0.ndim != 1 or s0.dtype != np.float64:
            s0 = np.atleast_1d(np.asarray(s0, dtype=float))
        near, rulings, far = (np.empty((len(s0), self.n + 1, 3)) for _ in range(3))
        tilts = LeadingWriter(self, near, rulings, far).place(s0)
        return LeadingPlacement(near, rulings, far, tilts)

    def writer(self, near: np.ndarray, rulings: np.ndarray, far: np.ndarray) -> LeadingWriter:
        """A :class:`LeadingWriter` that places the strip into ``near``, ``rulings`` and
        ``far`` ((k, n + 1, 3) arrays or views, kept by the caller) for ``k`` states at a time:
        :meth:`place` with the work arrays and their views made once (the redeploy's dispatch)."""
        return LeadingWriter(self, near, rulings, far)

    # -- naming the actuation by alpha at the reference vertex ------------------------------------
    def reference_alpha(self, s0) -> np.ndarray:
        """(k,) reflection angle alpha (radians) at the reference vertex for given ``s0``."""
        s0 = np.atleast_1d(np.asarray(s0, dtype=float))
        k, n = self.reference, self.n
        factors = self.tilt_factors
        if n == 1:
            return np.arcsin(np.clip(s0 * factors[0], -1.0, 1.0))

        def tilt(j):
            sp = np.clip(s0 * factors[j], -1.0, 1.0)
            return sp, np.sqrt(1.0 - sp**2)

        def half_turn(i):  # half the crease turn at interior vertex i (K2)
            sp_prev, cp_prev = tilt(i - 1)
            _, cp = tilt(i)
            return 0.5 * (
                np.arctan2(self._sin_back[i] * cp_prev, -self._cos_back[i])
                - np.arctan2(self._sin_fwd[i] * cp, self._cos_fwd[i])
            )

        if k == n:  # ruling in quad n - 1; tangent = last edge turned by +half the last turn
            sp, cp = tilt(n - 1)
            half = half_turn(n - 1)
            sa, ca = self._sin_back[n], self._cos_back[n]
            return np.arctan2(sa * sp, ca * np.sin(half) + sa * cp * np.cos(half))
        # ruling in the frame of quad k; the tangent T_k is u_k turned by -half
        sp, cp = tilt(k)
        half = half_turn(k if k > 0 else 1)
        sb, cb = self._sin_fwd[k], self._cos_fwd[k]
        return np.arctan2(sb * sp, cb * np.sin(half) + sb * cp * np.cos(half))

    @property
    def alpha_limit(self) -> float:
        """Largest reachable reference reflection angle, radians (the deployment limit)."""
        if self._alpha_limit is None:
            at_max = float(self.reference_alpha(self.s0_max)[0])
            # a reflection angle is at most 90 deg: where the surface at the reference vertex
            # stands perpendicular to O before any segment does, that is the limit
            self._alpha_limit = min(at_max, 0.5 * math.pi)
        return self._alpha_limit

    @property
    def limit_reason(self) -> str:
        """What stands perpendicular to the crease plane at the deployment limit."""
        j = self.limit_segment
        if self.alpha_limit >= 0.5 * math.pi:
            return (
                f"the surface at reference vertex {self.reference} stands perpendicular to the "
                "crease plane (alpha = 90 deg)"
            )
        return (
            f"crease segment {j} (crease vertices {j}-{j + 1}) stands perpendicular to the "
            "crease plane"
        )

    def s0_for_alpha(self, alpha) -> np.ndarray:
        """Invert :meth:`reference_alpha`: the degree of freedom for reference angles ``alpha``.

        Parameters
        ----------
        alpha : float or (k,) float
            Reference reflection angles in radians, ``0 <= alpha <= alpha_limit``.

        Raises
        ------
        DeploymentLimitError
            An angle is negative or beyond the deployment limit.
        """
        one = _one_angle(alpha) if self._one is not None else None
        if one is not None and 0.0 <= one <= self.alpha_limit * (1.0 + ZERO_LENGTH):
            # one reachable angle (the redeploy of a slider): the same iteration in floats
            return np.array([self._one.invert(min(one, self.alpha_limit))])
        alpha = np.atleast_1d(np.asarray(alpha, dtype=float))
        if not np.all(np.isfinite(alpha)):
            raise GeometryError(f"alpha must be finite, got {alpha.tolist()}")
        limit = self.alpha_limit
        j = self.limit_segment
        if np.any(alpha < 0.0):
            bad = float(np.degrees(alpha[alpha < 0.0][0]))
            raise DeploymentLimitError(
                f"alpha = {bad:.6g} deg is negative; the mechanism runs from the flat-folded "
                f"stack (alpha = 0) to its limit alpha = {math.degrees(limit):.6g} deg",
                alpha=bad,
                alpha_limit=math.degrees(limit),
                vertex=j,
            )
        if np.any(alpha > limit * (1.0 + ZERO_LENGTH)):
            bad = float(np.degrees(alpha[alpha > limit * (1.0 + ZERO_LENGTH)][0]))
            raise DeploymentLimitError(
                f"alpha = {bad:.6g} deg is beyond the deployment limit: the largest reachable "
                f"alpha at reference vertex {self.reference} is {math.degrees(limit):.6g} deg, "
                f"where {self.limit_reason}",
                alpha=bad,
                alpha_limit=math.degrees(limit),
                vertex=j,
            )
        return self._invert(np.minimum(alpha, limit))

    def _invert(self, alpha: np.ndarray) -> np.ndarray:
        # alpha(s0) is increasing on [0, s0_max]: safeguarded Newton with a shrinking bracket
        lo = np.zeros_like(alpha)
        hi = np.full_like(alpha, self.s0_max)
        guess_factor = self.tilt_factors[min(self.reference, self.n - 1)]
        s = np.clip(np.sin(alpha) / guess_factor, 0.0, self.s0_max)
        tol = MACHINE
        for _ in range(60):
            f = self.reference_alpha(s) - alpha
            if np.all(np.abs(f) <= tol):
                break
            lo = np.where(f < 0.0, s, lo)
            hi = np.where(f > 0.0, s, hi)
            ds = 1e-7 * self.s0_max
            probe = np.where(s + ds <= self.s0_max, s + ds, s - ds)
            slope = (self.reference_alpha(probe) - alpha - f) / (probe - s)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = s - f / slope
            newton_ok = (step >= lo) & (step <= hi) & np.isfinite(step)
            s = np.where(np.abs(f) <= tol, s, np.where(newton_ok, step, 0.5 * (lo + hi)))
        return s

    def place_alpha(self, alpha) -> LeadingPlacement:
        """Place the strip at reference reflection angles ``alpha`` (radians, scalar or (k,))."""
        return self.place(self.s0_for_alpha(alpha))


def _one_angle(alpha) -> float | None:
    """``alpha`` as a float if it is one finite number (a scalar or a 1-element 0-d/1-d array,
    which :meth:`LeadingStrip.s0_for_alpha` returns as a (1,) array), else None."""
    if isinstance(alpha, np.ndarray):
        if alpha.size != 1 or alpha.ndim > 1 or alpha.dtype.kind not in "fiub":
            return None
        value = float(alpha.reshape(-1)[0])
    elif isinstance(alpha, (float, int, np.floating, np.integer)):
        value = float(alpha)
    else:
        return None
    return value if math.isfinite(value) else None


def _clip(x: float, lo: float, hi: float) -> float:
    """``numpy.clip`` of one float: ``x`` unless it lies outside ``[lo, hi]`` (NaN stays)."""
    return hi if x > hi else (lo if x < lo else x)


class _ScalarAlpha:
    """:meth:`LeadingStrip.reference_alpha` and :meth:`LeadingStrip._invert` for one angle.

    The same floating-point operations in the same order, bit for bit: the products, sums,
    clips and square roots (correctly rounded in IEEE arithmetic) on Python floats, the
    arctangents, sines and cosines by NumPy on small arrays (NumPy's ``arctan2`` may differ from
    the C library's in the last bit), so the result is the array path's to the last bit
    (tests/test_kinematics_leading.py compares them). Each Newton step evaluates the angle at
    the iterate and at its probe together: four NumPy calls instead of some forty.
    """

    def __init__(self, strip: LeadingStrip):
        k, n = strip.reference, strip.n
        i = n - 1 if k == n else (k if k > 0 else 1)  # the vertex whose half turn is used
        j = n - 1 if k == n else k  # the segment whose tilt is used (i - 1 or i)
        self.strip = strip
        self.factor_prev = float(strip.tilt_factors[i - 1])
        self.factor = float(strip.tilt_factors[i])
        self.own_prev = j == i - 1
        self.turn_y = (float(strip._sin_back[i]), float(strip._sin_fwd[i]))
        self.turn_x = np.array([float(-strip._cos_back[i]), float(strip._cos_fwd[i])] * 2)
        at = strip._sin_back[n] if k == n else strip._sin_fwd[k]
        cos_at = strip._cos_back[n] if k == n else strip._cos_fwd[k]
        self.s_end, self.c_end = float(at), float(cos_at)

    def alphas(self, s: float, probe: float) -> list:
        """``reference_alpha`` at ``s`` and at ``probe``: two floats."""
        y_back, y_fwd = self.turn_y
        tilts, turn = [], []
        for value in (s, probe):
            sp_prev = _clip(value * self.factor_prev, -1.0, 1.0)
            cp_prev = math.sqrt(1.0 - sp_prev * sp_prev)
            sp = _clip(value * self.factor, -1.0, 1.0)
            cp = math.sqrt(1.0 - sp * sp)
            tilts.append((sp_prev, cp_prev) if self.own_prev else (sp, cp))
            turn += (y_back * cp_prev, y_fwd * cp)
        a = np.arctan2(turn, self.turn_x).tolist()
        half = np.array([0.5 * (a[0] - a[1]), 0.5 * (a[2] - a[3])])
        sin_h, cos_h = np.sin(half).tolist(), np.cos(half).tolist()
        se, ce = self.s_end, self.c_end
        y = [se * sp for sp, _ in tilts]
        x = [ce * sh + se * cp * ch for (_, cp), sh, ch in zip(tilts, sin_h, cos_h)]
        return np.arctan2(y, x).tolist()

    def invert(self, alpha: float) -> float:
        """:meth:`LeadingStrip._invert` of one angle (the same iterates, bit for bit)."""
        strip = self.strip
        s_max = float(strip.s0_max)
        guess_factor = strip.tilt_factors[min(strip.reference, strip.n - 1)]
        s = _clip(float(np.sin(alpha) / guess_factor), 0.0, s_max)
        lo, hi = 0.0, s_max
        tol = MACHINE
        ds = 1e-7 * s_max
        for _ in range(60):
            probe = s + ds if s + ds <= s_max else s - ds
            at_s, at_probe = self.alphas(s, probe)
            f = at_s - alpha
            if abs(f) <= tol:
                break
            if f < 0.0:
                lo = s
            if f > 0.0:
                hi = s
            slope = _divide(at_probe - alpha - f, probe - s)
            step = s - _divide(f, slope)
            s = step if lo <= step <= hi and math.isfinite(step) else 0.5 * (lo + hi)
        return s


def _divide(a: float, b: float) -> float:
    """``a / b`` with NumPy's (IEEE) result for ``b = 0``: a signed infinity or NaN."""
    if b != 0.0 or math.isnan(b):
        return a / b
    if a == 0.0 or math.isnan(a):
        return math.nan
    return math.copysign(math.inf, a) * math.copysign(1.0, b)


class LeadingWriter:
    """The placement of the leading strip for ``k`` states, written into kept arrays: the one
    implementation of :meth:`LeadingStrip.place` (which writes into new arrays).

    The floating-point operations of docs/geometry.md's placement, one array operation per
    step (``plain_place`` in tests/test_kinematics_leading.py, which gives the same bits), with
    the work arrays and every view made once (:meth:`LeadingStrip.writer`) and fewer NumPy
    calls: the two arctangents of (K2) as one call on the two windows of ``cos(psi)`` (a strided
    view); the cosines and sines of the crease directions in one (k, 2, n + 1) array, so that
    the crease's x and y sums are one product and one cumulative sum; the rulings' x and y as
    ``[cb, sb cos(psi)] cos(t) + [-sb cos(psi), cb] sin(t)`` (a difference is the sum with the
    negated operand, exactly); the tangent at the reference vertex of one state on floats.
    Not for two threads at once: each keeps its own writer.

    Parameters
    ----------
    strip : LeadingStrip
    near, rulings, far : (k, n + 1, 3) float
        Where the crease vertices, the unit rulings and the far boundary are written.
    """

    def __init__(self, strip: LeadingStrip, near: np.ndarray, rulings: np.ndarray, far):
        self.strip, self.near, self.rulings, self.far = strip, near, rulings, far
        k, n = near.shape[0], strip.n
        self.k, self.n = k, n
        # the clip's lower bound is a no-op for one state s0 >= 0 when no factor is negative
        self.nonnegative = bool((strip._factors_ext >= 0.0).all())
        self.sin_psi, self.cos_psi = np.empty((k, n + 1)), np.empty((k, n + 1))
        row, step = self.cos_psi.strides
        # cos(psi) of segments 0 ... n - 2 and 1 ... n - 1 as one (k, 2, n - 1) view
        self.windows = np.ndarray((k, 2, n - 1), buffer=self.cos_psi, strides=(row, step, step))
        sin_back, minus_cos_back, sin_fwd, cos_fwd = strip._turn_terms
        self.turn_y, self.turn_x = (
            np.stack([sin_back, sin_fwd]),
            np.stack([minus_cos_back, cos_fwd]),
        )
        self.halves = np.empty((k, 2, n - 1))
        self.turns = np.empty((k, n - 1))
        self.theta = np.zeros((k, n))  # column 0 stays 0
        self.shifted = np.empty((k, n + 1))  # theta + the anchor's shift, column n repeated
        self.angles = np.empty((k, 2, n + 1))  # cos(theta), sin(theta)
        self.cos_t, self.sin_t = self.angles[:, 0], self.angles[:, 1]
        self.sums = np.zeros((k, n + 1, 2))  # the crease's cumulative sums, vertex 0 stays 0
        self.sums_t = self.sums[:, 1:].transpose(0, 2, 1)  # (k, 2, n)
        self.steps = np.empty((k, 2, n))  # h cos(theta), h sin(theta)
        sb = strip._ruling_sin
        self.signed_sb = np.stack([-sb, sb])
        self.coefficients = np.empty((k, 3, n + 1))  # -sb cos(psi), cb, sb cos(psi)
        self.coefficients[:, 1] = strip._ruling_cos
        self.by_cos, self.by_sin = np.empty((k, 2, n + 1)), np.empty((k, 2, n + 1))
        self.anchor = np.empty((k, 1, 2))
        self.rulings_xy_t = rulings[:, :, :2].transpose(0, 2, 1)  # (k, 2, n + 1)
        near[:, :, 2] = 0.0  # the crease stays in O: written once
        r = strip.reference
        # the tangent at the reference vertex: theta[at] + half * turns[turn] (_tangent_angle);
        # one segment has no turn: its direction
        if n == 1:
            self.tangent = (0, None, 0.0)
        else:
            self.tangent = {0: (0, 0, -0.5), n: (n - 1, n - 2, 0.5)}.get(r, (r - 1, r - 1, 0.5))

    def place(self, s0: np.ndarray) -> np.ndarray:
        """Place the strip for ``s0`` (k,) float; returns the tilts (k, n)."""
        strip, n, k = self.strip, self.n, self.k
        sin_psi, cos_psi = self.sin_psi, self.cos_psi
        np.multiply(s0[:, None], strip._factors_ext, out=sin_psi)
        if not (self.nonnegative and k == 1 and s0[0] >= 0.0):
            np.maximum(sin_psi, -1.0, out=sin_psi)
        np.minimum(sin_psi, 1.0, out=sin_psi)
        np.square(sin_psi, out=cos_psi)
        np.subtract(1.0, cos_psi, out=cos_psi)
        np.sqrt(cos_psi, out=cos_psi)
        halves, turns, theta, shifted = self.halves, self.turns, self.theta, self.shifted
        np.multiply(self.turn_y, self.windows, out=halves)  # (K2)
        np.arctan2(halves, self.turn_x, out=halves)
        np.subtract(halves[:, 0], halves[:, 1], out=turns)
        np.add.accumulate(turns, axis=1, out=theta[:, 1:])
        at, turn, half = self.tangent
        if turn is None:  # one segment
            shift = (strip.anchor_angle - theta[:, at])[:, None]
        elif k == 1:
            shift = strip.anchor_angle - (theta.item(at) + half * turns.item(turn))
        else:
            shift = (strip.anchor_angle - (theta[:, at] + half * turns[:, turn]))[:, None]
        np.add(theta, shift, out=shifted[:, :n])
        shifted[:, n] = shifted[:, n - 1]
        np.cos(shifted, out=self.cos_t)
        np.sin(shifted, out=self.sin_t)
        np.multiply(strip.intrinsics.edge_lengths, self.angles[:, :, :n], out=self.steps)
        np.add.accumulate(self.steps, axis=2, out=self.sums_t)
        np.subtract(strip.anchor_point, self.sums[:, strip.reference], out=self.anchor[:, 0])
        np.add(self.sums, self.anchor, out=self.near[:, :, :2])
        coefficients = self.coefficients  # the rulings
        np.multiply(self.signed_sb, cos_psi[:, None], out=coefficients[:, ::2])
        np.multiply(coefficients[:, 1:], self.cos_t[:, None], out=self.by_cos)
        np.multiply(coefficients[:, :2], self.sin_t[:, None], out=self.by_sin)
        np.add(self.by_cos, self.by_sin, out=self.rulings_xy_t)
        np.multiply(strip._ruling_sin, sin_psi, out=self.rulings[:, :, 2])
        np.multiply(strip._ruling_xyz, self.rulings, out=self.far)
        np.add(self.far, self.near, out=self.far)
        return np.arcsin(sin_psi[:, :n])
