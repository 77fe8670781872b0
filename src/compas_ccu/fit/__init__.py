"""Fit to geometry (docs/fit.md): targets and scans as points, the exact distance from points to
the deployed plates, the as-built check of a scan (:func:`register`, ``ccu asbuilt``) and the
design fit of free design keys to a target (:func:`fit_design`, ``ccu fit``)."""

from __future__ import annotations

from compas_ccu.fit.design_fit import (
    DesignFit,
    FreeKey,
    fit_design,
    free_keys,
    parse_free,
    target_distance,
    target_spacing,
)
from compas_ccu.fit.distance import Distances, PlateSurface, closest_on_triangles, plate_triangles
from compas_ccu.fit.points import PointSet, point_set, read_points, sample_triangles
from compas_ccu.fit.register import AsBuilt, PlateDeviation, register

__all__ = ["PointSet", "read_points", "point_set", "sample_triangles"]
__all__ += ["PlateSurface", "Distances", "closest_on_triangles", "plate_triangles"]
__all__ += ["AsBuilt", "PlateDeviation", "register"]
__all__ += ["DesignFit", "FreeKey", "fit_design", "parse_free", "free_keys"]
__all__ += ["target_distance", "target_spacing"]
