"""The thick plates as rows of text: stack, hinges, collisions, bending, effort, material.

:func:`thickness_rows` words a :meth:`compas_ccu.thickness.ThickModel.summary` (``ccu info``,
``ccu fabricate``, the report), :func:`material_rows` the material constants and design factors
of a check, :func:`kink_note` a curvature peak at a kink of the crease.
"""

from __future__ import annotations

from compas_ccu.key_figures.rows import basis_text, utilisation_text
from compas_ccu.thickness.bending import bending_verdict
from compas_ccu.thickness.collision_check import collision_text
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = [
    "thickness_rows",
    "material_rows",
    "kink_note",
]


def thickness_rows(summary: dict) -> list:
    """Rows of a :meth:`compas_ccu.thickness.ThickModel.summary` (info, fabricate, report)."""
    bending, collisions = summary["bending"], summary["collisions"]
    pairs = summary["pairing"]
    plates = summary.get("stack_height_plates")  # fabrication.json: the stack with splices
    spliced = ""
    if plates is not None:
        spliced = (
            " (no splice plates)"
            if abs(summary["stack_height"] - plates) < ZERO_LENGTH
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
    rows += _collision_rows(summary, collisions)
    rows += _bending_rows(bending)
    push = summary.get("actuation")
    if push:
        rows.append(("deployment effort", _effort_text(push)))
    return rows


def _collision_rows(summary: dict, c: dict) -> list:
    """The collision check ``c`` along the path (``summary["collisions"]``) and the angle to
    which the thick plates are clear."""
    text = collision_text(c)
    rows = [
        (
            "collisions",
            f"** {text} **"
            if c["first"]
            else text.replace("none", "none from the flat stack to the design", 1),
        )
    ]
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
    return rows


def _bending_rows(b: dict) -> list:
    """The bending check, its basis, the characteristic utilisation and the creep."""
    rows = []
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
