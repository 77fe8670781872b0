"""Measurements of built structures: global shape, crease planarity along the path."""

from compas_ccu.analysis.global_shape import GlobalCurvature, global_curvature

__all__ = ["GlobalCurvature", "global_curvature"]
