"""Load cases of the structural checks: actions on the deployed shape, lumped to the FE nodes.

A design's ``[loads]`` section (docs/design-files.md) names characteristic actions; each that is
not zero gives a :class:`LoadCase` next to the self-weight (:func:`load_cases`):

================  ===========================================  ==========================
case              actions (characteristic)                     load duration (default)
================  ===========================================  ==========================
self-weight       G = ρ g t on the surface                     permanent
wet-concrete      G + wet concrete                             short-term
construction      G + wet concrete + live (or G + live)        short-term
snow              G + snow on the projected area               short-term
snow-half         G + snow on the half of the span before      short-term
                  its middle (the asymmetric case)
wind              G + pressure normal to the surface           instantaneous
area-load         G + a uniform load on the surface            short-term
                  (``--area-load``)
================  ===========================================  ==========================

The load-duration class of every variable action is the design's ``[loads] concrete_duration``,
``live_duration``, ``snow_duration``, ``wind_duration`` (EN 1995-1-1 Table 2.2; the defaults and
the allowed classes are :data:`compas_ccu.materials.ACTION_DURATIONS`); its ψ2 (the final
deflection and the creep of the buckling check) is
:data:`compas_ccu.fea.design_values.PSI_2`.

The serviceability state of a case takes the actions as they are; the ultimate state multiplies
the permanent ones by ``gamma_G`` and the variable ones by ``gamma_Q`` (EN 1990 6.4.3.2, one
leading variable action; a construction case's concrete and live load both lead: the fresh
concrete is a construction load, EN 1991-1-6 4.11). Under wind suction the self-weight is
favourable and takes ``gamma_G,inf = 1.0`` (EN 1990 Table A1.2(B)). The strength check of a
case uses the k_mod of its shortest action (EN 1995-1-1 3.1.3(2)).

Where an action acts (:func:`nodal_loads`), with the element areas (exact: the plates are
isometric to their cut patterns) and normals of the deployed kinematic shape:

* ``surface`` — per unit surface area, downwards (self-weight, a concrete layer of constant
  thickness);
* ``projected`` — per unit plan area: ``A |n · up|`` of every element, downwards (a slab level
  along its soffit line, snow, live load);
* ``normal`` — a pressure against the upper face: ``-p A n`` with ``n`` turned up (wind).

Every element passes a quarter of its load to each corner node.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compas_ccu.fea.design_values import PSI_2, action_duration, combination_duration
from compas_ccu.fea.problem import FEError
from compas_ccu.materials import ACTION_DURATIONS, LOAD_DURATIONS

__all__ = ["Action", "LoadCase", "load_cases", "nodal_loads", "GRAVITY", "CASE_NAMES"]

GRAVITY = 9.81

#: Every case name :func:`load_cases` can give, in order.
CASE_NAMES = (
    "self-weight",
    "wet-concrete",
    "construction",
    "snow",
    "snow-half",
    "wind",
    "area-load",
)
_WHERE = ("surface", "projected", "normal")


@dataclass(frozen=True)
class Action:
    """One characteristic action.

    Attributes
    ----------
    name : str
    value : float
        N/m² (Pa) of surface, plan area or normal pressure, see ``where``.
    where : {"surface", "projected", "normal"}
    permanent : bool
        Permanent (γ_G) or variable (γ_Q).
    duration : str
        EN 1995-1-1 load-duration class.
    half : bool
        Only on the half of the span before its middle.
    psi2 : float
        Quasi-permanent factor ψ2 of a variable action (EN 1990 Table A1.1): the creep of
        its final deflection (EN 1995-1-1 2.2.3(5)); a permanent action has 1.
    """

    name: str
    value: float
    where: str
    permanent: bool = False
    duration: str = "short-term"
    half: bool = False
    psi2: float = 0.0

    def __post_init__(self):
        if self.where not in _WHERE:
            raise FEError(
                f"action {self.name!r}: where must be one of {_WHERE}, got {self.where!r}"
            )
        if self.duration not in LOAD_DURATIONS:
            raise FEError(
                f"action {self.name!r}: duration must be one of {LOAD_DURATIONS}, got "
                f"{self.duration!r}"
            )
        if not 0.0 <= self.psi2 <= 1.0:
            raise FEError(f"action {self.name!r}: psi2 must be in [0, 1], got {self.psi2!r}")


@dataclass(frozen=True)
class LoadCase:
    """Self-weight and the actions of one case, with the partial factors of its ULS.

    Attributes
    ----------
    name : str
    actions : tuple of Action
    gamma_G, gamma_Q : float
    """

    name: str
    actions: tuple = field(default_factory=tuple)
    gamma_G: float = 1.35
    gamma_Q: float = 1.5

    @property
    def duration(self) -> str:
        """The load-duration class of the case: that of its shortest action (EN 1995-1-1
        3.1.3(2))."""
        return combination_duration(a.duration for a in self.actions)

    @property
    def psi2(self) -> float | None:
        """The largest ψ2 of the case's variable actions; None if it has none."""
        values = [a.psi2 for a in self.actions if not a.permanent]
        return max(values) if values else None

    def factor(self, action: Action) -> float:
        """The ULS partial factor of ``action`` in this case."""
        return self.gamma_G if action.permanent else self.gamma_Q

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "duration": self.duration,
            "actions": [
                {
                    "name": a.name,
                    "value_N_per_m2": a.value,
                    "where": a.where,
                    "half_span": a.half,
                    "gamma": self.factor(a),
                    "duration": a.duration,
                    "psi2": 1.0 if a.permanent else a.psi2,
                }
                for a in self.actions
            ],
        }


