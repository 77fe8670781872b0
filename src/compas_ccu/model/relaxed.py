"""The relaxed state of a model (docs/shape-control.md): deployed, its plates relaxed by least
squares (:func:`compas_ccu.kinematics.relaxation.relax`), refitted to the mechanism and made a
:class:`~compas_ccu.structure.Structure` whose metrics hold the relaxation's residuals.
:meth:`CCUModel.relax` is :func:`relaxed_structure`."""

from __future__ import annotations

import numpy as np

from compas_ccu.kinematics.relaxation import links_from_mechanism, relax

__all__ = ["relaxed_structure"]


def relaxed_structure(model, alpha: float, *, planarity_weight: float = 1.0, **options):
    """Deploy ``model`` to ``alpha`` (degrees) and relax its plates.

    Parameters
    ----------
    model : CCUModel
    alpha : float
        Reference reflection angle, degrees.
    planarity_weight : float
        Weight of the quads' non-planarity against their length errors.
    **options
        Passed on to :func:`compas_ccu.kinematics.relaxation.relax`.

    Returns
    -------
    structure : compas_ccu.structure.Structure
        The relaxed state; ``metrics["relaxation"]`` holds the residuals, per plate by plate id.
    relaxation : compas_ccu.kinematics.relaxation.Relaxation

    Examples
    --------
    An exact deployment is already relaxed (one evaluation, nothing moves):

    >>> from compas_ccu.model import load_model
    >>> structure, relaxation = relaxed_structure(load_model("examples/cone.toml"), 30.0)
    >>> structure.alpha, relaxation.converged, relaxation.displacement
    (30.0, True, 0.0)
    >>> metrics = structure.metrics["relaxation"]
    >>> metrics["nfev"], bool(metrics["max_strain"] < 1e-12)
    (1, True)
    """
    states = model.mechanism.deploy(np.radians([alpha]))
    result = relax(
        states.near[0],
        states.far[0],
        model.reference_lengths,
        links_from_mechanism(model.mechanism),
        planarity_weight=planarity_weight,
        **options,
    )
    relaxed = model.mechanism.refit(states, result.near[None], result.far[None])
    structure = model.structure(relaxed, 0, alpha)
    summary = result.summary()
    for key in ("max_strain_per_plate", "quad_planarity_per_plate", "displacement_per_plate"):
        summary[key] = [summary[key][i] for i in model.order]  # by plate id
    structure.metrics["relaxation"] = summary
    return structure, result
