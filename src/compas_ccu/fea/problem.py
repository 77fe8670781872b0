"""The engine-neutral FE problem and result: plain arrays, so every backend reads the same thing.

An :class:`FEProblem` is a shell model (nodes, 4-node shell elements, one material and
thickness), hinges (pairs of duplicated nodes whose translations are tied), supports whose
translations follow prescribed values step by step, and nodal loads given as a few load patterns
with one factor per step. A backend (:mod:`compas_ccu.fea.engines`) solves it geometrically
nonlinearly, step after step, cutting a step into smaller sub-steps when Newton does not
converge, and returns an :class:`FEResult` with the state at the end of every step.

Conventions
-----------
* Units: m, N, Pa, kg. Steps are numbered 1 .. S; step 0 is the stress-free reference.
* Element nodes are counter-clockwise seen from the element's top side: the local normal is
  ``(x2 - x0) x (x3 - x1)`` normalised; "top" surface stresses are at ``+t/2`` along it.
* Element forces are per unit length, averaged over the integration points, in the element's
  own local frame (e3 = the normal above, e1 in the element plane, engine specific):
  ``[n11, n22, n12, m11, m22, m12]`` with ``m11`` the moment that bends fibres along e1
  (stress ``sigma11 = n11/t + 6 m11/t^2 * z/(t/2)`` at height z). Only frame-invariant
  quantities are compared between engines (principal values, see :mod:`compas_ccu.fea.stresses`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compas_ccu.errors import ConvergenceError, FEError
from compas_ccu.materials import Material

__all__ = [
    "FEProblem",
    "LoadPattern",
    "FEResult",
    "ConvergenceError",
    "FEError",
    "buckling_steps",
]


def buckling_steps(buckling, steps: int) -> set:
    """The steps (1 .. ``steps``) at which to compute the linear buckling factor.

    ``buckling`` is False (none), True (the last step) or a sequence of step numbers.

    >>> sorted(buckling_steps(True, 8)), sorted(buckling_steps([3, 5], 8))
    ([8], [3, 5])
    """
    if buckling is True:
        return {int(steps)}
    if not buckling:
        return set()
    out = {int(k) for k in buckling}
    bad = sorted(k for k in out if not 1 <= k <= steps)
    if bad:
        raise FEError(f"buckling steps must lie in 1 .. {steps}, got {bad}")
    return out


@dataclass
class LoadPattern:
    """Nodal forces and moments scaled by one factor per step.

    Attributes
    ----------
    name : str
    loads : (N, 6) float
        Fx, Fy, Fz (N) and Mx, My, Mz (N m) per node, global axes.
    factors : (S,) float
        Factor of the pattern at the end of each step (linear in between).
    """

    name: str
    loads: np.ndarray
    factors: np.ndarray


@dataclass
class FEProblem:
    """An engine-neutral geometrically nonlinear shell problem.

    Attributes
    ----------
    nodes : (N, 3) float
        Reference (stress-free) coordinates.
    elements : (E, 4) int
        Node indices of every 4-node shell, counter-clockwise about its normal.
    material : Material
    thickness : float
        Plate thickness, m.
    orthotropic : bool
        Use E1, E2, G12 (directions below); otherwise the material's isotropic equivalent.
    directions : (E, 3) float
        Material direction 1 of every element in the reference configuration (unit, in plane).
    offsets : (E,) float or None
        Eccentricity of every element's material: its mid-surface lies at ``-offset`` along
        the element normal ``(x2 - x0) × (x3 - x1)`` from the element's nodes (the nodes on a
        plate face: axis-shift hinges, :mod:`compas_ccu.fea.eccentric`). None: the nodes are
        on the mid-surface. Element forces are reported about the mid-surface either way.
    ties : (T, 2) int
        Hinges: ``(master, slave)`` node pairs whose translations are equal (rotations free).
    tie_lengths : (T,) float
        Crease length belonging to each tie (for line springs), m.
    hinge_stiffness : float
        Rotational hinge spring per crease length, N m / rad / m (0: a free hinge).
    hinge_translational_stiffness : float or None
        If given, ties are springs of this stiffness per crease length (N/m/m) instead of
        rigid constraints.
    fixed : (F,) int
        Nodes whose three translations are prescribed.
    prescribed : (S, F, 3) float
        Their displacements from the reference at the end of every step; NaN frees a DOF for
        that step (its reaction must then be carried by a load pattern).
    fixed_rotations : (R,) int
        Nodes whose three rotations are held at zero (clamped edges), all steps.
    springs : (P, 2) int
        Node pairs joined by linear translational springs (supports on springs, a tie), the
        force on the second node ``k ⊙ (u_first - u_second)`` per global axis.
    spring_stiffness : (P, 3) float
        Stiffness of every spring along the global x, y, z axes, N/m.
    patterns : list of LoadPattern
    steps : int
        Number of steps S.
    name : str
    """

    nodes: np.ndarray
    elements: np.ndarray
    material: Material
    thickness: float
    steps: int
    orthotropic: bool = False
    directions: np.ndarray | None = None
    offsets: np.ndarray | None = None
    ties: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=int))
    tie_lengths: np.ndarray | None = None
    hinge_stiffness: float = 0.0
    hinge_translational_stiffness: float | None = None
    fixed: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    prescribed: np.ndarray | None = None
    fixed_rotations: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    springs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=int))
    spring_stiffness: np.ndarray | None = None
    patterns: list = field(default_factory=list)
    name: str = "ccu"

    def __post_init__(self):
        self.nodes = np.asarray(self.nodes, dtype=float)
        self.elements = np.asarray(self.elements, dtype=int)
        self.ties = np.asarray(self.ties, dtype=int).reshape(-1, 2)
        self.fixed = np.asarray(self.fixed, dtype=int).reshape(-1)
        self.fixed_rotations = np.asarray(self.fixed_rotations, dtype=int).reshape(-1)
        self.springs = np.asarray(self.springs, dtype=int).reshape(-1, 2)
        if self.spring_stiffness is None:
            self.spring_stiffness = np.zeros((len(self.springs), 3))
        self.spring_stiffness = np.asarray(self.spring_stiffness, dtype=float)
        n, s = len(self.nodes), int(self.steps)
        if s < 1:
            raise FEError(f"steps must be >= 1, got {self.steps!r}")
        if self.nodes.ndim != 2 or self.nodes.shape[1] != 3:
            raise FEError(f"nodes must be (N, 3), got shape {self.nodes.shape}")
        if self.elements.ndim != 2 or self.elements.shape[1] != 4:
            raise FEError(f"elements must be (E, 4), got shape {self.elements.shape}")
        if self.spring_stiffness.shape != (len(self.springs), 3) or np.any(
            ~(self.spring_stiffness >= 0.0)
        ):
            raise FEError(
                f"spring_stiffness must be ({len(self.springs)}, 3) and >= 0, got shape "
                f"{self.spring_stiffness.shape}"
            )
        for key in ("elements", "ties", "fixed", "fixed_rotations", "springs"):
            a = getattr(self, key)
            if a.size and (a.min() < 0 or a.max() >= n):
                raise FEError(f"{key} refer to nodes outside 0 .. {n - 1}")
        if not (self.thickness > 0.0):
            raise FEError(f"thickness must be > 0, got {self.thickness!r}")
        if self.directions is None:
            self.directions = np.tile([1.0, 0.0, 0.0], (len(self.elements), 1))
        self.directions = np.asarray(self.directions, dtype=float)
        if self.offsets is not None:
            self.offsets = np.asarray(self.offsets, dtype=float).reshape(-1)
            if self.offsets.shape != (len(self.elements),) or np.any(
                ~(np.abs(self.offsets) <= self.thickness)
            ):
                raise FEError(
                    f"offsets must be ({len(self.elements)},) finite values within the "
                    f"thickness {self.thickness!r} m, got shape {self.offsets.shape}"
                )
        if self.tie_lengths is None:
            self.tie_lengths = np.zeros(len(self.ties))
        self.tie_lengths = np.asarray(self.tie_lengths, dtype=float)
        if self.prescribed is None:
            self.prescribed = np.zeros((s, len(self.fixed), 3))
        self.prescribed = np.asarray(self.prescribed, dtype=float)
        if self.prescribed.shape != (s, len(self.fixed), 3):
            raise FEError(
                f"prescribed must be (steps, fixed, 3) = {(s, len(self.fixed), 3)}, "
                f"got {self.prescribed.shape}"
            )
        for p in self.patterns:
            p.loads = np.asarray(p.loads, dtype=float)
            p.factors = np.asarray(p.factors, dtype=float)
            if p.loads.shape != (n, 6) or p.factors.shape != (s,):
                raise FEError(
                    f"load pattern {p.name!r}: loads must be ({n}, 6) and factors ({s},), got "
                    f"{p.loads.shape} and {p.factors.shape}"
                )
        if self.hinge_stiffness < 0.0:
            raise FEError(f"hinge_stiffness must be >= 0, got {self.hinge_stiffness!r}")

    @property
    def material_used(self) -> Material:
        """The material as the engine sees it (isotropic equivalent unless orthotropic)."""
        return self.material if self.orthotropic else self.material.isotropic_equivalent()

    def loads_at(self, step: float) -> np.ndarray:
        """(N, 6) nodal loads at a (fractional) step, 0 .. S (linear between steps)."""
        out = np.zeros((len(self.nodes), 6))
        for p in self.patterns:
            f = np.interp(step, np.arange(self.steps + 1), np.r_[0.0, p.factors])
            out += f * p.loads
        return out

    def prescribed_at(self, step: float) -> np.ndarray:
        """(F, 3) prescribed displacements at a (fractional) step; NaN where free."""
        s = self.steps
        if step <= 0.0:
            return np.where(np.isnan(self.prescribed[0]), np.nan, 0.0)
        i = min(int(np.ceil(step)), s)
        lo = np.zeros_like(self.prescribed[0]) if i == 1 else self.prescribed[i - 2]
        hi = self.prescribed[i - 1]
        w = step - (i - 1)
        lo = np.where(np.isnan(lo), hi, lo)
        return lo + w * (hi - lo)


@dataclass
class FEResult:
    """What an engine returns: the state at the end of every converged step.

    Attributes
    ----------
    engine : str
    displacements : (k, N, 3) float
        Translations from the reference, k = converged steps (k = S when converged).
    rotations : (k, N, 3) float
        Rotation vectors (engine's total rotation measure), rad.
    forces : (k, E, 6) float
        Element forces ``[n11, n22, n12, m11, m22, m12]`` (N/m, N m/m), element frame.
    reactions : (k, F, 3) float
        Support reactions at the ``fixed`` nodes, N.
    tie_forces : (k, T, 3) float
        Hinge forces: the force every tie transmits to its slave node (plate b), N, global
        axes; the sum of the internal forces of the slave's elements at that node.
    converged : bool
    failed_step : int or None
    residual : float or None
        Last Newton residual of the failed step.
    iterations : (k,) int
        Newton iterations per step (summed over sub-steps).
    cuts : int
        How many times a step was cut.
    wall_time : float
        Seconds.
    message : str
    buckling_factor : float or None
        Linearised buckling factor of the last state under its loads (if asked for and the
        engine can), ``inf`` if none under increasing load.
    buckling_note : str
    buckling : dict
        Step (1 .. S) -> ``(factor, note)`` for every step the buckling factor was asked at.
    """

    engine: str
    displacements: np.ndarray
    rotations: np.ndarray
    forces: np.ndarray
    reactions: np.ndarray
    tie_forces: np.ndarray | None = None
    converged: bool = True
    failed_step: int | None = None
    residual: float | None = None
    iterations: np.ndarray | None = None
    cuts: int = 0
    wall_time: float = 0.0
    message: str = ""
    buckling_factor: float | None = None
    buckling_note: str = ""
    buckling: dict = field(default_factory=dict)

    @property
    def steps(self) -> int:
        return len(self.displacements)

    def positions(self, nodes: np.ndarray) -> np.ndarray:
        """(k, N, 3) deformed coordinates."""
        return np.asarray(nodes)[None] + self.displacements
