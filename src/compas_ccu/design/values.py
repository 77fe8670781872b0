"""Check one design-file value against its key: its type, its range and its units.

:func:`coerce_value` turns the TOML value of one :class:`~compas_ccu.design.key.Key` into the
value a validated design holds (floats, lists of floats, lengths in metres, a completed curve-file
reference, checked ``[[layout.patterns]]`` tables) or raises a :class:`DesignError` that names the
key, the value and what is allowed. :func:`compas_ccu.design.validation.validate` calls it for
every key of a document.
"""

from __future__ import annotations

import math
from typing import Callable

from compas_ccu.design.key import MAX_LENGTH, Key
from compas_ccu.design.units import DEFAULT_UNITS, LENGTH_UNITS, is_length, to_metres, unit_factor
from compas_ccu.errors import DesignError

__all__ = [
    "coerce_value",
    "is_number",
    "short_repr",
    "CURVE_FILE_KEYS",
    "CURVE_FILE_UNITS",
    "CURVE_FILE_PLACES",
    "PATTERN_KEYS",
]

#: The keys of a curve-file table (``points = { file = ..., layer = ... }``), and their types.
CURVE_FILE_KEYS = {
    "file": str,
    "layer": str,
    "name": str,
    "index": int,
    "units": str,
    "scale": float,
}
CURVE_FILE_UNITS = ("m", "cm", "mm", "in", "ft", "px")
#: The keys that take a curve file instead of a list of points.
CURVE_FILE_PLACES = ("crease.points", "target.apex", "target.support", "target.support_end")

#: The keys of one ``[[layout.patterns]]`` table: (required, documentation).
PATTERN_KEYS = {
    "parent": (True, "index of the plate it hangs from (0: the leading plate)"),
    "boundary": (True, "'near' or 'far': the parent's boundary that is the shared crease"),
    "near": (True, "[[x, y], ...]: the crease row, in the parent's row order"),
    "far": (True, "[[x, y], ...]: the far end of every ruling"),
    "id": (False, "the plate id"),
}


def is_number(v) -> bool:
    """A finite real number that a float holds (TOML integers may have any number of digits).

    Examples
    --------
    >>> is_number(2), is_number(2.5), is_number(True), is_number(float("nan")), is_number(10**400)
    (True, True, False, False, False)
    """
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return False
    if isinstance(v, int):
        return abs(v) <= 2**1023
    return math.isfinite(v)


def short_repr(value, limit: int = 60) -> str:
    """``repr(value)``, cut to ``limit`` characters (ending in ``...``) for a message.

    Examples
    --------
    >>> short_repr(list(range(30)), limit=20)
    '[0, 1, 2, 3, 4, 5...'
    """
    text = repr(value)
    return text if len(text) <= limit else f"{text[: limit - 3]}..."


def _rows(value, columns: int) -> bool:
    """A list of lists of ``columns`` numbers each (:func:`is_number`)."""
    return isinstance(value, list) and all(
        isinstance(p, list) and len(p) == columns and all(map(is_number, p)) for p in value
    )


def _curve_file(where: str, value) -> dict:
    """A curve-file reference (a path, or a table with ``file``), checked and completed."""
    table = {"file": value} if isinstance(value, str) else dict(value)
    for k, v in table.items():
        if k not in CURVE_FILE_KEYS:
            raise DesignError(
                f"unknown key in a curve file table; allowed: {', '.join(CURVE_FILE_KEYS)}",
                key=f"{where}.{k}",
            )
        want = CURVE_FILE_KEYS[k]
        if want is float and is_number(v):
            v = table[k] = float(v)
        if not isinstance(v, want) or isinstance(v, bool):
            raise DesignError(f"must be a {want.__name__}, got {short_repr(v)}", key=f"{where}.{k}")
    if not table.get("file"):
        raise DesignError("a curve file table needs file = PATH", key=f"{where}.file")
    if table.get("units") is not None and table["units"] not in CURVE_FILE_UNITS:
        raise DesignError(
            f"must be one of {', '.join(CURVE_FILE_UNITS)}, got {table['units']!r}",
            key=f"{where}.units",
        )
    if table.get("index") is not None and table["index"] < 0:
        raise DesignError(f"must be >= 0, got {table['index']}", key=f"{where}.index")
    if "scale" in table and not 0.0 < table["scale"] <= MAX_LENGTH:
        raise DesignError(f"must be > 0 and <= 1e6, got {table['scale']}", key=f"{where}.scale")
    return {k: table.get(k, 1.0 if k == "scale" else None) for k in CURVE_FILE_KEYS}


