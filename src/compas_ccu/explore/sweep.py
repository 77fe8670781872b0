"""Sweep files: a base design, the parameters to vary and how to sample them.

A sweep file is TOML (``docs/explore.md`` lists every key)::

    [sweep]
    name = "vault-sweep"
    base = "../vault.toml"            # the base design, relative to this file
    sampling = "grid"                 # grid | list | random | lhs
    samples = 200                     # random / lhs
    seed = 1                          # random / lhs

    [parameters]
    "crease.rise" = [0.8, 1.0, 1.2]                   # values: a grid axis, or choices
    "deployment.alpha" = {min = 20, max = 40, num = 5}  # a range (num: grid points)
    layout = [{label = "parallel", type = "parallel", plates = 6, spacing = 0.12},
              {label = "radial", type = "radial", plates = 6, angle = 6.0, axis = 3.0}]

A dotted parameter sets one key of the design; a parameter named after a section (``layout``)
replaces the whole section with each of its tables (dotted parameters apply on top). Every
variant is identified by its parameter values (:attr:`Variant.id`), so a sweep that grows keeps
the variants it already computed.

The parsing helpers (:func:`~compas_ccu.explore.parsing.parse_checks`, ``parse_fe``,
``parse_goals``, ``parse_parameter``, ...), :class:`Parameter` and :class:`Variant` are
:mod:`compas_ccu.explore.parsing`, shared with optimisation studies (:mod:`.study`), so both file
kinds give the same errors; they are re-exported here.
"""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path

import numpy as np

from compas_ccu import __version__, limits
from compas_ccu.design.document import read_toml
from compas_ccu.design.schema import SCHEMA
from compas_ccu.errors import SweepError
from compas_ccu.explore.parsing import (
    CHECK_KEYS,
    DEFAULT_CONSTRAINTS,
    FE_KEYS,
    NUMERIC_KINDS,
    RANGE_KEYS,
    SEARCH_KEYS,
    Parameter,
    Variant,
    apply_settings,
    column_value,
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
    schema_key,
    table,
)

__all__ = ["Parameter", "Variant", "Sweep", "load_sweep", "SAMPLINGS"]
# the parsing helpers, re-exported (they were defined here before explore/parsing.py)
__all__ += ["apply_settings", "default_constraints", "flatten", "integer", "known", "load_base"]
__all__ += ["parse_checks", "parse_fe", "parse_goals", "parse_parameter", "round_setting"]
__all__ += ["schema_key", "table", "column_value", "CHECK_KEYS", "DEFAULT_CONSTRAINTS", "FE_KEYS"]
__all__ += ["NUMERIC_KINDS", "RANGE_KEYS", "SEARCH_KEYS", "DEFAULT_OBJECTIVES"]

SAMPLINGS = ("grid", "list", "random", "lhs")
SECTIONS = ("sweep", "parameters", "variants", "checks", "fe", "objectives", "constraints")
SWEEP_KEYS = ("name", "description", "base", "sampling", "samples", "seed", "best")
DEFAULT_OBJECTIVES = {"rise": "max", "bending_utilisation": "min", "stack_height": "min"}


