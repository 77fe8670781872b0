"""The key figures and checks as rows of text: one wording of every number a user reads.

``ccu info`` prints these rows as lines (label padded to :data:`LABEL_WIDTH`), the HTML and PDF
report (:mod:`compas_ccu.viz.report`) as table rows: the same strings, so the terminal and the
report cannot disagree. A row is ``(label, text)``; a row that continues the one above has an
empty label; a failed check is marked ``** ... **`` in its text (:func:`row_failed`).

The numbers come from the library: :class:`compas_ccu.key_figures.KeyFigures`,
:meth:`compas_ccu.thickness.ThickModel.summary`, :func:`compas_ccu.fea.record.last_validation`
(a record: plain data) and :class:`compas_ccu.materials.Material` /
:class:`compas_ccu.materials.DesignFactors`.
"""

from __future__ import annotations

import math

from compas_ccu.key_figures.table import FIGURES
from compas_ccu.thickness.bending import bending_verdict
from compas_ccu.thickness.model import collision_text

__all__ = [
    "LABEL_WIDTH",
    "figure_rows",
    "thickness_rows",
    "validation_rows",
    "material_rows",
    "basis_text",
    "load_case_lines",
    "value_text",
    "rows_lines",
    "row_failed",
]

#: Width of the label column of ``ccu info``.
LABEL_WIDTH = 18


def rows_lines(rows) -> list:
    """Lines of text of ``rows``: the label padded to :data:`LABEL_WIDTH` (``ccu info``).

    >>> rows_lines([("plates", "10"), ("", "more")])
    ['plates            10', '                  more']
    """
    return [f"{label:<{LABEL_WIDTH}}{text}" for label, text in rows]


def row_failed(text: str) -> bool:
    """True if a row's text marks a failed check (``** ... **``)."""
    return "** " in text and " **" in text


def figure_rows(k) -> list:
    """Rows of the key figures ``k`` (:class:`compas_ccu.key_figures.KeyFigures` with the path
    figures): design, limits, shape, stack, invariants, layout, planarity.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> from compas_ccu.key_figures import key_figures
    >>> rows = figure_rows(key_figures(load_model("examples/vault.toml"), path=4))
    >>> rows[7]
    ('span', '2.5000 m (leading crease chord)')
    """
    rows = [
        ("design", f"{k.name}"),
        ("plates", f"{k.plates}"),
        ("creases", f"{k.creases}" + (f" ({k.crease_kinds})" if k.crease_kinds else "")),
        ("segments", f"{k.segments} per crease"),
        ("design alpha", f"{k.alpha_design:g} deg at reference vertex {k.reference_vertex}"),
        (
            "deployment limit",
            f"{k.alpha_limit:.4f} deg ("
            + (
                f"the surface at reference vertex {k.reference_vertex}"
                if k.alpha_limit >= 90.0
                else f"crease segment {k.limit_vertex}"
            )
            + " perpendicular to its plane)",
        ),
        (
            "overlap limit",
            f"{k.overlap_alpha:.4f} deg (largest alpha before a crease overlaps itself)",
        ),
        ("span", f"{k.crease_span:.4f} m (leading crease chord)"),
        ("rise", f"{k.crease_rise:.4f} m"),
        ("bounding box", f"{k.plan_x:.3f} x {k.plan_y:.3f} x {k.height:.3f} m"),
        ("flat stack", f"{k.stack_x:.3f} x {k.stack_y:.3f} m footprint"),
        (
            "invariants",
            f"max relative error {k.invariant_max_relative:.1e}, crease planarity "
            f"{k.crease_planarity_design:.1e} m",
        ),
        ("layout", f"{k.layout}"),
    ]
    if k.plane_inclination_axis is not None:
        rows.append(
            (
                "plane inclination",
                f"about the actuation axis {k.plane_inclination_axis:.3f} deg, "
                f"perpendicular {k.plane_inclination_perpendicular:.3f} deg (largest between "
                "neighbours)",
            )
        )
    if k.global_curvature is not None:
        rows.append(
            (
                "global shape",
                f"{k.global_curvature} (principal curvatures "
                f"{k.principal_curvature_1:.4g}, {k.principal_curvature_2:.4g} 1/m at the centre)",
            )
        )
    if k.crease_planarity_path is not None:
        state = (
            "exact"
            if k.crease_planarity_exact
            else f"at alpha = {k.crease_planarity_path_alpha:.4g} deg"
        )
        rows.append(
            (
                "path planarity",
                f"{k.crease_planarity_path:.2e} m largest crease deviation over "
                f"{k.path_states} states ({state}; 'ccu planarity' for the table)",
            )
        )
    if k.target_fit_planes is not None:
        rows.append(
            (
                "target fit",
                f"planes [{k.target_fit_planes}] solved, largest miss {k.target_fit_max:.2e} m",
            )
        )
    return rows


