"""Design files (TOML): schema, validation, typed sections and the design-state geometry."""

from __future__ import annotations

from compas_ccu.design.document import Design, load_design
from compas_ccu.design.schema import SCHEMA, validate

__all__ = ["Design", "load_design", "SCHEMA", "validate"]
