"""The studio's checks panel: the key figures of a model as rows that pass, warn or fail.

Every number comes from :func:`compas_ccu.key_figures.key_figures` (the one definition that
``ccu info``, the report, the sweeps and the catalog use) and from the thick-plate model's
collision and bending checks; this module only decides what is shown and in which colour.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from compas_ccu.errors import CCUError
from compas_ccu.key_figures import key_figures
from compas_ccu.key_figures.table import FIGURES
from compas_ccu.key_figures.text import size_figures, utilisation_text
from compas_ccu.thickness import ThickModel
from compas_ccu.thickness.bending import bending_verdict
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["Check", "StudioChecks", "design_checks", "first_collision", "PATH_STATES"]

#: Path states of the path figures (as ``ccu info``).
PATH_STATES = 24
#: States of the coarse collision scan from the flat stack to the overlap angle.
COLLISION_STATES = 25
#: Bisection steps that refine the first collision between two scanned states.
COLLISION_BISECTIONS = 6
#: Invariant error (relative) above which the exact kinematics has failed.
INVARIANT_LIMIT = EXACT_RELATIVE
#: Bending utilisation above which the row warns.
BENDING_WARN = 0.9

_UNITS = {f.name: f.unit for f in FIGURES}


@dataclass(frozen=True)
class Check:
    """One row of the checks panel: ``status`` is ``ok``, ``warn``, ``fail`` or ``info``."""

    name: str
    value: str
    status: str
    reason: str = ""


@dataclass
class StudioChecks:
    """The checks of one model.

    Attributes
    ----------
    figures : KeyFigures or None
    rows : list of Check
    collision : dict or None
        The first interpenetration along the path (``alpha``, ``plates``, ``depth``, ...).
    plate_utilisation : dict
        Plate id -> largest bending utilisation along the path to the design state.
    seconds : float
        Time the checks took.
    """

    figures: object
    rows: list
    collision: dict | None = None
    plate_utilisation: dict = field(default_factory=dict)
    seconds: float = 0.0

    @property
    def failed(self) -> list:
        return [r for r in self.rows if r.status == "fail"]


def _f(value, digits=4, unit="") -> str:
    if value is None:
        return "-"
    text = f"{value:.{digits}g}"
    return f"{text} {unit}".strip() if unit not in ("", "deg") else text + ("°" if unit else "")


def first_collision(thick: ThickModel, upto: float, *, states: int = COLLISION_STATES):
    """The first interpenetration of the thick plates from the flat stack to ``upto`` degrees
    (:meth:`compas_ccu.thickness.ThickModel.first_collision` with
    :data:`COLLISION_BISECTIONS` bisections, so the angle is known to ``upto / states / 64``).

    Returns
    -------
    dict or None
        The collision (``alpha``, ``plates``, ``depth``, ``crossing``, ``point``) or None.
    """
    return thick.first_collision(upto, states=states, bisections=COLLISION_BISECTIONS)[1]


def design_checks(model, *, path_states: int = PATH_STATES, thick=None) -> StudioChecks:
    """The checks panel of ``model`` (a :class:`compas_ccu.model.CCUModel`).

    ``thick``: its :class:`~compas_ccu.thickness.ThickModel` with the design's thickness and
    material if one is built already (the studio's view builds it), or the error that refused
    it; default: built here.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> checks = design_checks(load_model("examples/vault.toml"))
    >>> [(r.value, r.status) for r in checks.rows if r.name == "bending"], checks.collision
    ([('0.922', 'warn')], None)
    """
    t0 = time.perf_counter()
    rows = []
    given, thick = thick, None
    try:
        if isinstance(given, CCUError):
            raise given
        thick = ThickModel(model) if given is None else given
        figures = key_figures(model, path=path_states, thickness=thick)
    except CCUError as exc:
        figures = key_figures(model, path=path_states)
        rows.append(Check("thick plates", "not modelled", "fail", str(exc)))
    g = figures
    design = g.alpha_design
    rows.append(
        Check(
            "deployment limit",
            _f(g.alpha_limit, 5, "deg"),
            "ok" if g.alpha_limit > design else "fail",
            f"leading-crease segment {g.limit_vertex} stands perpendicular to its plane",
        )
    )
    overlap_ok = g.overlap_alpha > design
    rows.append(
        Check(
            "crease overlap",
            _f(g.overlap_alpha, 5, "deg"),
            "ok" if overlap_ok else "fail",
            "largest α before a crease overlaps itself"
            + ("" if overlap_ok else f": below the design α {design:g}°"),
        )
    )
    free = g.collision_free_alpha
    rows.append(
        Check(
            "plates crossing",
            _f(free, 5, "deg"),
            "ok" if free > design else "fail",
            "largest α from the flat stack without two plates crossing"
            + ("" if free > design else f": below the design α {design:g}°"),
        )
    )
    collision = None
    utilisation = {}
    if thick is not None:
        collision = first_collision(thick, min(free, g.alpha_limit))
        if collision is None:
            rows.append(
                Check(
                    "collision",
                    "none",
                    "ok",
                    f"thick plates clear from 0° to {min(free, g.alpha_limit):.4g}°",
                )
            )
        else:
            a, (p, q) = collision["alpha"], collision["plates"]
            how = "pass through each other" if collision.get("crossing") else "interpenetrate"
            bad = a <= design
            rows.append(
                Check(
                    "collision",
                    _f(a, 4, "deg"),
                    "fail" if bad else "warn",
                    f"plates {p} and {q} {how} at α = {a:.4g}°"
                    + (f", before the design α {design:g}°" if bad else ", beyond the design α"),
                )
            )
        bend = thick.bending(np.linspace(0.0, design, path_states + 1))
        per_plate = bend.per_plate.max(axis=0)
        ids = model.plates.output_ids
        utilisation = {int(i): float(u) for i, u in zip(ids, per_plate)}
        worst = int(np.argmax(per_plate))
        u = float(per_plate[worst])
        status = "fail" if u > 1.0 else ("warn" if u > BENDING_WARN else "ok")
        rows.append(
            Check(
                "bending",
                utilisation_text(u),
                status,
                f"largest utilisation (plate {ids[worst]}, {g.material}, t = "
                f"{g.thickness * 1000:.3g} mm, {bend.factors.label})"
                + (f": {bending_verdict(True, bend.factors.to_dict())}" if u > 1.0 else ""),
            )
        )
    exact = g.crease_planarity_exact
    rows.append(
        Check(
            "crease planarity",
            _f(g.crease_planarity_path, 3, "m"),
            "ok" if exact else "warn",
            "creases stay in their planes along the path"
            if exact
            else f"creases leave their planes (worst at α = {g.crease_planarity_path_alpha:.4g}°):"
            " the relaxed model is shown",
        )
    )
    inv = g.invariant_max_relative
    rows.append(
        Check(
            "invariants",
            f"{inv:.1e}",
            "ok" if inv <= INVARIANT_LIMIT else "fail",
            "isometry, planarity, hinges, mirror (relative to the size)",
        )
    )
    expected = model.design.values["design"]["expected"]
    cls = g.global_curvature
    rows.append(
        Check(
            "global curvature",
            str(cls),
            "warn" if expected and expected != cls else "info",
            f"expected {expected}" if expected else "from the deployed creases",
        )
    )
    for name, label in (
        *size_figures(g.layout),
        ("plan_x", "plan x"),
        ("plan_y", "plan y"),
        ("stack_length", "stack length"),
        ("stack_width", "stack width"),
        ("stack_height", "stack height"),
        ("mass", "mass"),
    ):
        value = g[name]
        if value is not None:
            rows.append(Check(label, _f(value, 4, _UNITS[name]), "info"))
    return StudioChecks(figures, rows, collision, utilisation, time.perf_counter() - t0)
