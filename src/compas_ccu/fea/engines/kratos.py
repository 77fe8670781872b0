"""Kratos Multiphysics backend (primary engine).

Element ``LegacyThickShellCorotationalElement3D4N`` with a plane-stress linear elastic law (the
variant that gives exact displacements *and* moments in the Sze–Liu–Lo roll-up, see
``shared/notes/fe-engines.md``; isotropic only: the wheels ship no orthotropic plane-stress
law); hinges as master–slave constraints on the
three translations; sparse LU; displacement criterion; incremental update static scheme with the
old stiffness in the first iteration (Newton diverges in the first steps of prescribed motion
otherwise). A step that does not converge is cut in halves; the state of the last converged
sub-step is restored by rebuilding the model and replaying the converged history, so the
corotational element state is exactly that of a clean run.
"""

from __future__ import annotations

import contextlib
import json
import os
import time

import numpy as np

from compas_ccu.fea.problem import FEError, FEProblem, FEResult, buckling_steps
from compas_ccu.tolerances import EXACT_RELATIVE, ZERO_LENGTH

__all__ = ["available", "solve"]

ELEMENT = "LegacyThickShellCorotationalElement3D4N"
#: The first property id of the element sections with an offset (after hinges and springs).
OFFSET_PROPERTIES = 1_000_000
_KM = None
#: Kratos' OpenMP threads unless ``OMP_NUM_THREADS`` is set: one. The time of a solve is the
#: single-threaded sparse LU; a second thread only assembles, and on a shared machine its
#: waiting threads spin: the cone's validation took 21 s of CPU with two threads on two busy
#: cores, 3.4 s with one (docs/benchmarks.md), with the same numbers.
THREADS = 1
#: How :meth:`_Model.buckling` finds the state with the loads raised by δ (see there).
BUCKLING_STATES = ("predictor", "converged")
BUCKLING_STATE = "predictor"


@contextlib.contextmanager
def _quiet():
    """Silence the C++ banners Kratos prints to stdout on import."""
    try:
        fd = os.dup(1)
    except OSError:  # no real stdout (e.g. a notebook): nothing to silence
        yield
        return
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            yield
    finally:
        os.dup2(fd, 1)
        os.close(fd)


def _kratos():
    global _KM
    if _KM is None:
        with _quiet():
            import KratosMultiphysics as KM
            import KratosMultiphysics.LinearSolversApplication as LSA
            import KratosMultiphysics.StructuralMechanicsApplication as SMA

            KM.Logger.GetDefaultOutput().SetSeverity(KM.Logger.Severity.WARNING)
            if not os.environ.get("OMP_NUM_THREADS"):
                KM.ParallelUtilities.SetNumThreads(THREADS)
        _KM = (KM, SMA, LSA)
    return _KM


def available() -> tuple:
    try:
        KM, _, _ = _kratos()
    except Exception as exc:  # ImportError or a broken wheel
        return False, f"KratosMultiphysics does not import: {exc}"
    try:
        from importlib.metadata import version

        return True, version("KratosMultiphysics")
    except Exception:
        return True, "0 (version unknown)"


