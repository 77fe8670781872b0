"""Finite-element validation of CCU deployment with open-source engines.

``validate(model, engine="kratos", mode="displacement", ...)`` meshes the plates as quad shells,
ties the hinges, deploys the structure geometrically nonlinearly and compares it with the exact
kinematic model. The engines (Kratos Multiphysics, OpenSeesPy) are optional and imported only
when a problem is solved; the pictures need the optional ``viz`` extra.

Modules, by job (each imports only those above it in this list):

* :mod:`~compas_ccu.fea.problem` — the engine-neutral problem and result, the errors;
* :mod:`~compas_ccu.fea.stresses` — surface stresses, principal values, summaries;
* :mod:`~compas_ccu.fea.engines` — the backends (``kratos``, ``opensees``);
* :mod:`~compas_ccu.fea.settings` — :class:`FESettings`, the options of a validation;
* :mod:`~compas_ccu.fea.mesh` — shell meshes of a model with exact kinematic node positions;
* :mod:`~compas_ccu.fea.solving` — hinge ties and solving with a named failure (shared by the
  strategies);
* :mod:`~compas_ccu.fea.history` — :class:`DeploymentHistory`, the step-by-step record both
  strategies return;
* :mod:`~compas_ccu.fea.displacement`, :mod:`~compas_ccu.fea.actuation` — the two deployment
  strategies;
* :mod:`~compas_ccu.fea.comparison` — the FE history against the kinematic model (deviation in
  % of span, with an explicit alignment);
* :mod:`~compas_ccu.fea.checks` — structural checks of the deployed state under load;
* :mod:`~compas_ccu.fea.output` — ``validation.json``, ``fe_results.npz`` and the pictures;
* :mod:`~compas_ccu.fea.validation` — :func:`validate` and :class:`Validation`, putting the
  jobs together;
* :mod:`~compas_ccu.fea.record` — the last validation of a design file, two engines' agreement.
"""

from __future__ import annotations

from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.problem import ConvergenceError, FEError
from compas_ccu.fea.settings import FESettings
from compas_ccu.fea.validation import Validation, validate

__all__ = [
    "validate",
    "FESettings",
    "Validation",
    "DeploymentHistory",
    "ConvergenceError",
    "FEError",
]
