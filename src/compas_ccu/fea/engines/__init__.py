"""FE backends behind one interface: ``solve(problem, **options) -> FEResult``.

* ``kratos`` — Kratos Multiphysics (primary; ``LegacyThickShellCorotationalElement3D4N``,
  master–slave ties, sparse LU), :mod:`compas_ccu.fea.engines.kratos`;
* ``opensees`` — OpenSeesPy (cross-check; ``ASDShellQ4 -corotational``, ``equalDOF`` ties,
  Transformation constraints), :mod:`compas_ccu.fea.engines.opensees`.

Both are optional dependencies (``pip install compas_ccu[fea]``), imported only when used.
"""

from __future__ import annotations

from compas_ccu.fea.engines import kratos, opensees
from compas_ccu.fea.problem import FEError

__all__ = ["ENGINES", "get_engine", "solve", "available"]

#: The backend modules by name (cheap to import: each imports its engine only when used).
ENGINES = {"kratos": kratos, "opensees": opensees}

DEFAULTS = {"tolerance": 1e-6, "max_iterations": 30, "max_cuts": 6, "buckling": False}


def get_engine(name: str):
    """The backend module ``name`` (it has ``solve`` and ``available``)."""
    if name not in ENGINES:
        raise FEError(f"unknown FE engine {name!r}; known: {sorted(ENGINES)}")
    return ENGINES[name]


def available(name: str) -> tuple:
    """``(True, version)`` if the engine imports, else ``(False, reason)``."""
    return get_engine(name).available()


def solve(problem, engine: str = "kratos", **options):
    """Solve ``problem`` with ``engine``; options: tolerance, max_iterations, max_cuts, buckling.

    Returns
    -------
    compas_ccu.fea.problem.FEResult
        ``converged`` is False (with ``failed_step`` and ``residual``) if a step failed after
        every cut; the history up to the failure is kept.
    """
    unknown = sorted(set(options) - set(DEFAULTS))
    if unknown:
        raise FEError(f"unknown solver option(s) {unknown}; known: {sorted(DEFAULTS)}")
    module = get_engine(engine)
    ok, info = module.available()
    if not ok:
        raise FEError(
            f"FE engine {engine!r} is not available ({info}); install it with "
            "`pip install compas_ccu[fea]` (make setup does)"
        )
    return module.solve(problem, **{**DEFAULTS, **options})
