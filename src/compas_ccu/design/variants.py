"""Derived designs: the same crease and rulings in another layout."""

from __future__ import annotations

from compas_ccu.design.document import Design

__all__ = ["quadrant_design"]


def quadrant_design(design, *, width: float | None = None):
    """The four quadrants of a design's leading crease (paper Fig. 2, Tachi 2013).

    The leading crease and ruling field of ``design`` with a single-crease layout: the leading
    plate, its CCU mirror partner, and the CCF continuations of both across the crease.

    Parameters
    ----------
    design : Design
    width : float, optional
        Plate width along the rulings, metres (default: the design's ``layout.width``, else a
        fifth of the crease span, else 0.3 m).

    Returns
    -------
    Design
        In the units of ``design``.

    Examples
    --------
    >>> from compas_ccu.design import load_design
    >>> from compas_ccu.model import CCUModel
    >>> q = quadrant_design(load_design("examples/vault.toml"))
    >>> q.layout.quadrants, len(CCUModel(q).plate_ids)
    (True, 4)
    """
    doc = design.metric_document()
    if width is None:
        width = design.layout.width
    if width is None:
        span = design.crease.span
        width = 0.2 * span if span else 0.3
    doc["layout"] = {"type": "single", "width": float(width), "quadrants": True}
    doc.setdefault("design", {})["name"] = f"{design.name} (four quadrants)"
    return Design.from_metric(
        doc, units=design.units, name=design.name, base=getattr(design, "base", None)
    )
