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
    "load_case_table",
    "design_values_text",
    "workshop_rows",
    "LOAD_CASE_COLUMNS",
    "value_text",
    "rows_lines",
    "row_failed",
    "size_figures",
    "utilisation_text",
    "deployment_utilisation_text",
    "kink_note",
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


def _design_alpha(k) -> str:
    """Which α the design angle is (a vertex's), and the edges' α from their fold angles (the
    fold a builder sets; at a kink or an inflection the two differ).

    >>> from compas_ccu.key_figures import KeyFigures
    >>> _design_alpha(KeyFigures(alpha_design=30.0, reference_vertex=32, fold_alpha_min=30.4506,
    ...     fold_alpha_max=30.4506, reference_fold_alpha=30.4506))
    '30 deg at reference vertex 32 (a vertex angle); every edge folds at alpha 30.45 deg'
    >>> _design_alpha(KeyFigures(alpha_design=30.0, reference_vertex=24, fold_alpha_min=30.0,
    ...     fold_alpha_max=43.77, reference_fold_alpha=30.001))[48:]
    'edges fold at alpha 30.00 ... 43.77 deg (30.00 there)'
    """
    text = f"{k.alpha_design:g} deg at reference vertex {k.reference_vertex} (a vertex angle)"
    if k.fold_alpha_min is None:  # a design without creases
        return text
    lo, hi = k.fold_alpha_min, k.fold_alpha_max
    if round(lo, 2) == round(hi, 2):
        return f"{text}; every edge folds at alpha {lo:.2f} deg"
    there = ""
    if k.reference_fold_alpha is not None:
        there = f" ({k.reference_fold_alpha:.2f} there)"
    return f"{text}; edges fold at alpha {lo:.2f} ... {hi:.2f} deg{there}"


def utilisation_text(u) -> str:
    """A utilisation as a user reads it: three decimals, and more where three would round a
    value across 1 (so that no failed check reads 1.000 and no passing one 1.000 either).

    Examples
    --------
    >>> utilisation_text(1.004), utilisation_text(0.5), utilisation_text(1.0)
    ('1.004', '0.500', '1.000')
    >>> utilisation_text(1.0004), utilisation_text(0.99996), utilisation_text(1.0 + 1e-12)
    ('1.0004', '0.99996', '1.000000000001')
    >>> utilisation_text(0.9995), utilisation_text(12.3456), utilisation_text(None)
    ('0.9995', '12.346', '—')
    >>> utilisation_text(float("nan")), utilisation_text(float("inf"))
    ('nan', 'inf')
    """
    if u is None:
        return "—"
    u = float(u)
    if not math.isfinite(u):
        return str(u)
    digits = 3
    while digits < 15 and u != 1.0 and float(f"{u:.{digits}f}") == 1.0:
        digits += 1
    return f"{u:.{digits}f}"


def size_figures(layout: str) -> tuple:
    """The figures that give a design's size, ``(name, label)``: the span and rise of a vault
    (its leading crease), the plan diameter and height of a radial dome or funnel (the whole
    structure; its leading crease's chord says little) with the thrust on its ring of feet.
    ``ccu info``, the report and the studio show these.

    >>> [name for name, _ in size_figures("radial")][:2]
    ['plan_diameter', 'height']
    """
    if layout == "radial":
        return (
            ("plan_diameter", "plan diameter"),
            ("height", "height"),
            ("crease_span", "leading crease chord"),
            ("crease_rise", "leading crease rise"),
            ("ring_thrust", "ring thrust"),
            ("ring_tension", "ring tension"),
        )
    return (("crease_span", "span"), ("crease_rise", "rise"), ("height", "height"))


def _size_rows(k) -> list:
    """The span and rise of a vault (its leading crease), the plan diameter and height of a
    radial layout (the whole dome or funnel: its leading crease's chord says little)."""
    if k.layout == "radial":
        return [
            ("plan diameter", f"{k.plan_diameter:.4f} m (the whole structure in plan)"),
            ("height", f"{k.height:.4f} m (the whole structure)"),
            (
                "leading crease",
                f"chord {k.crease_span:.4f} m, rise {k.crease_rise:.4f} m",
            ),
        ]
    return [
        ("span", f"{k.crease_span:.4f} m (leading crease chord)"),
        ("rise", f"{k.crease_rise:.4f} m"),
    ]


