"""Exact one-degree-of-freedom kinematics: leading strip, reflected plates, crease relations."""

from __future__ import annotations

from compas_ccu.kinematics.leading import LeadingStrip
from compas_ccu.kinematics.mechanism import Mechanism

__all__ = ["LeadingStrip", "Mechanism"]
