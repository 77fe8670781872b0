"""Fabrication output: cut patterns, hinge strips, Rhino, meshes, FOLD and the assembly sheet.

``ccu fabricate DESIGN --out DIR`` (:func:`compas_ccu.fabrication.fabricate.fabricate`) writes
every file; each writer is a pure function of a
:class:`compas_ccu.fabrication.data.FabricationData`, which :func:`fabrication_data` builds from
the thick plates of a model (:class:`compas_ccu.thickness.ThickModel`).
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fabrication.data import FabricationData
from compas_ccu.fabrication.hinges import check_hinge_width
from compas_ccu.thickness import ThickModel

__all__ = ["FabricationData", "fabrication_data"]


def fabrication_data(
    model, *, thickness=None, material=None, grain=None, hinge_width=None, thick=None
) -> FabricationData:
    """The fabrication data of a model's thick plates at its design state.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    thickness, material, grain : optional
        See :class:`compas_ccu.thickness.ThickModel`; default: the design's ``[plates]``.
    hinge_width : float, optional
        Textile hinge strip width, m; default: ``plates.hinge_width``.
    thick : compas_ccu.thickness.ThickModel, optional
        Reuse an existing thick model (the options above are then ignored).

    Returns
    -------
    FabricationData
        The cut patterns include the crease corrections of the design state (paper §5.3): the
        thick plates cut from them meet exactly along planar hinges at the design angle.
    """
    if thick is None:
        thick = ThickModel(model, thickness=thickness, material=material, grain=grain)
    if hinge_width is None:
        hinge_width = model.design.plates.hinge_width
    width = check_hinge_width(hinge_width)
    design = thick.deploy()
    stack = thick.flat_stack()
    flat = thick.cut_patterns()
    structure = model.deploy()
    creases = []
    for c in structure.creases:
        creases.append(
            {
                "id": c["id"],
                "plates": list(c["plates"]),
                "vertices": c["vertices"],
                "kind": c["kind"],
                "fold_angle": 2.0 * float(np.mean(c["alpha"])),
            }
        )
    return FabricationData(
        name=model.design.name,
        alpha=float(design.alpha),
        thickness=thick.thickness,
        material=thick.material.name,
        plate_ids=list(model.plate_ids),
        faces=model.faces,
        flat=flat,
        deployed_mid=design.solids.mean(axis=1),
        solids=design.solids,
        stack_solids=stack.solids,
        creases=creases,
        stack_position=list(thick.stack_position),
        hinge_width=width,
        metadata={"pairing": thick.pairing(), "grain": thick.grain},
    )
