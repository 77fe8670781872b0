"""The design-file schema in one import: the key table, validation and the generated reference.

The table :data:`SCHEMA` is the single source of truth: :func:`validate` checks a parsed TOML
document against it, and ``docs/design-files.md`` is generated from it
(``python -m compas_ccu.design.schema > docs/design-files.md``), so the documentation cannot
drift from the code.

This module re-exports the modules that do the work, one job each:

- :mod:`compas_ccu.design.key`: the :class:`Key` record and the bounds the tables share;
- :mod:`compas_ccu.design.keys_shape`, :mod:`compas_ccu.design.keys_structure`,
  :mod:`compas_ccu.design.keys_fabrication`: the keys of the sections, by job;
- :mod:`compas_ccu.design.schema_table`: :data:`SCHEMA`, the sections in order;
- :mod:`compas_ccu.design.values`: one value checked against its key;
- :mod:`compas_ccu.design.validation`: :func:`validate`, a whole document checked;
- :mod:`compas_ccu.design.schema_doc`: :func:`schema_markdown`, the reference page.
"""

from __future__ import annotations

# the ``X as X`` imports re-export names this module imported before it was split (the
# errors, rules, units and materials names), so that they stay importable from here
from compas_ccu.design.key import MAX_LENGTH, Key
from compas_ccu.design.keys_fabrication import STOCK_SHEET, design_sheet
from compas_ccu.design.keys_structure import MATERIAL_KEYS
from compas_ccu.design.rules import RULES as RULES
from compas_ccu.design.schema_doc import schema_markdown
from compas_ccu.design.schema_table import NAMED_SECTIONS, REQUIRED_SECTIONS, SCHEMA
from compas_ccu.design.units import DEFAULT_UNITS as DEFAULT_UNITS
from compas_ccu.design.units import LENGTH_UNITS as LENGTH_UNITS
from compas_ccu.design.units import is_length as is_length
from compas_ccu.design.units import to_metres as to_metres
from compas_ccu.design.units import unit_factor as unit_factor
from compas_ccu.design.validation import file_material, validate
from compas_ccu.design.values import (
    CURVE_FILE_KEYS,
    CURVE_FILE_PLACES,
    CURVE_FILE_UNITS,
    PATTERN_KEYS,
)
from compas_ccu.errors import DesignError as DesignError
from compas_ccu.materials import ACTION_DURATIONS as ACTION_DURATIONS
from compas_ccu.materials import LOAD_DURATIONS as LOAD_DURATIONS
from compas_ccu.materials import MATERIAL_KINDS as MATERIAL_KINDS
from compas_ccu.materials import MATERIALS as MATERIALS
from compas_ccu.materials import Material as Material
from compas_ccu.materials import MaterialError as MaterialError

__all__ = [
    "Key",
    "SCHEMA",
    "MATERIAL_KEYS",
    "NAMED_SECTIONS",
    "validate",
    "file_material",
    "schema_markdown",
    "MAX_LENGTH",
    "STOCK_SHEET",
    "REQUIRED_SECTIONS",
    "CURVE_FILE_KEYS",
    "CURVE_FILE_UNITS",
    "CURVE_FILE_PLACES",
    "PATTERN_KEYS",
    "design_sheet",
]


if __name__ == "__main__":  # pragma: no cover
    print(schema_markdown())