def thickness_rows(summary: dict) -> list:
    """Rows of a :meth:`compas_ccu.thickness.ThickModel.summary` (info, fabricate, report)."""
    b, c = summary["bending"], summary["collisions"]
    pairs = summary["pairing"]
    rows = [
        (
            "thickness",
            f"{summary['thickness'] * 1e3:.4g} mm {summary['material']}, flat "
            f"stack {summary['stack_height'] * 1e3:.4g} mm (order {summary['stack_order']})",
        ),
        (
            "axis-shift hinges",
            f"{pairs.count('intrados')} intrados-intrados, "
            f"{pairs.count('extrados')} extrados-extrados; offset crease correction "
            f"{max(summary['correction_design'], default=0.0) * 1e3:.3g} mm at the design, hinge "
            f"gap along the path {summary['hinge_gap_max_path'] * 1e3:.3g} mm",
        ),
    ]
    text = collision_text(c)
    rows.append(
        (
            "collisions",
            f"** {text} **"
            if c["first"]
            else text.replace("none", "none from the flat stack to the design", 1),
        )
    )
    worst = b["worst"]
    basis = b["basis"]
    design = basis["code"] != "characteristic"
    rows.append(
        (
            "bending check",
            f"max curvature {b['max_curvature']:.3g} 1/m, utilisation "
            f"{b['max_utilisation']:.2f} (plate {worst['plate']} at alpha {worst['alpha']:.3g} "
            f"deg; limit f{'_d' if design else '_k'}/(E t/2) >= "
            f"{b['curvature_limit_min']:.3g} 1/m)"
            + (f"  ** {bending_verdict(True, basis)} **" if b["exceeded"] else ""),
        )
    )
    rows.append(("bending basis", basis_text(basis)))
    if design:
        rows.append(
            (
                "",
                f"characteristic utilisation {b['max_utilisation_characteristic']:.2f} "
                f"(f_k/(E t/2) >= {b['curvature_limit_characteristic_min']:.3g} 1/m)",
            )
        )
    if b.get("final_modulus") is not None and basis.get("k_def") is not None:
        rows.append(
            (
                "",
                f"creep: k_def {basis['k_def']:g}, final stiffness E/(1 + k_def) "
                + " / ".join(f"{e / 1e9:.3g}" for e in b["final_modulus"])
                + " GPa (E1 / E2)",
            )
        )
    push = summary.get("actuation")
    if push:
        rows.append(
            (
                "deployment effort",
                f"bending energy {push['energy_J']:.4g} J at the design; force "
                f"between the feet {abs(push['force_design_N']):.4g} N there, up to "
                f"{push['force_max_N']:.4g} N along the path (docs/structural.md)",
            )
        )
    return rows


def basis_text(basis: dict) -> str:
    """The design factors of a bending or FE check (``DesignFactors.to_dict()``) as text.

    >>> basis_text({"code": "characteristic"})
    'characteristic strengths f_k (k_mod = gamma_M = 1)'
    """
    if basis["code"] == "characteristic":
        return "characteristic strengths f_k (k_mod = gamma_M = 1)"
    return (
        f"{basis['basis']}: f_d = k_mod f_k / gamma_M, k_mod {basis['k_mod']:g}, gamma_M "
        f"{basis['gamma_M']:g} ({basis['source']})"
    )


def load_case_lines(checks: dict) -> list:
    """The load-case table of ``ccu validate`` (the ``checks`` of ``validation.json``)."""
    c = checks
    sup = c.get("supports", {})
    kind = sup.get("type", "pinned") + (" with a tie" if sup.get("tie") else "")
    lines = [
        f"load cases (feet {kind}; deflection limit {c['deflection_limit_m'] * 1e3:.2f} mm; "
        "ULS stresses with the active bending, over k_mod f_k / gamma_M):",
        f"  {'case':<13}{'deflection':>12}{'util.':>7}{'k_mod':>7}{'buckling':>10}"
        f"{'reactions V / H, N (start | end)':>36}{'hinge N/m: tension | shear | mean':>36}",
    ]
    for k in c["cases"]:
        r, hg = k["reactions_uls"], k["hinges_uls"]
        b = k["buckling_factor"]
        flag = "" if k["deflection_ok"] and k["utilisation_ok"] else "  EXCEEDED"
        lines.append(
            f"  {k['name']:<13}{k['deflection_max_m'] * 1e3:>9.2f} mm"
            f"{k['utilisation_max']:>7.2f}{k['basis']['k_mod']:>7.2f}"
            f"{'—' if b is None else format(b, '.3g'):>10}"
            f"{r['start_vertical_N']:>10.0f} /{r['start_horizontal_N']:>6.0f} |"
            f"{r['end_vertical_N']:>8.0f} /{r['end_horizontal_N']:>6.0f}"
            + (f" tie {r['tie_N']:.0f}" if r.get("tie_N") else "")
            + f"{hg.get('tension_max_N_per_m', 0.0):>14.0f} |"
            f"{hg.get('out_of_plane_max_N_per_m', 0.0):>6.0f} |"
            f"{hg.get('line_mean_N_per_m', 0.0):>6.0f}{flag}"
        )
    g = c["governing"]
    lines.append(
        f"governing: deflection {g['deflection']}, utilisation {g['utilisation']}"
        + (f", buckling {g['buckling']}" if g.get("buckling") else "")
    )
    return lines


