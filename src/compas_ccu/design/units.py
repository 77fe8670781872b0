"""Length units of design files: ``[design] units`` and the conversion to metres.

A design file may give its lengths in ``m`` (default), ``mm``, ``cm``, ``ft`` or ``in``
(``[design] units = "mm"``). Every key whose schema unit is ``"m"`` (and the length columns of
the load rows, unit ``"m, load"``) is converted to metres when the design is read; inside
compas_ccu, and in every output, lengths are metres. Angles are degrees and forces, pressures,
densities and stiffnesses are SI whatever the units.

A length far outside the sizes a curved-crease structure has (a 2500 m span, a 0.008 mm plate)
is most likely written in other units than declared: :func:`plausibility_warnings` names the
key, the value, the units and the units that fit (:class:`compas_ccu.errors.UnitsWarning`).

This module knows the schema's key kinds and unit strings, not the schema itself
(:mod:`compas_ccu.design.values` imports it).

>>> to_metres("point2", "m", [1500.0, 250.0], "mm")
[1.5, 0.25]
>>> from_metres("float", "m", 0.3048, "ft")
1.0
"""

from __future__ import annotations

import copy
import math

from compas_ccu.errors import DesignError, UnitsWarning

__all__ = [
    "LENGTH_UNITS",
    "DEFAULT_UNITS",
    "UnitsWarning",
    "unit_factor",
    "is_length",
    "to_metres",
    "from_metres",
    "convert_document",
    "map_lengths",
    "plausibility_warnings",
    "PLAUSIBLE",
]

#: Metres per unit of every allowed ``[design] units``.
LENGTH_UNITS = {"m": 1.0, "mm": 1.0e-3, "cm": 1.0e-2, "ft": 0.3048, "in": 0.0254}
DEFAULT_UNITS = "m"

#: The length columns of "rows" keys (unit ``"m, load"``): the positions along the span; the
#: load intensities are relative (any unit) and are not converted.
_ROW_LENGTH_COLUMNS = {2: (0,), 4: (0, 1)}


def unit_factor(units) -> float:
    """Metres per unit of ``units``.

    Raises
    ------
    DesignError
        ``units`` is not one of :data:`LENGTH_UNITS` (key ``design.units``).

    Examples
    --------
    >>> unit_factor("mm"), unit_factor("in")
    (0.001, 0.0254)
    """
    if not isinstance(units, str) or units not in LENGTH_UNITS:
        raise DesignError(
            f"unknown length units {units!r}; allowed: {', '.join(LENGTH_UNITS)}",
            key="design.units",
        )
    return LENGTH_UNITS[units]


def is_length(unit: str) -> bool:
    """Whether a schema unit string marks a length (converted with ``[design] units``)."""
    return unit in ("m", "m, load")


def _times(value: float, f: float) -> float:
    """``value * f``, as ``value / (1 / f)`` where ``1 / f`` is a whole number (mm, cm to m):
    3050 mm is then the metre value nearest to 3.05 (3050 * 0.001 is one unit in the last place
    above it)."""
    whole = 1.0 / f
    return value / whole if whole > 1.0 and whole == round(whole) else value * f


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _map_value(kind: str, value, function):
    """``value`` of a length key (schema ``kind``) with ``function`` applied to each length in
    it: a number, the numbers of a point or point list, the ``near`` and ``far`` rows of every
    ``[[layout.patterns]]`` table, the position columns of load rows. Anything else (a
    curve-file reference, the load intensities, a pattern's ``parent``) is kept."""
    if kind == "patterns" and isinstance(value, list):  # the point rows of every table
        return [
            {k: _map_value("points2", v, function) if k in ("near", "far") else v
             for k, v in t.items()} if isinstance(t, dict) else t
            for t in value
        ]  # fmt: skip
    if kind == "rows" and isinstance(value, list):
        return [
            [function(v) if i in _ROW_LENGTH_COLUMNS.get(len(row), ()) and _is_number(v) else v
             for i, v in enumerate(row)] if isinstance(row, list) else row
            for row in value
        ]  # fmt: skip
    if isinstance(value, list):
        return [_map_value(kind, v, function) for v in value]
    return function(value) if _is_number(value) else value