def figure_rows(k) -> list:
    """Rows of the key figures ``k`` (:class:`compas_ccu.key_figures.KeyFigures` with the path
    figures): design, limits, shape, stack, invariants, layout, planarity.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> from compas_ccu.key_figures import key_figures
    >>> rows = figure_rows(key_figures(load_model("examples/vault.toml"), path=4))
    >>> rows[8]
    ('span', '2.5000 m (leading crease chord)')
    """
    rows = [
        ("design", f"{k.name}"),
        ("plates", f"{k.plates}"),
        ("creases", f"{k.creases}" + (f" ({k.crease_kinds})" if k.crease_kinds else "")),
        ("segments", f"{k.segments} per crease"),
        ("design alpha", _design_alpha(k)),
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
        (
            "collision free",
            f"{k.collision_free_alpha:.4f} deg (largest alpha from the flat stack without two "
            "plates crossing)",
        ),
        *_size_rows(k),
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
    plates = summary.get("stack_height_plates")  # fabrication.json: the stack with splices
    spliced = ""
    if plates is not None:
        spliced = (
            " (no splice plates)"
            if abs(summary["stack_height"] - plates) < 1e-12
            else f" with the splice plates ({plates * 1e3:.4g} mm plates)"
        )
    rows = [
        (
            "thickness",
            f"{summary['thickness'] * 1e3:.4g} mm {summary['material']}, flat "
            f"stack {summary['stack_height'] * 1e3:.4g} mm{spliced} (order "
            f"{summary['stack_order']})",
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
    if "collision_free_alpha" in summary:
        first = summary.get("first_collision")
        rows.append(
            (
                "thick clear to",
                f"{summary['collision_free_alpha']:.4f} deg (thick plates from the flat stack)"
                + (
                    f" (plates {first['plates'][0]} and {first['plates'][1]} meet at "
                    f"{first['alpha']:.4f} deg)"
                    if first
                    else ""
                ),
            )
        )
    worst = b["worst"]
    basis = b["basis"]
    design = basis["code"] != "characteristic"
    rows.append(
        (
            "bending check",
            f"max curvature {b['max_curvature']:.3g} 1/m, utilisation "
            f"{utilisation_text(b['max_utilisation'])} (plate {worst['plate']} at alpha "
            f"{worst['alpha']:.3g} "
            f"deg; limit f{'_d' if design else '_k'}(1-nu^2)/(E t/2) >= "
            f"{b['curvature_limit_min']:.3g} 1/m)"
            + (f"  ** {bending_verdict(True, basis)} **" if b["exceeded"] else ""),
        )
    )
    if worst.get("at_kink"):
        rows.append(("", kink_note(worst["ruling"])))
    rows.append(("bending basis", basis_text(basis)))
    if design:
        rows.append(
            (
                "",
                "characteristic utilisation "
                f"{utilisation_text(b['max_utilisation_characteristic'])} "
                f"(f_k(1-nu^2)/(E t/2) >= {b['curvature_limit_characteristic_min']:.3g} 1/m)",
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
        rows.append(("deployment effort", _effort_text(push)))
    return rows


def _effort_text(push: dict) -> str:
    """The deployment effort: the force between the feet of a vault, the thrust on the ring of
    feet of a radial dome or funnel (``ThickModel.summary()["actuation"]``).

    >>> _effort_text({"energy_J": 22.38, "force_design_N": -820.7, "force_max_N": 820.7,
    ...     "ring_radius_m": 1.647, "ring_angle_deg": 180.0, "ring_thrust_N_per_m": -49.72,
    ...     "ring_tension_N": -81.9})  # doctest: +NORMALIZE_WHITESPACE
    'bending energy 22.38 J at the design; the feet pull inwards on a ring through them (radius
    1.647 m, 180 deg) with 49.72 N/m: ring compression 81.9 N (docs/structural.md)'
    """
    energy = f"bending energy {push['energy_J']:.4g} J at the design"
    h = push.get("ring_thrust_N_per_m")
    if h is None:
        return (
            f"{energy}; force between the feet {abs(push['force_design_N']):.4g} N there, up to "
            f"{push['force_max_N']:.4g} N along the path (docs/structural.md)"
        )
    way, ring = ("outwards", "tension") if h >= 0.0 else ("inwards", "compression")
    return (
        f"{energy}; the feet {'push' if h >= 0.0 else 'pull'} {way} on a ring through them (radius "
        f"{push['ring_radius_m']:.4g} m, {push['ring_angle_deg']:.4g} deg) with {abs(h):.4g} "
        f"N/m: ring {ring} {abs(push['ring_tension_N']):.4g} N (docs/structural.md)"
    )


def kink_note(ruling: int) -> str:
    """What a curvature peak on the ruling of a crease kink means (a funicular's point load).

    >>> kink_note(31)[:60]
    'the peak is on ruling 31, at a kink of the crease (a point l'
    """
    return (
        f"the peak is on ruling {ruling}, at a kink of the crease (a point load of the "
        "funicular): the plates turn by a finite angle in one quad row there, so this "
        "curvature grows as the segments get shorter; spread the load (distributed_loads) or "
        "hinge or cut along that ruling (docs/shape-control.md)"
    )


def basis_text(basis: dict) -> str:
    """The design factors of a bending or FE check (``DesignFactors.to_dict()``) as text.

    >>> basis_text({"code": "characteristic"})
    'characteristic strengths f_k (k_mod = gamma_M = 1)'
    """
    if basis["code"] == "characteristic":
        return "characteristic strengths f_k (k_mod = gamma_M = 1)"
    creep = "" if basis.get("k_def") is None else f", k_def {basis['k_def']:g}"
    return (
        f"{basis['basis']}: f_d = k_mod f_k / gamma_M, k_mod {basis['k_mod']:g}, gamma_M "
        f"{basis['gamma_M']:g}{creep} ({basis['source']})"
    )


#: Column titles of the load-case table (:func:`load_case_table`), console and report alike.
LOAD_CASE_COLUMNS = (
    "case",
    "actions (characteristic)",
    "deflection (/limit), final",
    "utilisation (k_mod, f_d)",
    "buckling factor E_d (E_mean)",
    "reactions V / H, N (start | end)",
    "hinge N/m: tension / shear / mean",
)


def _actions_text(actions) -> str:
    return ", ".join(
        f"{a['name']} {a['value_N_per_m2']:.0f} N/m² ({a['where']}"
        + (", half span" if a["half_span"] else "")
        + f", γ {a['gamma']:g})"
        for a in actions
    )


def load_case_table(checks: dict) -> tuple:
    """The load cases of a validation as text cells: one definition for console and report.

    Parameters
    ----------
    checks : dict
        The ``checks`` of ``validation.json`` (with ``cases``).

    Returns
    -------
    heading : str
        Feet, deflection limit and design basis.
    rows : list of (list of str, bool)
        Per case, the cells under :data:`LOAD_CASE_COLUMNS` and whether it passes
        (deflection and utilisation).
    governing : str

    Examples
    --------
    >>> case = dict(name="snow", actions=[], deflection_max_m=0.002, deflection_ratio=0.4,
    ...     deflection_ok=True, utilisation_max=0.5, utilisation_ok=True, basis={"k_mod": 0.9},
    ...     strength_MPa=22.5, buckling_factor=None, hinges_uls={}, reactions_uls=dict(
    ...     start_vertical_N=1.0, start_horizontal_N=2.0, end_vertical_N=1.0,
    ...     end_horizontal_N=2.0))
    >>> checks = {"cases": [case], "deflection_limit_m": 0.005,
    ...     "governing": {"deflection": "snow", "utilisation": "snow"}}
    >>> heading, rows, governing = load_case_table(checks)
    >>> rows[0][0][2:5], rows[0][1]
    (['2.00 mm (0.400)', '0.500 (k_mod 0.9, 22.5 MPa)', '—'], True)
    >>> case.update(deflection_final_max_m=0.0036, buckling_factor=4.0, buckling_factor_mean=8.64)
    >>> load_case_table(checks)[1][0][0][2:5:2]
    ['2.00 mm (0.400), final 3.60 mm', '4 (8.64)']
    """
    c = checks
    sup = c.get("supports", {})
    kind = sup.get("type", "pinned") + (" with a tie" if sup.get("tie") else "")
    heading = (
        f"feet {kind}; deflection limit {c['deflection_limit_m'] * 1e3:.2f} mm; ULS stresses "
        "with the active bending, over k_mod f_k / gamma_M of each case's load duration"
    )
    rows = []
    for k in c["cases"]:
        r, hg = k["reactions_uls"], k["hinges_uls"]
        b, mean, fin = k["buckling_factor"], k.get("buckling_factor_mean"), None
        if k.get("deflection_final_max_m") is not None:
            fin = f", final {k['deflection_final_max_m'] * 1e3:.2f} mm"
        cells = [
            k["name"],
            _actions_text(k["actions"]),
            f"{k['deflection_max_m'] * 1e3:.2f} mm ({utilisation_text(k['deflection_ratio'])})"
            f"{fin or ''}",
            f"{utilisation_text(k['utilisation_max'])} (k_mod {k['basis']['k_mod']:g}, "
            f"{k['strength_MPa']:.3g} MPa)",
            ("—" if b is None else format(b, ".3g")) + ("" if mean is None else f" ({mean:.3g})"),
            f"{r['start_vertical_N']:.0f} / {r['start_horizontal_N']:.0f} | "
            f"{r['end_vertical_N']:.0f} / {r['end_horizontal_N']:.0f}"
            + (f"; tie {r['tie_N']:.0f}" if r.get("tie_N") else ""),
            f"{hg.get('tension_max_N_per_m', 0.0):.0f} / "
            f"{hg.get('out_of_plane_max_N_per_m', 0.0):.0f} / "
            f"{hg.get('line_mean_N_per_m', 0.0):.0f}",
        ]
        rows.append((cells, bool(k["deflection_ok"] and k["utilisation_ok"])))
    g = c["governing"]
    governing = f"deflection {g['deflection']}, utilisation {g['utilisation']}" + (
        f", buckling {g['buckling']}" if g.get("buckling") else ""
    )
    return heading, rows, governing


def design_values_text(checks: dict) -> str:
    """The design values of the load-case checks with their clauses (``fea.design_values``):
    k_mod, the design stiffness of the buckling factor, the creep of the final deflection;
    ``""`` for a ``validation.json`` from before them.

    >>> design_values_text({"stiffness": {"clauses": {"k_mod": "Table 3.1"}, "text": "E_d"}})
    'design values: k_mod of each case (Table 3.1); E_d'
    """
    stiffness = checks.get("stiffness")
    if not stiffness:
        return ""
    return (
        f"design values: k_mod of each case ({stiffness['clauses']['k_mod']}); {stiffness['text']}"
    )


def load_case_lines(checks: dict) -> list:
    """The load-case table of ``ccu validate`` as console lines (:func:`load_case_table`;
    the actions column is left out: each case's actions are in the design file)."""
    heading, rows, governing = load_case_table(checks)
    keep = [0, 2, 3, 4, 5, 6]
    titles = [LOAD_CASE_COLUMNS[i] for i in keep]
    table = [[cells[i] for i in keep] + ["" if ok else "EXCEEDED"] for cells, ok in rows]
    widths = [max(len(t), *(len(r[j]) for r in table)) for j, t in enumerate(titles)]
    lines = [f"load cases ({heading}):"]
    lines.append("  " + "  ".join(t.ljust(w) for t, w in zip(titles, widths)).rstrip())
    for r in table:
        lines.append("  " + "  ".join(v.ljust(w) for v, w in zip(r, widths + [0])).rstrip())
    note = design_values_text(checks)
    if note:
        lines.append(note)
    lines.append(f"governing: {governing}")
    return lines


def deployment_utilisation_text(summary: dict) -> str:
    """The deployed state's stress against the design strength f_d, from a validation summary
    (``validation.json``): the check of ``ccu validate --mode actuation``, which has no load
    cases. The peak surface principal stress (the load cases' measure) over
    ``f_d = k_mod f_k / gamma_M`` of the settings' ``design_code`` (``f_k`` the smaller
    strength, as the isotropic check).

    >>> summary = {"stresses": {"max_tension_MPa": 14.2, "max_compression_MPa": -15.1},
    ...     "settings": {"material": {"f1": 30e6, "f2": 30e6}, "design_code": {"code": "EC5",
    ...     "service_class": 1, "load_duration": "permanent", "k_mod": 0.6, "gamma_M": 1.2}}}
    >>> deployment_utilisation_text(summary)  # doctest: +NORMALIZE_WHITESPACE
    'deployed state: utilisation 1.007 (peak stress 15.1 MPa over f_d 15 MPa = k_mod 0.6 x f_k
    30 MPa / gamma_M 1.2, EC5 SC1 permanent)  ** EXCEEDED **'
    """
    st, s = summary["stresses"], summary["settings"]
    code, m = s["design_code"], s["material"]
    peak = max(st["max_tension_MPa"], -st["max_compression_MPa"])
    f_k = min(m["f1"], m["f2"]) / 1e6
    f_d = f_k * code["k_mod"] / code["gamma_M"]
    u = peak / f_d
    basis = (
        "characteristic"
        if code["code"] == "characteristic"
        else f"{code['code']} SC{code['service_class']} {code['load_duration']}"
    )
    return (
        f"deployed state: utilisation {utilisation_text(u)} (peak stress {peak:.3g} MPa over "
        f"f_d {f_d:.3g} MPa = k_mod {code['k_mod']:g} x f_k {f_k:.3g} MPa / gamma_M "
        f"{code['gamma_M']:g}, {basis})" + ("  ** EXCEEDED **" if u > 1.0 else "")
    )


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
                f"{c['deflection_limit_m'] * 1e3:.2f} mm)"
                + (
                    f", final {c['deflection_final_max_m'] * 1e3:.2f} mm"
                    if c.get("deflection_final_max_m") is not None
                    else ""
                )
                + f", utilisation {utilisation_text(c['utilisation_max'])}"
                + (
                    f", buckling factor {c['buckling_factor']:.3g}"
                    + (
                        f" (E_mean {c['buckling_factor_mean']:.3g})"
                        if c.get("buckling_factor_mean") is not None
                        else ""
                    )
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
        if c.get("stiffness"):
            rows.append(("", f"stiffness basis: {c['stiffness']['text']}"))
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


def workshop_rows(manifest: dict) -> list:
    """Rows on the workshop of a ``fabrication.json`` (``ccu fabricate``; the report).

    Sheets and their utilisation, the split plates, the splice plates in the stack (stack
    height with them, highest pile, mass, from which angle they clear the neighbouring plates),
    the splices' bending check (marked as failed above 1), the bill of materials' totals, the
    cost estimate and the assembly.

    Examples
    --------
    >>> work = {"sheets_in_stock": [[2.5, 1.25]], "sheet_count": 1, "utilisation": 0.5,
    ...     "kerf": 0.006, "bridge": 0.01, "grain": "along", "splits": {"0": []},
    ...     "sheets": [{"thickness": 0.008}]}
    >>> bom = {"plates": 2, "splices": 0, "parts_area_m2": 1.0, "mass_kg": 4.0,
    ...     "textile_length_m": 1.5, "textile_roll_width_m": 1.4, "glue_line_m": 6.0,
    ...     "fasteners": 0, "cost_total": 100.0, "currency": "EUR", "cost": {"sheets": 60.0}}
    >>> rows = workshop_rows({"workshop": work, "bom": bom, "assembly": [1, 2]})
    >>> rows[0][1]
    '1 of 2500 x 1250 mm, 8 mm thick; utilisation 50.0 % (kerf 6 mm, bridge 10 mm, grain along)'
    >>> rows[1]
    ('split plates', 'none: every plate fits a sheet')
    """
    w, b = manifest["workshop"], manifest["bom"]
    sizes = ", ".join(f"{x * 1e3:g} x {y * 1e3:g}" for x, y in w["sheets_in_stock"])
    counts: dict = {}
    for sheet in w.get("sheets", []):
        t = sheet.get("thickness")
        counts[t] = counts.get(t, 0) + 1
    if len(counts) == 1 and None not in counts:
        thick = f", {next(iter(counts)) * 1e3:g} mm thick"
    elif counts:
        thick = (
            " ("
            + ", ".join(
                f"{n} of {t * 1e3:g} mm"
                for t, n in sorted(counts.items(), key=lambda kv: -(kv[0] or 0))
            )
            + ")"
        )
    else:
        thick = ""
    split = {k: v for k, v in w["splits"].items() if v}
    rows = [
        (
            "sheets",
            f"{w['sheet_count']} of {sizes} mm{thick}; utilisation {100 * w['utilisation']:.1f} % "
            f"(kerf {w['kerf'] * 1e3:g} mm, bridge {w['bridge'] * 1e3:g} mm, grain {w['grain']})",
        ),
        (
            "split plates",
            ", ".join(f"P{k} at rulings {v}" for k, v in split.items())
            + f"; {b['splices']} splice plates"
            if split
            else "none: every plate fits a sheet",
        ),
    ]
    search = w.get("nesting_search")
    if search and search.get("seed") is not None:
        rows.append(
            (
                "nesting",
                f"{search['solver']} {search['version']}, seed {search['seed']}, "
                f"{search['steps']} steps per packing ({search['packings']} packings, "
                f"{search['steps_searched']} steps; the same seed and steps give the same sheets)",
            )
        )
    elif search:
        rows.append(("nesting", f"{search['solver']}: bounding boxes in rows (no search)"))
    spliced = manifest.get("splices") or {}
    if spliced.get("count"):
        clear = (spliced.get("collisions") or {}).get("clear_from_alpha")
        rows.append(
            (
                "splice plates",
                f"stack {spliced['stack_height'] * 1e3:.4g} mm with them (plates "
                f"{spliced['stack_height_plates'] * 1e3:.4g} mm); highest pile "
                f"{spliced['max_pile'] * 1e3:.4g} mm (cuts staggered; "
                f"{spliced['max_pile_unstaggered'] * 1e3:.4g} mm at the same rulings); "
                f"{spliced['mass']:.3f} kg; "
                + (
                    f"clear of the neighbouring plates from alpha {clear:.3g} deg"
                    if clear is not None
                    else "** inside a neighbouring plate at the design state **"
                ),
            )
        )
    check = w.get("splice_bending")
    if check and check.get("cuts"):
        worst = max(check["cuts"], key=lambda c: c["utilisation"])
        text = (
            f"utilisation {utilisation_text(worst['utilisation'])} (characteristic "
            f"{utilisation_text(worst['utilisation_characteristic'])}) at P{worst['plate']} ruling "
            f"{worst['ruling']}: the plate's {utilisation_text(worst['plate_utilisation'])} x "
            f"{check['factor']:.3g} (splices {check['splice_thickness'] * 1e3:g} mm glued on "
            f"both faces of {check['thickness'] * 1e3:g} mm)"
        )
        rows.append(("splice bending", f"** {text} **" if check["exceeded"] else text))
    rows += [
        (
            "bill of materials",
            f"{b['plates']} plate parts + {b['splices']} splices, {b['parts_area_m2']:.2f} m², "
            f"{b['mass_kg']:.1f} kg; textile {b['textile_length_m']:.2f} m of a "
            f"{b['textile_roll_width_m']:g} m roll; glue line {b['glue_line_m']:.1f} m; "
            f"{b['fasteners']} fasteners",
        ),
        (
            "cost estimate",
            f"{b['cost_total']:.0f} {b['currency']} ("
            + ", ".join(f"{k} {v:.0f}" for k, v in b["cost"].items())
            + ")",
        ),
        (
            "assembly",
            f"{len(manifest['assembly'])} steps in stack order (fabrication.json assembly, "
            "assembly.pdf)",
        ),
    ]
    return rows
