"""What both deployment strategies build on: the hinge ties and solving with a named failure.

* :func:`tie_set` — the hinge ties of a mesh once some nodes are prescribed (a tie between two
  prescribed nodes is dropped, a prescribed slave becomes the master);
* :func:`solve_steps` — solve an :class:`~compas_ccu.fea.problem.FEProblem` with the engine of
  the settings and raise :class:`~compas_ccu.fea.problem.ConvergenceError` naming the step and
  the reference angle if it does not converge.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from compas_ccu.fea.engines import solve
from compas_ccu.fea.mesh import ShellMesh
from compas_ccu.fea.problem import ConvergenceError, FEProblem, FEResult
from compas_ccu.fea.settings import FESettings

__all__ = ["tie_set", "solve_steps", "strip_nodes"]


def strip_nodes(result: FEResult, n_nodes: int) -> FEResult:
    """``result`` without the nodes after the first ``n_nodes`` (actuator anchors, ground
    nodes of support springs): they are no part of the structure. Reactions keep them."""
    return replace(
        result,
        displacements=result.displacements[:, :n_nodes],
        rotations=result.rotations[:, :n_nodes],
    )


def tie_set(mesh: ShellMesh, fixed: np.ndarray) -> tuple:
    """The hinge ties of ``mesh`` with the nodes ``fixed`` prescribed.

    A tie whose two nodes are both prescribed is dropped (the prescribed motion already keeps
    them together); a tie whose slave (second node) is prescribed is swapped so that the
    prescribed node is the master.

    Returns
    -------
    ties : (T, 2) int
        Master, slave node pairs.
    lengths : (T,) float
        Crease length each tie stands for, m.
    crease : (T,) int
        Crease index of each tie.
    keep : (len(mesh.ties),) bool
        Which of ``mesh.ties`` were kept.
    """
    ties = mesh.ties.copy()
    prescribed = np.zeros(len(mesh.nodes), dtype=bool)
    prescribed[fixed] = True
    keep = ~(prescribed[ties[:, 0]] & prescribed[ties[:, 1]])
    ties = ties[keep]
    swap = prescribed[ties[:, 1]]
    ties[swap] = ties[swap][:, ::-1]
    return ties, mesh.tie_lengths[keep], mesh.tie_crease[keep], keep


def solve_steps(
    problem: FEProblem, settings: FESettings, alphas: np.ndarray, *, buckling: bool = False
) -> FEResult:
    """Solve ``problem`` with the engine and Newton options of ``settings``.

    Parameters
    ----------
    problem : FEProblem
    settings : FESettings
    alphas : (S,) float
        Reference angle of every step, degrees (names the failed step's angle).
    buckling : bool
        Also compute the linear buckling factor at the last step (Kratos only).

    Raises
    ------
    ConvergenceError
        A step did not converge even after cutting it; the partial history is attached.
    """
    result = solve(
        problem,
        settings.engine,
        tolerance=settings.tolerance,
        max_iterations=settings.max_iterations,
        max_cuts=settings.max_cuts,
        buckling=buckling,
    )
    if not result.converged:
        step = result.failed_step
        raise ConvergenceError(
            f"the {settings.engine} analysis did not converge at step {step} of "
            f"{problem.steps} (alpha = {alphas[step - 1]:.4g} deg): {result.message}",
            step=step,
            residual=result.residual if result.residual is not None else float("nan"),
            result=result,
        )
    return result