def map_lengths(document: dict, schema: dict, function, *, skip=()) -> dict:
    """A copy of a design document with ``function`` applied to every length in it.

    The one walk over the length keys of a design (every key whose schema unit is a length,
    :func:`is_length`): the loader converts each key's value with it (:func:`to_metres`),
    :func:`convert_document` changes a document's units with it and ``ccu scale``
    (:func:`compas_ccu.explore.scale.scaled_document`) scales a design with it.

    Parameters
    ----------
    document : dict
        A design document (as parsed from TOML, or validated values).
    schema : dict
        :data:`compas_ccu.design.schema.SCHEMA`.
    function : callable
        Called with every length (a number) and returns its new value: every number of a
        length key, of its points and point lists, of the ``near`` and ``far`` rows of every
        ``[[layout.patterns]]`` table and the positions (not the intensities) of the load
        rows. Curve-file references, keys not in the schema, keys starting with ``_`` and
        every other value are kept.
    skip : iterable of str
        Sections (``"loads"``) or dotted keys (``"plates.thickness"``) left as they are.

    Returns
    -------
    dict
        A new document; ``document`` is not changed.

    Examples
    --------
    >>> from compas_ccu.design.schema import SCHEMA
    >>> doc = {"crease": {"span": 2.5, "segments": 64, "point_loads": [[0.5, 3.0]]},
    ...        "layout": {"type": "patterns", "patterns": [
    ...            {"parent": 0, "boundary": "near", "near": [[0, 1]], "far": [[0, 2]]}]}}
    >>> out = map_lengths(doc, SCHEMA, lambda v: 2 * v)
    >>> out["crease"], out["layout"]["patterns"][0]["far"]
    ({'span': 5.0, 'segments': 64, 'point_loads': [[1.0, 3.0]]}, [[0, 4]])
    """
    skip = set(skip)
    out = copy.deepcopy(document)
    for section, table in out.items():
        keys = schema.get(section)
        if keys is None or not isinstance(table, dict) or section in skip:
            continue
        for name, value in table.items():
            key = keys.get(name)
            if key is None or name.startswith("_") or f"{section}.{name}" in skip:
                continue
            if is_length(key.unit):
                table[name] = _map_value(key.kind, value, function)
    return out


def _scale(kind: str, unit: str, value, f: float):
    if value is None or f == 1.0 or not is_length(unit):
        return value
    return _map_value(kind, value, lambda v: _times(v, f))


def to_metres(kind: str, unit: str, value, units: str):
    """A validated value of a key (schema ``kind`` and ``unit``) given in ``units``, in metres.

    Non-length keys are returned unchanged.
    """
    return _scale(kind, unit, value, unit_factor(units))


def from_metres(kind: str, unit: str, value, units: str):
    """The inverse of :func:`to_metres`: a value in metres, in ``units``."""
    out = _scale(kind, unit, value, 1.0 / unit_factor(units))
    return _tidy(out)


def _tidy(value):
    """Round away the last-bit noise of a unit conversion (0.30479999999999996 -> 0.3048)."""
    if isinstance(value, list):
        return [_tidy(v) for v in value]
    if isinstance(value, dict):
        return {k: _tidy(v) for k, v in value.items()}
    if isinstance(value, float) and value != 0.0 and math.isfinite(value):
        return float(f"{value:.15g}")
    return value


