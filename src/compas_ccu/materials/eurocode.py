"""Design values of the plate materials after the Eurocodes: load-duration classes, k_mod and
k_def of plywood (EN 1995-1-1), the default partial factors γ_M, and :class:`DesignFactors`
(``f_d = k_mod f_k / γ_M``) made by :func:`design_factors` for a material
(docs/thickness.md, "Design values").
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from compas_ccu.materials.library import MaterialError, material

__all__ = [
    "LOAD_DURATIONS",
    "ACTION_DURATIONS",
    "K_MOD_PLYWOOD",
    "K_DEF_PLYWOOD",
    "GAMMA_M",
    "CODES",
    "DesignFactors",
    "design_factors",
    "k_mod_plywood",
]


#: EN 1995-1-1 2.3.1.2 load-duration classes, longest first.
LOAD_DURATIONS = ("permanent", "long-term", "medium-term", "short-term", "instantaneous")

#: The load-duration class of every variable action of a design's ``[loads]`` section
#: (EN 1995-1-1 2.3.1.2, Table 2.2 and its note): the default, then the classes a design may
#: choose (``[loads] <action>_duration``). Snow is short-term unless the design says
#: medium-term (a prolonged heavy snow load, Table 2.2 note); wind short-term or instantaneous;
#: the wet concrete and the construction load of the formwork short-term or medium-term (a
#: longer casting and curing). Self-weight is permanent.
ACTION_DURATIONS = {
    "concrete": ("short-term", ("medium-term", "short-term")),
    "live": ("short-term", ("medium-term", "short-term")),
    "snow": ("short-term", ("medium-term", "short-term")),
    "wind": ("instantaneous", ("short-term", "instantaneous")),
}

#: EN 1995-1-1 Table 3.1, plywood (EN 636): k_mod by service class, in the order of
#: :data:`LOAD_DURATIONS` (service class 3: EN 636-3 only).
K_MOD_PLYWOOD = {
    1: (0.60, 0.70, 0.80, 0.90, 1.10),
    2: (0.60, 0.70, 0.80, 0.90, 1.10),
    3: (0.50, 0.55, 0.65, 0.70, 0.90),
}

#: EN 1995-1-1 Table 3.2, plywood: k_def by service class.
K_DEF_PLYWOOD = {1: 0.80, 2: 1.00, 3: 2.50}

#: Default partial factor γ_M by material kind: plywood EN 1995-1-1 Table 2.3 (recommended
#: value; national annexes differ), aluminium EN 1999-1-1 6.1.3 (γ_M1, cross-section
#: resistance). None: no default, the design file must give it.
GAMMA_M = {"plywood": 1.2, "aluminium": 1.1, "gfrp": None, "other": None}

CODES = ("EC5", "characteristic")


def k_mod_plywood(service_class: int, load_duration: str = "permanent") -> float:
    """k_mod of plywood (EN 1995-1-1 Table 3.1).

    >>> k_mod_plywood(1), k_mod_plywood(2, "short-term"), k_mod_plywood(3, "instantaneous")
    (0.6, 0.9, 0.9)
    """
    if service_class not in K_MOD_PLYWOOD:
        raise MaterialError(f"service class must be 1, 2 or 3, got {service_class!r}")
    if load_duration not in LOAD_DURATIONS:
        raise MaterialError(
            f"load duration must be one of {', '.join(LOAD_DURATIONS)}, got {load_duration!r}"
        )
    return K_MOD_PLYWOOD[service_class][LOAD_DURATIONS.index(load_duration)]


@dataclass(frozen=True)
class DesignFactors:
    """The basis of a strength check: ``f_d = k_mod f_k / γ_M`` (or ``f_k``, characteristic).

    Attributes
    ----------
    code : {"EC5", "characteristic"}
    service_class : int
    load_duration : str
    k_mod, gamma_M : float
        1 and 1 for the characteristic basis.
    k_def : float or None
        Creep factor (reported: the final stiffness is ``E / (1 + k_def)``); None if unknown.
    source : str
        Where the factors come from.
    """

    code: str = "characteristic"
    service_class: int = 1
    load_duration: str = "permanent"
    k_mod: float = 1.0
    gamma_M: float = 1.0
    k_def: float | None = None
    source: str = "characteristic strengths f_k"

    @property
    def strength_factor(self) -> float:
        """``k_mod / γ_M``: the design strength over the characteristic one."""
        return self.k_mod / self.gamma_M

    @property
    def is_characteristic(self) -> bool:
        return self.code == "characteristic"

    @property
    def label(self) -> str:
        """A one-line name of the basis, e.g. ``EC5 SC1 permanent``."""
        if self.is_characteristic:
            return "characteristic"
        return f"{self.code} SC{self.service_class} {self.load_duration}"

    def text(self) -> str:
        """The factors as a line of text (``ccu info``, fabricate, the report)."""
        if self.is_characteristic:
            return "characteristic strengths f_k (k_mod = gamma_M = 1)"
        creep = "" if self.k_def is None else f", k_def {self.k_def:g}"
        return (
            f"design strengths f_d = k_mod f_k / gamma_M, {self.label}: k_mod {self.k_mod:g}, "
            f"gamma_M {self.gamma_M:g}{creep}"
        )

    def to_dict(self) -> dict:
        out = asdict(self)
        out["strength_factor"] = self.strength_factor
        out["basis"] = self.label
        return out


def design_factors(
    spec,
    code: str = "EC5",
    service_class: int = 1,
    load_duration: str = "permanent",
    gamma_M: float | None = None,
    k_mod: float | None = None,
    k_def: float | None = None,
) -> DesignFactors:
    """The design factors of the material ``spec`` (docs/thickness.md, "Design values").

    The keywords are the keys of the design file's ``[design_code]`` section.

    ``code = "EC5"``: k_mod from EN 1995-1-1 Table 3.1 (plywood) or 1.0 (aluminium: no
    load-duration factor, EN 1999), γ_M by kind (:data:`GAMMA_M`), k_def from Table 3.2
    (plywood) or 0 (aluminium); gfrp and kind ``other`` need ``gamma_M`` and ``k_mod``.
    ``code = "characteristic"``: k_mod = γ_M = 1, today's check.

    >>> f = design_factors(material("plywood"))
    >>> f.k_mod, f.gamma_M, f.k_def, f.strength_factor
    (0.6, 1.2, 0.8, 0.5)
    >>> design_factors(material("plywood"), "characteristic").strength_factor
    1.0
    """
    m = material(spec)
    if code not in CODES:
        raise MaterialError(f"design_code.code must be one of {', '.join(CODES)}, got {code!r}")
    table_k_mod = k_mod_plywood(service_class, load_duration)  # checks both
    default_k_def = {"plywood": K_DEF_PLYWOOD[service_class], "aluminium": 0.0}.get(m.kind)
    k_def_source = "k_def given"
    if k_def is None:
        k_def = default_k_def
        k_def_source = {
            "plywood": "k_def EN 1995-1-1 Table 3.2",
            "aluminium": "k_def 0: no creep (EN 1999-1-1)",
        }.get(m.kind, "")
    if code == "characteristic":
        return DesignFactors(
            code, service_class, load_duration, 1.0, 1.0, k_def, "characteristic strengths f_k"
        )
    sources = []
    if k_mod is None:
        if m.kind == "plywood":
            k_mod, why = table_k_mod, "EN 1995-1-1 Table 3.1"
        elif m.kind == "aluminium":
            k_mod, why = 1.0, "aluminium: no load-duration factor (EN 1999-1-1)"
        else:
            raise MaterialError(
                f"material {m.name!r} (kind {m.kind!r}) has no default k_mod: give "
                "design_code.k_mod and design_code.gamma_M, or design_code.code = "
                "'characteristic'"
            )
        sources.append(f"k_mod {why}")
    else:
        sources.append("k_mod given")
    if gamma_M is None:
        gamma_M = GAMMA_M[m.kind]
        if gamma_M is None:
            raise MaterialError(
                f"material {m.name!r} (kind {m.kind!r}) has no default gamma_M: give "
                "design_code.gamma_M, or design_code.code = 'characteristic'"
            )
        why = "EN 1995-1-1 Table 2.3" if m.kind == "plywood" else "EN 1999-1-1 6.1.3"
        sources.append(f"gamma_M {why}")
    else:
        sources.append("gamma_M given")
    if k_def_source:
        sources.append(k_def_source)
    for key, value in (("gamma_M", gamma_M), ("k_mod", k_mod)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
            raise MaterialError(f"design_code.{key} must be > 0, got {value!r}")
    return DesignFactors(
        code,
        service_class,
        load_duration,
        float(k_mod),
        float(gamma_M),
        None if k_def is None else float(k_def),
        "; ".join(sources),
    )