class _Model:
    """One Kratos model part built from an :class:`FEProblem`."""

    def __init__(self, problem: FEProblem, tolerance: float, max_iterations: int):
        KM, SMA, LSA = _kratos()
        self.KM, self.SMA = KM, SMA
        self.problem = p = problem
        self.model = KM.Model()
        mp = self.mp = self.model.CreateModelPart("ccu")
        mp.SetBufferSize(2)
        for var in (
            KM.DISPLACEMENT,
            KM.ROTATION,
            KM.REACTION,
            KM.REACTION_MOMENT,
            SMA.POINT_LOAD,
            SMA.POINT_MOMENT,
        ):
            mp.AddNodalSolutionStepVariable(var)
        mp.ProcessInfo[KM.DOMAIN_SIZE] = 3
        for i, (x, y, z) in enumerate(p.nodes):
            mp.CreateNewNode(i + 1, float(x), float(y), float(z))
        self._dofs()
        self._elements()
        self._hinges()
        self._conditions()
        self._supports()
        solver = LSA.SparseLUSolver()
        scheme = KM.ResidualBasedIncrementalUpdateStaticScheme()
        criterion = KM.DisplacementCriteria(tolerance, tolerance * 1e-3)
        criterion.SetEchoLevel(0)
        builder = KM.ResidualBasedBlockBuilderAndSolver(solver)
        settings = KM.Parameters(
            json.dumps(
                {
                    "max_iteration": int(max_iterations),
                    "compute_reactions": False,  # summed from element forces, see nodal_forces
                    "reform_dofs_at_each_step": False,
                    "move_mesh_flag": True,
                    "use_old_stiffness_in_first_iteration": True,
                }
            )
        )
        self.strategy = KM.ResidualBasedNewtonRaphsonStrategy(
            mp, scheme, criterion, builder, settings
        )
        self.strategy.SetEchoLevel(0)
        self.strategy.Initialize()
        self.scheme, self.builder = scheme, builder
        self.load_scale = 1.0
        self.criterion = criterion
        self.time = 0.0

    def _dofs(self):
        KM, mp = self.KM, self.mp
        for c in "XYZ":
            KM.VariableUtils().AddDof(
                getattr(KM, "DISPLACEMENT_" + c), getattr(KM, "REACTION_" + c), mp
            )
            KM.VariableUtils().AddDof(
                getattr(KM, "ROTATION_" + c), getattr(KM, "REACTION_MOMENT_" + c), mp
            )

    def _elements(self):
        KM, SMA, mp, p = self.KM, self.SMA, self.mp, self.problem
        m = p.material_used
        props = mp.GetProperties()[1]
        props.SetValue(KM.THICKNESS, p.thickness)
        props.SetValue(KM.DENSITY, m.density)
        if p.orthotropic:
            raise FEError(
                "orthotropic plates are not available with the Kratos 10.4.4 wheels (no "
                "orthotropic plane-stress law is shipped); use engine 'opensees' for them"
            )
        props.SetValue(KM.YOUNG_MODULUS, m.E1)
        props.SetValue(KM.POISSON_RATIO, m.nu12)
        props.SetValue(KM.CONSTITUTIVE_LAW, SMA.LinearElasticPlaneStress2DLaw())
        chosen = [props] * len(p.elements)
        if p.offsets is not None:  # one property per offset value: the section's SHELL_OFFSET
            values, which = np.unique(np.round(p.offsets, 12), return_inverse=True)
            table = []
            for k, value in enumerate(values.tolist()):
                q = mp.GetProperties()[OFFSET_PROPERTIES + k]
                q.SetValue(KM.THICKNESS, p.thickness)
                q.SetValue(KM.DENSITY, m.density)
                q.SetValue(KM.YOUNG_MODULUS, m.E1)
                q.SetValue(KM.POISSON_RATIO, m.nu12)
                q.SetValue(KM.CONSTITUTIVE_LAW, SMA.LinearElasticPlaneStress2DLaw())
                q.SetValue(SMA.SHELL_OFFSET, value)
                table.append(q)
            chosen = [table[k] for k in which.tolist()]
        for e, quad in enumerate(p.elements):
            mp.CreateNewElement(ELEMENT, e + 1, [int(i) + 1 for i in quad], chosen[e])

    def _hinges(self):
        KM, SMA, mp, p = self.KM, self.SMA, self.mp, self.problem
        rigid = p.hinge_translational_stiffness is None
        comps = ("X", "Y", "Z")
        cid, eid = 1, len(p.elements) + 1
        prescribed = set(map(int, p.fixed))
        self.carried = []  # (prescribed master, tied node): its force is part of the reaction
        for t, (a, b) in enumerate(p.ties):
            if rigid and int(b) in prescribed:
                if int(a) in prescribed:
                    raise FEError(
                        f"nodes {[int(a), int(b)]} are tied together (translations equal) and "
                        "all prescribed: prescribe one of them only"
                    )
                a, b = b, a  # a prescribed slave would be overridden: make it the master
            if rigid and int(a) in prescribed:
                self.carried.append((int(a), int(b)))
            na, nb = mp.GetNode(int(a) + 1), mp.GetNode(int(b) + 1)
            if rigid:
                for c in comps:
                    var = getattr(KM, "DISPLACEMENT_" + c)
                    mp.CreateNewMasterSlaveConstraint(
                        "LinearMasterSlaveConstraint", cid, na, var, nb, var, 1.0, 0.0
                    )
                    cid += 1
            length = float(p.tie_lengths[t])
            kt = 0.0 if rigid else p.hinge_translational_stiffness * length
            kr = p.hinge_stiffness * length
            if kt > 0.0 or kr > 0.0:
                props = mp.GetProperties()[t + 2]
                el = mp.CreateNewElement(
                    "SpringDamperElement3D", eid, [int(a) + 1, int(b) + 1], props
                )
                # the spring element reads its stiffness from the element's own data
                el.SetValue(SMA.NODAL_DISPLACEMENT_STIFFNESS, KM.Array3([kt, kt, kt]))
                el.SetValue(SMA.NODAL_ROTATIONAL_STIFFNESS, KM.Array3([kr, kr, kr]))
                eid += 1
        for s, ((a, b), k) in enumerate(zip(p.springs, p.spring_stiffness)):
            props = mp.GetProperties()[len(p.ties) + 2 + s]
            el = mp.CreateNewElement("SpringDamperElement3D", eid, [int(a) + 1, int(b) + 1], props)
            el.SetValue(SMA.NODAL_DISPLACEMENT_STIFFNESS, KM.Array3([float(x) for x in k]))
            el.SetValue(SMA.NODAL_ROTATIONAL_STIFFNESS, KM.Array3([0.0, 0.0, 0.0]))
            eid += 1

    def _conditions(self):
        mp, p = self.mp, self.problem
        loaded = np.zeros(len(p.nodes), dtype=bool)
        for pat in p.patterns:
            loaded |= np.any(pat.loads != 0.0, axis=1)
        self.loaded = np.flatnonzero(loaded)
        props = mp.GetProperties()[0]
        for c, i in enumerate(self.loaded):
            mp.CreateNewCondition("PointLoadCondition3D1N", 2 * c + 1, [int(i) + 1], props)
            mp.CreateNewCondition("PointMomentCondition3D1N", 2 * c + 2, [int(i) + 1], props)

    def _supports(self):
        KM, mp, p = self.KM, self.mp, self.problem
        for i in p.fixed_rotations:
            node = mp.GetNode(int(i) + 1)
            for c in "XYZ":
                node.Fix(getattr(KM, "ROTATION_" + c))

    def _apply(self, t: float):
        KM, SMA, mp, p = self.KM, self.SMA, self.mp, self.problem
        values = p.prescribed_at(t)
        for f, i in enumerate(p.fixed):
            node = mp.GetNode(int(i) + 1)
            for c, comp in enumerate("XYZ"):
                var = getattr(KM, "DISPLACEMENT_" + comp)
                v = values[f, c]
                if np.isnan(v):
                    node.Free(var)
                else:
                    node.Fix(var)
                    node.SetSolutionStepValue(var, 0, float(v))
        if len(self.loaded):
            loads = self.load_scale * p.loads_at(t)[self.loaded]
            for i, row in zip(self.loaded, loads):
                node = mp.GetNode(int(i) + 1)
                node.SetSolutionStepValue(SMA.POINT_LOAD, 0, KM.Array3(row[:3].tolist()))
                node.SetSolutionStepValue(SMA.POINT_MOMENT, 0, KM.Array3(row[3:].tolist()))

    def advance(self, t: float) -> tuple:
        """Solve at pseudo-time t; returns (converged, iterations, residual)."""
        KM, mp = self.KM, self.mp
        mp.CloneTimeStep(t)
        mp.ProcessInfo[KM.STEP] += 1
        self._apply(t)
        self.strategy.InitializeSolutionStep()
        self.strategy.Predict()
        converged = bool(self.strategy.SolveSolutionStep())
        iterations = int(mp.ProcessInfo[KM.NL_ITERATION_NUMBER])
        residual = (
            float(mp.ProcessInfo.GetValue(KM.CONVERGENCE_RATIO))
            if hasattr(KM, "CONVERGENCE_RATIO")
            else float("nan")
        )
        if converged:
            self.strategy.FinalizeSolutionStep()
            self.time = t
        return converged, iterations, residual

    def record(self) -> tuple:
        KM, SMA, mp, p = self.KM, self.SMA, self.mp, self.problem
        vu = KM.VariableUtils()
        disp = np.array(vu.GetSolutionStepValuesVector(mp.Nodes, KM.DISPLACEMENT, 0, 3))
        rot = np.array(vu.GetSolutionStepValuesVector(mp.Nodes, KM.ROTATION, 0, 3))
        disp, rot = disp.reshape(-1, 3), rot.reshape(-1, 3)
        info = mp.ProcessInfo
        forces = np.zeros((len(p.elements), 6))
        for e in range(len(p.elements)):
            el = mp.GetElement(e + 1)
            n = np.mean(
                [np.array(x) for x in el.CalculateOnIntegrationPoints(SMA.SHELL_FORCE, info)], 0
            )
            m = np.mean(
                [np.array(x) for x in el.CalculateOnIntegrationPoints(SMA.SHELL_MOMENT, info)], 0
            )
            forces[e] = (n[0, 0], n[1, 1], n[0, 1], m[0, 0], m[1, 1], m[0, 1])
        if p.offsets is not None:
            # Kratos reports the moments about the nodes' surface (M = ∫ σ z dz, z along the
            # element normal from the nodes); the material's mid-surface lies at z = -offset:
            # M_mid = M_nodes + offset N (tested on an eccentric cantilever)
            forces[:, 3:] += p.offsets[:, None] * forces[:, :3]
        reactions, ties = self.nodal_forces()
        reactions[np.isnan(p.prescribed_at(self.time))] = 0.0
        return disp, rot, forces, reactions, ties

    def nodal_forces(self) -> tuple:
        """Support reactions (F, 3) and hinge forces (T, 3) from the elements' internal forces.

        Kratos' REACTION is not reliable once master–slave constraints are present, so both are
        summed here: the internal force of every element at a node, minus the load there; a
        prescribed node carries the nodes tied to it as well.
        """
        KM, mp, p = self.KM, self.mp, self.problem
        if not hasattr(self, "_adjacent"):
            wanted = set(map(int, p.fixed)) | set(map(int, p.ties[:, 1]))
            wanted |= {b for _, b in self.carried}
            adjacent = []
            for el in mp.Elements:
                ids = [node.Id - 1 for node in el.GetNodes()]
                local = [(j, i) for j, i in enumerate(ids) if i in wanted]
                if local:
                    adjacent.append((el, local))
            self._adjacent = adjacent
        internal = np.zeros((len(p.nodes), 3))  # all elements (shells and springs)
        shells = np.zeros((len(p.nodes), 3))  # the plates only: what a hinge passes on
        rhs, info = KM.Vector(), mp.ProcessInfo
        n_shells = len(p.elements)
        for el, local in self._adjacent:
            el.CalculateRightHandSide(rhs, info)
            r = np.array(rhs)
            for j, i in local:
                internal[i] -= r[6 * j : 6 * j + 3]
                if el.Id <= n_shells:
                    shells[i] -= r[6 * j : 6 * j + 3]
        loads = self.load_scale * p.loads_at(self.time)[:, :3]
        net = internal - loads
        ties = (shells - loads)[p.ties[:, 1]] if len(p.ties) else np.zeros((0, 3))
        reactions = net[p.fixed].copy()
        where = {int(i): f for f, i in enumerate(p.fixed)}
        for a, b in self.carried:
            reactions[where[a]] += net[b]
        return reactions, ties

    def tangent(self):
        """(m, m) tangent stiffness at the current state on the free, independent DOFs."""
        import scipy.sparse as sp
        from KratosMultiphysics.scipy_conversion_tools import to_csr

        KM, mp = self.KM, self.mp
        A, b = self.strategy.GetSystemMatrix(), self.strategy.GetSystemVector()
        self.builder.Build(self.scheme, mp, A, b)
        self.builder.ApplyConstraints(self.scheme, mp, A, b)
        if not hasattr(self, "_active"):
            slaves = {int(c.GetSlaveDofsVector()[0].Id()) for c in mp.MasterSlaveConstraints}
            comps = [getattr(KM, f"{v}_{c}") for v in ("DISPLACEMENT", "ROTATION") for c in "XYZ"]
            active = []
            for node in mp.Nodes:
                for j, var in enumerate(comps):
                    if node.IsFixed(var) or (j < 3 and node.Id in slaves):
                        continue
                    active.append(node.GetDof(var).EquationId)
            self._active = np.array(sorted(active), dtype=int)
        k = sp.csr_matrix(to_csr(A))
        return k[self._active][:, self._active]

    def buckling(self, delta: float = 0.05, *, state: str | None = None) -> tuple:
        """Linearised buckling factor of the current state under its loads (Kratos only).

        ``K(λ) ≈ K0 + (λ - 1) ΔK`` with ``ΔK = (K(1 + δ) - K0) / δ`` from a second state with the
        loads raised by δ; the smallest positive λ with ``K(λ)`` singular is the factor by which
        the loads (self-weight + area load) may grow before the prestressed structure buckles.

        ``state`` (default :data:`BUCKLING_STATE`) is how the second state is found:
        ``"predictor"``, one Newton iteration from the loaded state with its tangent K0 — the
        linear predictor ``u0 + K0⁻¹ δ F``, which differs from the converged state by O(δ²) —
        and the steps that follow start from there (no solve back); ``"converged"``, the full
        Newton solve to the raised loads and back to the loaded state (the reference: two
        nonlinear solves more per analysis, the same factor within 1e-3 on the examples).
        """
        state = BUCKLING_STATE if state is None else state
        if state not in BUCKLING_STATES:
            raise FEError(f"buckling state must be one of {BUCKLING_STATES}, got {state!r}")
        self.__dict__.pop("_active", None)  # the free DOFs of this state's supports
        k0 = self.tangent()
        self.load_scale = 1.0 + delta
        if state == "predictor":
            ok = self.predict(self.time)
            if ok:  # the system matrix as the converged solve leaves it, see tangent
                self.system(self.time)
            k1 = self.tangent() if ok else None
            self.load_scale = 1.0  # the next step solves from the predicted state
        else:
            ok, _, _ = self.advance(self.time)
            k1 = self.tangent() if ok else None
            self.load_scale = 1.0  # back to the state itself, for the steps that follow
            back, _, _ = self.advance(self.time)
            if not back:
                raise FEError("the state did not converge again after the buckling analysis")
        if not ok:
            return None, "the loads raised by 5 % did not converge: the state is near a limit point"
        return _smallest_factor(k0, k1, delta)

    def system(self, t: float) -> None:
        """Leave the strategy's system matrix as a Newton iteration at the current state does:
        built afresh, with the constraints and the supports applied.

        :meth:`tangent` builds onto the system matrix without clearing it (the builder's
        ``Build`` adds), so a tangent is the sum of the matrix the last Newton iteration left
        and the new one; with the hinges' master–slave constraints the slaves' diagonal of the
        old matrix turns into a stiffness on their masters. The reference buckling analysis
        (``"converged"``) takes its second tangent after a Newton solve; this reproduces its
        system matrix after one predictor iteration, so that both give the same factor.
        """
        KM, mp = self.KM, self.mp
        A, b = self.strategy.GetSystemMatrix(), self.strategy.GetSystemVector()
        dx = self.strategy.GetSolutionVector()
        space = KM.UblasSparseSpace()
        space.SetToZeroMatrix(A)
        space.SetToZeroVector(b)
        self.builder.Build(self.scheme, mp, A, b)
        self.builder.ApplyConstraints(self.scheme, mp, A, b)
        self.builder.ApplyDirichletConditions(self.scheme, mp, A, dx, b)

    def predict(self, t: float) -> bool:
        """One Newton iteration towards the loads at pseudo-time ``t`` (with the current
        ``load_scale``) from the current state, kept as the state; False if it failed."""
        KM, mp = self.KM, self.mp
        mp.CloneTimeStep(t)
        mp.ProcessInfo[KM.STEP] += 1
        self._apply(t)
        # a Newton iteration with the tangent of the current state (not the previous step's)
        limit = self.strategy.GetMaxIterationNumber()
        self.strategy.SetMaxIterationNumber(1)
        self.strategy.SetUseOldStiffnessInFirstIterationFlag(False)
        try:
            self.strategy.InitializeSolutionStep()
            self.strategy.Predict()
            self.strategy.SolveSolutionStep()  # not converged after one iteration, as meant
            self.strategy.FinalizeSolutionStep()
        finally:
            self.strategy.SetMaxIterationNumber(limit)
            self.strategy.SetUseOldStiffnessInFirstIterationFlag(True)
        disp = KM.VariableUtils().GetSolutionStepValuesVector(mp.Nodes, KM.DISPLACEMENT, 0, 3)
        return bool(np.all(np.isfinite(np.array(disp))))


