"""Inverse design of a single crease, with the deployable model (paper §5.4).

* :func:`flat_design` -- the forward design of the computed cut pattern: ``state = "flat"``
  with the pattern's crease polyline and explicit ruling ends, i.e. what a workshop cuts;
* :func:`round_trip` -- target -> pattern -> deploy -> compare: the pattern design is deployed
  to the design angle and compared with the target after a best rigid alignment.

A design from a 3D target polyline is :func:`compas_ccu.design.inverse.design_from_crease`.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.design import Design
from compas_ccu.errors import DesignError
from compas_ccu.geometry import rigid_align
from compas_ccu.model.ccu_model import CCUModel

__all__ = ["flat_design", "round_trip"]


def flat_design(design, *, name: str | None = None):
    """The cut-pattern (forward) design of a single-crease design.

    Parameters
    ----------
    design : compas_ccu.design.Design
        A single-crease design (``layout.type = "single"``, no quadrants).

    Returns
    -------
    compas_ccu.design.Design
        ``crease.state = "flat"``, the pattern's crease as a polyline kept vertex by vertex,
        ``rulings.type = "explicit"`` with the pattern's ruling ends, the same reference vertex,
        design angle and plane placement, in the units of ``design``.
    """
    if design.layout.type != "single" or design.layout.quadrants:
        raise DesignError(
            "flat_design needs a single-crease design without quadrants; multi-crease crease "
            "planes are defined at the deployed state",
            key="layout.type",
        )
    model = CCUModel(design)
    flat = model.flat()[0]  # the leading plate's cut pattern, plane coordinates
    n = model.segments
    doc = design.metric_document()
    doc.setdefault("design", {})["name"] = name or f"{design.name}-pattern"
    doc["crease"] = {
        "profile": "polyline",
        "points": flat[: n + 1, :2].tolist(),
        "segments": n,
        "reference": model.reference / n,
        "state": "flat",
    }
    doc["rulings"] = {"type": "explicit", "points": flat[n + 1 :, :2].tolist()}
    doc["layout"] = {"type": "single"}
    return Design.from_metric(doc, units=design.units)


def round_trip(design) -> dict:
    """Target -> cut pattern -> deploy -> target, for a deployed-state single-crease design.

    Returns
    -------
    dict
        ``max`` (m) and ``max_relative`` (to the span) distance between the deployed pattern
        design and the target at the design angle, over the crease (``crease_max``) and over
        every plate vertex (``max``); ``alpha`` (degrees); ``span`` (m).
    """
    if design.crease.state != "deployed":
        raise DesignError("round_trip starts from a 3D target (crease.state = 'deployed')")
    target = CCUModel(design).deploy()
    pattern = CCUModel(flat_design(design)).deploy(design.alpha)
    a = np.asarray(pattern.deployed).reshape(-1, 3)
    b = np.asarray(target.deployed).reshape(-1, 3)
    moved = rigid_align(a, b).reshape(np.shape(target.deployed))
    dist = np.linalg.norm(moved - np.asarray(target.deployed), axis=-1)
    n = pattern.metrics["segments"]
    span = float(target.metrics["span"])
    return {
        "alpha": design.alpha,
        "span": span,
        "max": float(dist.max()),
        "max_relative": float(dist.max()) / span,
        "crease_max": float(dist[0, : n + 1].max()),
        "alpha_error": float(
            np.abs(
                np.asarray(pattern.metrics["alpha_leading"])
                - np.asarray(target.metrics["alpha_leading"])
            ).max()
        ),
    }
