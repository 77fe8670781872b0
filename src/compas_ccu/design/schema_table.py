"""The design-file key table :data:`SCHEMA`: every section, in the order of the documentation.

The sections are defined by job in :mod:`compas_ccu.design.keys_shape`,
:mod:`compas_ccu.design.keys_structure` and :mod:`compas_ccu.design.keys_fabrication`; this
module puts them in order and says which sections a design must have and which hold named
tables. :mod:`compas_ccu.design.validation` checks a document against the table,
:mod:`compas_ccu.design.schema_doc` writes ``docs/design-files.md`` from it.
"""

from __future__ import annotations

from compas_ccu.design.keys_fabrication import FABRICATION_SECTIONS
from compas_ccu.design.keys_shape import SHAPE_SECTIONS
from compas_ccu.design.keys_structure import MATERIAL_KEYS, STRUCTURE_SECTIONS

__all__ = ["SCHEMA", "SECTION_ORDER", "NAMED_SECTIONS", "REQUIRED_SECTIONS"]

#: The order of the sections: that of ``docs/design-files.md``, of validated designs and of the
#: sections an "unknown section" message lists.
SECTION_ORDER = (
    "design",
    "crease",
    "rulings",
    "deployment",
    "layout",
    "target",
    "plates",
    "design_code",
    "loads",
    "supports",
    "hinges",
    "fabrication",
    "plane",
)

_SECTIONS = {**SHAPE_SECTIONS, **STRUCTURE_SECTIONS, **FABRICATION_SECTIONS}

#: ``{section: {name: Key}}``: every key of a design file (``"_doc"``: the section's text).
SCHEMA: dict = {section: _SECTIONS[section] for section in SECTION_ORDER}

#: Sections that hold named tables (``[materials.NAME]``), with the keys of one table.
NAMED_SECTIONS = {"materials": MATERIAL_KEYS}

#: The sections a design file must have.
REQUIRED_SECTIONS = ("crease", "rulings", "deployment")