def _patterns(where: str, value) -> list:
    """The ``[[layout.patterns]]`` tables, each checked on its own (types, at least two
    points, finite numbers); how they fit together is checked when the design is built
    (:mod:`compas_ccu.design.patterns`)."""
    if not isinstance(value, list) or not value:
        raise DesignError(
            f"must be a non-empty array of tables [[layout.patterns]], got {short_repr(value)}",
            key=where,
        )
    return [_pattern(f"{where}[{i}]", table) for i, table in enumerate(value)]


def _pattern(at: str, table) -> dict:
    """One ``[[layout.patterns]]`` table, checked; ``at`` names it (``layout.patterns[i]``)."""
    if not isinstance(table, dict):
        raise DesignError(
            f"must be a table (parent, boundary, near, far, id), got {short_repr(table)}", key=at
        )
    for k in table:
        if k not in PATTERN_KEYS:
            raise DesignError(
                f"unknown key; allowed in a pattern: {', '.join(PATTERN_KEYS)}",
                key=f"{at}.{k}",
            )
    for k, (required, doc) in PATTERN_KEYS.items():
        if required and k not in table:
            raise DesignError(f"missing required key ({doc})", key=f"{at}.{k}")
    for k in ("parent", "id"):
        v = table.get(k, 0)
        if not isinstance(v, int) or isinstance(v, bool) or v < 0:
            raise DesignError(f"must be an integer >= 0, got {short_repr(v)}", key=f"{at}.{k}")
    if table["boundary"] not in ("near", "far"):
        raise DesignError(
            f"must be 'near' or 'far', got {short_repr(table['boundary'])}", key=f"{at}.boundary"
        )
    rows = {}
    for k in ("near", "far"):
        v = table[k]
        if not _rows(v, 2):
            raise DesignError(
                f"must be a list of [x, y] pairs of finite numbers, got {short_repr(v)}",
                key=f"{at}.{k}",
            )
        if len(v) < 2:
            raise DesignError(
                f"needs at least 2 points (one per crease vertex), got {len(v)}",
                key=f"{at}.{k}",
            )
        rows[k] = [[float(x), float(y)] for x, y in v]
    if len(rows["near"]) != len(rows["far"]):
        raise DesignError(
            f"{len(rows['far'])} ruling ends for {len(rows['near'])} crease points: one "
            "far end per crease vertex",
            key=f"{at}.far",
        )
    return {
        "parent": table["parent"],
        "boundary": table["boundary"],
        "near": rows["near"],
        "far": rows["far"],
        "id": table.get("id"),
    }


def coerce_value(section: str, name: str, key: Key, value, units: str = DEFAULT_UNITS):
    """The validated value of key ``section.name`` given ``value`` in a document.

    Parameters
    ----------
    section, name : str
        Where the key is: the message of an error names ``section.name``.
    key : Key
        The key's record in :data:`compas_ccu.design.schema_table.SCHEMA`.
    value
        The parsed TOML value.
    units : str
        The document's ``[design] units``: a length is converted from them to metres.

    Returns
    -------
    object
        The value converted to its kind (an integer of a float key to a float, lists of numbers
        to lists of floats, a curve-file path to a completed table) and lengths to metres.

    Raises
    ------
    DesignError
        The value has the wrong type or fails the key's check; a length that would pass in
        other units says which (``did you mean units = "mm"?``).

    Examples
    --------
    >>> from compas_ccu.design.key import positive
    >>> key = Key("float", "A length.", check=positive, check_doc="> 0", unit="m")
    >>> coerce_value("crease", "span", key, 1200, "mm")
    1.2
    >>> coerce_value("crease", "span", key, -1, "m")
    Traceback (most recent call last):
    ...
    compas_ccu.errors.DesignError: crease.span: must be > 0, got -1.0
    """
    where = f"{section}.{name}"
    # the value as the message shows it: a number of a float key as a float (-1 -> -1.0)
    given = float(value) if key.kind == "float" and is_number(value) else value
    length = is_length(key.unit)

    def fail(what, hint=""):
        shown = short_repr(given)
        if length and units != DEFAULT_UNITS:
            shown = f"{shown} {units}"
        raise DesignError(f"{what}, got {shown}{hint}", key=where)

    value = _typed(where, key, value, fail)
    if length and not isinstance(value, dict):  # a curve file has its own units
        value = to_metres(key.kind, key.unit, value, units)
    if key.check is not None:
        values = value if isinstance(value, list) and key.kind == "float_or_list" else [value]
        for v in values:
            if not key.check(v):
                if not length:
                    fail(f"must be {key.check_doc}")
                metres = "" if units == DEFAULT_UNITS else " m"
                fail(f"must be {key.check_doc}{metres}", _units_hint(key, v, units))
    return value


