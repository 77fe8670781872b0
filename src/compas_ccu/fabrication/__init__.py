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

__all__ = ["FabricationData", "fabrication_data", "workshop_ids"]


def workshop_ids(plate_ids, stack_position, creases) -> tuple:
    """Plate and crease ids that follow the flat-folded stack.

    Plate ``k`` is the plate at stack position ``k`` (0 = bottom); crease ``k`` is the ``k``-th
    crease from the bottom of the stack (sorted by the lower, then the upper stack position of
    its two plates): on a stacked chain crease ``k`` joins plates ``k`` and ``k + 1``.

    Parameters
    ----------
    plate_ids : list of int
        The model's plate ids (array order).
    stack_position : list of int
        Stack position of every plate (array order).
    creases : list of dict
        Crease records with the model's ``id`` and ``plates``.

    Returns
    -------
    plate_map, crease_map : dict
        Model id -> workshop id.

    Examples
    --------
    >>> creases = [{"id": 0, "plates": [1, 2]}, {"id": 1, "plates": [1, 0]}]
    >>> workshop_ids([0, 1, 2], [0, 1, 2], creases)
    ({0: 0, 1: 1, 2: 2}, {1: 0, 0: 1})
    """
    plate_map = {int(pid): int(k) for pid, k in zip(plate_ids, stack_position)}

    def key(c):
        a, b = (plate_map[int(x)] for x in c["plates"])
        return (min(a, b), max(a, b), int(c["id"]))

    ordered = sorted(creases, key=key)
    return plate_map, {int(c["id"]): k for k, c in enumerate(ordered)}


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
    # ids that follow the stack (plate k at stack position k, crease k the k-th from the
    # bottom); the model's ids are kept in the metadata
    plate_map, crease_map = workshop_ids(model.plate_ids, thick.stack_position, structure.creases)
    creases = []
    for c in structure.creases:
        creases.append(
            {
                "id": crease_map[int(c["id"])],
                "plates": [plate_map[int(x)] for x in c["plates"]],
                "vertices": c["vertices"],
                "kind": c["kind"],
                # the mean of the edges' fold angles, measured from the geometry (the
                # per-vertex reflection angles read off at a kink or an inflection)
                "fold_angle": float(np.mean(c["fold_angles"])),
            }
        )
    creases.sort(key=lambda c: c["id"])
    model_plates = sorted(plate_map, key=plate_map.get)
    model_creases = sorted(crease_map, key=crease_map.get)
    return FabricationData(
        name=model.design.name,
        alpha=float(design.alpha),
        thickness=thick.thickness,
        material=thick.material.name,
        plate_ids=[plate_map[int(pid)] for pid in model.plate_ids],
        faces=model.faces,
        flat=flat,
        deployed_mid=design.solids.mean(axis=1),
        solids=design.solids,
        stack_solids=stack.solids,
        creases=creases,
        stack_position=list(thick.stack_position),
        hinge_width=width,
        metadata={
            "pairing": [thick.pairing()[m] for m in model_creases],
            "grain": thick.grain,
            "model_plate_ids": model_plates,
            "model_crease_ids": model_creases,
        },
    )
