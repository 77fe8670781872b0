"""Inverse design (paper §5.4, docs/shape-control.md): from a 3D target crease to a design.

A design with ``crease.state = "deployed"`` *is* an inverse design: its profile is the 3D crease
at the design reflection angle and the cut pattern is computed so that the deployment reaches it
(Eq. 8 on every vertex, exact isometry of planar quads). This module adds

* :func:`design_from_crease` -- a design from a 3D target polyline anywhere in space (its plane
  is fitted and refused if the polyline is not planar: a CCU crease is planar, docs/kinematics.md);
* :func:`write_design` -- a design back to a TOML file.

The forward design of a computed cut pattern and the round trip target -> pattern -> target
need the deployable model: :mod:`compas_ccu.model.inverse`.

Inverse design of the plane layout from apex and support curves is the ``[target]`` table of a
design file (:mod:`compas_ccu.design.targets`).
"""

from __future__ import annotations

import numpy as np

from compas_ccu.design import Design
from compas_ccu.design.writer import design_toml
from compas_ccu.errors import DesignError
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["design_from_crease", "write_design"]


def design_from_crease(
    points,
    *,
    alpha: float,
    rulings: dict | None = None,
    width: float,
    reference: float = 0.5,
    name: str = "target",
    up=(0.0, 0.0, 1.0),
    tolerance: float = EXACT_RELATIVE,
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
    >>> from compas_ccu.model import round_trip
    >>> err = round_trip(d)
    >>> bool(err.max_relative < 1e-9)
    True
    """

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
            f"a CCU crease must be planar (docs/geometry.md §1), but target point {i} lies "
            f"{off[i]:.3g} m "
            f"from the best-fit plane ({off[i] / span:.3g} of the chord; tolerance {tolerance:g})"
        )
    x = chord - (chord @ normal) * normal
    x /= np.linalg.norm(x)
    y = np.cross(normal, x)
    u = np.asarray(up, dtype=float)
    sign = np.sign(u @ y) if abs(u @ y) > EXACT_RELATIVE * np.linalg.norm(u) else 0.0
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


def write_design(design, path, *, header: str | None = None, units: str | None = None) -> None:
    """Write a design's document as a TOML file, ``[design]`` first, point lists one point per
    line (:func:`compas_ccu.design.writer.design_toml`).

    Parameters
    ----------
    design : Design
    path : path-like
    header : str, optional
        Comment lines on top (default: the design's description).
    units : str, optional
        Length units of the file (default: the design's own ``[design] units``, so a design
        read in millimetres is written in millimetres).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from compas_ccu.design import load_design
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "vault-mm.toml"
    >>> write_design(load_design("examples/vault.toml"), path, units="mm")
    >>> again = load_design(path)
    >>> again.units, again.crease.span, again.document["crease"]["span"]
    ('mm', 2.5, 2500.0)
    """
    document = design.document if units is None else design.document_in(units)
    text = header if header is not None else design.sections.design.description
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(design_toml(document, header=text or None))
