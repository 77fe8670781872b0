"""Typed design sections, generated from the schema: ``design.crease.span`` instead of dicts.

Every section of :data:`compas_ccu.design.schema.SCHEMA` becomes a frozen dataclass with one
field per key (the validated value, or None where unset and without default), so a misspelt key
is an ``AttributeError`` at the line that misspells it rather than a silent ``None``.

>>> from compas_ccu.design.schema import validate
>>> values = validate({"crease": {"profile": "arc", "span": 2.0, "rise": 0.5},
...                    "rulings": {"type": "orthogonal"}, "deployment": {"alpha": 30.0},
...                    "layout": {"width": 0.3}})
>>> sections = DesignSections.from_values(values)
>>> sections.crease.span, sections.layout.type, sections.plates.material
(2.0, 'single', 'plywood')
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields, make_dataclass

from compas_ccu.design.schema import SCHEMA, file_material

__all__ = ["SECTION_TYPES", "DesignSections", "MaterialsSection"]


def _section_type(section: str, keys: dict):
    names = [name for name in keys if not name.startswith("_")]
    cls = make_dataclass(
        f"{section.capitalize()}Section",
        [(name, object) for name in names],
        frozen=True,
        namespace={"to_dict": lambda self: asdict(self)},
    )
    cls.__module__ = __name__
    cls.__doc__ = f"The [{section}] section of a design file. {keys['_doc']}"
    return cls


#: One frozen dataclass per design-file section, fields in schema order.
SECTION_TYPES = {section: _section_type(section, keys) for section, keys in SCHEMA.items()}


DesignSection = SECTION_TYPES["design"]
CreaseSection = SECTION_TYPES["crease"]
RulingsSection = SECTION_TYPES["rulings"]
DeploymentSection = SECTION_TYPES["deployment"]
LayoutSection = SECTION_TYPES["layout"]
TargetSection = SECTION_TYPES["target"]
PlatesSection = SECTION_TYPES["plates"]
PlaneSection = SECTION_TYPES["plane"]
DesignCodeSection = SECTION_TYPES["design_code"]
LoadsSection = SECTION_TYPES["loads"]
SupportsSection = SECTION_TYPES["supports"]
HingesSection = SECTION_TYPES["hinges"]
FabricationSection = SECTION_TYPES["fabrication"]


class MaterialsSection(Mapping):
    """The ``[materials.NAME]`` tables of a design file: name -> :class:`~compas_ccu.materials.
    Material` (read only).

    >>> section = MaterialsSection({"stiff": {"base": "plywood", "E": 10e9}})
    >>> section["stiff"].E1, list(section)
    (10000000000.0, ['stiff'])
    """

    def __init__(self, values: dict):
        self._values = copy.deepcopy(values)
        self._materials = {name: file_material(name, v) for name, v in self._values.items()}

    def __getitem__(self, name):
        return self._materials[name]

    def __iter__(self):
        return iter(self._materials)

    def __len__(self):
        return len(self._materials)

    def __eq__(self, other):
        return isinstance(other, MaterialsSection) and self._values == other._values

    __hash__ = None

    def __repr__(self):
        return f"MaterialsSection({sorted(self._materials)})"

    def to_dict(self) -> dict:
        """``{name: {key: value}}``, the form :func:`validate` returns."""
        return copy.deepcopy(self._values)


@dataclass(frozen=True)
class DesignSections:
    """All sections of a validated design, typed (one field per section of the schema)."""

    design: DesignSection
    crease: CreaseSection
    rulings: RulingsSection
    deployment: DeploymentSection
    layout: LayoutSection
    target: TargetSection
    plates: PlatesSection
    design_code: DesignCodeSection
    loads: LoadsSection
    supports: SupportsSection
    hinges: HingesSection
    fabrication: FabricationSection
    plane: PlaneSection
    materials: MaterialsSection

    @classmethod
    def from_values(cls, values: dict) -> DesignSections:
        """Typed sections from :func:`compas_ccu.design.schema.validate` output."""
        out = {
            f.name: SECTION_TYPES[f.name](**values[f.name])
            for f in fields(cls)
            if f.name in SECTION_TYPES
        }
        return cls(**out, materials=MaterialsSection(values.get("materials", {})))

    def to_values(self) -> dict:
        """``{section: {key: value}}``, the form :func:`validate` returns."""
        return {f.name: getattr(self, f.name).to_dict() for f in fields(self)}
