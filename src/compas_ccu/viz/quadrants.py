"""The four quadrants of one planar crease (paper Fig. 2): CCF Q1, Q3 and CCU Q2, Q4."""

from __future__ import annotations

import numpy as np

from compas_ccu.design.variants import quadrant_design
from compas_ccu.errors import OptionError
from compas_ccu.model import CCUModel
from compas_ccu.viz import colors as C
from compas_ccu.viz.render import draw_scene
from compas_ccu.viz.scene import scene_from_structure

__all__ = ["plot_quadrants", "quadrant_pairs"]


def quadrant_pairs(structure) -> dict[str, dict]:
    """Map ``"Q1" .. "Q4"`` to the crease record of each quadrant of a four-quadrant structure.

    Q2 is the synclastic CCU pair (crease convex for both plates), Q4 the anticlastic one
    (concave for both), Q1 the CCF pair of the leading plate, Q3 the other CCF pair.
    """
    out = {}
    for c in structure.creases:
        if c["kind"] == "synclastic":
            out["Q2"] = c
        elif c["kind"] == "anticlastic":
            out["Q4"] = c
        elif c["kind"] == "ccf":
            out["Q1" if structure.plate_ids[0] in c["plates"] else "Q3"] = c
    missing = sorted({"Q1", "Q2", "Q3", "Q4"} - set(out))
    if missing:
        kinds = [c["kind"] for c in structure.creases]
        raise OptionError(
            f"not a four-quadrant structure: no crease for {', '.join(missing)} "
            f"(crease kinds {kinds}); build one with compas_ccu.design.variants.quadrant_design"
        )
    return out


def plot_quadrants(design, *, alpha: float | None = None, width: float | None = None):
    """Top: each quadrant's plate pair deployed; bottom: the same pair at α = 0 (paper Fig. 2).

    Parameters
    ----------
    design : compas_ccu.design.Design
        Any design: its leading crease and ruling field are used (see
        :func:`compas_ccu.design.variants.quadrant_design`).
    alpha : float, optional
        Deployed state, degrees (default: the design α).
    width : float, optional
        Plate width (default: see ``quadrant_design``).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from compas_ccu.design import load_design
    >>> fig = plot_quadrants(load_design("examples/quadrants.toml"))
    >>> [ax.get_title().split(":")[0] for ax in fig.axes[::2]]
    ['Q1', 'Q2', 'Q3', 'Q4']
    """
    from matplotlib.figure import Figure

    model = CCUModel(quadrant_design(design, width=width))
    deployed = model.deploy(alpha)
    flat = model.deploy(0.0)
    pairs = quadrant_pairs(deployed)
    index = {pid: i for i, pid in enumerate(deployed.plate_ids)}
    top = scene_from_structure(deployed, ground=False)
    bottom = scene_from_structure(flat, ground=False)
    fig = Figure(figsize=(13.0, 6.4), layout="constrained")
    kinds = {
        "Q1": "CCF, folded leftwards",
        "Q2": "CCU, synclastic",
        "Q3": "CCF, folded rightwards",
        "Q4": "CCU, anticlastic",
    }
    for col, q in enumerate(("Q1", "Q2", "Q3", "Q4")):
        c = pairs[q]
        plates = [index[p] for p in c["plates"]]
        sub = top.subset(plates, creases=[c["id"]])
        ax = fig.add_subplot(2, 4, col + 1)
        draw_scene(ax, sub, "perspective")
        sb = np.asarray(c.get("sum_beta", []), dtype=float)
        relation = {"Q2": "Σβ < 360°", "Q4": "Σβ > 360°"}.get(q, "Σβ = 360°")
        mean = f", mean {sb.mean():.2f}°" if sb.size else ""
        ax.set_title(f"{q}: {kinds[q]}\n{relation}{mean}", fontsize=9.5)
        ax.title.set_color(C.KIND_COLORS[c["kind"]])
        ax2 = fig.add_subplot(2, 4, 4 + col + 1)
        sub2 = bottom.subset(plates, creases=[c["id"]])
        draw_scene(ax2, sub2, "elevation" if _upright(sub2) else "plan")
        ax2.set_title(
            "crease pattern: one developable sheet"
            if c["kind"] == "ccf"
            else "flat-folded: the two plates stacked",
            fontsize=8.5,
            color="#444444",
        )
    fig.suptitle(
        f"{design.name}: four quadrants of the leading crease, top α = {deployed.alpha:g}°, "
        "bottom α = 0",
        fontsize=11,
    )
    return fig


def _upright(scene) -> bool:
    """True if the flat state lies in a vertical plane (then the elevation shows it)."""
    ext = np.ptp(scene.vertices.reshape(-1, 3), axis=0)
    return bool(ext[2] > ext[1])
