"""Optimisation study files (``ccu optimize``): a base design, the parameters to search, the
objectives and the constraints.

A study file is TOML (``docs/optimize.md`` lists every key)::

    [study]
    name = "vault-concrete"
    base = "../vault.toml"            # the base design, relative to this file
    trials = 60                       # evaluations (``--trials`` overrides)
    seed = 0
    sampler = "auto"                  # auto | tpe | nsga2 | nsga3 | random

    [parameters]
    "plates.thickness" = {min = 0.004, max = 0.020}          # continuous
    "layout.plates" = {min = 4, max = 12}                    # an integer key: integers
    "crease.rise" = {min = 0.6, max = 1.4, step = 0.05}      # a discrete range
    "plates.material" = ["plywood", "birch-plywood"]        # categorical

    [checks]                          # as in a sweep file
    collisions = true

    [fe]                              # FE options (FESettings), as in a sweep file
    element_size = 0.25
    area_load = 1884.0

    [objectives]
    mass = "min"

    [constraints]                     # the cheap (kinematic) ones decide whether FE runs
    bending_utilisation = {max = 1.0}
    collision_free = true
    fe_deflection_ratio = {max = 1.0}
    fe_buckling_factor = {min = 3.0}

Sections, parameters, objectives and constraints are parsed by the helpers of sweep files
(:mod:`compas_ccu.explore.sweep`), so both give the same errors; a study's range has no grid
points but may have a ``step``, a log scale or ``integer = true``.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from compas_ccu import __version__, limits
from compas_ccu.design.document import read_toml
from compas_ccu.design.schema import SCHEMA
from compas_ccu.errors import SweepError
from compas_ccu.explore.metrics import metric_group
from compas_ccu.explore.parsing import (
    SEARCH_KEYS,
    Variant,
    apply_settings,
    default_constraints,
    flatten,
    integer,
    known,
    load_base,
    parse_checks,
    parse_fe,
    parse_goals,
    parse_parameter,
    round_setting,
    table,
)

if TYPE_CHECKING:  # optuna is imported when a study samples, not with this module
    from optuna.distributions import BaseDistribution

__all__ = ["Study", "load_study", "SAMPLERS"]

#: The samplers of a study: ``auto`` is TPE for one objective and NSGA-II for several.
SAMPLERS = ("auto", "tpe", "nsga2", "nsga3", "random")
SECTIONS = ("study", "parameters", "checks", "fe", "objectives", "constraints")
STUDY_KEYS = ("name", "description", "base", "trials", "seed", "sampler", "population")
STUDY_KEYS += ("startup", "best")
#: Significant digits of a sampled continuous value (the design files stay readable; a
#: thickness to 1e-8 m is more than any workshop makes).
DIGITS = 6


class Study:
    """A validated optimisation study file.

    Parameters
    ----------
    document : dict
        The parsed study TOML.
    base_dir : path-like
        Folder against which ``study.base`` is resolved (the study file's folder).
    name : str, optional
        Fallback name when the file has no ``study.name``.

    Attributes
    ----------
    parameters : list of compas_ccu.explore.sweep.Parameter
        The search space: ranges (continuous, integer, stepped, log-scale) and choices.
    objectives : dict
        Metric -> "min" / "max" (required: at least one).
    constraints : dict
        Metric -> ``{min, max}`` or a bool (default: the plates do not break, and do not
        collide when collisions are checked).
    cheap_constraints, fe_constraints : dict
        The constraints on metrics measured before the FE stage, and on the FE's metrics: a
        design that misses a cheap one gets no FE (:attr:`options` ``fe_when``).

    Raises
    ------
    SweepError
        Unknown section or key, a bad range, an unknown metric, an FE metric without ``[fe]``,
        a missing or invalid base design: the message names the key and the value.

    Examples
    --------
    >>> study = Study({"study": {"base": "vault.toml", "trials": 20},
    ...                "parameters": {"crease.rise": {"min": 0.6, "max": 1.4},
    ...                               "layout.plates": {"min": 4, "max": 12, "step": 2}},
    ...                "objectives": {"mass": "min"}}, base_dir="examples")
    >>> study.sampler_name, [p.integer for p in study.parameters], study.constraints
    ('tpe', [False, True], {'bending_utilisation': {'max': 1.0}})
    >>> v = study.variant({"crease.rise": 0.8, "layout.plates": 6})
    >>> study.document_for(v)["layout"]["plates"], v.params
    (6, {'crease.rise': 0.8, 'layout.plates': 6})
    """

    def __init__(self, document: dict, *, base_dir=".", name: str | None = None):
        if not isinstance(document, dict):
            raise SweepError(f"a study must be a table, got {type(document).__name__}")
        for section in document:
            if section not in SECTIONS:
                raise SweepError(f"unknown section; allowed: {', '.join(SECTIONS)}", key=section)
        head = table(document, "study")
        known(head, STUDY_KEYS, "study")
        self.name = str(head.get("name") or name or "study")
        self.description = str(head.get("description", ""))
        self.trials = integer(head, "trials", 50, 1, "study")
        limits.check("variants", self.trials, what="trials (study.trials)")
        self.seed = integer(head, "seed", 0, 0, "study")
        self.best = integer(head, "best", 5, 0, "study")
        self.startup = integer(head, "startup", 10, 0, "study")
        self.population = integer(head, "population", None, 2, "study")
        self.sampler = head.get("sampler", "auto")
        if self.sampler not in SAMPLERS:
            raise SweepError(
                f"must be one of {', '.join(SAMPLERS)}, got {self.sampler!r}", key="study.sampler"
            )

        self.path_states, self.collisions = parse_checks(document)
        self.fe = parse_fe(document)
        self.base_path, self.base_document = load_base(head, base_dir, "study")
        entries = flatten(table(document, "parameters"), range_keys=SEARCH_KEYS + ("num",))
        if not entries:
            raise SweepError("needs at least one parameter to search", key="[parameters]")
        self.parameters = [
            parse_parameter(name, spec, SCHEMA, search=True) for name, spec in entries.items()
        ]
        goals = {"collisions": self.collisions, "fe": self.fe}
        if "objectives" not in document:
            raise SweepError("missing: what to optimise, e.g. mass = 'min'", key="[objectives]")
        self.objectives = parse_goals(document, "objectives", {}, **goals)
        constraints = default_constraints(self.collisions)
        self.constraints = parse_goals(document, "constraints", constraints, **goals)
        self.document = document

    # -- the search space and its designs ------------------------------------------------------
    @property
    def parameter_names(self) -> list:
        """Parameter columns of the results table, in order."""
        return [p.name for p in self.parameters]

    @property
    def sampler_name(self) -> str:
        """The sampler that runs: ``auto`` resolved (TPE for one objective, else NSGA-II)."""
        if self.sampler != "auto":
            return self.sampler
        return "tpe" if len(self.objectives) == 1 else "nsga2"

    @property
    def cheap_constraints(self) -> dict:
        return {k: v for k, v in self.constraints.items() if metric_group(k) != "fe"}

    @property
    def fe_constraints(self) -> dict:
        return {k: v for k, v in self.constraints.items() if metric_group(k) == "fe"}

    def variant(self, settings: dict, index: int = 0) -> Variant:
        """The design of parameter values ``settings`` (name -> design value) as a
        :class:`~compas_ccu.explore.sweep.Variant` (its id is a hash of the values)."""
        by_name = {p.name: p for p in self.parameters}
        params = {n: by_name[n].column(v) for n, v in settings.items()}
        return Variant(index, dict(settings), params)

    def variant_of_row(self, row: dict) -> Variant:
        """The variant of a results row (its parameter columns)."""
        settings = {p.name: p.value(row[p.name]) for p in self.parameters}
        return self.variant(settings, int(row.get("trial", 0)))

    def document_for(self, variant: Variant) -> dict:
        """The design document of ``variant``: the base with its parameter values."""
        return apply_settings(self.base_document, variant, self.base_path)

    def distributions(self) -> dict[str, BaseDistribution]:
        """Optuna's distribution of every parameter (needs optuna), parameter name ->
        distribution in the study's order: ranges are float or int distributions (step, log),
        values and section tables categorical over their table values (labels for tables, JSON
        text for lists)."""
        from optuna.distributions import (
            CategoricalDistribution,
            FloatDistribution,
            IntDistribution,
        )

        out = {}
        for p in self.parameters:
            if not p.is_range:
                out[p.name] = CategoricalDistribution([p.column(v) for v in p.values])
            elif p.integer:
                step = int(p.step) if p.step is not None else 1
                out[p.name] = IntDistribution(int(p.low), int(p.high), log=p.log, step=step)
            else:
                out[p.name] = FloatDistribution(p.low, p.high, log=p.log, step=p.step)
        return out

    def settings_of(self, params: dict) -> dict[str, Any]:
        """Design values of the parameter values a sampler proposed (``trial.params``),
        parameter name -> value in the study's order: continuous values rounded to
        :data:`DIGITS` significant digits (stepped ones to 12: ``0.1 + 3 * 0.05`` is 0.25) and
        kept in their range, integers as int, choices decoded.

        >>> study = Study({"study": {"base": "vault.toml"},
        ...                "parameters": {"plates.thickness": {"min": 0.004, "max": 0.02}},
        ...                "objectives": {"mass": "min"}}, base_dir="examples")
        >>> study.settings_of({"plates.thickness": 0.0073361760376214})
        {'plates.thickness': 0.00733618}
        """
        out = {}
        for p in self.parameters:
            value = params[p.name]
            if not p.is_range:
                out[p.name] = p.value(value)
            elif p.integer:
                out[p.name] = int(value)
            elif p.step is not None:
                out[p.name] = round_setting(value)
            else:
                rounded = float(f"{float(value):.{DIGITS}g}")
                out[p.name] = min(max(rounded, p.low), p.high)
        return out

    # -- evaluation ------------------------------------------------------------------------------
    @property
    def options(self) -> dict:
        """Evaluation options of every trial (:func:`compas_ccu.explore.evaluate_variant`):
        with ``[fe]``, the FE runs only for designs that meet the cheap constraints."""
        options = {"path_states": self.path_states, "collisions": self.collisions, "fe": self.fe}
        if self.fe is not None and self.cheap_constraints:
            options["fe_when"] = self.cheap_constraints
        return options

    @property
    def fingerprint(self) -> str:
        """Hash of everything that decides which trials a run makes and their numbers: the
        base design, the evaluation options, the search space, the objectives, the
        constraints, the sampler and its seed, and the compas_ccu version (not the name, the
        trial budget or ``best``)."""

        space = [
            {k: v for k, v in vars(p).items() if v is not None and v is not False}
            for p in self.parameters
        ]
        text = json.dumps(
            {
                "base": self.base_document,
                "options": self.options,
                "parameters": space,
                "objectives": self.objectives,
                "constraints": self.constraints,
                "sampler": [self.sampler_name, self.seed, self.startup, self.population],
                "version": __version__,
            },
            sort_keys=True,
            default=str,
        )
        return hashlib.sha1(text.encode("utf-8")).hexdigest()[:16]

    def __repr__(self) -> str:
        return (
            f"Study({self.name!r}, {self.trials} trials, sampler={self.sampler_name!r}, "
            f"parameters={self.parameter_names}, objectives={self.objectives})"
        )


def load_study(path, *, seed: int | None = None) -> Study:
    """Load and validate a study TOML file (``base`` is resolved against its folder).

    Parameters
    ----------
    path : path-like
    seed : int, optional
        Overrides ``study.seed`` (``ccu optimize --seed``): another seed is another study.

    Raises
    ------
    SweepError
        The file is missing, not TOML, or not a valid study (the message names the key).
    """
    path = Path(path)
    document = read_toml(path, error=SweepError, what="study")
    if seed is not None and isinstance(document, dict):
        head = document.setdefault("study", {})
        if isinstance(head, dict):
            head["seed"] = seed
    try:
        return Study(document, base_dir=path.parent, name=path.stem)
    except SweepError as exc:
        raise SweepError(f"{path}: {exc}") from exc
