"""Planar-quad developable strips: intrinsics, frames, ruling fields, development."""

from __future__ import annotations

from compas_ccu.strips.intrinsics import StripIntrinsics, sector_angles, strip_intrinsics

__all__ = ["StripIntrinsics", "sector_angles", "strip_intrinsics"]
