"""Text of the ``ccu`` commands: the lines of ``ccu info`` and of the thickness summary.

Only formatting: the numbers come from the library (:mod:`compas_ccu.key_figures`,
:meth:`compas_ccu.thickness.ThickModel.summary`, :func:`compas_ccu.fea.record.last_validation`).
"""

from __future__ import annotations

from compas_ccu.thickness.bending import bending_verdict
from compas_ccu.thickness.model import collision_text

__all__ = ["info_lines", "thickness_lines", "validation_lines"]


def info_lines(k) -> list:
    """``ccu info`` lines of the key figures ``k`` (:class:`compas_ccu.key_figures.KeyFigures`
    with the path figures): design, limits, shape, stack, invariants, layout, planarity."""
    lines = [
        f"design            {k.name}",
        f"plates            {k.plates}",
        f"creases           {k.creases}" + (f" ({k.crease_kinds})" if k.crease_kinds else ""),
        f"segments          {k.segments} per crease",
        f"design alpha      {k.alpha_design:g} deg at reference vertex {k.reference_vertex}",
        f"deployment limit  {k.alpha_limit:.4f} deg ("
        + (
            f"the surface at reference vertex {k.reference_vertex}"
            if k.alpha_limit >= 90.0
            else f"crease segment {k.limit_vertex}"
        )
        + " perpendicular to its plane)",
        f"overlap limit     {k.overlap_alpha:.4f} deg (largest alpha before a crease "
        "overlaps itself)",
        f"span              {k.crease_span:.4f} m (leading crease chord)",
        f"rise              {k.crease_rise:.4f} m",
        f"bounding box      {k.plan_x:.3f} x {k.plan_y:.3f} x {k.height:.3f} m",
        f"flat stack        {k.stack_x:.3f} x {k.stack_y:.3f} m footprint",
        f"invariants        max relative error {k.invariant_max_relative:.1e}, crease planarity "
        f"{k.crease_planarity_design:.1e} m",
        f"layout            {k.layout}",
    ]
    if k.plane_inclination_axis is not None:
        lines.append(
            f"plane inclination about the actuation axis {k.plane_inclination_axis:.3f} deg, "
            f"perpendicular {k.plane_inclination_perpendicular:.3f} deg (largest between "
            "neighbours)"
        )
    if k.global_curvature is not None:
        lines.append(
            f"global shape      {k.global_curvature} (principal curvatures "
            f"{k.principal_curvature_1:.4g}, {k.principal_curvature_2:.4g} 1/m at the centre)"
        )
    state = (
        "exact"
        if k.crease_planarity_exact
        else f"at alpha = {k.crease_planarity_path_alpha:.4g} deg"
    )
    lines.append(
        f"path planarity    {k.crease_planarity_path:.2e} m largest crease deviation over "
        f"{k.path_states} states ({state}; 'ccu planarity' for the table)"
    )
    if k.target_fit_planes is not None:
        lines.append(
            f"target fit        planes [{k.target_fit_planes}] solved, largest miss "
            f"{k.target_fit_max:.2e} m"
        )
    return lines


def thickness_lines(summary: dict) -> list:
    """Text lines of a :meth:`compas_ccu.thickness.ThickModel.summary` (info, fabricate)."""
    b, c = summary["bending"], summary["collisions"]
    pairs = summary["pairing"]
    lines = [
        f"thickness         {summary['thickness'] * 1e3:.4g} mm {summary['material']}, flat "
        f"stack {summary['stack_height'] * 1e3:.4g} mm (order {summary['stack_order']})",
        f"axis-shift hinges {pairs.count('intrados')} intrados-intrados, "
        f"{pairs.count('extrados')} extrados-extrados; offset crease correction "
        f"{max(summary['correction_design'], default=0.0) * 1e3:.3g} mm at the design, hinge "
        f"gap along the path {summary['hinge_gap_max_path'] * 1e3:.3g} mm",
    ]
    text = collision_text(c)
    lines.append(
        "collisions        "
        + (
            f"** {text} **"
            if c["first"]
            else text.replace("none", "none from the flat stack to the design", 1)
        )
    )
    worst = b["worst"]
    basis = b["basis"]
    design = basis["code"] != "characteristic"
    lines.append(
        f"bending check     max curvature {b['max_curvature']:.3g} 1/m, utilisation "
        f"{b['max_utilisation']:.2f} (plate {worst['plate']} at alpha {worst['alpha']:.3g} deg; "
        f"limit f{'_d' if design else '_k'}/(E t/2) >= {b['curvature_limit_min']:.3g} 1/m)"
        + (f"  ** {bending_verdict(True, basis)} **" if b["exceeded"] else "")
    )
    lines.append(f"bending basis     {basis_text(basis)}")
    if design:
        lines.append(
            f"                  characteristic utilisation "
            f"{b['max_utilisation_characteristic']:.2f} (f_k/(E t/2) >= "
            f"{b['curvature_limit_characteristic_min']:.3g} 1/m)"
        )
    if b.get("final_modulus") is not None and basis.get("k_def") is not None:
        lines.append(
            f"                  creep: k_def {basis['k_def']:g}, final stiffness E/(1 + k_def) "
            + " / ".join(f"{e / 1e9:.3g}" for e in b["final_modulus"])
            + " GPa (E1 / E2)"
        )
    push = summary.get("actuation")
    if push:
        lines.append(
            f"deployment effort bending energy {push['energy_J']:.4g} J at the design; force "
            f"between the feet {abs(push['force_design_N']):.4g} N there, up to "
            f"{push['force_max_N']:.4g} N along the path (docs/structural.md)"
        )
    return lines


def basis_text(basis: dict) -> str:
    """The design factors of a bending or FE check (``DesignFactors.to_dict()``) as text."""
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


def validation_lines(record: dict | None) -> list:
    """``ccu info`` lines on the last FE validation record of a design file, if any."""
    if record is None:
        return ["FE validation     none yet ('ccu validate' to run one)"]
    d = record["deviation"]
    c = record.get("checks") or {}
    plates = record.get("plates") or {}
    with_plates = f" with {plates['thickness'] * 1e3:.4g} mm {plates['material']}" if plates else ""
    line = (
        f"FE validation     {record['engine']} {record['mode']}{with_plates}, alpha "
        f"{record['alpha']:.4g} deg: "
        f"deviation max {d['max_percent']:.3f} % / mean {d['mean_percent']:.3f} % of span, "
        f"bending {record['stresses']['max_bending_MPa']:.1f} MPa"
    )
    lines = [line]
    if c:
        lines.append(
            f"FE checks         deflection {c['deflection_max_m'] * 1e3:.2f} mm (limit "
            f"{c['deflection_limit_m'] * 1e3:.2f} mm), utilisation {c['utilisation_max']:.2f}"
            + (
                f", buckling factor {c['buckling_factor']:.3g}"
                if c.get("buckling_factor") is not None
                else ""
            )
            + ("" if c["deflection_ok"] and c["utilisation_ok"] else "  ** NOT OK **")
        )
        if c.get("governing"):
            g = c["governing"]
            names = ", ".join(k["name"] for k in c.get("cases", []))
            lines.append(
                f"                  load cases {names}; governing: deflection "
                f"{g['deflection']}, utilisation {g['utilisation']}"
                + (f", buckling {g['buckling']}" if g.get("buckling") else "")
            )
        if c.get("basis"):
            lines.append(f"                  strength basis {basis_text(c['basis'])}")
    lines.append(f"                  ({record['when']}, {record['out']})")
    return lines
