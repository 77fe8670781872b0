"""The check sheet of a design: every check an engineer signs, with its value, limit and clause.

``ccu check`` (and the end of ``make demo``) prints it; each check is a :class:`Check` computed
from the records the other commands write, plain data only, so the sheet reads the same numbers
as ``ccu info``, ``fabrication.json`` and ``validation.json``:

* :func:`design_checks` — the kinematic and thick model of ``ccu info --json``: the invariants
  of the isometry, the design angle inside the deployment, overlap and collision limits, the
  thick plates free of each other from the flat stack to the design, and the plates' bending
  (EN 1995-1-1 6.1.6 with the design strength of 2.4.1 for plywood; docs/thickness.md).
* :func:`fabrication_checks` — a ``fabrication.json``: the splice plates' bending, their
  collisions, the thick plates as written, every part nested on a stock sheet.
* :func:`fe_checks` — a ``validation.json``: per load case the ULS utilisation against its
  design strength, the instantaneous and final deflection against the limit, and the design
  buckling factor λ_d ≥ 1 (docs/structural.md).

A check that does not apply (no splice plates, an engine without buckling) is left out, with
the reason in :attr:`Check.note` of a neighbouring row where it matters; a check never passes
for want of a number.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from compas_ccu.key_figures.rows import utilisation_text
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "Check",
    "INVARIANT_TOLERANCE",
    "design_checks",
    "fabrication_checks",
    "fe_checks",
    "failed",
    "check_lines",
]

#: The largest relative error of the kinematic invariants (isometry, planarity, mirror) a
#: certified state may have: the exact construction holds them to ~1e-15.
INVARIANT_TOLERANCE = EXACT_RELATIVE


@dataclass(frozen=True)
class Check:
    """One check: ``value`` against ``limit`` (``relation`` ``"<="`` or ``">="``).

    Examples
    --------
    >>> c = Check("design", "plate bending utilisation", 0.922, 1.0, "<=", "EN 1995-1-1 6.1.6")
    >>> c.ok, c.brief()
    (True, 'design plate bending utilisation 0.922 <= 1')
    >>> c.text().split()[-4:]
    ['ok', 'EN', '1995-1-1', '6.1.6']
    >>> Check("FE", "buckling factor", 0.68, 1.0, ">=", "").ok
    False
    """

    source: str
    name: str
    value: float
    limit: float
    relation: str
    clause: str
    note: str = ""

    @property
    def ok(self) -> bool:
        if self.relation == "<=":
            return bool(self.value <= self.limit)
        if self.relation == ">=":
            return bool(self.value >= self.limit)
        raise ValueError(f"a check's relation is '<=' or '>=', not {self.relation!r}")

    def text(self) -> str:
        """One line: source, check, value, relation, limit, verdict, clause (and note)."""
        value = self.value_text()
        line = (
            f"{self.source:<12} {self.name:<32} {value:>9} {self.relation} "
            f"{_number(self.limit):<7} {'ok' if self.ok else 'FAILED':<7} {self.clause}"
        )
        return line + (f" ({self.note})" if self.note else "")

    def brief(self) -> str:
        """Source, check, value, relation and limit: ``FE snow ULS utilisation 1.02 <= 1``."""
        return (
            f"{self.source} {self.name} {self.value_text()} {self.relation} {_number(self.limit)}"
        )

    def value_text(self) -> str:
        """The value as printed: a utilisation (limit 1) by :func:`utilisation_text`."""
        return utilisation_text(self.value) if self.limit == 1.0 else _number(self.value)

    def to_dict(self) -> dict:
        return {**asdict(self), "ok": self.ok}


def _number(v: float) -> str:
    """3 digits for a utilisation near 1 (never rounded onto its limit), short elsewhere.

    >>> _number(0.9984), _number(1.0), _number(1.0004), _number(3.2e-16), _number(68.15320448)
    ('0.998', '1', '1.000', '3.2e-16', '68.15')
    """
    if v == 0.0 or 1e-3 <= abs(v) < 1e4:
        if abs(v) >= 10:
            return f"{v:.4g}"
        text = f"{v:.3f}"
        short = text.rstrip("0").rstrip(".")
        # trailing zeros go only where they hide nothing: 1.0004 stays "1.000", not "1"
        return short if float(short) == v else text
    return f"{v:.2g}"


def design_checks(figures: dict, thickness: dict | None) -> list:
    """The checks of a design's kinematic and thick model (``ccu info --json``'s data).

    Parameters
    ----------
    figures : dict
        :meth:`compas_ccu.key_figures.KeyFigures.to_dict` of the design state.
    thickness : dict or None
        :meth:`compas_ccu.thickness.ThickModel.summary` (None: the thick model failed, a
        failed check of its own).
    """
    alpha = figures["alpha_design"]
    checks = [
        Check(
            "design",
            "kinematic invariants",
            figures["invariant_max_relative"],
            INVARIANT_TOLERANCE,
            "<=",
            "isometry, quad planarity, mirror (docs/geometry.md)",
        ),
        Check(
            "design",
            "design angle in the deployment",
            alpha,
            figures["alpha_limit"],
            "<=",
            "deployment limit, deg (docs/geometry.md)",
        ),
    ]
    for key, name in (
        ("overlap_alpha", "design angle before overlap"),
        ("collision_free_alpha", "design angle collision-free"),
    ):
        if figures.get(key) is not None:
            checks.append(Check("design", name, alpha, figures[key], "<=", "thin plates, deg"))
    if thickness is None:
        return checks + [
            Check("design", "thick model", 1.0, 0.0, "<=", "the thick plates cannot be built")
        ]
    if thickness.get("collision_free_alpha") is not None:
        checks.append(
            Check(
                "design",
                "thick plates clear to the design",
                alpha,
                thickness["collision_free_alpha"],
                "<=",
                "thick plates from the flat stack, deg",
            )
        )
    c = thickness["collisions"]
    checks.append(
        Check(
            "design",
            "thick plates' penetration, m",
            float(c["max_penetration"]),
            float(c["tolerance"]),
            "<=",
            "from the flat stack to the design",
        )
    )
    b = thickness["bending"]
    checks.append(
        Check(
            "design",
            "plate bending utilisation",
            float(b["max_utilisation"]),
            1.0,
            "<=",
            _bending_clause(b["basis"]),
            f"plate {b['worst']['plate']}, "
            f"characteristic {b['max_utilisation_characteristic']:.3f}",
        )
    )
    return checks


def _bending_clause(basis: dict) -> str:
    if basis.get("code") == "characteristic":
        return "characteristic strength f_k"
    if basis.get("code") == "EC9":
        return f"EN 1999-1-1 6.2.5, {basis.get('basis', '')}".rstrip(", ")
    return f"EN 1995-1-1 6.1.6, f_d = k_mod f_k / gamma_M ({basis.get('basis', '')})"


def fabrication_checks(manifest: dict) -> list:
    """The checks of a ``fabrication.json`` (``ccu fabricate``): what the workshop adds.

    The plates' bending and collisions are :func:`design_checks`' (the manifest repeats them);
    here: the splice plates' bending and collisions, the thick plates as written and every part
    on a stock sheet.
    """
    checks = []
    w = manifest.get("workshop") or {}
    s = w.get("splice_bending") or {}
    cuts = s.get("cuts") or []
    if cuts:
        worst = max(cuts, key=lambda c: c["utilisation"])
        checks.append(
            Check(
                "fabrication",
                "splice plate bending utilisation",
                float(worst["utilisation"]),
                1.0,
                "<=",
                _bending_clause(manifest["bending"]["basis"]),
                f"plate {worst['plate']} cut along ruling {worst['ruling']}",
            )
        )
    spliced = (manifest.get("splices") or {}).get("collisions") or {}
    if spliced.get("splices") and spliced.get("clearance_design") is not None:
        # near the flat stack the splice plates hold the plates apart (the stack height with
        # them); at the design state each must be clear of its neighbour (docs/fabrication.md)
        checks.append(
            Check(
                "fabrication",
                "splice plates' clearance, m",
                float(spliced["clearance_design"]),
                -float(spliced["tolerance"]),
                ">=",
                "splice plates against the neighbouring plates at the design",
                "inside a neighbour at the design"
                if spliced.get("clear_from_alpha") is None
                else f"clear from alpha {spliced['clear_from_alpha']:g} deg",
            )
        )
    collisions = manifest.get("collisions") or {}
    if collisions:
        checks.append(
            Check(
                "fabrication",
                "written plates' penetration, m",
                float(collisions["max_penetration"]),
                float(collisions["tolerance"]),
                "<=",
                "the thick plates as written",
            )
        )
    sheets = w.get("sheets")
    rows = (manifest.get("bom") or {}).get("rows") or []
    if sheets is not None and rows:
        # every cut part of the bill of materials on a stock sheet (re-read from both records)
        cut = {r["item"] for r in rows if r.get("sheet") is not None}
        nested = {name for sheet in sheets for name in sheet["parts"]}
        stock = " + ".join(f"{a:g} x {b:g} m" for a, b in w.get("sheets_in_stock", []))
        checks.append(
            Check(
                "fabrication",
                "BOM parts not on a sheet",
                len(cut - nested),
                0,
                "<=",
                f"{len(cut)} parts on {len(sheets)} stock sheets of {stock}",
            )
        )
    return checks


def fe_checks(validation: dict) -> list:
    """The checks of a ``validation.json`` (``ccu validate``): every load case's.

    A case's buckling check needs the engine's buckling analysis (Kratos): without it the row
    is left out and the utilisation row says so.
    """
    c = validation.get("checks")
    if not c:
        return []
    checks = []
    for case in c["cases"]:
        src = f"FE {case['name']}"
        basis = case.get("basis") or {}
        checks.append(
            Check(
                src,
                "ULS utilisation",
                float(case["utilisation_max"]),
                1.0,
                "<=",
                _fe_strength_clause(basis),
                f"plate {case['utilisation_plate']}, {case['stress_max_MPa']:.3g} MPa of "
                f"{case['strength_MPa']:.3g}",
            )
        )
        checks.append(
            Check(
                src,
                "SLS deflection / limit",
                float(case["deflection_ratio"]),
                1.0,
                "<=",
                "EN 1995-1-1 7.2, instantaneous",
                f"{case['deflection_max_m'] * 1e3:.3g} mm of "
                f"{case['deflection_limit_m'] * 1e3:.3g}",
            )
        )
        if case.get("deflection_final_ratio") is not None:
            checks.append(
                Check(
                    src,
                    "final deflection / limit",
                    float(case["deflection_final_ratio"]),
                    1.0,
                    "<=",
                    "EN 1995-1-1 2.2.3(5), u_fin against the instantaneous limit",
                )
            )
        if case.get("buckling_factor") is not None:
            checks.append(
                Check(
                    src,
                    "design buckling factor",
                    float(case["buckling_factor"]),
                    1.0,
                    ">=",
                    "EN 1995-1-1 2.4.1(2)P, 2.3.2.2: E_mean / (gamma_M (1 + psi2 k_def))",
                    f"mean-stiffness factor {case['buckling_factor_mean']:.3g}",
                )
            )
    return checks


def _fe_strength_clause(basis: dict) -> str:
    if basis.get("code") == "EC9":
        return f"EN 1999-1-1 6.2.1 ({basis.get('basis', '')})"
    if basis.get("code") == "characteristic":
        return "characteristic strength f_k"
    return f"EN 1995-1-1 6.1, k_mod {basis.get('k_mod', 0):g} ({basis.get('basis', '')})"


def failed(checks) -> list:
    """The failed checks of ``checks``, in order."""
    return [c for c in checks if not c.ok]


def check_lines(checks) -> list:
    """The sheet as lines: a header, one line per check, and the verdict with every failure.

    >>> lines = check_lines([Check("FE a", "design buckling factor", 0.68, 1.0, ">=", "x")])
    >>> lines[-1]
    '1 check: 0 passed, 1 FAILED: FE a design buckling factor 0.680 >= 1'
    """
    lines = [f"{'source':<12} {'check':<32} {'value':>9}    {'limit':<7} {'verdict':<7} basis"]
    lines += [c.text() for c in checks]
    bad = failed(checks)
    n = len(checks)
    head = f"{n} check{'s' if n != 1 else ''}: {n - len(bad)} passed"
    if not bad:
        return lines + [head + ", none failed"]
    return lines + [head + f", {len(bad)} FAILED: " + "; ".join(c.brief() for c in bad)]
