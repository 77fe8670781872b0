"""Validate a parsed design document against :data:`~compas_ccu.design.schema_table.SCHEMA`.

:func:`validate` checks the sections and keys of a document (each value by
:func:`compas_ccu.design.values.coerce_value`), its ``[materials.NAME]`` tables
(:func:`file_material`) and then the rules between keys (:data:`compas_ccu.design.rules.RULES`),
and fills in the defaults.
"""

from __future__ import annotations

import re

from compas_ccu.design.rules import RULES
from compas_ccu.design.schema_table import NAMED_SECTIONS, REQUIRED_SECTIONS, SCHEMA
from compas_ccu.design.units import DEFAULT_UNITS
from compas_ccu.design.values import coerce_value, short_repr
from compas_ccu.errors import DesignError
from compas_ccu.materials import MATERIALS, Material, MaterialError

__all__ = ["validate", "file_material"]

_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*\Z")


def file_material(name: str, values: dict) -> Material:
    """The :class:`~compas_ccu.materials.Material` of a validated ``[materials.NAME]`` table.

    Raises
    ------
    DesignError
        A value is missing, given twice (``E`` and ``E1``) or impossible (``nu12`` against
        ``E1/E2``); the key is ``materials.NAME.KEY``.

    Examples
    --------
    >>> m = file_material("stiff", {"base": "plywood", "E": 10e9})
    >>> m.E1 == m.E2 == 10e9, round(m.G12 / 1e9, 3), m.f1 / 1e6, m.kind
    (True, 3.846, 30.0, 'plywood')
    """
    where = f"materials.{name}"
    given = {k: v for k, v in values.items() if v is not None}
    base = given.pop("base", None)
    for short, longs in (("E", ("E1", "E2")), ("f", ("f1", "f2"))):
        both = [k for k in longs if k in given]
        if short in given and both:
            raise DesignError(
                f"give {short} (isotropic) or {' and '.join(longs)}, not both",
                key=f"{where}.{both[0]}",
            )
    out = MATERIALS[base].to_dict() if base is not None else {}
    out["name"] = name
    if base is not None:
        out["description"] = f"{base} with " + ", ".join(
            f"{k} = {v:g}" for k, v in given.items() if isinstance(v, float)
        )
    if "E" in given:
        E = given.pop("E")
        nu = given.get("nu12", out.get("nu12"))
        out.update(E1=E, E2=E)
        if "G12" not in given and nu is not None:
            out["G12"] = E / (2.0 * (1.0 + nu))
    if "f" in given:
        f = given.pop("f")
        out.update(f1=f, f2=f)
    out.update(given)
    out.setdefault("kind", "other")
    missing = [k for k in ("E1", "E2", "G12", "nu12", "density", "f1", "f2") if k not in out]
    if missing:
        raise DesignError(
            f"missing {', '.join(missing)}: give every value (E or E1 and E2, G12 unless E is "
            f"given, nu12, density, f or f1 and f2), or a base = one of {', '.join(MATERIALS)}",
            key=where,
        )
    try:
        return Material(**out)
    except MaterialError as exc:
        text = str(exc)
        key = next((k for k in ("nu12", "E1", "E2", "G12", "f1", "f2") if k in text), None)
        message = text.split(": ", 1)[-1]
        raise DesignError(message, key=f"{where}.{key}" if key else where) from None


def _validate_named(section: str, given, keys: dict) -> dict:
    """The named tables ``[section.NAME]`` of a document, each checked against ``keys``."""
    out = {}
    for name, table in given.items():
        where = f"{section}.{name}"
        if not isinstance(table, dict):
            raise DesignError(
                f"must be a table [{section}.NAME] of values, got {short_repr(table)}", key=where
            )
        if not _NAME.match(name):
            raise DesignError(
                "a name is letters, digits, '-' and '_' (starting with a letter or digit)",
                key=f"[{where}]",
            )
        if section == "materials" and name in MATERIALS:
            raise DesignError(
                f'shadows the library material {name!r}; give it another name and base = "{name}"',
                key=f"[{where}]",
            )
        allowed = [k for k in keys if not k.startswith("_")]
        for k in table:
            if k not in allowed:
                raise DesignError(
                    f"unknown key; allowed in [{section}.NAME]: {', '.join(allowed)}",
                    key=f"{where}.{k}",
                )
        values = {
            k: coerce_value(where, k, keys[k], table[k]) if k in table else None for k in allowed
        }
        if section == "materials":
            file_material(name, values)  # every value together (missing, nu12 vs E1/E2)
        out[name] = values
    return out


def _units(document: dict) -> str:
    """The ``[design] units`` of a document, checked first: every length depends on it."""
    table = document.get("design")
    if not isinstance(table, dict) or "units" not in table:
        return DEFAULT_UNITS
    return coerce_value("design", "units", SCHEMA["design"]["units"], table["units"])


def _validate_section(section: str, keys: dict, given: dict, units: str) -> dict:
    """The keys of one section of :data:`SCHEMA`: the given ones checked, defaults filled in."""
    allowed = [k for k in keys if not k.startswith("_")]
    for name in given:
        if name not in allowed:
            raise DesignError(
                f"unknown key; allowed in [{section}]: {', '.join(allowed)}",
                key=f"{section}.{name}",
            )
    values = {}
    for name in allowed:
        key = keys[name]
        if name in given:
            values[name] = coerce_value(section, name, key, given[name], units)
        elif key.required:
            raise DesignError("missing required key", key=f"{section}.{name}")
        else:
            values[name] = key.default
    return values


def validate(document: dict) -> dict:
    """Validate a parsed design document and fill in defaults.

    Parameters
    ----------
    document : dict
        The parsed TOML.

    Returns
    -------
    dict
        ``{section: {key: value}}`` with every key of :data:`SCHEMA` present (None if unset),
        and ``{"materials": {name: {key: value}}}`` for the ``[materials.NAME]`` tables.
        Lengths are metres: a document with ``[design] units`` other than ``"m"`` is
        converted (:mod:`compas_ccu.design.units`); ``design.units`` keeps the file's units.

    Raises
    ------
    DesignError
        Unknown section or key, wrong type, value out of range, missing required key. The
        message starts with the dotted key name.
    """
    if not isinstance(document, dict):
        raise DesignError(f"a design must be a table, got {type(document).__name__}")
    out: dict = {}
    units = _units(document)
    for section in document:
        if section not in SCHEMA and section not in NAMED_SECTIONS:
            raise DesignError(
                f"unknown section; allowed: {', '.join([*SCHEMA, *NAMED_SECTIONS])}",
                key=f"[{section}]",
            )
        if not isinstance(document[section], dict):
            raise DesignError("must be a table", key=f"[{section}]")
    for section, keys in NAMED_SECTIONS.items():
        out[section] = _validate_named(section, document.get(section, {}), keys)
    for section, keys in SCHEMA.items():
        if section in REQUIRED_SECTIONS and section not in document:
            raise DesignError("missing required section", key=f"[{section}]")
        out[section] = _validate_section(section, keys, document.get(section, {}), units)
    for rule in RULES:
        if rule.applies(out) and not rule.holds(out):
            message = rule.message(out) if callable(rule.message) else rule.message
            raise DesignError(message, key=rule.key)
    return out
