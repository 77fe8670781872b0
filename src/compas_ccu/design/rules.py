"""The rules between design keys: keys required only for some types, refused combinations.

:func:`compas_ccu.design.schema.validate` checks them, in the order of :data:`RULES`, once every
key is valid on its own; ``docs/design-files.md`` lists them (generated).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

from compas_ccu.materials import GAMMA_M, MATERIALS

__all__ = ["Rule", "RULES", "MULTI_CREASE", "plate_material_kind"]

MULTI_CREASE = ("parallel", "inclined", "radial")
#: The layouts that give their plates by their cut patterns (explicit rulings).
CUT_PATTERN = ("single", "patterns")


@dataclass(frozen=True)
class Rule:
    """A rule between keys that the table of keys cannot say: a key required only for some
    types, or a combination of values that is refused.

    ``applies(values)`` says whether the rule is in force for validated values (defaults filled
    in); then ``holds(values)`` must be true, else the error names ``key`` with ``message``
    (a string, or a function of the values for a message that quotes them).
    """

    key: str
    doc: str
    applies: Callable = field(compare=False)
    holds: Callable = field(compare=False)
    message: Any = field(default="", compare=False)


def _required(section: str, name: str, when: str, applies: Callable) -> Rule:
    return Rule(
        f"{section}.{name}",
        f"required for {when}",
        applies,
        lambda v: v[section][name] is not None,
        f"required for {when}",
    )


def _ruling_type(kind):
    return lambda v: v["rulings"]["type"] == kind


def _layout_type(*kinds):
    return lambda v: v["layout"]["type"] in kinds


def _has_target(v) -> bool:
    return any(value is not None for value in v["target"].values())


def plate_material_kind(v) -> str:
    """The kind of the plate material of validated values (a library or a file material)."""
    name = v["plates"]["material"]
    table = v.get("materials", {}).get(name)
    if table is None:
        return MATERIALS[name].kind if name in MATERIALS else "other"
    if table.get("kind") is not None:
        return table["kind"]
    return MATERIALS[table["base"]].kind if table.get("base") is not None else "other"


def _needs_factor(v) -> bool:
    return v["design_code"]["code"] == "EC5" and GAMMA_M.get(plate_material_kind(v)) is None


def _factor_rule(name: str) -> Rule:
    return Rule(
        f"design_code.{name}",
        "required for code 'EC5' with a plate material of kind 'gfrp' or 'other' (no default "
        "design factors)",
        _needs_factor,
        lambda v: v["design_code"][name] is not None,
        lambda v: (
            f"required for code 'EC5' with plate material {v['plates']['material']!r} of kind "
            f"{plate_material_kind(v)!r} (no default design factors); or code = "
            "'characteristic'"
        ),
    )


#: The conditional rules, checked in this order after every key has been checked on its own.
RULES = (
    _required("rulings", "direction", "type 'cylindrical'", _ruling_type("cylindrical")),
    _required("rulings", "apex", "type 'conical'", _ruling_type("conical")),
    _required("rulings", "gamma", "type 'angle'", _ruling_type("angle")),
    _required("rulings", "points", "type 'explicit'", _ruling_type("explicit")),
    Rule(
        "rulings.points",
        "explicit rulings need crease.state = 'flat' and layout type 'single' or 'patterns'",
        _ruling_type("explicit"),
        lambda v: v["crease"]["state"] == "flat" and v["layout"]["type"] in CUT_PATTERN,
        lambda v: (
            "explicit rulings describe a cut pattern: they need crease.state = 'flat' and "
            f"layout type 'single' or 'patterns', got state {v['crease']['state']!r} and "
            f"layout {v['layout']['type']!r}"
        ),
    ),
    Rule(
        "layout.type",
        "layout type 'patterns' needs rulings.type = 'explicit' and crease.state = 'flat'",
        _layout_type("patterns"),
        lambda v: v["rulings"]["type"] == "explicit" and v["crease"]["state"] == "flat",
        lambda v: (
            "layout 'patterns' lists cut patterns: the leading plate is one too, so it needs "
            "rulings.type = 'explicit' and crease.state = 'flat', got rulings "
            f"{v['rulings']['type']!r} and state {v['crease']['state']!r}"
        ),
    ),
    _required("layout", "patterns", "layout type 'patterns'", _layout_type("patterns")),
    Rule(
        "[target]",
        "target curves need layout type 'parallel' or 'inclined'",
        _has_target,
        _layout_type("parallel", "inclined"),
        lambda v: (
            f"target curves need layout type 'parallel' or 'inclined', got {v['layout']['type']!r}"
        ),
    ),
    Rule(
        "target.support_end",
        "needs target.support as well",
        lambda v: v["target"]["support_end"] is not None,
        lambda v: v["target"]["support"] is not None,
        "needs target.support as well",
    ),
    Rule(
        "crease.state",
        "multi-crease layouts need crease.state = 'deployed'",
        _layout_type(*MULTI_CREASE),
        lambda v: v["crease"]["state"] == "deployed",
        lambda v: (
            f"layout '{v['layout']['type']}' needs crease.state = 'deployed': the crease "
            "planes are placed at the design state"
        ),
    ),
    _required(
        "layout",
        "width",
        "layout type 'single'",
        lambda v: v["layout"]["type"] == "single" and v["rulings"]["type"] != "explicit",
    ),
    Rule(
        "layout.plates",
        "required for layout types 'parallel', 'inclined' and 'radial'",
        _layout_type(*MULTI_CREASE),
        lambda v: v["layout"]["plates"] is not None,
        lambda v: f"required for layout type '{v['layout']['type']}'",
    ),
    Rule(
        "layout.spacing",
        "required for layout types 'parallel' and 'inclined'",
        _layout_type("parallel", "inclined"),
        lambda v: v["layout"]["spacing"] is not None,
        lambda v: f"required for layout type '{v['layout']['type']}'",
    ),
    _required("layout", "angle", "layout type 'radial'", _layout_type("radial")),
    _required("layout", "axis", "layout type 'radial'", _layout_type("radial")),
    Rule(
        "plates.material",
        "a library material or one of the file's [materials.NAME] tables",
        lambda v: True,
        lambda v: (
            v["plates"]["material"] in MATERIALS
            or v["plates"]["material"] in v.get("materials", {})
        ),
        lambda v: (
            f"unknown material {v['plates']['material']!r}; known: "
            + ", ".join(repr(n) for n in [*MATERIALS, *v.get("materials", {})])
        ),
    ),
    _factor_rule("gamma_M"),
    _factor_rule("k_mod"),
)
