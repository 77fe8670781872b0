"""Finite-element validation of CCU deployment with open-source engines.

``validate(model, engine="kratos", mode="displacement", ...)`` meshes the plates as quad shells,
ties the hinges, deploys the structure geometrically nonlinearly and compares it with the exact
kinematic model (:mod:`compas_ccu.fea.validation`). The engines (Kratos Multiphysics, OpenSeesPy)
are optional and imported only when a problem is solved.

Modules: :mod:`~compas_ccu.fea.problem` (the engine-neutral problem and result),
:mod:`~compas_ccu.fea.mesh` (shell meshes of a model), :mod:`~compas_ccu.fea.engines` (backends),
:mod:`~compas_ccu.fea.stresses`, :mod:`~compas_ccu.fea.validation`,
:mod:`~compas_ccu.fea.actuation`, :mod:`~compas_ccu.fea.buckling`.
"""

from __future__ import annotations

__all__ = ["validate", "FESettings", "Validation", "ConvergenceError", "FEError"]


def __getattr__(name):
    if name in ("validate", "FESettings", "Validation"):
        from compas_ccu.fea import validation

        return getattr(validation, name)
    if name in ("ConvergenceError", "FEError"):
        from compas_ccu.fea import problem

        return getattr(problem, name)
    raise AttributeError(name)
