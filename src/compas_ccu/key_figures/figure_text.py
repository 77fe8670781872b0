"""The key figures of a design as rows of text: design, limits, shape, stack, invariants.

:func:`figure_rows` words a :class:`compas_ccu.key_figures.KeyFigures` (``ccu info``, the
report); :func:`size_figures` names the figures that give a design's size (a vault's span and
rise, a radial layout's plan diameter and height), the same for ``ccu info``, the report and the
studio.
"""

from __future__ import annotations

__all__ = [
    "figure_rows",
    "size_figures",
]


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
    return rows + _measured_rows(k)


def _measured_rows(k) -> list:
    """The rows of the figures a design may not have: plane inclination, global shape, path
    planarity and the fit to a target."""
    rows = []
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