def convert_document(document: dict, schema: dict, *, to: str, source: str | None = None) -> dict:
    """A design document with its lengths converted from ``source`` units to ``to`` units.

    Parameters
    ----------
    document : dict
        A parsed design document (values of the right types; keys not in ``schema`` are kept).
    schema : dict
        :data:`compas_ccu.design.schema.SCHEMA`.
    to : str
        Target units; written as ``[design] units`` (omitted for metres).
    source : str, optional
        Units of ``document`` (default: its ``[design] units``, else metres).

    Examples
    --------
    >>> from compas_ccu.design.schema import SCHEMA
    >>> doc = {"design": {"units": "mm"}, "crease": {"span": 2500, "points": [[0, 1]]}}
    >>> convert_document(doc, SCHEMA, to="m")
    {'design': {}, 'crease': {'span': 2.5, 'points': [[0.0, 0.001]]}}
    """
    if source is None:
        source = (document.get("design") or {}).get("units", DEFAULT_UNITS)
    f = unit_factor(source) / unit_factor(to)
    if f == 1.0:
        out = copy.deepcopy(document)
    else:
        out = map_lengths(document, schema, lambda v: _tidy(v * f))
    design = dict(out.get("design", {}))
    design.pop("units", None)
    if to != DEFAULT_UNITS:
        design["units"] = to
    if design or "design" in document:
        out["design"] = design
    return out


#: Plausible ranges (metres) of a few lengths that tell the scale of a design, and a typical
#: value: a value outside its range is warned about (:func:`plausibility_warnings`).
PLAUSIBLE = {
    "crease": (0.05, 200.0, 3.0),  # span, radius or extent of the points
    "crease.rise": (0.005, 200.0, 1.0),
    "layout.width": (0.005, 200.0, 0.4),
    "layout.ccf_width": (0.005, 200.0, 0.4),
    "layout.spacing": (0.002, 50.0, 0.15),
    "plates.thickness": (0.0002, 0.1, 0.008),
    "plates.hinge_width": (0.001, 2.0, 0.05),
    "loads.concrete_thickness": (0.005, 2.0, 0.08),
}


def _crease_size(crease: dict):
    if crease.get("span") is not None:
        return "crease.span", crease["span"]
    if crease.get("radius") is not None:
        return "crease.radius", crease["radius"]
    points = crease.get("points")
    if points:
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        return "crease.points", max(max(xs) - min(xs), max(ys) - min(ys))
    return None, None


def plausibility_warnings(values: dict, units: str) -> list:
    """Messages on lengths that are implausible for the design's units.

    Parameters
    ----------
    values : dict
        The validated values (metres, :func:`compas_ccu.design.schema.validate`).
    units : str
        The document's ``[design] units``.

    Returns
    -------
    list of str
        One message per implausible length, naming the key, the value as given, its size in
        metres and the units that would make it plausible.

    Examples
    --------
    >>> values = {"crease": {"span": 2500.0}, "layout": {}, "plates": {}}
    >>> print(*plausibility_warnings(values, "m"))  # doctest: +NORMALIZE_WHITESPACE
    crease.span = 2500 m is implausible for a curved-crease structure (plausible: 0.05 ... 200
    m): did you mean units = "mm" (2.5 m)?
    """
    found = []
    key, size = _crease_size(values.get("crease", {}))
    if key is not None:
        found.append((key, size, PLAUSIBLE["crease"]))
    for dotted, bounds in PLAUSIBLE.items():
        if "." not in dotted:
            continue
        section, name = dotted.split(".")
        value = (values.get(section) or {}).get(name)
        if isinstance(value, list):
            value = max(value) if value else None
        if value is not None:
            found.append((dotted, value, bounds))
    messages = []
    for key, metres, (low, high, typical) in found:
        if low <= metres <= high or metres <= 0.0:
            continue
        given = metres / LENGTH_UNITS[units]
        shown = f"{given:.6g} {units}" + ("" if units == "m" else f" ({metres:.6g} m)")
        if key == "crease.points":
            shown = f"extent {shown}"
        better = [
            (abs(math.log(given * f / typical)), u, given * f)
            for u, f in LENGTH_UNITS.items()
            if u != units and low <= given * f <= high
        ]
        hint = ""
        if better:
            _, u, m = min(better)
            hint = f': did you mean units = "{u}" ({m:.6g} m)?'
        messages.append(
            f"{key} = {shown} is implausible for a curved-crease structure (plausible: "
            f"{low:g} ... {high:g} m){hint}"
        )
    return messages