def _typed(where: str, key: Key, value, fail: Callable):
    """``value`` checked against the kind of ``key`` and converted to it (file units, no range
    check yet); ``fail(what)`` raises the error of ``where``."""
    kind = key.kind
    if kind == "float":
        if not is_number(value):
            fail("must be a finite number")
        value = float(value)
    elif kind == "int":
        if not isinstance(value, int) or isinstance(value, bool):
            fail("must be an integer")
    elif kind == "str":
        if not isinstance(value, str):
            fail("must be a string")
        if key.choices and value not in key.choices:
            fail(f"must be one of {', '.join(repr(c) for c in key.choices)}")
    elif kind == "bool":
        if not isinstance(value, bool):
            fail("must be true or false")
    elif kind in ("point2", "point3"):
        dim = 2 if kind == "point2" else 3
        if not (isinstance(value, list) and len(value) == dim and all(map(is_number, value))):
            fail(f"must be a list of {dim} numbers")
        value = [float(v) for v in value]
    elif where in CURVE_FILE_PLACES and isinstance(value, (str, dict)):
        value = _curve_file(where, value)
    elif kind in ("points2", "polyline2", "sizes2"):
        if not _rows(value, 2):
            fail("must be a list of [x, y] number pairs")
        least = {"points2": 3, "polyline2": 2}.get(kind, 1)
        if len(value) < least:
            fail(f"needs at least {least} points")
        value = [[float(x), float(y)] for x, y in value]
    elif kind == "rows":
        if not _rows(value, key.columns) or not value:
            fail(f"must be a non-empty list of rows of {key.columns} numbers")
        value = [[float(v) for v in p] for p in value]
    elif kind == "patterns":
        value = _patterns(where, value)
    elif kind == "float_or_list":
        if is_number(value):
            value = float(value)
        elif isinstance(value, list) and value and all(map(is_number, value)):
            value = [float(v) for v in value]
        else:
            fail("must be a number or a non-empty list of numbers")
    elif kind == "gamma":
        value = _gamma(value, fail)
    return value


def _gamma(value, fail: Callable):
    """A ruling angle: a number, or ``[[s, gamma], ...]`` over arc-length fractions 0 ... 1."""
    if is_number(value):
        value = float(value)
    elif isinstance(value, list) and len(value) >= 2 and _rows(value, 2):
        value = [[float(s), float(g)] for s, g in value]
        s = [p[0] for p in value]
        if s[0] != 0.0 or s[-1] != 1.0 or any(b <= a for a, b in zip(s, s[1:])):
            fail("must have increasing arc-length fractions from 0 to 1")
    else:
        fail("must be a number or a list of [s, gamma] pairs")
    values = [value] if isinstance(value, float) else [g for _, g in value]
    if not all(0.0 < g < 180.0 for g in values):
        fail("ruling angles must be in (0, 180) degrees")
    return value


def _units_hint(key: Key, metres: float, units: str) -> str:
    """``(= 0.2 m): did you mean units = "mm"?`` for a length that fails its check in
    ``units`` but would pass in other units."""
    if isinstance(metres, list):  # a list of sizes: no single value to convert
        return ""
    given = metres / unit_factor(units)
    note = "" if units == DEFAULT_UNITS else f" (= {metres:.6g} m)"
    fits = [u for u, f in LENGTH_UNITS.items() if u != units and key.check(given * f)]
    if fits:
        note += f': did you mean units = "{fits[0]}"?'
    return note
