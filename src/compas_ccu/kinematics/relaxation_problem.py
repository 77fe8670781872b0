"""The least-squares problem of a relaxation: unknowns, residuals, Jacobian, normal equations.

docs/kinematics.md, relaxation; the model is stated in :mod:`compas_ccu.kinematics.relaxation`.
:class:`RelaxationProblem` holds what one set of plates, links and held plates fixes (the
merged crease vertices, the free unknowns, the sparsity pattern of the Jacobian and the banded
reverse Cuthill-McKee ordering of ``J^T J``) and solves one state with Levenberg-Marquardt
(:mod:`compas_ccu.kinematics.levenberg_marquardt`) or :func:`scipy.optimize.least_squares`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.linalg import solveh_banded
from scipy.optimize import least_squares
from scipy.sparse.csgraph import reverse_cuthill_mckee
from scipy.sparse.linalg import lsmr

from compas_ccu.errors import CCUError, GeometryError
from compas_ccu.kinematics.levenberg_marquardt import levenberg_marquardt
from compas_ccu.kinematics.plates import boundary_rows
from compas_ccu.strips.intrinsics import QUAD_LENGTH_PAIRS
from compas_ccu.tolerances import SOLVER, ZERO_LENGTH

__all__ = ["RelaxationProblem"]

_PAIRS = QUAD_LENGTH_PAIRS
#: number of unknowns up to which scipy's trust-region subproblem is solved densely (exact SVD)
EXACT_LIMIT = 300
# lsmr tolerances of the sparse subproblem: scipy's default 1e-6 leaves the trust-region
# iteration crawling (max_nfev reached at strains ~1e-3); 1e-12 converges in ~5 iterations
_LSMR_OPTIONS = {"atol": SOLVER, "btol": SOLVER}


class RelaxationProblem:
    """Index arrays, sparsity pattern and residual/Jacobian of one relaxation problem.

    Examples
    --------
    The problem of two plates of two quads, plate 1 hanging on plate 0's near boundary; the
    reference lengths of a unit square (sides 1, diagonals sqrt 2) fit the placed squares:

    >>> import numpy as np
    >>> ref = np.tile([1.0, 1.0, 1.0, 1.0, np.sqrt(2.0), np.sqrt(2.0)], (2, 2, 1))
    >>> problem = RelaxationProblem(2, 2, ref, [(1, 0, "near")], (0,), 1.0)
    >>> near = np.array([[[0.0, 0, 0], [1, 0, 0], [2, 0, 0]]] * 2)
    >>> far = near + np.array([[[0.0, 1.0, 0.0]], [[0.0, -1.0, 0.0]]])
    >>> pos = problem.start(near, far)
    >>> pos.shape, float(np.abs(problem.residuals(pos)).max()), problem.jacobian(pos).shape
    ((9, 3), 0.0, (14, 9))
    """

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
        """Levenberg-Marquardt from the start ``base`` (N, 3) (:mod:`.levenberg_marquardt`).

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
        x, out = levenberg_marquardt(
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
            solver = "exact" if 3 * self.nfree <= EXACT_LIMIT else "lsmr"

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

    def hinge_gap(self, near: np.ndarray, far: np.ndarray) -> float:
        """Largest distance (m) between a plate's near vertex and its parent's crease vertex."""
        gap = 0.0
        for plate, boundary in self.boundary_of.items():
            parent = self.parents[plate]
            hinge = boundary_rows(near[parent], far[parent], boundary)[0]
            gap = max(gap, float(np.linalg.norm(near[plate] - hinge, axis=-1).max()))
        return gap

    def run(self, near, far, *, ftol, xtol, gtol, max_nfev, tr_solver, solver):
        """Relax one state: the start, the solution and the solver outcome.

        Parameters
        ----------
        near, far : (p, n + 1, 3) float
            The kinematic guess.
        ftol, xtol, gtol, max_nfev, tr_solver, solver
            Checked options (:func:`compas_ccu.kinematics.relaxation.relax`).

        Returns
        -------
        base, positions : (N, 3) float
            The node positions of the start (crease vertices merged) and of the solution.
        outcome : dict
            ``cost``, ``optimality``, ``nfev``, ``njev``, ``status``, ``message``.
        """
        if not (np.all(np.isfinite(near)) and np.all(np.isfinite(far))):
            raise GeometryError("near and far must be finite (found nan or inf)")
        base = self.start(near, far)
        self.check_guess(base)
        if self.nfree == 0:
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
            return base, base, out
        step = self._solve_lm if solver == "lm" else self._solve_scipy
        pos, out = step(
            base, ftol=ftol, xtol=xtol, gtol=gtol, max_nfev=max_nfev, tr_solver=tr_solver
        )
        return base, pos, out
