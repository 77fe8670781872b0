"""Writing a validation: ``validation.json``, ``fe_results.npz`` and the pictures.

The only module of :mod:`compas_ccu.fea` that draws: the pictures need the optional ``viz``
extra (matplotlib), imported when they are drawn.
"""

from __future__ import annotations

import os

import numpy as np

from compas_ccu.fea.checks import StructuralChecks, structural_checks
from compas_ccu.fea.comparison import Comparison
from compas_ccu.fea.stresses import signed_bending_stress
from compas_ccu.outputs import write_json
from compas_ccu.viz.fea import plot_fe_curves, plot_fe_shape, plot_load_cases

__all__ = ["write_results", "write_figures", "load_case_titles"]


def write_results(out, summary: dict, comparison: Comparison, *, figures: bool = True) -> list:
    """Write ``validation.json`` (``summary``), ``fe_results.npz`` and the pictures into ``out``.

    ``fe_results.npz`` holds, for every step: node ``positions`` and their ``kinematic``
    positions (k, N, 3), element ``forces`` (k, E, 6) and the plane stresses
    ``stress_top`` / ``stress_bottom`` / ``stress_membrane`` (k, E, 3) in the element frame,
    support ``reactions``, hinge ``tie_forces`` (k, T, 3) of the node pairs ``ties``, the
    ``deviation`` (k, N) in m and the ``alignment`` it was measured after (``"none"`` or
    ``"rigid"``, see :mod:`compas_ccu.fea.comparison`); plus the mesh (``nodes``, ``elements``,
    ``element_plate``) and the reference angles ``alphas``.

    Returns
    -------
    list of str
        The paths written.
    """
    h = comparison.history
    os.makedirs(out, exist_ok=True)
    paths = []
    path = os.path.join(out, "validation.json")
    write_json(path, summary)
    paths.append(path)
    path = os.path.join(out, "fe_results.npz")
    stresses = h.stresses()
    np.savez_compressed(
        path,
        nodes=h.mesh.nodes,
        elements=h.mesh.elements,
        element_plate=h.mesh.element_plate,
        alphas=h.alphas,
        positions=h.positions,
        kinematic=h.kinematic,
        forces=h.result.forces,
        stress_top=stresses.top,
        stress_bottom=stresses.bottom,
        stress_membrane=stresses.membrane,
        reactions=h.result.reactions,
        tie_forces=h.result.tie_forces,
        ties=h.problem.ties,
        deviation=comparison.deviation,
        alignment=np.array(comparison.alignment),
    )
    paths.append(path)
    if figures:
        paths += write_figures(out, comparison)
    return paths


def write_figures(out, comparison: Comparison) -> list:
    """``fe_stress.png`` (Fig. 7 colouring), ``fe_deviation.png``, ``fe_curves.png`` and,
    with load cases, ``fe_load_cases.png`` (:func:`load_case_titles`).

    Drawn at the last deployment step. Needs matplotlib (the ``viz`` extra).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = comparison.history
    os.makedirs(out, exist_ok=True)
    k = h.deployment_steps - 1
    x = h.positions[k]
    name = h.model.design.name
    # the surface facing up (the extrados) on every plate: alternate plates are mirrored in
    # the stack, so their element normals point down; bending flips sign between the faces
    bend = signed_bending_stress(h.result.forces[k], thickness=h.settings.thickness)
    up = h.mesh.element_normals(x) @ h.model.axes[1]
    bend = np.where(up < 0.0, -bend, bend)
    paths = []
    fig = plot_fe_shape(
        x,
        h.mesh.elements,
        bend,
        mode="stress",
        label="bending stress, upper surface [MPa]",
        title=f"{name}, alpha = {h.alphas[k]:.1f} deg ({h.result.engine}): "
        "active bending, tension blue, compression red",
    )
    paths.append(os.path.join(out, "fe_stress.png"))
    fig.savefig(paths[-1], dpi=130)
    plt.close(fig)
    dev = comparison.deviation_percent()[k]
    aligned = ", rigidly aligned" if comparison.alignment == "rigid" else ""
    fig = plot_fe_shape(
        x,
        h.mesh.elements,
        dev,
        mode="deviation",
        title=f"{name}: FE against the kinematic model{aligned}, max {dev.max():.3f} % of span",
    )
    paths.append(os.path.join(out, "fe_deviation.png"))
    fig.savefig(paths[-1], dpi=130)
    plt.close(fig)
    lp = h.load_path()
    d = comparison.deviation_percent()[: k + 1]
    fig = plot_fe_curves(
        np.r_[0.0, h.alphas[: k + 1]],
        deviation_max=np.r_[0.0, d.max(axis=1)],
        deviation_mean=np.r_[0.0, d.mean(axis=1)],
        force=np.array(lp["generalised_force_J_per_rad"], dtype=float),  # None: nan
        energy=np.asarray(lp["work_J"]),
        title=f"{name}: deployment ({h.settings.mode})",
    )
    paths.append(os.path.join(out, "fe_curves.png"))
    fig.savefig(paths[-1], dpi=130)
    plt.close(fig)
    checks = structural_checks(h)
    if checks:
        d = h.result.displacements
        fig = plot_load_cases(
            h.positions[k],
            np.array([d[step["sls"]] - d[k] for step in h.load_steps]),
            h.mesh.elements,
            load_case_titles(checks),
        )
        fig.suptitle(
            f"{name}: deflection under the characteristic loads of every case "
            f"(limit {checks.deflection_limit_m * 1e3:.2f} mm)",
            fontsize=11,
        )
        paths.append(os.path.join(out, "fe_load_cases.png"))
        fig.savefig(paths[-1], dpi=130)
        plt.close(fig)
    return paths


def load_case_titles(checks: StructuralChecks) -> list:
    """One line per load case: deflection, utilisation and buckling factor (the pictures)."""
    out = []
    for c in checks.cases:
        b = c["buckling_factor"]
        out.append(
            f"{c['name']}: {c['deflection_max_m'] * 1e3:.2f} mm, utilisation "
            f"{c['utilisation_max']:.3f}" + ("" if b is None else f", buckling {b:.3g}")
        )
    return out
