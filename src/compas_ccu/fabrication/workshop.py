"""The workshop: plates split to fit the sheets, parts nested onto sheets, the bill of materials
and the assembly sequence.

:func:`plan_workshop` turns a :class:`~compas_ccu.fabrication.data.FabricationData` and the
design's ``[fabrication]`` section (:class:`WorkshopOptions`) into a :class:`WorkshopPlan`:

1. every plate is checked against the sheets in stock in the orientations the grain allows; a
   plate that fits no sheet is split along rulings (straight lines on the plate, so the joint
   does not fight the bending), as few parts as the sheets allow, the cuts staggered between
   plates so that the splice plates do not pile up in the stack
   (:mod:`compas_ccu.fabrication.splices`), and every cut gets two splice plates (one on each
   face) with their fasteners;
2. every part (plate parts and splice plates) is nested onto sheets by a true-shape nester
   (:mod:`compas_ccu.fabrication.nesting`: compas_nest onto the sheets directly, or spyrrow's
   strip packing cut into sheets; shelves of bounding boxes, with a warning, when neither is
   installed); the hinge strips are packed onto the textile roll the same way (the roll's
   used length);
3. the bill of materials (areas, masses, sheets, textile, glue line, fasteners, cost) and the
   assembly steps in stack order (:mod:`compas_ccu.fabrication.assembly`).

:func:`write_sheet_dxf` writes one sheet's DXF with kerf-compensated toolpaths. Units: metres
and degrees here, millimetres in the DXF files.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

from compas_ccu.errors import CCUWarning
from compas_ccu.fabrication.assembly import assembly_steps
from compas_ccu.fabrication.bom import bill_of_materials, write_bom_csv
from compas_ccu.fabrication.nesting import (
    nest_parts,
    nest_roll,
    nesting_choice,
    nesting_search,
)
from compas_ccu.fabrication.parts import make_parts, splice_bending
from compas_ccu.fabrication.plan import Part, WorkshopOptions, WorkshopPlan
from compas_ccu.fabrication.sheet_dxf import SHEET_LAYERS, write_sheet_dxf
from compas_ccu.fabrication.splices import (
    splice_records,
    split_plate,
)

__all__ = [
    "plan_workshop",
    "WorkshopOptions",
    "Part",
    "WorkshopPlan",
    "split_plate",
    "splice_bending",
    "write_sheet_dxf",
    "write_bom_csv",
    "SHEET_LAYERS",
    "make_parts",
    "nest_parts",
    "nest_roll",
    "bill_of_materials",
    "nesting_search",
]


def plan_workshop(
    data,
    strips,
    options: WorkshopOptions,
    *,
    density: float,
    pairing=None,
    utilisation=None,
    strength_factor: float = 1.0,
):
    """Split, nest, count and order: the :class:`WorkshopPlan` of a design.

    Parameters
    ----------
    data : FabricationData
    strips : list of compas_ccu.fabrication.hinges.HingeStrip
    options : WorkshopOptions
    density : float
        Plate material density, kg/m³ (masses).
    pairing : list of str, optional
        Per crease id: the faces its hinge joins (``ThickModel.pairing``).
    utilisation : (p, 2n + 2) float, optional
        The plates' bending utilisation per vertex (:func:`splice_bending`); without it the
        splices are not checked.
    strength_factor : float
        Design over characteristic strength of ``utilisation`` (:func:`splice_bending`).

    Returns
    -------
    WorkshopPlan

    Raises
    ------
    GeometryError
        A part fits no sheet (e.g. a plate wider than every sheet), or a hinge strip is wider
        than the roll.
    """
    nesting, warning = nesting_choice(options.nesting)  # the nester installed, or shelves
    if warning is not None:
        warnings.warn(warning, CCUWarning, stacklevel=2)
    options = replace(options, nesting=nesting)
    parts, splits = make_parts(data, options)
    log: list = []
    sheets = nest_parts(parts, options, log=log)
    roll = nest_roll(strips, options, log=log)
    plan = WorkshopPlan(
        options=options,
        parts=parts,
        sheets=sheets,
        splits=splits,
        roll=roll,
        design=data.name,
        model_plate_ids=data.metadata.get("model_plate_ids"),
        nesting_search=nesting_search(options, log),
        splices=splice_records(data, splits, options),
        warnings=[] if warning is None else [warning],
    )
    plan.bom = bill_of_materials(data, parts, sheets, roll, options, density)
    plan.assembly = assembly_steps(data, splits, pairing)
    if utilisation is not None:
        plan.splice_bending = splice_bending(
            data, splits, utilisation, options, strength_factor=strength_factor
        )
    return plan
