"""Rhino 8 / Grasshopper: the logic of the components and the geometry conversions.

The Grasshopper Python 3 components live in ``components/<Name>/`` (``code.py``,
``metadata.json``, ``icon.png``: the COMPAS convention); each one's code converts its inputs and
calls one function of :mod:`compas_ccu.ghpython.components`, so that the logic runs (and is
tested) on any CPython. Nothing here imports Rhino at import time: inside Rhino,
:mod:`compas_ccu.ghpython.convert` turns the output into Rhino geometry through
``compas_rhino.conversions``; elsewhere it stays COMPAS geometry. docs/rhino.md: installing in
Rhino 8 and what was verified where.
"""

from __future__ import annotations

from compas_ccu.ghpython.components import (
    as_model,
    checks_component,
    crease_design,
    cut_patterns_component,
    deploy_component,
    design_component,
    fabricate_component,
)
from compas_ccu.ghpython.convert import (
    crease_plane,
    curve_points,
    document_unit_scale,
    to_host,
    to_host_surface,
)

__all__ = [
    "as_model",
    "crease_design",
    "design_component",
    "deploy_component",
    "checks_component",
    "cut_patterns_component",
    "fabricate_component",
    "curve_points",
    "crease_plane",
    "to_host",
    "to_host_surface",
    "document_unit_scale",
]
