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
    Levenberg-Marquardt (:func:`_levenberg_marquardt`) with the analytic Jacobian, assembled with
    NumPy per quad as ``(nq, 7, 12)`` blocks. Every step solves the damped normal equations
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
import scipy.sparse as sp
from scipy.linalg import solveh_banded
from scipy.optimize import least_squares
from scipy.sparse.csgraph import reverse_cuthill_mckee
from scipy.sparse.linalg import lsmr

from compas_ccu.errors import CCUError, GeometryError
from compas_ccu.kinematics.plates import boundary_rows
from compas_ccu.strips.intrinsics import QUAD_LENGTH_PAIRS, quad_corners, quad_lengths
from compas_ccu.tolerances import SOLVER, ZERO_LENGTH

__all__ = ["Relaxation", "relax", "relax_states", "links_from_mechanism"]

_PAIRS = QUAD_LENGTH_PAIRS
# number of unknowns up to which the trust-region subproblem is solved densely (exact SVD)
_EXACT_LIMIT = 300
# lsmr tolerances of the sparse subproblem: scipy's default 1e-6 leaves the trust-region
# iteration crawling (max_nfev reached at strains ~1e-3); 1e-12 converges in ~5 iterations
_LSMR_OPTIONS = {"atol": SOLVER, "btol": SOLVER}
# Levenberg-Marquardt: initial damping (relative to the Marquardt scale diag(J^T J)), its floor
# and the ceiling beyond which a step that cannot be computed is given up
_LM_DAMPING = 1e-6
_LM_DAMPING_MIN = 1e-15
_LM_DAMPING_MAX = 1e16
_EPS = float(np.finfo(float).eps)
_MESSAGES = {
    -1: "The damped normal equations could not be solved for any damping.",
    0: "The maximum number of function evaluations is exceeded.",
    1: "`gtol` termination condition is satisfied.",
    2: "`ftol` termination condition is satisfied.",
    3: "`xtol` termination condition is satisfied.",
    4: "Both `ftol` and `xtol` termination conditions are satisfied.",
}


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
    """``(plate, parent, boundary)`` of every non-leading plate of a :class:`Mechanism`."""
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


def _termination(reduction, predicted, cost, step_norm, x_norm, ftol, xtol):
    """Convergence tests on a trial step: status 2 (cost), 3 (step), 4 (both) or None.

    The cost test is MINPACK's: the actual and the predicted reduction of the cost are both
    below ``ftol * cost`` (neither the step nor the linear model can gain more, also when
    round-off rejects the step); the step test is scipy's, ``|step| < xtol (xtol + |x|)``,
    for rejected steps too (the step has become negligible).
    """
    cost_met = abs(reduction) < ftol * cost and predicted < ftol * cost
    step_met = step_norm < xtol * (xtol + x_norm)
    if cost_met and step_met:
        return 4
    if cost_met:
        return 2
    if step_met:
        return 3
    return None