class Sweep:
    """A validated sweep file.

    Parameters
    ----------
    document : dict
        The parsed sweep TOML.
    base_dir : path-like
        Folder against which ``sweep.base`` is resolved (the sweep file's folder).
    name : str, optional
        Fallback name when the file has no ``sweep.name``.

    Raises
    ------
    SweepError
        Unknown section or key, bad sampling, bad parameter, missing or invalid base design.

    Examples
    --------
    >>> sweep = Sweep({"sweep": {"base": "vault.toml"},
    ...                "parameters": {"crease.rise": [0.8, 1.0], "layout.plates": [4, 6, 8]}},
    ...               base_dir="examples")
    >>> len(sweep.variants), sweep.variants[1].params
    (6, {'crease.rise': 0.8, 'layout.plates': 6})
    >>> sweep.document_for(sweep.variants[1])["layout"]["plates"]
    6
    """

    def __init__(self, document: dict, *, base_dir=".", name: str | None = None):

        if not isinstance(document, dict):
            raise SweepError(f"a sweep must be a table, got {type(document).__name__}")
        for section in document:
            if section not in SECTIONS:
                raise SweepError(f"unknown section; allowed: {', '.join(SECTIONS)}", key=section)
        head = table(document, "sweep")
        known(head, SWEEP_KEYS, "sweep")
        self.name = str(head.get("name") or name or "sweep")
        self.description = str(head.get("description", ""))
        self.sampling = head.get("sampling", "grid")
        if self.sampling not in SAMPLINGS:
            raise SweepError(
                f"must be one of {', '.join(SAMPLINGS)}, got {self.sampling!r}",
                key="sweep.sampling",
            )
        self.samples = integer(head, "samples", None, 1, "sweep")
        self.seed = integer(head, "seed", 0, 0, "sweep")
        self.best = integer(head, "best", 5, 0, "sweep")
        if self.sampling in ("random", "lhs") and self.samples is None:
            raise SweepError(f"sampling {self.sampling!r} needs samples", key="sweep.samples")

        self.path_states, self.collisions = parse_checks(document)
        self.fe = parse_fe(document)
        self.base_path, self.base_document = load_base(head, base_dir, "sweep")
        self.parameters = self._parameters(document, SCHEMA)
        self.variants = self._variants(document, SCHEMA)
        goals = {"collisions": self.collisions, "fe": self.fe}
        self.objectives = parse_goals(document, "objectives", DEFAULT_OBJECTIVES, **goals)
        constraints = default_constraints(self.collisions)
        self.constraints = parse_goals(document, "constraints", constraints, **goals)
        self.document = document

    # -- parsing ------------------------------------------------------------------------------
    def _parameters(self, document: dict, schema: dict) -> list:
        entries = flatten(table(document, "parameters"))
        if self.sampling == "list":
            if entries:
                raise SweepError(
                    "sampling 'list' takes its variants from [[variants]], not [parameters]",
                    key="[parameters]",
                )
            return []
        if not entries:
            raise SweepError("needs at least one parameter to vary", key="[parameters]")
        return [parse_parameter(name, spec, schema) for name, spec in entries.items()]

    def _variants(self, document: dict, schema: dict) -> list:
        if self.sampling == "list":
            rows = document.get("variants")
            if not (isinstance(rows, list) and rows and all(isinstance(r, dict) for r in rows)):
                raise SweepError(
                    "sampling 'list' needs [[variants]] tables of parameter values", key="variants"
                )
            rows = [flatten(r) for r in rows]
            for i, row in enumerate(rows):
                for name in row:
                    if schema_key(name, schema, f"variants[{i}].{name}") is None:
                        raise SweepError(
                            "list variants set design keys (section.key), not whole sections",
                            key=f"variants[{i}].{name}",
                        )
            names = list(dict.fromkeys(n for r in rows for n in r))
            settings = [{n: r[n] for n in names if n in r} for r in rows]
        elif "variants" in document:
            raise SweepError("[[variants]] needs sampling = 'list'", key="variants")
        elif self.sampling == "grid":
            axes = [p.grid_values() for p in self.parameters]
            count = math.prod(len(a) for a in axes)
            limits.check("variants", count, what="variants of the grid")
            grid = np.stack(np.meshgrid(*[np.arange(len(a)) for a in axes], indexing="ij"), -1)
            grid = grid.reshape(-1, len(axes))
            settings = [
                {p.name: axes[j][i] for j, (p, i) in enumerate(zip(self.parameters, row))}
                for row in grid.tolist()
            ]
        else:
            limits.check("variants", self.samples, what="samples (sweep.samples)")
            rng = np.random.default_rng(self.seed)
            d, n = len(self.parameters), self.samples
            if self.sampling == "lhs":
                from scipy.stats import qmc

                unit = qmc.LatinHypercube(d=d, seed=rng).random(n)
            else:
                unit = rng.random((n, d))
            columns = [p.from_unit(unit[:, j]) for j, p in enumerate(self.parameters)]
            settings = [
                {p.name: col[i] for p, col in zip(self.parameters, columns)} for i in range(n)
            ]
        by_name = {p.name: p for p in self.parameters}
        variants, seen = [], set()
        for values in settings:
            params = {
                n: (by_name[n].column(v) if n in by_name else column_value(v))
                for n, v in values.items()
            }
            variant = Variant(len(variants), values, params)
            if variant.id in seen:  # random choices can repeat a design: compute it once
                continue
            seen.add(variant.id)
            variants.append(variant)
        self.duplicates = len(settings) - len(variants)
        return variants

    # -- use ----------------------------------------------------------------------------------
    @property
    def parameter_names(self) -> list:
        """Parameter columns of the results table, in order."""
        if self.parameters:
            return [p.name for p in self.parameters]
        return list(dict.fromkeys(n for v in self.variants for n in v.params))

    def document_for(self, variant: Variant) -> dict:
        """The design document of ``variant``: the base with its parameters applied."""
        return apply_settings(self.base_document, variant, self.base_path)

    @property
    def options(self) -> dict:
        """Evaluation options of every variant (:func:`compas_ccu.explore.evaluate_variant`)."""
        return {"path_states": self.path_states, "collisions": self.collisions, "fe": self.fe}

    @property
    def fingerprint(self) -> str:
        """Hash of what decides a variant's numbers besides its parameters: the base design,
        the evaluation options and the compas_ccu version."""

        text = json.dumps(
            {"base": self.base_document, "options": self.options, "version": __version__},
            sort_keys=True,
            default=str,
        )
        return hashlib.sha1(text.encode("utf-8")).hexdigest()[:16]

    def __repr__(self) -> str:
        return (
            f"Sweep({self.name!r}, {len(self.variants)} variants, sampling={self.sampling!r}, "
            f"parameters={self.parameter_names})"
        )


def load_sweep(path) -> Sweep:
    """Load and validate a sweep TOML file (``base`` is resolved against its folder).

    Raises
    ------
    SweepError
        The file is missing, not TOML, or not a valid sweep (the message names the key).
    """

    path = Path(path)
    document = read_toml(path, error=SweepError, what="sweep")
    try:
        return Sweep(document, base_dir=path.parent, name=path.stem)
    except SweepError as exc:
        raise SweepError(f"{path}: {exc}") from exc
