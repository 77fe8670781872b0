"""The FE validation as text: the record's rows, the load-case table, the deployed state.

:func:`validation_rows` words the last validation record of a design file
(:func:`compas_ccu.fea.record.last_validation`; ``ccu info``, the report),
:func:`load_case_table` the load cases of a ``validation.json`` as cells under
:data:`LOAD_CASE_COLUMNS` (the report's table; :func:`load_case_lines` the console's),
:func:`design_values_text` their design values and :func:`deployment_utilisation_text` the check
of ``ccu validate --mode actuation``.
"""

from __future__ import annotations

from compas_ccu.key_figures.rows import basis_text, utilisation_text

__all__ = [
    "validation_rows",
    "LOAD_CASE_COLUMNS",
    "load_case_table",
    "load_case_lines",
    "design_values_text",
    "deployment_utilisation_text",
]


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
