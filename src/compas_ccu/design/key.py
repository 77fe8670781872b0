"""The record of one design-file key, and the bounds the key tables share.

A section table (:mod:`compas_ccu.design.keys_shape`, :mod:`compas_ccu.design.keys_structure`,
:mod:`compas_ccu.design.keys_fabrication`) maps key names to :class:`Key` records;
:data:`compas_ccu.design.schema_table.SCHEMA` gathers the sections.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, Callable

__all__ = [
    "Key",
    "MAX_LENGTH",
    "positive",
    "non_negative",
    "angle_open",
    "fraction",
    "with_units",
]


@dataclass(frozen=True)
class Key:
    """One design-file key."""

    kind: str  # "float", "int", "str", "bool", "point2", "point3", "points2", "polyline2",
    # "sizes2" (one or more [x, y] pairs), "float_or_list", "gamma", "patterns" (an array of
    # tables of PATTERN_KEYS)
    doc: str
    default: Any = None
    required: bool = False
    choices: tuple = ()
    check: Callable | None = field(default=None, compare=False)
    check_doc: str = ""
    when: str = ""  # documentation: when the key applies
    columns: int = 0  # kind "rows": numbers per row
    unit: str = ""  # "m", "deg", "1" (dimensionless) or "" (not a quantity); set by with_units


#: The largest length a design may give, m: beyond it the profile solvers lose their precision
#: long before a plate structure could exist.
MAX_LENGTH = 1.0e6


def positive(v):
    """A length > 0 and <= :data:`MAX_LENGTH`."""
    return 0.0 < v <= MAX_LENGTH


def non_negative(v):
    """A length >= 0 and <= :data:`MAX_LENGTH`."""
    return 0.0 <= v <= MAX_LENGTH


def angle_open(v):
    """An angle strictly between 0 and 90 degrees."""
    return 0.0 < v < 90.0


def fraction(v):
    """A fraction from 0 to 1."""
    return 0.0 <= v <= 1.0


def with_units(sections: dict, units: dict) -> dict:
    """Set the unit of every quantity key of ``sections`` from ``units``.

    Parameters
    ----------
    sections : dict
        ``{section: {name: Key}}``; changed in place and returned.
    units : dict
        ``{section: {name: unit}}``: ``"m"``, ``"deg"``, ``"1"`` (dimensionless), ...

    Returns
    -------
    dict
        ``sections``.

    Examples
    --------
    >>> sections = with_units({"s": {"a": Key("float", "A length.")}}, {"s": {"a": "m"}})
    >>> sections["s"]["a"].unit
    'm'
    """
    for section, section_units in units.items():
        for name, unit in section_units.items():
            sections[section][name] = replace(sections[section][name], unit=unit)
    return sections
