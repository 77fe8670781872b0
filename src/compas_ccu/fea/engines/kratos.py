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

This module steps the model, records its results, runs the buckling analysis and drives the
solve; Kratos is imported by :mod:`.kratos_import`, the model part built by :mod:`.kratos_build`
and the buckling factor's linear algebra is :mod:`.kratos_buckling`.
"""

from __future__ import annotations

import time

import numpy as np

from compas_ccu.fea.engines.kratos_buckling import (
    rebuild_system,
    smallest_factor,
    tangent_stiffness,
)
from compas_ccu.fea.engines.kratos_build import ELEMENT as ELEMENT
from compas_ccu.fea.engines.kratos_build import OFFSET_PROPERTIES as OFFSET_PROPERTIES
from compas_ccu.fea.engines.kratos_build import model_part, newton_strategy
from compas_ccu.fea.engines.kratos_import import THREADS as THREADS
from compas_ccu.fea.engines.kratos_import import available, kratos_modules
from compas_ccu.fea.problem import FEError, FEProblem, FEResult, buckling_steps
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = ["available", "solve"]

#: How :meth:`_Model.buckling` finds the state with the loads raised by δ (see there).
BUCKLING_STATES = ("predictor", "converged")
BUCKLING_STATE = "predictor"


class _Model:
    """One Kratos model part built from an :class:`FEProblem`."""

    def __init__(self, problem: FEProblem, tolerance: float, max_iterations: int):
        KM, SMA, LSA = kratos_modules()
        self.KM, self.SMA = KM, SMA
        self.problem = problem
        self.model, self.mp, self.carried, self.loaded = model_part(KM, SMA, problem)
        self.strategy, self.scheme, self.builder, self.criterion = newton_strategy(
            KM, LSA, self.mp, tolerance, max_iterations
        )
        self.load_scale = 1.0
        self.time = 0.0
        self.active_dofs = None  # the free, independent DOFs of the tangent (kratos_buckling)

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
        """(m, m) tangent stiffness at the current state on the free, independent DOFs
        (:func:`.kratos_buckling.tangent_stiffness`)."""
        return tangent_stiffness(self)

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
        self.active_dofs = None  # the free DOFs of this state's supports
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
        return smallest_factor(k0, k1, delta)

    def system(self, t: float) -> None:
        """Leave the strategy's system matrix as a Newton iteration at the current state does
        (:func:`.kratos_buckling.rebuild_system`)."""
        rebuild_system(self)

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
    disp, rot, forces, reac, ties = _stacked(problem, rows)
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


def _stacked(problem: FEProblem, rows: list) -> tuple:
    """The records of the converged steps stacked: displacements (s, n, 3), rotations
    (s, n, 3), element forces (s, e, 6), reactions (s, f, 3) and tie forces (s, t, 3)."""
    if rows:
        return tuple(np.array(a) for a in zip(*rows))
    n, e, f = len(problem.nodes), len(problem.elements), len(problem.fixed)
    return (
        np.zeros((0, n, 3)),
        np.zeros((0, n, 3)),
        np.zeros((0, e, 6)),
        np.zeros((0, f, 3)),
        np.zeros((0, len(problem.ties), 3)),
    )
