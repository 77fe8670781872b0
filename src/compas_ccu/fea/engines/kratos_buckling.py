"""The linear algebra of the Kratos engine's linearised buckling factor (the ``buckling`` of
the :mod:`.kratos` model): the tangent stiffness of a state on its free, independent DOFs, the
system matrix rebuilt as a Newton iteration leaves it, and the smallest load factor that makes
the interpolated stiffness singular (shift-invert ARPACK)."""

from __future__ import annotations

import numpy as np

from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["tangent_stiffness", "rebuild_system", "smallest_factor"]


def tangent_stiffness(model):
    """(m, m) tangent stiffness at the current state on the free, independent DOFs.

    Parameters
    ----------
    model : compas_ccu.fea.engines.kratos._Model
        Its ``active_dofs`` (the equation ids kept) are found on the first call and kept until
        set to None (a new state's supports).

    Returns
    -------
    scipy.sparse.csr_matrix
    """
    import scipy.sparse as sp
    from KratosMultiphysics.scipy_conversion_tools import to_csr

    KM, mp = model.KM, model.mp
    A, b = model.strategy.GetSystemMatrix(), model.strategy.GetSystemVector()
    model.builder.Build(model.scheme, mp, A, b)
    model.builder.ApplyConstraints(model.scheme, mp, A, b)
    if model.active_dofs is None:
        model.active_dofs = _active_dofs(KM, mp)
    k = sp.csr_matrix(to_csr(A))
    return k[model.active_dofs][:, model.active_dofs]


def _active_dofs(KM, mp) -> np.ndarray:
    """The equation ids of the DOFs neither fixed nor the translation of a master–slave slave,
    sorted."""
    slaves = {int(c.GetSlaveDofsVector()[0].Id()) for c in mp.MasterSlaveConstraints}
    comps = [getattr(KM, f"{v}_{c}") for v in ("DISPLACEMENT", "ROTATION") for c in "XYZ"]
    active = []
    for node in mp.Nodes:
        for j, var in enumerate(comps):
            if node.IsFixed(var) or (j < 3 and node.Id in slaves):
                continue
            active.append(node.GetDof(var).EquationId)
    return np.array(sorted(active), dtype=int)


def rebuild_system(model) -> None:
    """Leave the strategy's system matrix of ``model`` as a Newton iteration at the current
    state does: built afresh, with the constraints and the supports applied.

    :func:`tangent_stiffness` builds onto the system matrix without clearing it (the builder's
    ``Build`` adds), so a tangent is the sum of the matrix the last Newton iteration left
    and the new one; with the hinges' master–slave constraints the slaves' diagonal of the
    old matrix turns into a stiffness on their masters. The reference buckling analysis
    (``"converged"``) takes its second tangent after a Newton solve; this reproduces its
    system matrix after one predictor iteration, so that both give the same factor.
    """
    KM, mp = model.KM, model.mp
    A, b = model.strategy.GetSystemMatrix(), model.strategy.GetSystemVector()
    dx = model.strategy.GetSolutionVector()
    space = KM.UblasSparseSpace()
    space.SetToZeroMatrix(A)
    space.SetToZeroVector(b)
    model.builder.Build(model.scheme, mp, A, b)
    model.builder.ApplyConstraints(model.scheme, mp, A, b)
    model.builder.ApplyDirichletConditions(model.scheme, mp, A, dx, b)


def smallest_factor(k0, k1, delta: float) -> tuple:
    """The smallest λ > 1 with ``K0 + (λ - 1) (K1 - K0) / δ`` singular (shift-invert ARPACK).

    Returns
    -------
    factor : float
        ``inf`` if no positive eigenvalue (no buckling under increasing load).
    note : str
    """
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