def load_cases(loads, *, self_weight: float, area_load: float = 0.0) -> list:
    """The load cases of a ``[loads]`` section.

    Parameters
    ----------
    loads : mapping
        The keys of a design file's ``[loads]`` section (``LoadsSection.to_dict()``).
    self_weight : float
        ρ g t of the plates, N/m².
    area_load : float
        A uniform load on the surface, N/m² (0: no ``area-load`` case).

    Returns
    -------
    list of LoadCase
        ``self-weight`` first, then the cases of the non-zero actions in :data:`CASE_NAMES`
        order.

    Examples
    --------
    >>> cases = load_cases({"concrete_thickness": 0.08, "concrete_density": 2500.0,
    ...                     "concrete_area": "projected", "live": 750.0, "snow": 0.0,
    ...                     "wind": 0.0, "gamma_G": 1.35, "gamma_Q": 1.5},
    ...                    self_weight=47.1)
    >>> [(c.name, c.duration) for c in cases]
    [('self-weight', 'permanent'), ('wet-concrete', 'short-term'), ('construction', 'short-term')]
    >>> round(cases[1].actions[1].value, 1)
    1962.0
    """
    g = dict(gamma_G=float(loads.get("gamma_G", 1.35)), gamma_Q=float(loads.get("gamma_Q", 1.5)))
    weight = Action("self-weight", float(self_weight), "surface", True, "permanent", psi2=1.0)

    durations = {key: action_duration(key, loads) for key in ACTION_DURATIONS}  # all checked

    def variable(key: str, name: str, value: float, where: str, **kw) -> Action:
        return Action(name, value, where, duration=durations[key], psi2=PSI_2[key][0], **kw)

    cases = [LoadCase("self-weight", (weight,), **g)]
    t_c = float(loads.get("concrete_thickness") or 0.0)
    concrete = None
    if t_c > 0.0:
        rho = float(loads.get("concrete_density", 2600.0))
        where = loads.get("concrete_area", "projected")
        concrete = variable("concrete", "wet concrete", rho * GRAVITY * t_c, where)
        cases.append(LoadCase("wet-concrete", (weight, concrete), **g))
    live = float(loads.get("live") or 0.0)
    if live > 0.0:
        extra = (concrete,) if concrete is not None else ()
        live_action = variable("live", "live", live, "projected")
        cases.append(LoadCase("construction", (weight, *extra, live_action), **g))
    snow = float(loads.get("snow") or 0.0)
    if snow > 0.0:
        cases.append(LoadCase("snow", (weight, variable("snow", "snow", snow, "projected")), **g))
        half = variable("snow", "snow (half span)", snow, "projected", half=True)
        cases.append(LoadCase("snow-half", (weight, half), **g))
    wind = float(loads.get("wind") or 0.0)
    if wind != 0.0:
        action = variable("wind", "wind", wind, "normal")
        # suction lifts the shell: its own weight is then favourable, gamma_G,inf = 1.0
        g_wind = {**g, "gamma_G": 1.0} if wind < 0.0 else g
        cases.append(LoadCase("wind", (weight, action), **g_wind))
    if area_load > 0.0:
        cases.append(
            LoadCase(
                "area-load",
                (weight, Action("area load", area_load, "surface", psi2=PSI_2["area"][0])),
                **g,
            )
        )
    return cases


def nodal_loads(
    elements: np.ndarray,
    positions: np.ndarray,
    action: Action,
    *,
    up: np.ndarray,
    span_axis: np.ndarray,
    middle: float,
) -> np.ndarray:
    """(N, 6) the nodal forces of ``action`` on the deployed shape ``positions``.

    Parameters
    ----------
    elements : (E, 4) int
    positions : (N, 3) float
        The deployed (kinematic) node positions, m.
    action : Action
    up : (3,) float
        The design's up direction (unit).
    span_axis : (3,) float
        The direction of the span (unit); with ``middle`` it picks the half of a half-span
        action: the elements whose centre lies at ``x · span_axis < middle``.
    middle : float
        The middle of the span along ``span_axis``, m.

    Returns
    -------
    (N, 6) float
        Forces (N) in the first three columns, zero moments.
    """
    x = np.asarray(positions, dtype=float)
    q = x[elements]
    n = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
    area = 0.5 * np.linalg.norm(n, axis=1)
    n = n / np.maximum(2.0 * area, np.finfo(float).tiny)[:, None]
    up = np.asarray(up, dtype=float)
    cos = n @ up
    if action.where == "surface":
        force = -action.value * area[:, None] * up[None]
    elif action.where == "projected":
        force = -action.value * (area * np.abs(cos))[:, None] * up[None]
    else:  # a pressure against the upper face
        upper = np.where(cos >= 0.0, 1.0, -1.0)[:, None] * n
        force = -action.value * area[:, None] * upper
    if action.half:
        force[q.mean(axis=1) @ np.asarray(span_axis, dtype=float) >= middle] = 0.0
    out = np.zeros((len(x), 6))
    for corner in range(4):
        np.add.at(out[:, :3], elements[:, corner], force / 4.0)
    return out
