"""Design documents as compact TOML text: one point per line, not one number per line.

``tomli_w`` writes every element of a nested array on its own line, so a spline's control
points ``[[0.25, 1.2], [1.0, 1.0]]`` become eight lines of single numbers. :func:`design_toml`
writes a number list and a short point list inline and a long point list one point ``[x, y]``
per line; scalars are formatted by ``tomli_w`` (valid TOML, exact floats). A list of tables
(``layout.patterns``) is written as an array of tables, ``[[layout.patterns]]`` per table.

>>> print(design_toml({"crease": {"profile": "spline", "points": [[0.25, 1.2], [1.0, 1.0]]}}))
[crease]
profile = "spline"
points = [[0.25, 1.2], [1.0, 1.0]]
<BLANKLINE>
"""

from __future__ import annotations

import math

import tomli_w

from compas_ccu.errors import DesignError

__all__ = ["design_toml", "toml_value"]

#: A list whose inline text is longer than this is written one element per line.
INLINE_WIDTH = 72


def _scalar(value) -> str:
    if isinstance(value, float) and not math.isfinite(value):
        raise DesignError(f"cannot write a non-finite number {value!r}")
    return tomli_w.dumps({"v": value}).split("=", 1)[1].strip()


def toml_value(value, *, indent: str = "") -> str:
    """The TOML text of a value: scalars and short lists inline, a long list of lists one
    element per line.

    Examples
    --------
    >>> toml_value([1.0, 2, "a"])
    '[1.0, 2, "a"]'
    >>> print(toml_value([[float(i), 0.5] for i in range(8)]))
    [
        [0.0, 0.5],
        [1.0, 0.5],
        [2.0, 0.5],
        [3.0, 0.5],
        [4.0, 0.5],
        [5.0, 0.5],
        [6.0, 0.5],
        [7.0, 0.5],
    ]
    """
    if isinstance(value, dict):
        inner = ", ".join(f"{_key(k)} = {toml_value(v)}" for k, v in value.items())
        return "{ " + inner + " }" if inner else "{}"
    if not isinstance(value, (list, tuple)):
        return _scalar(value)
    items = [toml_value(v, indent=indent + "    ") for v in value]
    inline = "[" + ", ".join(items) + "]"
    nested = any(isinstance(v, (list, tuple, dict)) for v in value)
    if "\n" not in inline and (len(inline) <= INLINE_WIDTH or not nested):
        return inline
    inner = indent + "    "
    return "[\n" + "".join(f"{inner}{item},\n" for item in items) + indent + "]"


def _key(name: str) -> str:
    return tomli_w.dumps({name: 0}).split("=", 1)[0].strip()


def _is_array_of_tables(value) -> bool:
    return (
        isinstance(value, (list, tuple)) and bool(value) and all(isinstance(v, dict) for v in value)
    )


def _table(header: str, table: dict, *, array: bool = False) -> list:
    lines = [f"[[{header}]]" if array else f"[{header}]"] if header else []
    subtables, arrays = [], []
    for name, value in table.items():
        if value is None:
            continue
        if isinstance(value, dict):
            subtables.append((name, value))
            continue
        if _is_array_of_tables(value):
            arrays.append((name, value))
            continue
        lines.append(f"{_key(name)} = {toml_value(value)}")
    out = [lines] if len(lines) > 1 or not (subtables or arrays) or not header or array else []
    for name, value in subtables:
        out += _table(f"{header}.{_key(name)}" if header else _key(name), value)
    for name, value in arrays:  # [[header.name]], one block per table
        for item in value:
            out += _table(f"{header}.{_key(name)}" if header else _key(name), item, array=True)
    return out


def design_toml(document: dict, *, header: str | None = None) -> str:
    """A design document as TOML text, ``[design]`` first; None values are left out.

    Parameters
    ----------
    document : dict
        ``{section: {key: value}}`` (``[materials.NAME]`` tables as nested dicts).
    header : str, optional
        Written as comment lines on top.

    Raises
    ------
    DesignError
        A non-finite number (TOML has no exact representation the design files accept).
    """
    ordered = {k: document[k] for k in ("design",) if k in document}
    ordered.update({k: v for k, v in document.items() if k != "design"})
    top = {k: v for k, v in ordered.items() if not isinstance(v, dict)}
    blocks = []
    if top:
        blocks += [line for line in _table("", top) if line]
    for section, table in ordered.items():
        if isinstance(table, dict):
            blocks += [block for block in _table(_key(section), table) if block]
    text = "\n\n".join("\n".join(block) for block in blocks) + "\n"
    if header:
        text = "".join(f"# {line}\n" for line in header.splitlines()) + "\n" + text
    return text
