"""Plate thickness (paper §5.3): axis-shift solids, collisions and the bending check."""

from __future__ import annotations

from compas_ccu.thickness.axis_shift import place_thick, solid_faces, vertex_offsets
from compas_ccu.thickness.bending import BendingCheck, bending_check
from compas_ccu.thickness.model import CollisionReport, ThickModel, ThickState

__all__ = [
    "ThickModel",
    "ThickState",
    "CollisionReport",
    "BendingCheck",
    "bending_check",
    "place_thick",
    "solid_faces",
    "vertex_offsets",
]
