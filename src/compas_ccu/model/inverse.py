"""Inverse design of a single crease, with the deployable model (paper §5.4).

* :func:`flat_design` -- the forward design of the computed cut pattern: ``state = "flat"``
  with the pattern's crease polyline and explicit ruling ends, i.e. what a workshop cuts;
* :func:`round_trip` -- target -> pattern -> deploy -> compare: the pattern design is deployed
  to the design angle and compared with the target after a best rigid alignment.

A design from a 3D target polyline is :func:`compas_ccu.design.inverse.design_from_crease`.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from compas_ccu.design import Design
from compas_ccu.errors import DesignError
from compas_ccu.geometry import rigid_align
from compas_ccu.model.ccu_model import CCUModel

__all__ = ["flat_design", "patterns_design", "round_trip", "RoundTrip"]


def flat_design(design, *, name: str | None = None):
    """The cut-pattern (forward) design of a single-crease design.

    Parameters
    ----------
    design : compas_ccu.design.Design
        A single-crease design (``layout.type = "single"``, no quadrants).

    Returns
    -------
    compas_ccu.design.Design
        ``crease.state = "flat"``, the pattern's crease as a polyline kept vertex by vertex,
        ``rulings.type = "explicit"`` with the pattern's ruling ends, the same reference vertex,
        design angle and plane placement, in the units of ``design``.

    Examples
    --------
    A deployed-state arch of 8 segments and its cut pattern:

    >>> from compas_ccu.design import Design
    >>> crease = {"profile": "arc", "span": 2.0, "rise": 0.5, "segments": 8, "state": "deployed"}
    >>> arch = Design({
    ...     "crease": crease, "rulings": {"type": "orthogonal"}, "deployment": {"alpha": 30.0},
    ...     "layout": {"type": "single", "width": 0.3},
    ... }, name="arch")
    >>> flat = flat_design(arch)
    >>> flat.name, flat.crease.state, flat.crease.profile, len(flat.crease.points)
    ('arch-pattern', 'flat', 'polyline', 9)
    >>> flat.document["rulings"]["type"]
    'explicit'
    """
    if design.layout.type != "single" or design.layout.quadrants:
        raise DesignError(
            "flat_design needs a single-crease design without quadrants; multi-crease crease "
            "planes are defined at the deployed state",
            key="layout.type",
        )
    model = CCUModel(design)
    flat = model.flat()[0]  # the leading plate's cut pattern, plane coordinates
    n = model.segments
    doc = design.metric_document()
    doc.setdefault("design", {})["name"] = name or f"{design.name}-pattern"
    doc["crease"] = {
        "profile": "polyline",
        "points": flat[: n + 1, :2].tolist(),
        "segments": n,
        "reference": model.reference / n,
        "state": "flat",
    }
    doc["rulings"] = {"type": "explicit", "points": flat[n + 1 :, :2].tolist()}
    doc["layout"] = {"type": "single"}
    return Design.from_metric(doc, units=design.units)


def patterns_design(design, *, name: str | None = None):
    """The cut-pattern design of any design: every plate by its cut pattern (layout
    ``patterns``, docs/import.md).

    The leading plate becomes the ``state = "flat"`` crease polyline with explicit ruling ends
    (as :func:`flat_design`), every other plate a ``[[layout.patterns]]`` table in mechanism
    order: its parent, the parent's boundary it hangs from, its crease row and ruling ends in
    the flat-folded stack (plane coordinates), and its plate id.

    Parameters
    ----------
    design : compas_ccu.design.Design
        Any design (single, with quadrants, multi-crease).

    Returns
    -------
    compas_ccu.design.Design
        The same reference vertex, design angle, plane placement and other sections, in the
        units of ``design``; deployed to the design angle it is the design's structure.

    Raises
    ------
    DesignError
        A design with quadrants (curved-crease-folding continuations share a boundary).

    Examples
    --------
    >>> from compas_ccu.design import load_design
    >>> d = patterns_design(load_design("examples/vault.toml"))
    >>> d.layout.type, len(d.layout.patterns), d.layout.leading, d.crease.state
    ('patterns', 9, 5, 'flat')
    """
    model = CCUModel(design)
    if any(plate.relation != "ccu" for plate in model.mechanism.plates):
        raise DesignError(
            "the curved-crease-folding continuations of quadrants have no cut-pattern layout "
            "(a pattern hangs from its parent as the CCU mirror image, one crease per boundary)",
            key="layout.quadrants",
        )
    st = model.mechanism.place(0.0)
    plane = np.array([1.0, model.flip])
    near, far = st.near[0][..., :2] * plane, st.far[0][..., :2] * plane
    ids = list(model.geometry.plate_ids)
    n = model.segments
    doc = design.metric_document()
    doc.setdefault("design", {})["name"] = name or f"{design.name}-patterns"
    doc["crease"] = {
        "profile": "polyline",
        "points": near[0].tolist(),
        "segments": n,
        "reference": model.reference / n,
        "state": "flat",
    }
    doc["rulings"] = {"type": "explicit", "points": far[0].tolist()}
    tables = [
        {
            "parent": int(plate.parent),
            "boundary": plate.boundary,
            "id": int(ids[k]),
            "near": near[k].tolist(),
            "far": far[k].tolist(),
        }
        for k, plate in enumerate(model.mechanism.plates)
        if k > 0
    ]
    doc["layout"] = {"type": "patterns", "leading": int(ids[0]), "patterns": tables}
    doc.pop("target", None)  # the planes they solved are in the patterns
    return Design.from_metric(doc, units=design.units)


@dataclass(frozen=True)
class RoundTrip:
    """How far a deployed cut pattern lands from its 3D target (:func:`round_trip`).

    Attributes
    ----------
    alpha : float
        The design angle, degrees.
    span : float
        The target's span, m.
    max : float
        The largest distance of a plate vertex from the target's, after a rigid alignment, m.
    max_relative : float
        ``max`` over the span.
    crease_max : float
        The largest distance over the leading crease's vertices, m.
    alpha_error : float
        The largest difference of the leading crease's reflection angles, degrees.

    Examples
    --------
    >>> RoundTrip(30.0, 2.0, 2e-15, 1e-15, 1e-15, 0.0).as_dict()["span"]
    2.0
    """

    alpha: float
    span: float
    max: float
    max_relative: float
    crease_max: float
    alpha_error: float

    def as_dict(self) -> dict:
        """``{field: value}`` (for JSON)."""
        return asdict(self)


def round_trip(design) -> RoundTrip:
    """Target -> cut pattern -> deploy -> target, for a deployed-state single-crease design.

    Returns
    -------
    RoundTrip
        ``max`` (m) and ``max_relative`` (to the span) distance between the deployed pattern
        design and the target at the design angle, over the crease (``crease_max``) and over
        every plate vertex (``max``); ``alpha`` (degrees); ``span`` (m); ``alpha_error``
        (degrees).

    Examples
    --------
    >>> from compas_ccu.design import Design
    >>> crease = {"profile": "arc", "span": 2.0, "rise": 0.5, "segments": 8, "state": "deployed"}
    >>> arch = Design({
    ...     "crease": crease, "rulings": {"type": "orthogonal"}, "deployment": {"alpha": 30.0},
    ...     "layout": {"type": "single", "width": 0.3},
    ... }, name="arch")
    >>> result = round_trip(arch)
    >>> result.alpha, result.span, bool(result.max_relative < 1e-12)
    (30.0, 2.0, True)
    """
    if design.crease.state != "deployed":
        raise DesignError("round_trip starts from a 3D target (crease.state = 'deployed')")
    target = CCUModel(design).deploy()
    pattern = CCUModel(flat_design(design)).deploy(design.alpha)
    a = np.asarray(pattern.deployed).reshape(-1, 3)
    b = np.asarray(target.deployed).reshape(-1, 3)
    moved = rigid_align(a, b).reshape(np.shape(target.deployed))
    dist = np.linalg.norm(moved - np.asarray(target.deployed), axis=-1)
    n = pattern.metrics["segments"]
    span = float(target.metrics["span"])
    leading = np.asarray(pattern.metrics["alpha_leading"])
    return RoundTrip(
        alpha=design.alpha,
        span=span,
        max=float(dist.max()),
        max_relative=float(dist.max()) / span,
        crease_max=float(dist[0, : n + 1].max()),
        alpha_error=float(np.abs(leading - np.asarray(target.metrics["alpha_leading"])).max()),
    )
