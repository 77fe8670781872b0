"""Levenberg-Marquardt for sparse or banded least squares, with scipy's termination codes.

The solver of :func:`compas_ccu.kinematics.relaxation.relax` (docs/kinematics.md): the caller
supplies the residuals, the Gauss-Newton data at a point (``linearise``) and a solve of the damped
normal equations (``solve``), so the same iteration runs on a banded Cholesky factor or on LSMR.
The damping follows Nielsen's gain-ratio update, the scaling is Marquardt's running maximum of
``diag(J^T J)``, and the run stops as :func:`scipy.optimize.least_squares` does (the same status
codes and messages), so both solvers report alike.

Examples
--------
Rosenbrock's valley, ``r = (10 (y - x^2), 1 - x)``, from ``(-1.2, 1)``:

>>> import numpy as np
>>> def residuals(v):
...     return np.array([10.0 * (v[1] - v[0] ** 2), 1.0 - v[0]])
>>> def linearise(v, r):
...     jac = np.array([[-20.0 * v[0], 10.0], [-1.0, 0.0]])
...     return jac.T @ jac, jac.T @ r, np.diag(jac.T @ jac).copy()
>>> def solve(system, g, damping, scale):
...     return np.linalg.solve(system + damping * np.diag(scale), -g)
>>> x, outcome = levenberg_marquardt(
...     residuals, linearise, solve, [-1.2, 1.0], ftol=1e-12, xtol=1e-12, gtol=1e-12, max_nfev=200
... )
>>> np.round(x, 9).tolist(), outcome["status"] > 0
([1.0, 1.0], True)
"""

from __future__ import annotations

import numpy as np

from compas_ccu.tolerances import MACHINE

__all__ = ["levenberg_marquardt", "termination", "MESSAGES"]

# the initial damping (relative to the Marquardt scale diag(J^T J)), its floor and the ceiling
# beyond which a step that cannot be computed is given up
DAMPING_START = 1e-6
DAMPING_MIN = MACHINE
DAMPING_MAX = 1e16
#: scipy.optimize.least_squares' messages, by status code (-1: this solver's own)
MESSAGES = {
    -1: "The damped normal equations could not be solved for any damping.",
    0: "The maximum number of function evaluations is exceeded.",
    1: "`gtol` termination condition is satisfied.",
    2: "`ftol` termination condition is satisfied.",
    3: "`xtol` termination condition is satisfied.",
    4: "Both `ftol` and `xtol` termination conditions are satisfied.",
}


def termination(reduction, predicted, cost, step_norm, x_norm, ftol, xtol):
    """Convergence tests on a trial step: status 2 (cost), 3 (step), 4 (both) or None.

    The cost test is MINPACK's: the actual and the predicted reduction of the cost are both
    below ``ftol * cost`` (neither the step nor the linear model can gain more, also when
    round-off rejects the step); the step test is scipy's, ``|step| < xtol (xtol + |x|)``,
    for rejected steps too (the step has become negligible).

    Examples
    --------
    >>> termination(1e-15, 1e-15, 1.0, 0.1, 1.0, ftol=1e-12, xtol=1e-12)  # no cost to gain
    2
    >>> termination(0.5, 0.4, 1.0, 1e-20, 1.0, ftol=1e-12, xtol=1e-12)  # a negligible step
    3
    >>> print(termination(0.5, 0.4, 1.0, 0.1, 1.0, ftol=1e-12, xtol=1e-12))
    None
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


def levenberg_marquardt(residuals, linearise, solve, x0, *, ftol, xtol, gtol, max_nfev):
    """Minimise ``0.5 |r(x)|^2`` by Levenberg-Marquardt (Marquardt scaling, Nielsen damping).

    Every step solves ``(J^T J + lam D) step = -J^T r`` with ``D`` the running maximum of
    ``diag(J^T J)`` (MINPACK's scaling, invariant to the units of the unknowns) and accepts it
    when the cost decreases. The damping follows the gain ratio ``rho`` = actual / predicted
    reduction (Nielsen 1999): on success ``lam *= max(1/3, 1 - (2 rho - 1)^3)``, otherwise
    ``lam *= nu``, ``nu *= 2``. It stops with scipy's status codes: ``1`` when
    ``max |J^T r| < gtol``, ``2`` / ``3`` / ``4`` by :func:`termination`, ``0`` after
    ``max_nfev`` residual evaluations, ``-1`` when ``solve`` fails even for damping
    ``DAMPING_MAX``.

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
        Tolerances of the cost and step tests (:func:`termination`) and of the gradient
        test; ``None`` disables a test.
    max_nfev : int

    Returns
    -------
    x : (n,) float
    outcome : dict
        ``cost``, ``optimality`` (``max |J^T r|``), ``nfev``, ``njev``, ``status``, ``message``.

    Examples
    --------
    The linear least-squares line through three points, ``r = (a + b t_i - y_i)``:

    >>> import numpy as np
    >>> t, y = np.array([0.0, 1.0, 2.0]), np.array([1.0, 3.0, 5.0])
    >>> jac = np.c_[np.ones(3), t]
    >>> def residuals(v):
    ...     return v[0] + v[1] * t - y
    >>> def linearise(v, r):
    ...     return jac.T @ jac, jac.T @ r, np.diag(jac.T @ jac).copy()
    >>> def solve(system, g, damping, scale):
    ...     return np.linalg.solve(system + damping * np.diag(scale), -g)
    >>> x, outcome = levenberg_marquardt(
    ...     residuals, linearise, solve, [0.0, 0.0], ftol=1e-12, xtol=1e-12, gtol=1e-12, max_nfev=50
    ... )
    >>> np.round(x, 9).tolist(), outcome["status"] > 0
    ([1.0, 2.0], True)
    """
    ftol, xtol, gtol = (0.0 if t is None else float(t) for t in (ftol, xtol, gtol))
    x = np.array(x0, dtype=float)
    r = residuals(x)
    cost = 0.5 * float(r @ r)
    system, g, diag = linearise(x, r)
    nfev = njev = 1
    scale = np.where(diag > 0.0, diag, 1.0)
    lam, nu = DAMPING_START, 2.0
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
                if lam >= DAMPING_MAX:
                    status = -1
                lam, nu = min(lam * nu, DAMPING_MAX), 2.0 * nu
                continue
            x_new = x + step
            r_new = residuals(x_new)
            nfev += 1
            if not np.all(np.isfinite(r_new)):
                lam, nu = min(lam * nu, DAMPING_MAX), 2.0 * nu
                continue
            cost_new = 0.5 * float(r_new @ r_new)
            reduction = cost - cost_new
            predicted = 0.5 * float(lam * (scale * step) @ step - g @ step)
            ratio = reduction / predicted if predicted > 0.0 else 0.0
            if reduction > 0.0:
                accepted = True
                shrink = max(1.0 / 3.0, 1.0 - (2.0 * min(ratio, 1.0) - 1.0) ** 3)
                lam = max(lam * shrink, DAMPING_MIN)
                nu = 2.0
            else:
                lam, nu = min(lam * nu, DAMPING_MAX), 2.0 * nu
            status = termination(
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
        "message": MESSAGES[status],
    }
    return x, outcome
