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
second order. The problem is solved by :func:`scipy.optimize.least_squares` (trust region
reflective) with an analytic sparse Jacobian assembled with NumPy from the quad index arrays.

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
from scipy.optimize import least_squares

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
        Final gradient norm (infinity norm, as reported by scipy).
    nfev, njev : int
        Residual and Jacobian evaluations.
    status : int
        scipy's termination status (``> 0``: a convergence test was met; ``0``: ``max_nfev``
        reached).
    message : str
    converged : bool
        ``status > 0``.
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

    def residuals(self, pos: np.ndarray) -> np.ndarray:
        corners = pos[self.quads]  # (nq, 4, 3)
        lengths = np.linalg.norm(corners[:, _PAIRS[:, 1]] - corners[:, _PAIRS[:, 0]], axis=-1)
        strain = (lengths - self.ref) / self.ref
        *_, s, det = self._planarity_terms(corners)
        planar = self.weight * det / (s * self.scale)
        return np.concatenate([strain.ravel(), planar])

    def jacobian(self, pos: np.ndarray) -> sp.csr_matrix:
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
        data = np.concatenate([len_block.ravel(), pl_block.ravel()])[self.select]
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.nres, 3 * self.nfree))

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
    def solve(self, near, far, *, ftol, xtol, gtol, max_nfev, tr_solver) -> Relaxation:
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
            pos, cost, opt, nfev, njev, status = base, 0.0, 0.0, 0, 0, 1
            message = "nothing to relax: every vertex is held"
            if self.quads.shape[0]:
                cost = 0.5 * float(np.sum(self.residuals(base) ** 2))
        else:
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
            pos = self.positions(sol.x, base)
            cost, opt = float(sol.cost), float(sol.optimality)
            nfev, njev = int(sol.nfev), int(sol.njev or 0)
            status, message = int(sol.status), str(sol.message)
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
            cost=cost,
            optimality=opt,
            nfev=nfev,
            njev=njev,
            status=status,
            message=message,
            converged=status > 0,
            fixed=self.fixed,
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


def _tr_solver(tr_solver: str) -> str:
    if tr_solver not in ("auto", "exact", "lsmr"):
        raise CCUError(f"tr_solver must be 'auto', 'exact' or 'lsmr', got {tr_solver!r}")
    return tr_solver


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
        Passed to :func:`scipy.optimize.least_squares`.
    tr_solver : {"auto", "exact", "lsmr"}
        Trust-region subproblem solver; ``"auto"``: dense ``"exact"`` up to 300 unknowns, the
        sparse iterative ``"lsmr"`` above.

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
    near, far = _shape(near, far, 3, "(p, n + 1, 3)")
    p, n = near.shape[0], near.shape[1] - 1
    problem = _Problem(p, n, reference_lengths, links, fixed, planarity_weight)
    return problem.solve(
        near,
        far,
        ftol=ftol,
        xtol=xtol,
        gtol=gtol,
        max_nfev=max_nfev,
        tr_solver=_tr_solver(tr_solver),
    )


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
) -> list:
    """Relax ``k`` states independently (same plates, links and options), see :func:`relax`.

    The index arrays and the Jacobian's sparsity pattern are built once for all states.

    Parameters
    ----------
    near, far : (k, p, n + 1, 3) float
        E.g. ``MechanismStates.near`` and ``.far``.
    reference_lengths, links, fixed, planarity_weight, ftol, xtol, gtol, max_nfev, tr_solver
        As for :func:`relax`.

    Returns
    -------
    list of Relaxation
        One per state.
    """
    near, far = _shape(near, far, 4, "(k, p, n + 1, 3)")
    p, n = near.shape[1], near.shape[2] - 1
    problem = _Problem(p, n, reference_lengths, links, fixed, planarity_weight)
    tr_solver = _tr_solver(tr_solver)
    return [
        problem.solve(
            near[k], far[k], ftol=ftol, xtol=xtol, gtol=gtol, max_nfev=max_nfev, tr_solver=tr_solver
        )
        for k in range(near.shape[0])
    ]