def validation_rows(record: dict | None) -> list:
    """Rows on the last FE validation record of a design file (``ccu info``), if any."""
    if record is None:
        return [("FE validation", "none yet ('ccu validate' to run one)")]
    d = record["deviation"]
    c = record.get("checks") or {}
    plates = record.get("plates") or {}
    with_plates = f" with {plates['thickness'] * 1e3:.4g} mm {plates['material']}" if plates else ""
    rows = [
        (
            "FE validation",
            f"{record['engine']} {record['mode']}{with_plates}, alpha "
            f"{record['alpha']:.4g} deg: "
            f"deviation max {d['max_percent']:.3f} % / mean {d['mean_percent']:.3f} % of span, "
            f"bending {record['stresses']['max_bending_MPa']:.1f} MPa",
        )
    ]
    if c:
        rows.append(
            (
                "FE checks",
                f"deflection {c['deflection_max_m'] * 1e3:.2f} mm (limit "
                f"{c['deflection_limit_m'] * 1e3:.2f} mm), utilisation {c['utilisation_max']:.2f}"
                + (
                    f", buckling factor {c['buckling_factor']:.3g}"
                    if c.get("buckling_factor") is not None
                    else ""
                )
                + ("" if c["deflection_ok"] and c["utilisation_ok"] else "  ** NOT OK **"),
            )
        )
        if c.get("governing"):
            g = c["governing"]
            names = ", ".join(k["name"] for k in c.get("cases", []))
            rows.append(
                (
                    "",
                    f"load cases {names}; governing: deflection "
                    f"{g['deflection']}, utilisation {g['utilisation']}"
                    + (f", buckling {g['buckling']}" if g.get("buckling") else ""),
                )
            )
        if c.get("basis"):
            rows.append(("", f"strength basis {basis_text(c['basis'])}"))
    rows.append(("", f"({record['when']}, {record['out']})"))
    return rows


def material_rows(material, factors=None, *, thickness=None, grain=None) -> list:
    """Rows of the material constants of a check: stiffness, density, strengths, factors.

    Parameters
    ----------
    material : compas_ccu.materials.Material
    factors : compas_ccu.materials.DesignFactors, optional
        The design factors applied to the strengths.
    thickness : float, optional
        Plate thickness, m.
    grain : float, optional
        Face grain direction, degrees.

    Examples
    --------
    >>> from compas_ccu.materials import design_factors, material
    >>> m = material("plywood")
    >>> rows = material_rows(m, design_factors(m), thickness=0.008)
    >>> rows[0][1].startswith("plywood"), rows[2]
    (True, ('stiffness', 'E1 9 GPa, E2 9 GPa, G12 3.462 GPa, nu12 0.3'))
    """
    m = material
    rows = [
        ("material", f"{m.name} ({m.kind})" + (f": {m.description}" if m.description else "")),
    ]
    plates = []
    if thickness is not None:
        plates.append(f"thickness {thickness * 1e3:.4g} mm")
    if grain is not None:
        plates.append(f"face grain {grain:g} deg")
    rows.append(("plates", ", ".join(plates) if plates else "not given"))
    rows += [
        (
            "stiffness",
            f"E1 {m.E1 / 1e9:.4g} GPa, E2 {m.E2 / 1e9:.4g} GPa, G12 {m.G12 / 1e9:.4g} GPa, "
            f"nu12 {m.nu12:.4g}",
        ),
        ("density", f"{m.density:.4g} kg/m3"),
        ("strengths", f"f1 {m.f1 / 1e6:.4g} MPa, f2 {m.f2 / 1e6:.4g} MPa (characteristic f_k)"),
    ]
    if factors is not None:
        rows.append(("design factors", factors.text()))
        if not factors.is_characteristic:
            rows.append(
                (
                    "",
                    f"design strengths f_d f1 {m.f1 * factors.strength_factor / 1e6:.4g} MPa, "
                    f"f2 {m.f2 * factors.strength_factor / 1e6:.4g} MPa ({factors.source})",
                )
            )
    return rows


def value_text(name: str, value) -> str:
    """One key figure's value with its unit (the complete table of the report).

    >>> value_text("crease_span", 2.5), value_text("plates", 10), value_text("k_def", None)
    ('2.5 m', '10', '—')
    """
    unit = _UNITS[name]
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        text = f"{value:.6g}" if math.isfinite(value) else str(value)
    else:
        text = str(value)
    return f"{text} {unit}" if unit and text else text


_UNITS = {f.name: f.unit for f in FIGURES}
