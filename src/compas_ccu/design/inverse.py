"""Inverse design (paper §5.4, SPEC §2): from a 3D target crease to the cut pattern, and back.

A design with ``crease.state = "deployed"`` *is* an inverse design: its profile is the 3D crease
at the design reflection angle and the cut pattern is computed so that the deployment reaches it
(Eq. 8 on every vertex, exact isometry of planar quads). This module adds

* :func:`design_from_crease` -- a design from a 3D target polyline anywhere in space (its plane
  is fitted and refused if the polyline is not planar: a CCU crease is planar, SPEC §1);
* :func:`flat_design` -- the forward design of the computed cut pattern: ``state = "flat"``
  with the pattern's crease polyline and explicit ruling ends, i.e. what a workshop cuts;
* :func:`round_trip` -- target -> pattern -> deploy -> compare: the pattern design is deployed
  to the design angle and compared with the target after a best rigid alignment.

Inverse design of the plane layout from apex and support curves is the ``[target]`` table of a
design file (:mod:`compas_ccu.design.targets`).
"""

from __future__ import annotations

import copy
import math

import numpy as np

from compas_ccu.analysis.alignment import rigid_align
from compas_ccu.errors import DesignError

__all__ = ["design_from_crease", "flat_design", "round_trip", "write_design"]


def design_from_crease(
    points,
    *,
    alpha: float,
    rulings: dict | None = None,
    width: float,
    reference: float = 0.5,
    name: str = "target",
    up=(0.0, 0.0, 1.0),
    tolerance: float = 1e-9,
):
    """A single-crease design whose crease reaches the 3D target ``points`` at ``alpha``.

    Parameters
    ----------
    points : (n + 1, 3) float
        The target crease polyline in world coordinates, m; it becomes the crease's vertices.
    alpha : float
        Design reflection angle at the reference vertex, degrees.
    rulings : dict, optional
        The ``[rulings]`` table (default ``{"type": "orthogonal"}``) in the profile frame:
        x along the chord from the first to the last point, y in the plane towards ``up``.
    width : float
        Ruling length of the plates, m.
    reference : float
        Arc-length fraction of the reference vertex.
    up : (3,) float
        World direction the profile's y axis should follow (its projection into the plane);
        if it is normal to the plane, the side towards which the polyline bulges is used.
    tolerance : float
        Largest allowed distance of a point from the fitted plane, relative to the chord.

    Returns
    -------
    compas_ccu.design.Design

    Raises
    ------
    DesignError
        Fewer than 3 points, or the points are not planar.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, np.pi, 33)
    >>> arch = np.c_[np.cos(t), np.full(33, 2.0), np.sin(t)]  # upright half circle at y = 2
    >>> d = design_from_crease(arch, alpha=30.0, width=0.3)
    >>> err = round_trip(d)
    >>> bool(err["max_relative"] < 1e-9)
    True
    """
    from compas_ccu.design import Design

    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3 or len(p) < 3:
        raise DesignError(f"the target crease must be (n >= 3, 3) points, got shape {p.shape}")
    chord = p[-1] - p[0]
    span = float(np.linalg.norm(chord))
    if span <= 0.0:
        raise DesignError("the target crease is closed (first and last point coincide)")
    centre = p.mean(axis=0)
    _, _, vt = np.linalg.svd(p - centre)
    normal = vt[2]
    off = np.abs((p - centre) @ normal)
    if off.max() > tolerance * span:
        i = int(np.argmax(off))
        raise DesignError(
            f"a CCU crease must be planar (SPEC §1), but target point {i} lies {off[i]:.3g} m "
            f"from the best-fit plane ({off[i] / span:.3g} of the chord; tolerance {tolerance:g})"
        )
    x = chord - (chord @ normal) * normal
    x /= np.linalg.norm(x)
    y = np.cross(normal, x)
    u = np.asarray(up, dtype=float)
    sign = np.sign(u @ y) if abs(u @ y) > 1e-9 * np.linalg.norm(u) else 0.0
    if sign == 0.0:
        bulge = (p - p[0]) @ y
        sign = 1.0 if bulge[np.argmax(np.abs(bulge))] >= 0.0 else -1.0
    y *= sign
    origin = 0.5 * (p[0] + p[-1])
    profile = np.c_[(p - origin) @ x, (p - origin) @ y]
    return Design(
        {
            "design": {"name": name},
            "crease": {
                "profile": "polyline",
                "points": profile.tolist(),
                "segments": len(p) - 1,
                "reference": float(reference),
                "state": "deployed",
            },
            "rulings": dict(rulings or {"type": "orthogonal"}),
            "deployment": {"alpha": float(alpha)},
            "layout": {"type": "single", "width": float(width)},
            "plane": {"origin": origin.tolist(), "xaxis": x.tolist(), "yaxis": y.tolist()},
        }
    )


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
        design angle and plane placement.
    """
    from compas_ccu.design import Design

    layout = design.values["layout"]
    if layout["type"] != "single" or layout["quadrants"]:
        raise DesignError(
            "flat_design needs a single-crease design without quadrants; multi-crease crease "
            "planes are defined at the deployed state",
            key="layout.type",
        )
    model = design.build()
    flat = model.flat()[0]  # the leading plate's cut pattern, plane coordinates
    n = model.segments
    doc = copy.deepcopy(design.document)
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
    return Design(doc)


def round_trip(design) -> dict:
    """Target -> cut pattern -> deploy -> target, for a deployed-state single-crease design.

    Returns
    -------
    dict
        ``max`` (m) and ``max_relative`` (to the span) distance between the deployed pattern
        design and the target at the design angle, over the crease (``crease_max``) and over
        every plate vertex (``max``); ``alpha`` (degrees); ``span`` (m).
    """
    if design.values["crease"]["state"] != "deployed":
        raise DesignError("round_trip starts from a 3D target (crease.state = 'deployed')")
    target = design.build().deploy()
    pattern = flat_design(design).build().deploy(design.alpha)
    a = np.asarray(pattern.deployed).reshape(-1, 3)
    b = np.asarray(target.deployed).reshape(-1, 3)
    moved = rigid_align(a, b).reshape(np.shape(target.deployed))
    dist = np.linalg.norm(moved - np.asarray(target.deployed), axis=-1)
    n = pattern.metrics["segments"]
    span = float(target.metrics["span"])
    return {
        "alpha": design.alpha,
        "span": span,
        "max": float(dist.max()),
        "max_relative": float(dist.max()) / span,
        "crease_max": float(dist[0, : n + 1].max()),
        "alpha_error": float(
            np.abs(
                np.asarray(pattern.metrics["alpha_leading"])
                - np.asarray(target.metrics["alpha_leading"])
            ).max()
        ),
    }


def write_design(design, path, *, header: str | None = None) -> None:
    """Write a design's document as a TOML file (``tomli_w``), ``[design]`` first.

    ``header`` (default: the design's description) is written as comment lines on top.
    """
    import tomli_w

    def clean(value):
        if isinstance(value, dict):
            return {k: clean(v) for k, v in value.items() if v is not None}
        if isinstance(value, (list, tuple)):
            return [clean(v) for v in value]
        if isinstance(value, float) and not math.isfinite(value):
            raise DesignError(f"cannot write a non-finite number {value!r}")
        return value

    doc = clean(design.document)
    ordered = {k: doc[k] for k in ("design",) if k in doc}
    ordered.update({k: v for k, v in doc.items() if k != "design"})
    text = header if header is not None else design.values["design"]["description"]
    comment = "".join(f"# {line}\n" for line in text.splitlines()) + ("\n" if text else "")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(comment + tomli_w.dumps(ordered))
