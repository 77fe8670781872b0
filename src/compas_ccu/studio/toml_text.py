"""The TOML text of a studio document, keeping the comments and layout of the file it came from.

:func:`document_text` writes a document over the text it was read from with tomlkit, so the
comments, order and layout of every unchanged key stay. tomlkit builds and parses arrays
element by element (a 10,000-point crease took about a minute), so long arrays of numbers never
go through it: in the source they are masked by placeholders before tomlkit parses it, and a
new one is written once as compact text (``[[0.0, 1.0], [2.0, 3.0]]``) in place of its
placeholder after tomlkit has written the rest. The time is linear in the text.
"""

from __future__ import annotations

import json
import math
import re
import uuid

from compas_ccu.design.document import parse_toml
from compas_ccu.errors import DesignError

__all__ = ["document_text"]

#: Arrays of numbers with more characters than this bypass tomlkit.
LONG = 200
_KEY_LINE = re.compile(r"^[ \t]*[A-Za-z0-9_\-.\"' ]+?[ \t]*=[ \t]*\[", re.MULTILINE)
_NUMERIC = re.compile(r"[0-9eE+\-.,\[\] \t\r\n_a-z]*")  # digits, inf, nan, true, false


def document_text(document: dict, source: str | None = None, parsed: dict | None = None) -> str:
    """TOML text of ``document``; with ``source`` (the text it was read from) the comments,
    order and layout of the unchanged keys are kept (tomlkit). ``parsed``, the values of
    ``source`` if known, saves parsing its long arrays again.

    Raises
    ------
    DesignError
        A value TOML cannot hold (None, an object), naming its key.

    Examples
    --------
    >>> document_text({"crease": {"points": [[0.0, 1.0], [2.0, 3.0]]}}, "[crease] # c\\n")
    '[crease] # c\\npoints = [[0.0, 1.0], [2.0, 3.0]]\\n'
    """
    for section, values in document.items():
        for name, value in values.items() if isinstance(values, dict) else [("", values)]:
            if not _writable(value):
                key = f"{section}.{name}" if name else f"[{section}]"
                raise DesignError(
                    f"a {type(value).__name__} cannot be written to a TOML file", key=key
                )
    return _document_text(document, source, parsed)


def _writable(value) -> bool:
    if isinstance(value, (list, tuple)):
        return all(map(_writable, value))
    if isinstance(value, dict):
        return all(map(_writable, value.values()))
    return isinstance(value, (str, int, float, bool))


def _numbers(value) -> bool:
    """A (nested) list whose leaves are all numbers or booleans."""
    stack = [value]
    while stack:
        v = stack.pop()
        if isinstance(v, (list, tuple)):
            stack.extend(v)
        elif not isinstance(v, (int, float)):
            return False
    return True


def _number(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return repr(float(v))


def _array_text(value) -> str:
    """Compact TOML of a (nested) list of numbers (JSON's, in C, when every number is finite:
    the same text)."""
    try:
        return json.dumps(value, allow_nan=False)
    except ValueError:
        return _slow_array_text(value)


def _slow_array_text(value) -> str:
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(map(_slow_array_text, value)) + "]"
    return _number(value)


def _mask(source: str, token: str):
    """``source`` with every long array of numbers that is a key's value replaced by a
    placeholder string, and ``{placeholder: array text}``."""
    if '"""' in source or "'''" in source:  # an array in a multi-line string is not a value
        return source, {}
    out, raw, last = [], {}, 0
    for match in _KEY_LINE.finditer(source):
        start = match.end() - 1
        if start < last:
            continue
        depth, i, n = 0, start, len(source)
        while i < n:
            c = source[i]
            if c == "[":
                depth += 1
            elif c == "]":
                depth -= 1
                if depth == 0:
                    break
            elif c in "\"'#{=":
                i = n
                break
            i += 1
        if i >= n or i + 1 - start <= LONG:
            continue
        text = source[start : i + 1]
        if not _NUMERIC.fullmatch(text):
            continue
        name = f"{token}{len(raw)}"
        raw[name] = text
        out.append(source[last:start])
        out.append(f'"{name}"')
        last = i + 1
    out.append(source[last:])
    return "".join(out), raw


def _document_text(document: dict, source: str | None, parsed: dict | None) -> str:
    import tomlkit

    token = f"ccu-array-{uuid.uuid4().hex}-"
    masked, raw = _mask(source, token) if source else ("", {})
    doc = tomlkit.parse(masked) if source else tomlkit.document()

    def current(item, section, name):
        value = item.unwrap() if hasattr(item, "unwrap") else item
        if isinstance(value, str) and value in raw:
            table = (parsed or {}).get(section)
            if isinstance(table, dict) and name in table:
                return table[name]
            return parse_toml(f"v = {raw[value]}")["v"]
        return value

    def put(table, name, value):
        if isinstance(value, (list, tuple)) and _numbers(value):
            text = _array_text(value)
            if len(text) > LONG:
                placeholder = f"{token}{len(raw)}"
                raw[placeholder] = text
                table[name] = placeholder
                return
        table[name] = value

    for section in list(doc.keys()):
        if section not in document:
            del doc[section]
    for section, values in document.items():
        if not isinstance(values, dict):
            put(doc, section, values)
            continue
        if section not in doc or not isinstance(doc[section], dict):
            doc[section] = tomlkit.table()
        table = doc[section]
        for name in list(table.keys()):
            if name not in values:
                del table[name]
        for name, value in values.items():
            if name not in table or not _identical(current(table[name], section, name), value):
                put(table, name, value)
    text = tomlkit.dumps(doc)
    if raw:
        text = re.sub(f'"({re.escape(token)}[0-9]+)"', lambda m: raw[m.group(1)], text)
    return text


def _identical(a, b) -> bool:
    """Equal values of equal types all the way down (1 and 1.0 differ in a TOML file)."""
    if isinstance(a, (list, tuple)):
        return isinstance(b, (list, tuple)) and len(a) == len(b) and all(map(_identical, a, b))
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return True
    return type(a) is type(b) and a == b
