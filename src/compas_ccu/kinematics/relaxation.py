"""Least-squares relaxation of the placed plates where the mirror construction is not exact.

docs/geometry.md §2, several creases: where a crease between two plates leaves its plane at an
intermediate deployment state, the mirror construction of :class:`compas_ccu.kinematics.Mechanism`
has no exact solution; the reflected plates then change the lengths of their quads. :func:`relax` is
the stated fallback: starting from the kinematic guess it moves the vertices of the non-fixed plates
so that every quad is as close as possible to its cut pattern, and reports what is left.

Unknowns
    The vertices of every plate, with each non-leading plate's near boundary *merged* with the
    boundary of its parent it hangs on (``links``). Hinge coincidence is therefore exact by
    construction, also along chains and where several plates share one crease. The vertices of
    the ``fixed`` plates (by default the leading plate, whose kinematics is exact), including
    crease vertices they share, are held.

Residuals, for every quad ``a, b, c, d = near[j], near[j + 1], far[j + 1], far[j]`` of every
non-fixed plate
    * the six relative length errors ``(L - L0) / L0`` of the sides ``ab, bc, cd, da`` and
      diagonals ``ac, bd`` (the order of ``compas_ccu.strips.intrinsics.quad_lengths``);
    * one planarity residual ``w * h / l0``: ``h = (b - a) . (u x v) / |u x v|`` with
      ``u = c - a``, ``v = d - b`` is the signed distance between the two diagonal lines of the
      quad (zero exactly when the quad is planar; every vertex lies within ``|h|`` of the plane
      of the other three, up to the quad's shape), ``l0 = sqrt(L0_ac L0_bd)`` the design
      diagonal scale and ``w = planarity_weight``. It is smooth wherever the diagonals are not
      parallel, and dimensionless like the strains, so ``w = 1`` weighs a warp ``h`` like a
      strain ``h / l0``.

Six lengths fix a quad up to congruence, so at an exact solution the planarity residual is
redundant; it matters where no exact solution exists, because a warp changes lengths only to
second order.

Solver
    Levenberg-Marquardt (:mod:`~compas_ccu.kinematics.levenberg_marquardt`) with the analytic
    Jacobian (:mod:`~compas_ccu.kinematics.relaxation_problem`), assembled with NumPy per quad
    as ``(nq, 7, 12)`` blocks. Every step solves the damped normal equations
    ``(J^T J + lam D) step = -J^T r`` directly: the free vertices are ordered by reverse
    Cuthill-McKee, for a stack of strips crease vertex by crease vertex across the plates, so
    ``J^T J`` is banded (each quad couples neighbouring vertices along its strip and the plates
    across its hinges; ~30 sub-diagonals for 10 plates, whatever the number of segments) and a
    banded Cholesky factorisation (:func:`scipy.linalg.solveh_banded`) costs ``O(N band^2)``.
    ``D`` is Marquardt's scaling ``diag(J^T J)`` (running maximum), the damping ``lam`` follows
    Nielsen's gain-ratio update, and the run stops on the gradient, the cost reduction or the
    step (scipy's status codes), or after ``max_nfev`` residual evaluations (not converged).
    ``solver="scipy"`` runs the former :func:`scipy.optimize.least_squares` (trust region
    reflective with the same sparse Jacobian and an LSMR subproblem), the reference: both reach
    the same cost to ~12 digits, the LM path 20-30 times faster on catalog Fig. 12a and 100-170
    times on the radial Fig. 12c (docs/benchmarks.md).

The result reports the strain and planarity after relaxation, how far the vertices moved and the
strain before relaxation, so nothing is hidden: a relaxed state with ``max_strain > 0`` is not
an isometry of the cut patterns, and the plates would have to stretch (or bend out of their
developable shape) by that much.

Examples
--------
>>> import numpy as np
>>> from compas_ccu.model import load_model
>>> from compas_ccu.kinematics.relaxation import links_from_mechanism, relax
>>> model = load_model("examples/vault.toml")
>>> states = model.mechanism.deploy(np.radians([20.0]))
>>> ref = model.reference_lengths.copy()
>>> ref[3, :, 2] *= 1.002  # plate 3's far edges 0.2 % longer than plate 4's near edges
>>> result = relax(states.near[0], states.far[0], ref, links_from_mechanism(model.mechanism))
>>> result.converged
True
>>> round(result.initial_max_strain, 4), round(result.max_strain, 4)  # the shared edges split it
(0.002, 0.001)
>>> float(np.abs(result.near[4] - result.far[3]).max())  # hinge coincidence is exact
0.0
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compas_ccu.errors import CCUError, GeometryError
from compas_ccu.kinematics.relaxation_problem import RelaxationProblem
from compas_ccu.strips.intrinsics import quad_corners, quad_lengths
from compas_ccu.tolerances import SOLVER

__all__ = ["Relaxation", "relax", "relax_states", "links_from_mechanism"]

_EPS = float(np.finfo(float).eps)


@dataclass(frozen=True, eq=False)
class Relaxation:
    """Result of :func:`relax`: relaxed plates and what the relaxation could not remove.

    Attributes
    ----------
    near, far : (p, n + 1, 3) float
        Relaxed boundaries, same frame and units as the input. Shared crease vertices coincide
        exactly.
    strain : (p, n, 6) float
        Relative length errors ``(L - L0) / L0`` of every quad (sides ab, bc, cd, da, diagonals
        ac, bd) after relaxation, fixed plates included.
    max_strain : float
        ``max |strain|``.
    max_strain_per_plate : (p,) float
    quad_planarity : float
        Largest distance (m) of a quad vertex from the plane of the other three, after.
    quad_planarity_per_plate : (p,) float
    displacement : float
        Largest distance (m) a vertex moved from the guess (a near vertex that did not coincide
        with its parent's crease vertex in the guess moves to it).
    displacement_per_plate : (p,) float
    initial_max_strain : float
        ``max |strain|`` of the start (the guess with merged crease vertices): what relaxing
        gained is ``initial_max_strain - max_strain``.
    initial_quad_planarity : float
        ``quad_planarity`` of the start, m.
    initial_hinge_gap : float
        Largest distance (m) in the guess between a plate's near vertex and its parent's crease
        vertex (zero for a guess from the mechanism).
    cost : float
        Final value of ``0.5 * sum(residuals ** 2)``.
    optimality : float
        Final gradient norm ``max |J^T r|`` (infinity norm, as scipy reports it).
    nfev, njev : int
        Residual evaluations (every trial step, rejected ones included) and Jacobian
        evaluations (the start and every accepted step).
    status : int
        Termination status, scipy's codes for both solvers: ``1`` gradient (``gtol``), ``2``
        cost reduction (``ftol``), ``3`` step (``xtol``), ``4`` ``ftol`` and ``xtol``: a
        convergence test was met; ``0``: ``max_nfev`` reached; ``-1`` (``solver="lm"``): the
        damped normal equations could not be solved.
    message : str
    converged : bool
        ``status > 0``.
    fixed : tuple of int
        The held plates.
    solver : str
        ``"lm"`` or ``"scipy"``: the solver that produced the result (:func:`relax`).

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> states = model.mechanism.deploy(np.radians([20.0]))
    >>> links = links_from_mechanism(model.mechanism)
    >>> result = relax(states.near[0], states.far[0], model.reference_lengths, links)
    >>> result.converged, result.strain.shape, bool(result.max_strain < 1e-12)  # exact already
    (True, (2, 48, 6), True)
    """

    near: np.ndarray
    far: np.ndarray
    strain: np.ndarray
    max_strain: float
    max_strain_per_plate: np.ndarray
    quad_planarity: float
    quad_planarity_per_plate: np.ndarray
    displacement: float
    displacement_per_plate: np.ndarray
    initial_max_strain: float
    initial_quad_planarity: float
    initial_hinge_gap: float
    cost: float
    optimality: float
    nfev: int
    njev: int
    status: int
    message: str
    converged: bool
    fixed: tuple = field(default=(0,))
    solver: str = "lm"

    def summary(self) -> dict:
        """Plain-Python numbers for JSON: scalars, per-plate lists and the solver outcome."""
        return {
            "max_strain": float(self.max_strain),
            "initial_max_strain": float(self.initial_max_strain),
            "quad_planarity": float(self.quad_planarity),
            "initial_quad_planarity": float(self.initial_quad_planarity),
            "displacement": float(self.displacement),
            "initial_hinge_gap": float(self.initial_hinge_gap),
            "max_strain_per_plate": [float(v) for v in self.max_strain_per_plate],
            "quad_planarity_per_plate": [float(v) for v in self.quad_planarity_per_plate],
            "displacement_per_plate": [float(v) for v in self.displacement_per_plate],
            "cost": float(self.cost),
            "optimality": float(self.optimality),
            "nfev": int(self.nfev),
            "njev": int(self.njev),
            "status": int(self.status),
            "message": str(self.message),
            "converged": bool(self.converged),
            "fixed": [int(i) for i in self.fixed],
            "solver": str(self.solver),
        }


def links_from_mechanism(mechanism) -> list:
    """``(plate, parent, boundary)`` of every non-leading plate of a :class:`Mechanism`.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> links_from_mechanism(load_model("examples/vault.toml").mechanism)[:5]
    [(1, 0, 'far'), (2, 1, 'far'), (3, 2, 'far'), (4, 3, 'far'), (5, 0, 'near')]
    """
    return [
        (i, int(plate.parent), str(plate.boundary))
        for i, plate in enumerate(mechanism.plates)
        if plate.parent is not None
    ]


def _vertex_plane_distance(quads: np.ndarray) -> np.ndarray:
    """(...) largest distance of a quad corner from the plane of the other three, ``(..., 4, 3)``.

    ``6 V = |det(b - a, c - a, d - a)|``; corner ``i`` lies ``6 V / (2 A_i)`` from the plane of
    the opposite triangle of area ``A_i``.
    """
    a, b, c, d = (quads[..., i, :] for i in range(4))
    six_v = np.abs(np.einsum("...i,...i", b - a, np.cross(c - a, d - a)))
    twice_area = np.stack(
        [
            np.linalg.norm(np.cross(c - b, d - b), axis=-1),
            np.linalg.norm(np.cross(c - a, d - a), axis=-1),
            np.linalg.norm(np.cross(b - a, d - a), axis=-1),
            np.linalg.norm(np.cross(b - a, c - a), axis=-1),
        ],
        axis=-1,
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        dist = np.where(twice_area > 0.0, six_v[..., None] / twice_area, 0.0)
    return dist.max(axis=-1)


def _shape(near, far, ndim: int, what: str):
    near = np.asarray(near, dtype=float)
    far = np.asarray(far, dtype=float)
    if near.shape != far.shape:
        raise GeometryError(
            f"near and far must have the same shape, got {near.shape} and {far.shape}"
        )
    if near.ndim != ndim or near.shape[-1] != 3 or near.shape[-2] < 2 or near.shape[-3] < 1:
        raise GeometryError(f"near and far must have shape {what}, got {near.shape}")
    return near, far


def _options(solver: str, tr_solver: str, max_nfev, ftol, xtol, gtol) -> dict:
    """Checked solver options (``tr_solver="auto"`` is ``"exact"`` for LM).

    Tolerances as scipy takes them: ``None`` or ``>= 0`` (``None`` or below the machine
    epsilon disables a test), at least one of them above the machine epsilon.
    """
    if solver not in ("lm", "scipy"):
        raise CCUError(f"solver must be 'lm' or 'scipy', got {solver!r}")
    if tr_solver not in ("auto", "exact", "lsmr"):
        raise CCUError(f"tr_solver must be 'auto', 'exact' or 'lsmr', got {tr_solver!r}")
    if max_nfev is not None and (
        isinstance(max_nfev, bool) or not isinstance(max_nfev, (int, np.integer)) or max_nfev < 1
    ):
        raise CCUError(f"max_nfev must be None or a positive integer, got {max_nfev!r}")
    tolerances = {"ftol": ftol, "xtol": xtol, "gtol": gtol}
    for name, tol in tolerances.items():
        if tol is not None and not (np.isfinite(tol) and tol >= 0.0):
            raise CCUError(f"{name} must be None or a finite number >= 0, got {tol!r}")
    if all(tol is None or tol < _EPS for tol in tolerances.values()):
        raise CCUError(
            f"at least one of ftol, xtol and gtol must be above the machine epsilon ({_EPS:.2e}): "
            f"with no convergence test the solver could only stop at max_nfev"
        )
    if solver == "lm" and tr_solver == "auto":
        tr_solver = "exact"
    return {"solver": solver, "tr_solver": tr_solver, "max_nfev": max_nfev, **tolerances}


def _result(problem, near, far, base, pos, out, solver: str) -> Relaxation:
    """Measure a solved state: strains, planarity and displacements before and after."""
    init_near, init_far = problem.plates(base)
    out_near, out_far = problem.plates(pos)
    strain = quad_lengths(out_near, out_far) / problem.ref_all - 1.0
    init_strain = quad_lengths(init_near, init_far) / problem.ref_all - 1.0
    planarity = _vertex_plane_distance(quad_corners(out_near, out_far)).max(axis=1)
    init_planarity = _vertex_plane_distance(quad_corners(init_near, init_far)).max()
    moved = np.maximum(
        np.linalg.norm(out_near - near, axis=-1).max(axis=1),
        np.linalg.norm(out_far - far, axis=-1).max(axis=1),
    )
    per_plate = np.abs(strain).max(axis=(1, 2))
    return Relaxation(
        near=out_near,
        far=out_far,
        strain=strain,
        max_strain=float(per_plate.max()),
        max_strain_per_plate=per_plate,
        quad_planarity=float(planarity.max()),
        quad_planarity_per_plate=planarity,
        displacement=float(moved.max()),
        displacement_per_plate=moved,
        initial_max_strain=float(np.abs(init_strain).max()),
        initial_quad_planarity=float(init_planarity),
        initial_hinge_gap=problem.hinge_gap(near, far),
        cost=out["cost"],
        optimality=out["optimality"],
        nfev=out["nfev"],
        njev=out["njev"],
        status=out["status"],
        message=out["message"],
        converged=out["status"] > 0,
        fixed=problem.fixed,
        solver=solver,
    )


def _relax_one(problem, near, far, options: dict) -> Relaxation:
    near = np.asarray(near, dtype=float)
    far = np.asarray(far, dtype=float)
    base, pos, out = problem.run(near, far, **options)
    return _result(problem, near, far, base, pos, out, options["solver"])


def relax(
    near,
    far,
    reference_lengths,
    links,
    *,
    fixed=(0,),
    planarity_weight: float = 1.0,
    ftol: float = SOLVER,
    xtol: float = SOLVER,
    gtol: float = SOLVER,
    max_nfev: int = 200,
    tr_solver: str = "auto",
    solver: str = "lm",
) -> Relaxation:
    """Relax placed plates towards isometry with their cut patterns (least squares).

    Parameters
    ----------
    near, far : (p, n + 1, 3) float
        Kinematic guess: near (crease-side) and far boundary of every plate. Quad ``j`` of a
        plate is ``near[j], near[j + 1], far[j + 1], far[j]``.
    reference_lengths : (p, n, 6) float
        Design lengths of every quad: sides ab, bc, cd, da and diagonals ac, bd (the order of
        ``compas_ccu.strips.intrinsics.quad_lengths``); all positive.
    links : list of (int, int, str)
        ``(plate, parent, boundary)`` for every non-leading plate ``1 ... p - 1``: the plate's
        near boundary is the parent's ``"near"`` or ``"far"`` boundary (vertex ``j`` to vertex
        ``j``); parents come before their plates. :func:`links_from_mechanism` reads them off a
        mechanism.
    fixed : sequence of int
        Plates held in place (default: the leading plate 0, whose kinematics is exact), with
        every crease vertex they share; at least one (it removes the rigid motions). Their quads
        add no residuals.
    planarity_weight : float
        Weight ``w >= 0`` of the quad planarity residuals against the strains (module docs).
    ftol, xtol, gtol, max_nfev
        Convergence tests: relative cost reduction (``ftol``), step length relative to the
        unknowns (``xtol``), largest gradient component ``|J^T r|`` (``gtol``); at most
        ``max_nfev`` residual evaluations (``None``: ``100 x`` the number of unknowns), after
        which the result is reported as not converged. ``"lm"`` applies them as
        `levenberg_marquardt.termination` says (MINPACK's cost test), ``"scipy"`` as
        :func:`scipy.optimize.least_squares` does. ``None`` disables a test; at least one
        must stay above the machine epsilon.
    tr_solver : {"auto", "exact", "lsmr"}
        How the linear subproblem of a step is solved. ``"exact"``: directly (``solver="lm"``:
        banded Cholesky of the damped normal equations; ``"scipy"``: dense SVD); ``"lsmr"``:
        iteratively by LSMR (slow: ~1,000 iterations a step on the catalog designs).
        ``"auto"``: ``"exact"`` for ``"lm"``; for ``"scipy"`` dense ``"exact"`` up to 300
        unknowns and ``"lsmr"`` above.
    solver : {"lm", "scipy"}
        ``"lm"`` (default): Levenberg-Marquardt with a direct banded solve (module docs);
        ``"scipy"``: :func:`scipy.optimize.least_squares` (trust region reflective,
        ``x_scale="jac"``), the reference it was checked against (same residuals to the
        solver tolerance, 20-170 times slower on the catalog designs).

    Returns
    -------
    Relaxation

    Raises
    ------
    GeometryError
        Inconsistent shapes, a link to an unknown plate, a plate before its parent, a missing or
        duplicate link, non-positive reference lengths, a degenerate quad in the guess.
    CCUError
        An invalid solver parameter.

    Examples
    --------
    The cone pair of ``examples/cone.toml`` with the far edges of plate 1 cut 0.1 % long: the
    relaxation spreads the misfit over the free plate's quads:

    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> states = model.mechanism.deploy(np.radians([20.0]))
    >>> ref = model.reference_lengths.copy()
    >>> ref[1, :, 2] *= 1.001
    >>> result = relax(states.near[0], states.far[0], ref, links_from_mechanism(model.mechanism))
    >>> result.converged, round(result.initial_max_strain, 6), round(result.max_strain, 6)
    (True, 0.000999, 5e-06)
    """
    options = _options(solver, tr_solver, max_nfev, ftol, xtol, gtol)
    near, far = _shape(near, far, 3, "(p, n + 1, 3)")
    p, n = near.shape[0], near.shape[1] - 1
    problem = RelaxationProblem(p, n, reference_lengths, links, fixed, planarity_weight)
    return _relax_one(problem, near, far, options)


def relax_states(
    near,
    far,
    reference_lengths,
    links,
    *,
    fixed=(0,),
    planarity_weight: float = 1.0,
    ftol: float = SOLVER,
    xtol: float = SOLVER,
    gtol: float = SOLVER,
    max_nfev: int = 200,
    tr_solver: str = "auto",
    solver: str = "lm",
) -> list:
    """Relax ``k`` states independently (same plates, links and options), see :func:`relax`.

    The index arrays, the Jacobian's sparsity pattern and the banded ordering are built once
    for all states.

    Parameters
    ----------
    near, far : (k, p, n + 1, 3) float
        E.g. ``MechanismStates.near`` and ``.far``.
    reference_lengths, links, fixed, planarity_weight, ftol, xtol, gtol, max_nfev
        As for :func:`relax`.
    tr_solver, solver
        As for :func:`relax`.

    Returns
    -------
    list of Relaxation
        One per state.

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> states = model.mechanism.deploy(np.radians([20.0, 30.0]))
    >>> ref = model.reference_lengths.copy()
    >>> ref[1, :, 2] *= 1.001
    >>> results = relax_states(states.near, states.far, ref, links_from_mechanism(model.mechanism))
    >>> [(r.converged, round(r.max_strain, 6)) for r in results]
    [(True, 5e-06), (True, 5e-06)]
    """
    options = _options(solver, tr_solver, max_nfev, ftol, xtol, gtol)
    near, far = _shape(near, far, 4, "(k, p, n + 1, 3)")
    p, n = near.shape[1], near.shape[2] - 1
    problem = RelaxationProblem(p, n, reference_lengths, links, fixed, planarity_weight)
    return [_relax_one(problem, near[k], far[k], options) for k in range(near.shape[0])]
