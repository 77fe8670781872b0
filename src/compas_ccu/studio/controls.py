"""The design panel's controls, generated from the design-file schema.

Every key of :data:`compas_ccu.design.schema.SCHEMA` becomes one :class:`Control`: a dropdown for
keys with choices, a checkbox for booleans and a text field for everything else. A text field
holds the value as it would be written in a TOML file (``2.5``, ``[[0, 1], [2, 3]]``), so any key
of any kind can be edited the same way, an empty field removes the key, and a value that is not
valid gets exactly the message the ``ccu`` command gives for the same file (the schema's check,
naming the key and the value).

Keys that apply only to some profile, ruling or layout types (the schema's ``when``) are shown
only for those types: :func:`applies`.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

from compas_ccu.design.document import parse_toml
from compas_ccu.design.schema import SCHEMA
from compas_ccu.errors import OptionError
from compas_ccu.limits import LIMITS
from compas_ccu.studio.files import MAX_DEPTH, nesting_depth

__all__ = ["Control", "UNSET", "design_controls", "applies", "format_value", "parse_value"]
__all__ += ["options", "shown_value", "edited_value", "check_field_text"]

#: The value of a field that is empty: the key is removed from the design.
UNSET = object()

#: The key whose value selects which keys of a section apply (the schema's ``when``).
SWITCHES = {"crease": "profile", "rulings": "type", "layout": "type"}


@dataclass(frozen=True)
class Control:
    """One design-file key as a control of the design panel.

    Attributes
    ----------
    section, name : str
        The key ``section.name``.
    widget : str
        ``"dropdown"``, ``"checkbox"`` or ``"text"``.
    kind : str
        The schema kind (``float``, ``points2``, ...).
    unit : str
        ``m``, ``deg``, ``1`` or empty.
    doc, allowed : str
        The schema's meaning and allowed values.
    choices : tuple of str
        The options of a dropdown (an unset optional key is the empty option).
    when : tuple of str
        The types of the section's switch key the control applies to (empty: always).
    required : bool
    default : object
    """

    section: str
    name: str
    widget: str
    kind: str
    unit: str
    doc: str
    allowed: str
    choices: tuple
    when: tuple
    required: bool
    default: object

    @property
    def key(self) -> str:
        """``section.name``, as the error messages name it."""
        return f"{self.section}.{self.name}"

    @property
    def label(self) -> str:
        """The name with its unit, e.g. ``span [m]``."""
        unit = self.unit if self.unit not in ("", "1") else ""
        return f"{self.name} [{unit}]" if unit else self.name

    @property
    def hint(self) -> str:
        """The meaning, the allowed values and the default, for a tooltip."""
        parts = [self.doc]
        if self.allowed:
            parts.append(f"Allowed: {self.allowed}.")
        if self.required:
            parts.append("Required.")
        elif self.default is not None:
            parts.append(f"Default: {format_value(self, self.default)}.")
        return " ".join(parts)


def design_controls() -> tuple:
    """Every key of the schema as a :class:`Control`, in schema order.

    Returns
    -------
    tuple of Control

    Examples
    --------
    >>> controls = design_controls()
    >>> rise = next(c for c in controls if c.key == "crease.rise")
    >>> rise.widget, rise.label, rise.when
    ('text', 'rise [m]', ('arc', 'catenary', 'elastica', 'funicular'))
    """
    out = []
    for section, keys in SCHEMA.items():
        for name, key in keys.items():
            if name.startswith("_"):
                continue
            if key.choices:
                widget = "dropdown"
            elif key.kind == "bool":
                widget = "checkbox"
            else:
                widget = "text"
            when = tuple(w.strip() for w in key.when.split(",")) if key.when else ()
            out.append(
                Control(
                    section=section,
                    name=name,
                    widget=widget,
                    kind=key.kind,
                    unit=key.unit,
                    doc=key.doc,
                    allowed=", ".join(key.choices) if key.choices else key.check_doc,
                    choices=tuple(key.choices),
                    when=when,
                    required=key.required,
                    default=key.default,
                )
            )
    return tuple(out)


def applies(control: Control, document: dict) -> bool:
    """Whether ``control`` applies to ``document`` (its section's type is in ``when``).

    A key the document sets is always shown, so that a value that does not apply can be seen
    and removed.
    """
    section = document.get(control.section, {})
    if not isinstance(section, dict):
        return True
    if control.name in section or not control.when:
        return True
    switch = SWITCHES.get(control.section)
    if switch is None:
        return True
    current = section.get(switch, SCHEMA[control.section][switch].default)
    return current in control.when


def _number(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isfinite(value) and value == int(value) and abs(value) < 1e15:
            return f"{value:.1f}"
        return repr(value)
    return repr(value) if isinstance(value, int) else str(value)


def _toml(value) -> str:
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return _number(value)


def format_value(control: Control, value) -> str:
    """The text of a value in a field: numbers as typed in TOML, strings without quotes.

    >>> c = next(c for c in design_controls() if c.key == "crease.points")
    >>> format_value(c, [[0.0, 0.0], [1.25, 0.5]])
    '[[0.0, 0.0], [1.25, 0.5]]'
    >>> format_value(next(c for c in design_controls() if c.key == "crease.rise"), "2")
    '"2"'
    """
    if value is None or value is UNSET:
        return ""
    if isinstance(value, str) and (control.kind == "str" or control.widget == "dropdown"):
        return value
    return _toml(value)  # a string where a number belongs shows its quotes: "2" is not 2


def parse_value(control: Control, text: str):
    """The design value of a field's text: a TOML value, or :data:`UNSET` for an empty field.

    Text that is not a TOML value is returned as the string itself, so that the schema refuses
    it with the message the ``ccu`` command gives (``crease.rise: must be a finite number, got
    'abc'``); a string key may be typed without quotes.

    >>> c = next(c for c in design_controls() if c.key == "crease.rise")
    >>> parse_value(c, " 1.5 "), parse_value(c, "1e-3"), parse_value(c, "abc")
    (1.5, 0.001, 'abc')
    >>> parse_value(c, "") is UNSET
    True
    """
    if control.widget == "checkbox":
        return bool(text)
    text = str(text).strip()
    if text == "":
        return UNSET
    if control.widget == "dropdown" or control.kind == "str":
        return text
    fast = _number_array(text)
    if fast is not None:
        return fast
    try:
        return parse_toml(f"value = {text}")["value"]
    except (ValueError, RecursionError):
        # not a TOML value (tomllib.TOMLDecodeError): the schema names the key and the text
        return text


def _number_array(text: str):
    """The value of a long array of numbers through the JSON parser (in C; on arrays of
    numbers JSON is a subset of TOML with the same values), or None to parse it as TOML."""
    if len(text) < 1000 or not text.startswith("["):
        return None
    try:
        value = json.loads(text)
    except (ValueError, RecursionError):
        return None
    stack = [value]
    while stack:
        v = stack.pop()
        if isinstance(v, list):
            stack.extend(v)
        elif isinstance(v, bool) or isinstance(v, float):
            continue
        elif not isinstance(v, int) or not -(2**63) <= v < 2**63:
            return None
    return value


def check_field_text(control: Control, text) -> None:
    """Refuse the text of a field that cannot be a design value before it is parsed: longer
    than a design file may be (the limit ``upload_bytes``) or nested deeper than
    :data:`compas_ccu.studio.files.MAX_DEPTH`.

    Raises
    ------
    OptionError
        One line naming the key and the size or depth.
    """
    if control.widget != "text":
        return
    text = str(text)
    size = len(text.encode("utf-8"))
    if size > LIMITS.upload_bytes:
        raise OptionError(
            f"{control.key}: the value is {size:,} bytes; a design file may have at most "
            f"{LIMITS.upload_bytes:,} bytes (the limit upload_bytes)"
        )
    depth = nesting_depth(f"value = {text}")
    if depth > MAX_DEPTH:
        raise OptionError(
            f"{control.key}: the value nests arrays {depth} deep; a design value nests at "
            f"most {MAX_DEPTH} deep"
        )


def options(control: Control) -> tuple:
    """The options of a dropdown: the choices, with an empty first option for an optional key
    without a default (selecting it removes the key)."""
    if control.required or control.default is not None:
        return control.choices
    return ("",) + control.choices


def shown_value(control: Control, value):
    """What the control shows for the document's ``value`` (UNSET: the default, or empty).

    >>> c = next(c for c in design_controls() if c.key == "layout.type")
    >>> shown_value(c, UNSET), shown_value(c, "radial")
    ('single', 'radial')
    """
    if control.widget == "checkbox":
        return value if isinstance(value, bool) else bool(control.default)
    text = format_value(control, value)
    if control.widget == "dropdown":
        choices = options(control)
        if not text:
            text = str(control.default) if control.default is not None else choices[0]
        return text if text in choices else choices[0]
    return text


def edited_value(control: Control, shown):
    """The document value of what the control shows after an edit (:data:`UNSET` removes the
    key): the inverse of :func:`shown_value`."""
    if control.widget == "dropdown" and shown == "" and not control.required:
        return UNSET
    return parse_value(control, shown)
