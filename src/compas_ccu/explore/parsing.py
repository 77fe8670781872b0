"""The parts of sweep and study files: parameters, variants and the parsing helpers.

Sweep files (:mod:`compas_ccu.explore.sweep`) and optimisation study files
(:mod:`compas_ccu.explore.study`) share their sections (``[checks]``, ``[fe]``,
``[objectives]``, ``[constraints]``), the form of ``[parameters]`` (:func:`parse_parameter`:
values, ranges, whole-section tables), the base design (:func:`load_base`) and how a variant's
settings are applied to it (:func:`apply_settings`), so both file kinds give the same errors
and the same designs. A :class:`Variant` is identified by a hash of its parameter values.
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from compas_ccu import limits
from compas_ccu.design.curve_files import absolute_curve_files
from compas_ccu.design.document import load_design
from compas_ccu.errors import DesignError, SweepError
from compas_ccu.explore.metrics import metric, metric_group, metric_names
from compas_ccu.fea.problem import FEError
from compas_ccu.fea.validation import FESettings
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["Parameter", "Variant", "parse_parameter", "parse_checks", "parse_fe", "parse_goals"]
__all__ += ["table", "known", "integer", "flatten", "schema_key", "default_constraints"]
__all__ += ["load_base", "apply_settings", "round_setting", "column_value"]
__all__ += ["CHECK_KEYS", "FE_KEYS", "DEFAULT_CONSTRAINTS", "RANGE_KEYS", "SEARCH_KEYS"]
__all__ += ["NUMERIC_KINDS"]

CHECK_KEYS = ("path_states", "collisions")
FE_KEYS = (
    "engine",
    "mode",
    "element_size",
    "steps",
    "orthotropic",
    "hinge_stiffness",
    "control",
    "self_weight",
    "checks",
    "area_load",
    "load_cases",
    "deflection_limit",
)
DEFAULT_CONSTRAINTS = {"bending_utilisation": {"max": 1.0}}
RANGE_KEYS = ("min", "max", "num")
#: Keys of a range in an optimisation study (``ccu optimize``): no grid points, an optional
#: step (a discrete range), a log scale and integer values.
SEARCH_KEYS = ("min", "max", "step", "log", "integer")
NUMERIC_KINDS = ("float", "int", "float_or_list", "gamma")


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def round_setting(value) -> float:
    """A sampled number to 12 significant digits (linspace gives 0.7999999999999999 for 0.8)."""
    return float(f"{float(value):.12g}")


def column_value(value):
    """The value as stored in the results table: scalars as they are, lists as JSON text."""
    if isinstance(value, (bool, int, float, str)):
        return value
    return json.dumps(value, separators=(",", ":"))


@dataclass(frozen=True)
class Parameter:
    """One parameter of a sweep (or of an optimisation study's search space).

    Attributes
    ----------
    name : str
        ``"section.key"`` (one design key) or ``"section"`` (whole-section tables).
    values : tuple or None
        Discrete values (a grid axis; the choices for random / LHS sampling).
    low, high : float or None
        A range: grid points ``linspace(low, high, num)``; uniform for random / LHS sampling.
    num : int or None
        Grid points of a range.
    integer : bool
        The design key is an integer (ranges give integers).
    labels : tuple or None
        Whole-section parameters: the label of each table (the column value).
    step : float or None
        Optimisation studies: a discrete range of values ``min + k step``.
    log : bool
        Optimisation studies: search the range on a log scale.
    """

    name: str
    values: tuple | None = None
    low: float | None = None
    high: float | None = None
    num: int | None = None
    integer: bool = False
    labels: tuple | None = None
    step: float | None = None
    log: bool = False

    @property
    def section(self) -> str:
        return self.name.split(".", 1)[0]

    @property
    def is_range(self) -> bool:
        return self.values is None

    def grid_values(self) -> list:
        """Values of a grid axis."""
        if not self.is_range:
            return list(self.values)
        if self.num is None:
            raise SweepError(
                "a range needs num (grid points) for grid sampling, e.g. "
                f"{{min = {self.low:g}, max = {self.high:g}, num = 5}}",
                key=f"parameters.{self.name}",
            )
        values = np.linspace(self.low, self.high, self.num)
        if self.integer:
            return list(dict.fromkeys(int(round(v)) for v in values))
        return [round_setting(v) for v in values]

    def from_unit(self, u: np.ndarray) -> list:
        """Values for samples ``u`` in [0, 1): uniform over the range or over the choices."""
        u = np.clip(np.asarray(u, dtype=float), 0.0, np.nextafter(1.0, 0.0))
        if not self.is_range:
            return [self.values[int(i)] for i in np.floor(u * len(self.values))]
        if self.integer:
            lo, hi = int(self.low), int(self.high)
            return [lo + int(i) for i in np.floor(u * (hi - lo + 1))]
        return [round_setting(v) for v in self.low + u * (self.high - self.low)]

    def column(self, value):
        """The table value of ``value`` (the label of a section table)."""
        if self.labels is not None:
            return self.labels[self.values.index(value)]
        return column_value(value)

    def value(self, column):
        """The design value of a table value ``column`` (inverse of :meth:`column`)."""
        if self.is_range:
            return column
        for value in self.values:
            if self.column(value) == column:
                return value
        raise SweepError(f"{column!r} is none of the values {list(self.values)!r}", key=self.name)


@dataclass(frozen=True)
class Variant:
    """One design of the sweep.

    Attributes
    ----------
    index : int
        Position in the sweep.
    settings : dict
        Parameter name -> value applied to the base design.
    params : dict
        Parameter name -> value as stored in the results table (labels, JSON for lists).
    """

    index: int
    settings: dict = field(compare=False)
    params: dict

    @property
    def id(self) -> str:
        """Stable identifier: a hash of the parameter values (12 hex digits)."""
        text = json.dumps(self.params, sort_keys=True, separators=(",", ":"))
        return hashlib.sha1(text.encode("utf-8")).hexdigest()[:12]


# -- parsing helpers, shared by sweep files and optimisation studies (explore/study.py) --------
def table(document: dict, section: str) -> dict:
    """The table ``[section]`` of a parsed file ({} when absent)."""
    value = document.get(section, {})
    if not isinstance(value, dict):
        raise SweepError("must be a table", key=f"[{section}]")
    return value


def known(entries: dict, allowed, section: str) -> None:
    """Refuse keys of ``entries`` that are not ``allowed`` in ``[section]``."""
    for key in entries:
        if key not in allowed:
            raise SweepError(
                f"unknown key; allowed in [{section}]: {', '.join(allowed)}",
                key=f"{section}.{key}",
            )


def integer(entries: dict, key: str, default, low: int, section: str):
    """``entries[key]`` (or ``default``) as an integer >= ``low``; None stays None."""
    value = entries.get(key, default)
    if value is None:
        return None
    if not (isinstance(value, int) and not isinstance(value, bool)) or value < low:
        raise SweepError(f"must be an integer >= {low}, got {value!r}", key=f"{section}.{key}")
    return value


def parse_checks(document: dict) -> tuple:
    """``(path_states, collisions)`` of the ``[checks]`` section."""
    checks = table(document, "checks")
    known(checks, CHECK_KEYS, "checks")
    path_states = integer(checks, "path_states", 21, 2, "checks")
    collisions = checks.get("collisions", False)
    if not isinstance(collisions, bool):
        raise SweepError(f"must be true or false, got {collisions!r}", key="checks.collisions")
    return path_states, collisions


def parse_fe(document: dict):
    """The FE options of the ``[fe]`` section (passed to :class:`FESettings`), or None."""
    if "fe" not in document:
        return None
    entries = table(document, "fe")
    known(entries, FE_KEYS, "fe")

    options = {"engine": "kratos", "element_size": 0.25, "steps": 4, **entries}
    probe = dict(options)
    if "load_cases" in probe:  # a case exists once the design's [loads] name its action:
        # check the names here with every action present; a variant without one fails alone
        probe["loads"] = dict.fromkeys(("concrete_thickness", "live", "snow", "wind"), 1.0)
        probe["area_load"] = probe.get("area_load") or 1.0
    try:
        FESettings(**probe)
    except (FEError, TypeError, ValueError) as exc:
        raise SweepError(str(exc), key="[fe]") from exc
    if options["engine"] not in ("kratos", "opensees"):
        raise SweepError(
            f"engine must be 'kratos' or 'opensees', got {options['engine']!r}", key="fe.engine"
        )
    return options


def default_constraints(collisions: bool) -> dict:
    """The constraints when a file has no ``[constraints]``: the plates do not break (and do
    not collide, when collisions are checked)."""
    out = dict(DEFAULT_CONSTRAINTS)
    if collisions:
        out["collision_free"] = True
    return out


def _check_metric(name: str, names: list, where: str) -> None:
    """A metric the evaluation measures, or an error saying which section measures it."""
    if name in names:
        return
    group = metric_group(name)
    if group == "fe":
        raise SweepError(
            "an FE metric: measured only with an [fe] section (docs/explore.md)", key=where
        )
    if group == "collisions":
        raise SweepError(
            "a metric of the collision check: measured only with [checks] collisions = true",
            key=where,
        )
    raise SweepError(f"unknown metric; available: {', '.join(names)}", key=where)


def parse_goals(document: dict, section: str, default: dict, *, collisions: bool, fe) -> dict:
    """``[objectives]`` (metric -> "min" / "max") or ``[constraints]`` (metric -> ``{min, max}``
    or a bool), checked against the metrics the evaluation measures."""

    if section not in document:
        return dict(default)
    entries = table(document, section)
    names = metric_names(collisions=collisions, fe=fe is not None)
    for name, goal in entries.items():
        where = f"{section}.{name}"
        _check_metric(name, names, where)
        if section == "objectives":
            if goal not in ("min", "max"):
                raise SweepError(f"must be 'min' or 'max', got {goal!r}", key=where)
            if metric(name).dtype not in ("float", "int"):
                raise SweepError(
                    f"an objective must be a number; {name} is {metric(name).dtype}", key=where
                )
        if section == "constraints":
            ok = isinstance(goal, bool) or (
                isinstance(goal, dict)
                and goal
                and set(goal) <= {"min", "max"}
                and all(_is_number(v) for v in goal.values())
            )
            if not ok:
                raise SweepError(
                    f"must be true / false or a table {{min = ..., max = ...}}, got {goal!r}",
                    key=where,
                )
    if section == "objectives" and not entries:
        raise SweepError("needs at least one metric", key="[objectives]")
    return dict(entries)


def flatten(entries: dict, prefix: str = "", *, range_keys=RANGE_KEYS) -> dict:
    """``{"crease": {"rise": [...]}}`` (TOML dotted keys) -> ``{"crease.rise": [...]}``."""
    out = {}
    for key, value in entries.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict) and not prefix and not set(value) <= set(range_keys):
            out.update(flatten(value, f"{name}.", range_keys=range_keys))
        else:
            out[name] = value
    return out


def schema_key(name: str, schema: dict, where: str):
    """The :class:`~compas_ccu.design.schema.Key` of a dotted name (None: a section)."""
    section, _, key = name.partition(".")
    if section not in schema:
        raise SweepError(
            f"unknown design section {section!r}; sections: {', '.join(schema)}", key=where
        )
    if not key:
        return None
    allowed = [k for k in schema[section] if not k.startswith("_")]
    if key not in allowed or "." in key:
        raise SweepError(
            f"unknown design key; allowed in [{section}]: {', '.join(allowed)}", key=where
        )
    return schema[section][key]


def _section_parameter(name: str, spec, where: str) -> Parameter:
    """Whole-section tables, e.g. ``layout = [{label = "a", ...}, ...]``."""
    if not (isinstance(spec, list) and spec and all(isinstance(v, dict) for v in spec)):
        raise SweepError(
            "a section parameter takes a list of tables, e.g. "
            f"{name} = [{{label = 'a', ...}}, {{label = 'b', ...}}]",
            key=where,
        )
    values, labels = [], []
    for entries in spec:
        entries = dict(entries)
        label = entries.pop("label", None)
        values.append(entries)
        labels.append(
            str(label)
            if label is not None
            else ", ".join(f"{k}={column_value(v)}" for k, v in entries.items())
        )
    if len(set(labels)) != len(labels):
        raise SweepError(f"labels must be different, got {labels}", key=where)
    return Parameter(name, values=tuple(values), labels=tuple(labels))


def _range_bounds(spec: dict, key, where: str, allowed) -> tuple:
    """(low, high, integer key) of a range table, checked."""
    unknown = set(spec) - set(allowed)
    if unknown or not {"min", "max"} <= set(spec):
        form = ", ".join(f"{k} = ..." for k in allowed)
        raise SweepError(f"a range is {{{form}}}, got {spec!r}", key=where)
    if key.kind not in NUMERIC_KINDS:
        raise SweepError(f"a range needs a numeric design key, not {key.kind}", key=where)
    low, high = spec["min"], spec["max"]
    if not (_is_number(low) and _is_number(high) and math.isfinite(low + high)):
        raise SweepError(f"min and max must be numbers, got {low!r}, {high!r}", key=where)
    if high < low:
        raise SweepError(f"max {high!r} is below min {low!r}", key=where)
    integer_key = key.kind == "int"
    if integer_key and not (float(low).is_integer() and float(high).is_integer()):
        raise SweepError(f"an integer key needs integer min and max, got {spec!r}", key=where)
    return float(low), float(high), integer_key


def _search_range(name: str, spec: dict, key, where: str) -> Parameter:
    """A range of an optimisation study: ``{min, max}`` and optional ``step``, ``log``,
    ``integer``."""
    if "num" in spec:
        raise SweepError(
            "num sets grid points of a sweep; an optimisation searches the whole range "
            f"(a discrete range: step = ...), got {spec!r}",
            key=where,
        )
    low, high, integer_key = _range_bounds(spec, key, where, SEARCH_KEYS)
    flags = {k: spec.get(k, integer_key if k == "integer" else False) for k in ("log", "integer")}
    for k, v in flags.items():
        if not isinstance(v, bool):
            raise SweepError(f"{k} must be true or false, got {v!r}", key=f"{where}.{k}")
    if integer_key and not flags["integer"]:
        raise SweepError(f"{name} is an integer key: integer = false is not possible", key=where)
    if flags["integer"] and not (low.is_integer() and high.is_integer()):
        raise SweepError(f"integer = true needs integer min and max, got {spec!r}", key=where)
    step = spec.get("step")
    if step is not None:
        if not (_is_number(step) and math.isfinite(step) and step > 0):
            raise SweepError(f"step must be a number > 0, got {step!r}", key=f"{where}.step")
        if flags["integer"] and not float(step).is_integer():
            raise SweepError(f"an integer range needs an integer step, got {step!r}", key=where)
        count = (high - low) / step
        if abs(count - round(count)) > EXACT_RELATIVE * max(1.0, count):
            raise SweepError(
                f"step {step!r} does not divide the range {low:g} .. {high:g} into whole steps",
                key=where,
            )
        if flags["log"]:
            raise SweepError("a range takes a step or a log scale, not both", key=where)
        step = float(step)
    if flags["log"] and low <= 0:
        raise SweepError(f"a log-scale range needs min > 0, got {low!r}", key=where)
    return Parameter(
        name, low=low, high=high, integer=flags["integer"], step=step, log=flags["log"]
    )


def parse_parameter(name: str, spec, schema: dict, *, search: bool = False) -> Parameter:
    """One entry of ``[parameters]``: values, a range or whole-section tables.

    ``search``: an optimisation study's parameter (ranges ``{min, max, step, log, integer}``,
    values must be different); else a sweep's (ranges ``{min, max, num}``).
    """
    where = f"parameters.{name}"
    key = schema_key(name, schema, where)
    if key is None:
        return _section_parameter(name, spec, where)
    if isinstance(spec, list):
        if not spec:
            raise SweepError("needs at least one value", key=where)
        kinds = {type(v) if not _is_number(v) else float for v in spec}
        if len(kinds) > 1:
            raise SweepError(f"values must all be of one type, got {spec!r}", key=where)
        columns = [column_value(v) for v in spec]
        if search and len(set(columns)) != len(columns):
            raise SweepError(f"values must be different, got {spec!r}", key=where)
        return Parameter(name, values=tuple(spec))
    if isinstance(spec, dict) and search:
        return _search_range(name, spec, key, where)
    if isinstance(spec, dict):
        low, high, integer_key = _range_bounds(spec, key, where, RANGE_KEYS)
        num = spec.get("num")
        if num is not None and not (
            isinstance(num, int) and not isinstance(num, bool) and 1 <= num <= 2**53
        ):
            raise SweepError(f"num must be an integer >= 1, got {num!r}", key=where)
        if num is not None:
            limits.check("variants", num, what=f"grid points of {name} ({where}.num)")
        return Parameter(name, low=low, high=high, num=num, integer=integer_key)
    form = "{min, max, step}" if search else "{min, max, num}"
    raise SweepError(f"must be a list of values or a range {form}, got {spec!r}", key=where)


def load_base(head: dict, base_dir, section: str) -> tuple:
    """(resolved path, design document) of the base design named by ``[section] base``."""
    if "base" not in head:
        raise SweepError(
            "missing: the base design file, e.g. base = 'vault.toml'", key=f"{section}.base"
        )
    path = (Path(base_dir) / str(head["base"])).resolve()
    try:
        base = load_design(path)
    except DesignError as exc:
        raise SweepError(f"base design: {exc}", key=f"{section}.base") from exc
    # curve files named by the base design are read from its folder wherever a variant runs
    return path, absolute_curve_files(base.document, path.parent)


def apply_settings(base_document: dict, variant: Variant, base_path) -> dict:
    """The base design document with the settings of ``variant`` applied (whole sections
    first, then single keys), named ``<base name>-<variant id>``."""
    doc = copy.deepcopy(base_document)
    items = sorted(variant.settings.items(), key=lambda kv: "." in kv[0])  # sections first
    for name, value in items:
        section, _, key = name.partition(".")
        if key:
            doc.setdefault(section, {})[key] = copy.deepcopy(value)
        else:
            doc[section] = copy.deepcopy(value)
    name = doc.setdefault("design", {}).get("name") or Path(base_path).stem
    doc["design"]["name"] = f"{name}-{variant.id}"
    return doc
