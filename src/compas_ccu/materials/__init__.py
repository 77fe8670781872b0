"""Plate materials: a small documented library for the FE model and the bending check.

:mod:`.library` holds the materials (:class:`Material`, :data:`MATERIALS`, :func:`material`),
:mod:`.eurocode` their design values (:class:`DesignFactors`, :func:`design_factors`); both are
imported from here.

Values are typical (rounded) mean stiffnesses and characteristic bending strengths from
manufacturers' data sheets and EN 13986 / EN 1999 tables; they are a starting point, not a design
value: replace them with your supplier's figures (a design file or the API takes any values).

Direction 1 is the face-grain direction of plywood (the long side of the board), direction 2 the
cross direction. Units are SI: Pa, kg/m³.

>>> from compas_ccu.materials import material
>>> m = material("birch-plywood")
>>> round(m.E1 / 1e9, 1), m.is_isotropic
(11.0, False)
>>> round(material("plywood").curvature_limit(0.008), 3)   # f (1 - nu^2) / (E t / 2), 1/m
0.758
"""

from __future__ import annotations

from compas_ccu.materials.eurocode import (
    ACTION_DURATIONS,
    GAMMA_M,
    K_DEF_PLYWOOD,
    K_MOD_PLYWOOD,
    LOAD_DURATIONS,
    DesignFactors,
    design_factors,
    k_mod_plywood,
)
from compas_ccu.materials.eurocode import CODES as CODES
from compas_ccu.materials.library import (
    MATERIAL_KINDS,
    MATERIALS,
    Material,
    MaterialError,
    material,
)

__all__ = [
    "Material",
    "MATERIALS",
    "MATERIAL_KINDS",
    "material",
    "MaterialError",
    "LOAD_DURATIONS",
    "ACTION_DURATIONS",
    "K_MOD_PLYWOOD",
    "K_DEF_PLYWOOD",
    "GAMMA_M",
    "DesignFactors",
    "design_factors",
    "k_mod_plywood",
]