def _smallest_factor(k0, k1, delta: float) -> tuple:
    """The smallest λ > 1 with ``K0 + (λ - 1) (K1 - K0) / δ`` singular (shift-invert ARPACK)."""
    import scipy.sparse.linalg as sla

    dk = (k1 - k0) / delta
    lu = sla.splu(k0.tocsc())
    op = sla.LinearOperator(k0.shape, matvec=lambda x: lu.solve(-(dk @ x)), dtype=float)
    theta = sla.eigs(op, k=min(6, k0.shape[0] - 2), which="LR", return_eigenvectors=False)
    theta = theta.real[
        (np.abs(theta.imag) < EXACT_RELATIVE * np.abs(theta).max()) & (theta.real > 0)
    ]
    if not theta.size:
        return float("inf"), "no buckling under increasing load (no positive eigenvalue)"
    return float(1.0 + 1.0 / theta.max()), "linearised buckling of the loaded deployed state"


def solve(
    problem: FEProblem,
    *,
    tolerance: float,
    max_iterations: int,
    max_cuts: int,
    buckling=False,
) -> FEResult:
    """Solve ``problem`` step by step (see :mod:`compas_ccu.fea.problem`); ``buckling``:
    False, True (the last step) or the steps at which to compute the linear buckling factor."""
    start = time.perf_counter()
    wanted = buckling_steps(buckling, problem.steps)
    factors = {}
    history = []  # converged pseudo-times, replayed after a failed attempt
    model = _Model(problem, tolerance, max_iterations)
    rows, iterations = [], []
    cuts, failed, residual, message = 0, None, None, ""
    for step in range(1, problem.steps + 1):
        its, level = 0, 0
        while model.time < step - ZERO_LENGTH:
            target = min(model.time + 1.0 / 2**level, float(step))
            ok, n_it, res = model.advance(target)
            its += n_it
            if ok:
                history.append(target)
                continue
            residual = res
            if level >= max_cuts:
                failed = step
                break
            level += 1
            cuts += 1
            # rebuild and replay the converged history: a clean corotational state
            model = _Model(problem, tolerance, max_iterations)
            for t in history:
                model.advance(t)
        if failed is not None:
            message = (
                f"step {step} of {problem.steps} did not converge after {max_cuts} cuts "
                f"(smallest sub-step {1.0 / 2**max_cuts:.3g} of a step): last relative "
                f"displacement-increment norm {residual:.3e} > tolerance {tolerance:.1e}"
            )
            break
        iterations.append(its)
        rows.append(model.record())
        if step in wanted:
            factors[step] = model.buckling()
    if rows:
        disp, rot, forces, reac, ties = (np.array(a) for a in zip(*rows))
    else:
        n, e, f = len(problem.nodes), len(problem.elements), len(problem.fixed)
        disp, rot, forces, reac, ties = (
            np.zeros((0, n, 3)),
            np.zeros((0, n, 3)),
            np.zeros((0, e, 6)),
            np.zeros((0, f, 3)),
            np.zeros((0, len(problem.ties), 3)),
        )
    factor, note = factors[max(factors)] if factors else (None, "")
    return FEResult(
        engine="kratos",
        buckling_factor=factor,
        buckling_note=note,
        buckling=factors,
        displacements=disp,
        rotations=rot,
        forces=forces,
        reactions=reac,
        tie_forces=ties,
        converged=failed is None,
        failed_step=failed,
        residual=residual,
        iterations=np.array(iterations, dtype=int),
        cuts=cuts,
        wall_time=time.perf_counter() - start,
        message=message,
    )