def _levenberg_marquardt(residuals, linearise, solve, x0, *, ftol, xtol, gtol, max_nfev):
    """Minimise ``0.5 |r(x)|^2`` by Levenberg-Marquardt (Marquardt scaling, Nielsen damping).

    Every step solves ``(J^T J + lam D) step = -J^T r`` with ``D`` the running maximum of
    ``diag(J^T J)`` (MINPACK's scaling, invariant to the units of the unknowns) and accepts it
    when the cost decreases. The damping follows the gain ratio ``rho`` = actual / predicted
    reduction (Nielsen 1999): on success ``lam *= max(1/3, 1 - (2 rho - 1)^3)``, otherwise
    ``lam *= nu``, ``nu *= 2``. It stops with scipy's status codes: ``1`` when
    ``max |J^T r| < gtol``, ``2`` / ``3`` / ``4`` by :func:`_termination`, ``0`` after
    ``max_nfev`` residual evaluations, ``-1`` when ``solve`` fails even for damping
    ``_LM_DAMPING_MAX``.

    Parameters
    ----------
    residuals : callable, (n,) -> (M,) float
        Residuals; a trial step with non-finite residuals is rejected (more damping).
    linearise : callable, ((n,) x, (M,) r) -> (system, (n,) g, (n,) diag)
        Gauss-Newton data at ``x`` with residuals ``r``: whatever ``solve`` takes, the gradient
        ``J^T r`` and ``diag(J^T J)``.
    solve : callable, (system, (n,) g, float lam, (n,) D) -> (n,) step
        Solves ``(J^T J + lam diag(D)) step = -g``; raises ``numpy.linalg.LinAlgError`` if it
        cannot (e.g. a Cholesky factor that is not positive definite).
    x0 : (n,) float
    ftol, xtol, gtol : float or None
        Tolerances of the cost and step tests (:func:`_termination`) and of the gradient
        test; ``None`` disables a test.
    max_nfev : int

    Returns
    -------
    x : (n,) float
    outcome : dict
        ``cost``, ``optimality`` (``max |J^T r|``), ``nfev``, ``njev``, ``status``, ``message``.
    """
    ftol, xtol, gtol = (0.0 if t is None else float(t) for t in (ftol, xtol, gtol))
    x = np.array(x0, dtype=float)
    r = residuals(x)
    cost = 0.5 * float(r @ r)
    system, g, diag = linearise(x, r)
    nfev = njev = 1
    scale = np.where(diag > 0.0, diag, 1.0)
    lam, nu = _LM_DAMPING, 2.0
    status = None
    while status is None:
        if np.abs(g).max() < gtol:
            status = 1
            break
        if nfev >= max_nfev:
            status = 0
            break
        accepted = False
        while status is None and not accepted and nfev < max_nfev:
            try:
                step = solve(system, g, lam, scale)
            except np.linalg.LinAlgError:
                if lam >= _LM_DAMPING_MAX:
                    status = -1
                lam, nu = min(lam * nu, _LM_DAMPING_MAX), 2.0 * nu
                continue
            x_new = x + step
            r_new = residuals(x_new)
            nfev += 1
            if not np.all(np.isfinite(r_new)):
                lam, nu = min(lam * nu, _LM_DAMPING_MAX), 2.0 * nu
                continue
            cost_new = 0.5 * float(r_new @ r_new)
            reduction = cost - cost_new
            predicted = 0.5 * float(lam * (scale * step) @ step - g @ step)
            ratio = reduction / predicted if predicted > 0.0 else 0.0
            if reduction > 0.0:
                accepted = True
                shrink = max(1.0 / 3.0, 1.0 - (2.0 * min(ratio, 1.0) - 1.0) ** 3)
                lam = max(lam * shrink, _LM_DAMPING_MIN)
                nu = 2.0
            else:
                lam, nu = min(lam * nu, _LM_DAMPING_MAX), 2.0 * nu
            status = _termination(
                reduction,
                predicted,
                cost,
                float(np.linalg.norm(step)),
                float(np.linalg.norm(x)),
                ftol,
                xtol,
            )
        if accepted:
            x, r, cost = x_new, r_new, cost_new
            system, g, diag = linearise(x, r)
            njev += 1
            scale = np.maximum(scale, diag)
    outcome = {
        "cost": cost,
        "optimality": float(np.abs(g).max()),
        "nfev": nfev,
        "njev": njev,
        "status": status,
        "message": _MESSAGES[status],
    }
    return x, outcome


