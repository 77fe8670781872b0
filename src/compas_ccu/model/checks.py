"""The checks of a model: the design's size against the work limits, the design state before
any deployment, and a path's size (:mod:`compas_ccu.limits`)."""

from __future__ import annotations

import numpy as np

from compas_ccu import limits
from compas_ccu.errors import DeploymentLimitError, DesignError, GeometryError
from compas_ccu.kinematics.checks import crossing_rulings
from compas_ccu.kinematics.invariants import EXACT_KEYS
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["check_size", "check_design", "check_reproduced", "check_path"]


def check_size(design) -> None:
    """Refuse designs beyond the work limits before anything is built.

    Examples
    --------
    >>> from compas_ccu.design import load_design
    >>> check_size(load_design("examples/cone.toml")) is None  # 2 plates of 48 quads: fine
    True
    """
    n = design.crease.segments
    layout = design.layout
    if layout.patterns is not None:
        plates, key = len(layout.patterns) + 1, "layout.patterns"
    else:
        plates = layout.plates if layout.plates is not None else (4 if layout.quadrants else 2)
        key = "layout.plates"
    limits.check("segments", n, what="crease segments (crease.segments)")
    limits.check("plates", plates, what=f"plates ({key})")
    limits.check(
        "vertices", plates * (2 * n + 2), what=f"vertices ({plates} plates x {n} segments)"
    )


def check_design(model) -> None:
    """Refuse, before any deployment, designs whose pattern or design state is impossible.

    * rulings that cross inside a plate (a quad of the cut pattern folds over: the crease
      is curved too tightly for the plate's width there);
    * a flat-state design whose design angle lies beyond the deployment limit;
    * a mechanism that does not reproduce its own design state to the exactness bar
      (:func:`check_reproduced`: never silently deploy something other than the design);
    * a crease that overlaps itself at the design state.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> check_design(load_model("examples/cone.toml")) is None
    True
    """
    bad = crossing_rulings(model.flat()[..., :2], model.plates.quads)
    if bad is not None:
        p, j = bad
        raise GeometryError(
            f"the rulings of plate {model.plate_ids[p]} cross between crease vertices {j} and "
            f"{j + 1}: its cut pattern folds over itself (the crease is curved too tightly "
            "there for the plate's width or the plane spacing); reduce the width / "
            "spacing, smooth the profile, or put the plate on the other side"
        )
    limit = model.alpha_limit
    if model.alpha_design > limit:
        raise DeploymentLimitError(
            f"the design alpha {model.alpha_design:.6g} deg cannot be reached: this cut "
            f"pattern unfolds at most to {limit:.6g} deg, where "
            f"{model.mechanism.leading.limit_reason}",
            alpha=model.alpha_design,
            alpha_limit=limit,
            vertex=model.limit_vertex,
        )
    g = model.geometry
    s0 = model.mechanism.leading.s0_for_alpha(g.design_alpha) if g.state == "deployed" else 0.0
    st = model.mechanism.place(s0)
    check_reproduced(model, st)
    design = model.invariants(st)
    worst = float(design.worst(EXACT_KEYS)[0])
    # half the bar: a reader that measures planarity or lengths another way sees up to
    # twice the round-off of the world coordinates
    if not worst <= 0.5 * EXACT_RELATIVE * model.size:
        far = float(np.abs(model.frame.origin).max())
        raise DesignError(
            f"world coordinates {far:.3g} m from the origin hold this {model.size:.3g} m "
            f"structure only to {worst:.2g} m, more than half the exactness bar of "
            f"{EXACT_RELATIVE:g} of its size; place it nearer the origin (and move it "
            "into place in CAD)",
            key="plane.origin",
        )
    at_design = st if g.state == "deployed" else model.mechanism.deploy(g.design_alpha)
    model.check_overlap(at_design, [model.alpha_design])


def check_reproduced(model, st) -> None:
    """Refuse a design whose mechanism, placed at the design angle, misses the design state.

    The builder refuses the designs known to be impossible (rulings across the crease, planes
    that cross) before this; what is left is a design so close to degenerate that round-off
    decides its shape. The message names the plate, the crease vertex, the miss and what to
    change, as a refusal of the input.

    Parameters
    ----------
    model : CCUModel
    st : compas_ccu.kinematics.mechanism.MechanismStates
        The mechanism placed at the design state (one state).

    Raises
    ------
    GeometryError

    Examples
    --------
    ``examples/cone.toml`` is designed flat: its mechanism at ``s0 = 0`` is the design state, a
    deployed state is not:

    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> check_reproduced(model, model.mechanism.place(0.0)) is None
    True
    >>> check_reproduced(model, model.mechanism.deploy(np.radians([20.0])))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    compas_ccu.errors.GeometryError: this design cannot be deployed exactly: ...
    """
    g = model.geometry
    misses = np.maximum(
        np.abs(st.near[0] - g.design_near).max(axis=-1),
        np.abs(st.far[0] - g.design_far).max(axis=-1),
    )  # (p, n + 1)
    miss = float(misses.max()) if np.all(np.isfinite(misses)) else float("inf")
    if miss <= EXACT_RELATIVE * model.size:
        return
    p, i = (
        int(v) for v in np.unravel_index(np.argmax(np.nan_to_num(misses, nan=np.inf)), misses.shape)
    )
    raise GeometryError(
        f"this design cannot be deployed exactly: its mechanism, placed at the design alpha "
        f"{model.alpha_design:.6g} deg, misses the design state by {miss:.3g} m "
        f"({miss / model.size:.2g} of the {model.size:.3g} m structure; the bar is "
        f"{EXACT_RELATIVE:g}) at plate {model.geometry.plate_ids[p]}, crease vertex {i}: the "
        "design is too close to degenerate there (rulings almost along the crease or "
        "almost meeting, crease planes almost meeting, an almost straight crease between "
        "plates); use fewer or more crease segments, move crease.reference or change the "
        "layout there"
    )


def check_path(model, count: int) -> None:
    """Refuse a path beyond the work limits before its arrays are made (limits module).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> check_path(model, 100) is None
    True
    >>> check_path(model, 10**9)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    compas_ccu.errors.LimitError: 1000000000 states of one path exceed the limit of 10000 ...
    """
    limits.check("states", count, what="states of one path")
    # the placed boundaries, their world copies and the invariants' temporaries: about a
    # dozen float arrays of (states, plates, 2n + 2, 3)
    nbytes = 12 * count * model.plates.count * model.plates.vertex_count * 3 * 8
    limits.check_memory(nbytes, what=f"a path of {count} states")
