"""The reverse of fabrication: plate DXFs back to a design that deploys (``ccu import``).

A folder of plate cut files, as :func:`compas_ccu.fabrication.dxf.write_plate_dxf` writes them
or drawn by hand to the same convention (docs/import.md), is read back:

``CUT``
    the closed outline of the plate (LWPOLYLINE or POLYLINE, bulges allowed);
``CREASE``
    every crease of the plate, on the outline: LWPOLYLINE, POLYLINE, ARC, SPLINE or a chain of
    LINEs. XDATA ``COMPAS_CCU`` (crease id, other plate id) pairs the plates; without it the
    plates are paired by their creases' lengths;
``RULING_SCORE``
    every interior ruling as a LINE from the crease to the other side of the plate (or on the
    reference layer ``RULING``, where ``ccu fabricate`` puts them when they are not scored).
    The two end rulings are the outline's edges at the crease's ends.

The crease vertices are the crease's end points and the rulings' feet on it, in order along it;
the ruling ends are the rulings' far end points. :func:`import_structure` joins every plate of
the folder into one mechanism that deploys the whole structure, and writes it as a design
document (``ccu import``): the leading plate as a ``state = "flat"`` design with ``explicit``
rulings, every other plate as a ``[[layout.patterns]]`` table (its cut pattern, its parent and
the parent's boundary it hangs from; :mod:`compas_ccu.design.patterns`).
:func:`import_design` turns one crease and its two plates into a single-crease design, the one
:func:`compas_ccu.model.flat_design` writes (``ccu import --leading-pair-only``); there the
partner must be the leading plate's mirror image (same crease, same rulings).

Inconsistent drawings are refused before anything is written, the error naming the plate file
and the entity (DXF handle): a missing layer, a ruling that does not start on the crease or
crosses another one, partner creases of different length, a partner that is not the mirror
image of the leading plate.

This module is the import's public face: the convention above and every public name of
``ccu import``, from the modules that do the work: reading the drawings
(:mod:`compas_ccu.fabrication.plate_drawings`), pairing their creases
(:mod:`~compas_ccu.fabrication.crease_pairs`), the folder and its leading pair
(:mod:`~compas_ccu.fabrication.import_selection`), undoing the thickness correction
(:mod:`~compas_ccu.fabrication.import_thickness`), the attachment tree
(:mod:`~compas_ccu.fabrication.import_tree`), the import itself
(:mod:`~compas_ccu.fabrication.import_documents`) and the round-trip errors
(:mod:`~compas_ccu.fabrication.round_trip`).
"""

from __future__ import annotations

from compas_ccu.design.writer import design_toml
from compas_ccu.fabrication.crease_pairs import CreasePair, crease_pattern, pair_creases
from compas_ccu.fabrication.import_documents import import_design, import_structure
from compas_ccu.fabrication.import_thickness import UNDO_TOLERANCE, thickness_shifts
from compas_ccu.fabrication.import_tree import ImportedStructure, structure_document
from compas_ccu.fabrication.plate_drawings import (
    CreaseDrawing,
    PlateDrawing,
    read_plate_drawing,
    read_plate_folder,
)
from compas_ccu.fabrication.round_trip import (
    RoundTripDeviation,
    round_trip_error,
    structure_error,
    structure_round_trip_error,
)

__all__ = [
    "import_design",
    "round_trip_error",
    "import_structure",
    "structure_round_trip_error",
    "structure_error",
    "RoundTripDeviation",
    "design_toml",
    "PlateDrawing",
    "CreaseDrawing",
    "CreasePair",
    "read_plate_drawing",
    "read_plate_folder",
    "crease_pattern",
    "pair_creases",
    "ImportedStructure",
    "structure_document",
    "thickness_shifts",
    "UNDO_TOLERANCE",
]
