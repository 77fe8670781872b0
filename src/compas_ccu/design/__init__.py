"""Design files (TOML): schema, validation, and construction of the design state."""

from __future__ import annotations

from compas_ccu.design.model import Design, load_design
from compas_ccu.design.schema import SCHEMA, validate

__all__ = ["Design", "load_design", "SCHEMA", "validate"]