class _Problem:
    """Index arrays, sparsity pattern and residual/Jacobian of one relaxation problem."""

    def __init__(self, p: int, n: int, reference_lengths, links, fixed, planarity_weight):
        ref = np.asarray(reference_lengths, dtype=float)
        if ref.shape != (p, n, 6):
            raise GeometryError(
                f"reference_lengths must have shape (p, n, 6) = {(p, n, 6)} to match near/far, "
                f"got {ref.shape}"
            )
        if not np.all(np.isfinite(ref)) or np.any(ref <= 0.0):
            bad = np.argwhere(~(np.isfinite(ref) & (ref > 0.0)))[0]
            raise GeometryError(
                f"reference lengths must be finite and positive, got {ref[tuple(bad)]!r} at "
                f"plate {bad[0]}, quad {bad[1]}, length {bad[2]} (0-3 sides ab, bc, cd, da; "
                f"4-5 diagonals ac, bd)"
            )
        weight = float(planarity_weight)
        if not np.isfinite(weight) or weight < 0.0:
            raise CCUError(f"planarity_weight must be finite and >= 0, got {planarity_weight!r}")
        fixed = tuple(sorted({int(i) for i in np.atleast_1d(np.asarray(fixed, dtype=int))}))
        if not fixed:
            raise CCUError(
                "fixed must name at least one plate: with none held the rigid motions of the "
                "whole structure are free and the problem has no unique solution"
            )
        for i in fixed:
            if not 0 <= i < p:
                raise GeometryError(f"fixed plate {i} does not exist (plates 0 ... {p - 1})")
        m = n + 1
        self.p, self.n, self.m = p, n, m
        self.fixed = fixed
        # global vertex id: plate * 2m + (near 0..n | far m..2m-1); rep = id of the vertex it is
        # merged into (a plate's near boundary into its parent's boundary, through chains)
        rep = np.arange(p * 2 * m).reshape(p, 2 * m)
        parents = np.full(p, -1)
        self.boundary_of = {}
        seen = set()
        for link in sorted(self._check_links(links, p), key=lambda t: t[0]):
            plate, parent, boundary = link
            if plate in seen:
                raise GeometryError(f"plate {plate} has more than one link")
            seen.add(plate)
            parents[plate] = parent
            self.boundary_of[plate] = boundary
            rows = boundary_rows(np.arange(m), np.arange(m, 2 * m), boundary)[0]
            rep[plate, :m] = rep[parent, rows]
        missing = sorted(set(range(1, p)) - seen)
        if missing:
            raise GeometryError(
                f"plates {missing} have no link: every non-leading plate needs "
                f"(plate, parent, boundary)"
            )
        self.parents = parents
        self.rep = rep
        nodes, node_of = np.unique(rep.ravel(), return_inverse=True)
        self.node_rep = nodes  # (N,) global vertex id whose guess position a node starts at
        self.node_of = node_of.reshape(p, 2 * m)  # (p, 2m) node of every plate vertex
        held = np.zeros(nodes.size, dtype=bool)
        held[self.node_of[list(fixed)].ravel()] = True
        self.held = held
        free_index = np.full(nodes.size, -1)
        free_index[~held] = np.arange(int((~held).sum()))
        self.free_index = free_index
        self.nfree = int((~held).sum())
        # quads of the non-fixed plates: (nq, 4) nodes a, b, c, d
        moving = np.array([i for i in range(p) if i not in fixed], dtype=int)
        self.moving = moving
        j = np.arange(n)
        local = np.stack([j, j + 1, m + j + 1, m + j], axis=-1)  # (n, 4)
        self.quads = self.node_of[moving][:, local].reshape(-1, 4)
        self.ref_all = ref
        self.ref = ref[moving].reshape(-1, 6)  # (nq, 6)
        self.scale = np.sqrt(self.ref[:, 4] * self.ref[:, 5])  # (nq,) diagonal scale l0
        self.weight = weight
        self._pattern()
        if self.nfree:
            self._normal_pattern()

    @staticmethod
    def _check_links(links, p: int) -> list:
        out = []
        for link in links:
            try:
                plate, parent, boundary = link
            except (TypeError, ValueError):
                raise GeometryError(
                    f"a link must be (plate, parent, boundary), got {link!r}"
                ) from None
            plate, parent = int(plate), int(parent)
            if not 0 < plate < p:
                raise GeometryError(
                    f"link {link!r}: plate {plate} does not exist or is the leading plate "
                    f"(linked plates are 1 ... {p - 1})"
                )
            if not 0 <= parent < p:
                raise GeometryError(
                    f"link {link!r}: parent {parent} does not exist (plates 0 ... {p - 1})"
                )
            if parent >= plate:
                raise GeometryError(
                    f"link {link!r}: plate {plate} comes before (or is) its parent {parent}; "
                    f"every plate must come after its parent"
                )
            if boundary not in ("near", "far"):
                raise GeometryError(
                    f"link {link!r}: boundary must be 'near' or 'far', got {boundary!r}"
                )
            out.append((plate, parent, boundary))
        return out

    def _pattern(self) -> None:
        """Rows and columns of the Jacobian and the map from dense blocks to CSR data."""
        nq = self.quads.shape[0]
        self.nres = 7 * nq
        xyz = np.arange(3)
        # length rows: (nq, 6, 2, 3) -- row q * 6 + e, the two nodes of pair e, x y z
        len_nodes = self.quads[:, _PAIRS]  # (nq, 6, 2)
        len_rows = np.broadcast_to(np.arange(6 * nq).reshape(nq, 6, 1, 1), (nq, 6, 2, 3))
        len_cols = 3 * self.free_index[len_nodes][..., None] + xyz
        len_free = np.broadcast_to((self.free_index[len_nodes] >= 0)[..., None], (nq, 6, 2, 3))
        # planarity rows: (nq, 4, 3)
        pl_rows = np.broadcast_to((6 * nq + np.arange(nq)).reshape(nq, 1, 1), (nq, 4, 3))
        pl_cols = 3 * self.free_index[self.quads][..., None] + xyz
        pl_free = np.broadcast_to((self.free_index[self.quads] >= 0)[..., None], (nq, 4, 3))
        rows = np.concatenate([len_rows.ravel(), pl_rows.ravel()])
        cols = np.concatenate([len_cols.ravel(), pl_cols.ravel()])
        keep = np.concatenate([len_free.ravel(), pl_free.ravel()])
        rows, cols = rows[keep], cols[keep]
        order = np.lexsort((cols, rows))
        self.select = np.flatnonzero(keep)[order]  # dense block entries -> CSR data
        self.indices = cols[order]
        self.indptr = np.r_[0, np.cumsum(np.bincount(rows, minlength=self.nres))]

    # -- state <-> unknowns ----------------------------------------------------------------
    def start(self, near: np.ndarray, far: np.ndarray) -> np.ndarray:
        """(N, 3) node positions of a guess (merged vertices take the parent's position)."""
        verts = np.concatenate([near, far], axis=1).reshape(-1, 3)
        return verts[self.node_rep]

    def positions(self, x: np.ndarray, base: np.ndarray) -> np.ndarray:
        pos = base.copy()
        pos[~self.held] = x.reshape(-1, 3)
        return pos

    def plates(self, pos: np.ndarray):
        verts = pos[self.node_of]  # (p, 2m, 3)
        return verts[:, : self.m], verts[:, self.m :]

    # -- residuals and Jacobian ------------------------------------------------------------
    def _planarity_terms(self, corners: np.ndarray):
        a, b, c, d = (corners[:, i] for i in range(4))
        w, u, v = b - a, c - a, d - b
        cross = np.cross(u, v)
        s = np.linalg.norm(cross, axis=-1)
        det = np.einsum("qi,qi->q", w, cross)
        return w, u, v, cross, s, det

    def quad_residuals(self, pos: np.ndarray) -> np.ndarray:
        """(nq, 7) residuals of every quad of the non-fixed plates at node positions ``pos``.

        ``pos`` is (N, 3); the columns are the six strains (sides ab, bc, cd, da, diagonals ac,
        bd) and the weighted planarity ``w h / l0`` (module docs).
        """
        corners = pos[self.quads]  # (nq, 4, 3)
        lengths = np.linalg.norm(corners[:, _PAIRS[:, 1]] - corners[:, _PAIRS[:, 0]], axis=-1)
        out = np.empty((corners.shape[0], 7))
        out[:, :6] = (lengths - self.ref) / self.ref
        *_, s, det = self._planarity_terms(corners)
        out[:, 6] = self.weight * det / (s * self.scale)
        return out

    def residuals(self, pos: np.ndarray) -> np.ndarray:
        """(7 nq,) residual vector, the rows of :meth:`jacobian`: all strains, then planarities."""
        r = self.quad_residuals(pos)
        return np.concatenate([r[:, :6].ravel(), r[:, 6]])

    def _blocks(self, pos: np.ndarray):
        """Analytic derivatives at ``pos`` (N, 3), per quad.

        Returns ``(nq, 6, 2, 3)`` of every strain with respect to the two nodes of its pair and
        ``(nq, 4, 3)`` of the planarity with respect to the corners a, b, c, d.
        """
        corners = pos[self.quads]
        edge = corners[:, _PAIRS[:, 1]] - corners[:, _PAIRS[:, 0]]  # (nq, 6, 3)
        lengths = np.linalg.norm(edge, axis=-1)
        g = edge / (lengths * self.ref)[..., None]  # d strain / d (second vertex)
        len_block = np.stack([-g, g], axis=2)  # (nq, 6, 2, 3)
        w, u, v, cross, s, det = self._planarity_terms(corners)
        s_ = s[:, None]
        det_ = det[:, None]
        dw = cross / s_
        du = np.cross(v, w) / s_ - det_ * np.cross(v, cross) / s_**3
        dv = np.cross(w, u) / s_ - det_ * np.cross(cross, u) / s_**3
        pl_block = np.stack([-(dw + du), dw - dv, du, dv], axis=1)  # (nq, 4, 3)
        pl_block *= (self.weight / self.scale)[:, None, None]
        return len_block, pl_block

    def jacobian(self, pos: np.ndarray) -> sp.csr_matrix:
        """(7 nq, 3 nfree) sparse Jacobian of :meth:`residuals`; column ``3 free_index + xyz``."""
        len_block, pl_block = self._blocks(pos)
        data = np.concatenate([len_block.ravel(), pl_block.ravel()])[self.select]
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.nres, 3 * self.nfree))

    def quad_jacobian(self, pos: np.ndarray) -> np.ndarray:
        """(nq, 7, 12) dense Jacobian of :meth:`quad_residuals` per quad.

        Row ``k`` of quad ``q`` is residual ``k`` of that quad; column ``3 i + xyz`` is corner
        ``i`` (a, b, c, d), held corners included (the assembly drops them).
        """
        len_block, pl_block = self._blocks(pos)
        nq = len_block.shape[0]
        out = np.zeros((nq, 7, 4, 3))
        rows = np.arange(6)
        out[:, rows, _PAIRS[:, 0]] = len_block[:, :, 0]
        out[:, rows, _PAIRS[:, 1]] = len_block[:, :, 1]
        out[:, 6] = pl_block
        return out.reshape(nq, 7, 12)

    # -- banded normal equations -----------------------------------------------------------
    def _normal_pattern(self) -> None:
        """Order the unknowns for a narrow band and map quad blocks into banded storage.

        The free nodes are ordered by reverse Cuthill-McKee on their quad adjacency; for a
        stack of strips that is crease vertex by crease vertex across the plates, so ``J^T J``
        couples only unknowns ``band`` apart (about 3 x the number of plate boundaries, against
        3 x the vertices of a boundary in the natural plate-by-plate order). ``order`` (nfree,)
        is the node of every unknown triple ``x[3 k : 3 k + 3]``.
        """
        nq, nfree = self.quads.shape[0], self.nfree
        free = self.free_index[self.quads]  # (nq, 4), -1: held
        a = np.repeat(free, 4, axis=1).ravel()
        b = np.tile(free, (1, 4)).ravel()
        both = (a >= 0) & (b >= 0)
        graph = sp.csr_matrix((np.ones(int(both.sum())), (a[both], b[both])), shape=(nfree, nfree))
        perm = reverse_cuthill_mckee(graph, symmetric_mode=True)
        rank = np.empty(nfree, dtype=int)
        rank[perm] = np.arange(nfree)
        self.order = np.flatnonzero(~self.held)[perm]
        cols = np.where(free[..., None] >= 0, 3 * rank[free][..., None] + np.arange(3), -1)
        cols = cols.reshape(nq, 12)  # unknown of every quad corner coordinate, -1: held
        row = np.broadcast_to(cols[:, :, None], (nq, 12, 12))
        col = np.broadcast_to(cols[:, None, :], (nq, 12, 12))
        lower = (row >= 0) & (col >= 0) & (row >= col)
        size = 3 * nfree
        self.band = int((row - col)[lower].max())
        self.band_select = np.flatnonzero(lower)  # entries of the (nq, 12, 12) blocks kept
        self.band_slot = (row - col)[lower] * size + col[lower]  # in (band + 1, size) storage
        self.grad_select = np.flatnonzero(cols.ravel() >= 0)
        self.grad_slot = cols.ravel()[self.grad_select]
        # column of :meth:`jacobian` of every unknown (the order of the iterative path)
        self.columns = (3 * self.free_index[self.order][:, None] + np.arange(3)).ravel()

    def normal_equations(self, pos: np.ndarray, r: np.ndarray):
        """Banded Gauss-Newton matrix ``J^T J`` and gradient ``J^T r`` in the unknown order.

        Parameters
        ----------
        pos : (N, 3) float
            Node positions.
        r : (nq, 7) float
            :meth:`quad_residuals` at ``pos``.

        Returns
        -------
        ab : (band + 1, 3 nfree) float
            Lower banded storage, ``ab[i - j, j] = (J^T J)[i, j]`` for ``i >= j`` (the form of
            :func:`scipy.linalg.solveh_banded` with ``lower=True``).
        g : (3 nfree,) float
        """
        jq = self.quad_jacobian(pos)  # (nq, 7, 12)
        size = 3 * self.nfree
        aq = np.matmul(jq.transpose(0, 2, 1), jq)  # (nq, 12, 12)
        gq = np.einsum("qkc,qk->qc", jq, r)  # (nq, 12)
        ab = np.bincount(
            self.band_slot,
            weights=aq.ravel()[self.band_select],
            minlength=(self.band + 1) * size,
        )
        g = np.bincount(self.grad_slot, weights=gq.ravel()[self.grad_select], minlength=size)
        return ab.reshape(self.band + 1, size), g

    def check_guess(self, pos: np.ndarray) -> None:
        """Refuse quads whose diagonals are parallel (the planarity residual is undefined)."""
        if self.quads.shape[0] == 0:
            return
        *_, s, _ = self._planarity_terms(pos[self.quads])
        bad = ~(s > ZERO_LENGTH * self.scale**2)
        if bad.any():
            q = int(np.flatnonzero(bad)[0])
            raise GeometryError(
                f"plate {int(self.moving[q // self.n])}, quad {q % self.n}: the diagonals of "
                f"the guess are parallel or of zero length (degenerate quad), cannot relax"
            )

    # -- solve -----------------------------------------------------------------------------
    def _solve_lm(self, base, *, ftol, xtol, gtol, max_nfev, tr_solver):
        """Levenberg-Marquardt from the start ``base`` (N, 3); see :func:`_levenberg_marquardt`.

        ``tr_solver`` ``"exact"``: banded Cholesky of the damped normal equations;
        ``"lsmr"``: LSMR on the damped least-squares problem (iterative, no ``J^T J``).
        Returns the node positions and the solver outcome.
        """

        def positions(x):
            pos = base.copy()
            pos[self.order] = x.reshape(-1, 3)
            return pos

        def residuals(x):
            return self.quad_residuals(positions(x)).ravel()

        if tr_solver == "lsmr":

            def linearise(x, r):
                r = r.reshape(-1, 7)
                r = np.concatenate([r[:, :6].ravel(), r[:, 6]])  # the rows of jacobian()
                jac = self.jacobian(positions(x))[:, self.columns]
                diag = np.asarray(jac.multiply(jac).sum(axis=0)).ravel()
                return (jac, r), jac.T @ r, diag

            def solve(system, g, damping, scale):
                jac, r = system
                c = np.sqrt(scale)  # y = c * step: (J / c) y ~ -r, damped by sqrt(damping)
                y = lsmr(jac @ sp.diags(1.0 / c), -r, damp=np.sqrt(damping), **_LSMR_OPTIONS)[0]
                return y / c

        else:

            def linearise(x, r):
                ab, g = self.normal_equations(positions(x), r.reshape(-1, 7))
                return ab, g, ab[0].copy()

            def solve(ab, g, damping, scale):
                ab = ab.copy()
                ab[0] += damping * scale
                return solveh_banded(ab, -g, lower=True, overwrite_ab=True, check_finite=False)

        x0 = base[self.order].ravel()
        if max_nfev is None:
            max_nfev = 100 * x0.size  # scipy's default
        x, out = _levenberg_marquardt(
            residuals,
            linearise,
            solve,
            x0,
            ftol=ftol,
            xtol=xtol,
            gtol=gtol,
            max_nfev=max_nfev,
        )
        return positions(x), out

    def _solve_scipy(self, base, *, ftol, xtol, gtol, max_nfev, tr_solver):
        """:func:`scipy.optimize.least_squares` (trf) from ``base`` (N, 3), the reference path."""
        solver = tr_solver
        if solver == "auto":
            solver = "exact" if 3 * self.nfree <= _EXACT_LIMIT else "lsmr"

        def fun(x):
            return self.residuals(self.positions(x, base))

        if solver == "exact":

            def jac(x):
                return self.jacobian(self.positions(x, base)).toarray()

        else:

            def jac(x):
                return self.jacobian(self.positions(x, base))

        sol = least_squares(
            fun,
            base[~self.held].ravel(),
            jac=jac,
            method="trf",
            tr_solver=solver,
            x_scale="jac",
            ftol=ftol,
            xtol=xtol,
            gtol=gtol,
            max_nfev=max_nfev,
            tr_options=_LSMR_OPTIONS if solver == "lsmr" else {},
        )
        out = {
            "cost": float(sol.cost),
            "optimality": float(sol.optimality),
            "nfev": int(sol.nfev),
            "njev": int(sol.njev or 0),
            "status": int(sol.status),
            "message": str(sol.message),
        }
        return self.positions(sol.x, base), out

    def solve(self, near, far, *, ftol, xtol, gtol, max_nfev, tr_solver, solver) -> Relaxation:
        near = np.asarray(near, dtype=float)
        far = np.asarray(far, dtype=float)
        if not (np.all(np.isfinite(near)) and np.all(np.isfinite(far))):
            raise GeometryError("near and far must be finite (found nan or inf)")
        base = self.start(near, far)
        self.check_guess(base)
        gap = 0.0
        for plate, boundary in self.boundary_of.items():
            parent = self.parents[plate]
            hinge = boundary_rows(near[parent], far[parent], boundary)[0]
            gap = max(gap, float(np.linalg.norm(near[plate] - hinge, axis=-1).max()))
        init_near, init_far = self.plates(base)
        if self.nfree == 0:
            pos = base
            out = {
                "cost": 0.0,
                "optimality": 0.0,
                "nfev": 0,
                "njev": 0,
                "status": 1,
                "message": "nothing to relax: every vertex is held",
            }
            if self.quads.shape[0]:
                out["cost"] = 0.5 * float(np.sum(self.residuals(base) ** 2))
        else:
            run = self._solve_lm if solver == "lm" else self._solve_scipy
            pos, out = run(
                base, ftol=ftol, xtol=xtol, gtol=gtol, max_nfev=max_nfev, tr_solver=tr_solver
            )
        out_near, out_far = self.plates(pos)
        strain = quad_lengths(out_near, out_far) / self.ref_all - 1.0
        init_strain = quad_lengths(init_near, init_far) / self.ref_all - 1.0
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
            initial_hinge_gap=gap,
            cost=out["cost"],
            optimality=out["optimality"],
            nfev=out["nfev"],
            njev=out["njev"],
            status=out["status"],
            message=out["message"],
            converged=out["status"] > 0,
            fixed=self.fixed,
            solver=solver,
        )


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
        :func:`_termination` says (MINPACK's cost test), ``"scipy"`` as
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
    """
    options = _options(solver, tr_solver, max_nfev, ftol, xtol, gtol)
    near, far = _shape(near, far, 3, "(p, n + 1, 3)")
    p, n = near.shape[0], near.shape[1] - 1
    problem = _Problem(p, n, reference_lengths, links, fixed, planarity_weight)
    return problem.solve(near, far, **options)


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
    """
    options = _options(solver, tr_solver, max_nfev, ftol, xtol, gtol)
    near, far = _shape(near, far, 4, "(k, p, n + 1, 3)")
    p, n = near.shape[1], near.shape[2] - 1
    problem = _Problem(p, n, reference_lengths, links, fixed, planarity_weight)
    return [problem.solve(near[k], far[k], **options) for k in range(near.shape[0])]
