"""Splitting the plates into parts that fit the sheets: a plate that fits no sheet is cut along
rulings (:mod:`compas_ccu.fabrication.splices` staggers the cuts), every part carries its
creases, score lines and labels, and the splice plates' bending is checked.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fabrication.plan import Part, SpliceBending, SpliceCutBending, WorkshopOptions
from compas_ccu.fabrication.splices import (
    splice_rectangle,
    stagger_cuts,
    sub_outline,
)
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = [
    "make_parts",
    "splice_bending",
]


def _rulings_between(flat, n: int, j0: int, j1: int) -> list:
    return [np.array([flat[j], flat[n + 1 + j]]) for j in range(j0 + 1, j1)]


def _part_creases(flat, n: int, j0: int, j1: int, on_plate, kinds: dict) -> list:
    """The crease edges of a plate that lie on its part between rulings ``j0`` and ``j1``."""
    out = []
    for cid, _, verts in on_plate:
        verts = [int(v) for v in verts]
        base = 0 if max(verts) <= n else n + 1  # the near or the far row
        inside = [v for v in verts if j0 <= v - base <= j1]
        if len(inside) >= 2:
            out.append({"crease": int(cid), "kind": kinds[int(cid)], "points": flat[inside]})
    return out


def make_parts(data, options: WorkshopOptions, splits: dict | None = None) -> tuple:
    """The plate parts and splice plates of every plate: ``(parts, splits)``; the cuts
    ``splits`` (plate id -> rulings), default
    :func:`~compas_ccu.fabrication.splices.stagger_cuts`."""
    splits = stagger_cuts(data, options) if splits is None else splits
    n = data.segments
    grain = float(data.metadata.get("grain", 0.0) or 0.0)
    t = float(data.thickness)
    t_splice = t if options.splice_thickness is None else float(options.splice_thickness)
    parts = []
    for i, pid in enumerate(data.plate_ids):
        flat = np.asarray(data.flat[i], dtype=float)
        cuts = list(splits.get(int(pid), []))
        bounds = [0, *cuts, n]
        k = len(bounds) - 1
        stack = int(data.stack_position[i])
        on_plate = data.plate_creases(i)
        creases = [f"C{cid}-P{other}" for cid, other, _ in on_plate]
        kinds = {int(c["id"]): str(c.get("kind", "")) for c in data.creases}
        splice_rects = [splice_rectangle(flat, n, j, options, data.hinge_width) for j in cuts]
        for q, (a, b) in enumerate(zip(bounds, bounds[1:])):
            name = f"P{pid}" if k == 1 else f"P{pid}.{q + 1}"
            label = [name + ("" if k == 1 else f" of {k}"), f"stack {stack + 1}", *creases, "UP"]
            marks = [r for j, r in zip(cuts, splice_rects) if j in (a, b)]
            parts.append(
                Part(
                    name=name,
                    kind="plate",
                    plate=int(pid),
                    outline=sub_outline(flat, n, a, b),
                    grain=grain,
                    score=_rulings_between(flat, n, a, b),
                    marks=marks,
                    label=label,
                    thickness=t,
                    creases=_part_creases(flat, n, a, b, on_plate, kinds),
                )
            )
        for q, rect in enumerate(splice_rects):
            for face in ("U", "D"):
                name = f"S{pid}.{q + 1}{face}"
                side = "upper" if face == "U" else "lower"
                parts.append(
                    Part(
                        name=name,
                        kind="splice",
                        plate=int(pid),
                        outline=rect,
                        grain=grain,
                        label=[name, f"P{pid}.{q + 1}/{q + 2} {side}"],
                        thickness=t_splice,
                    )
                )
    return parts, splits


def splice_bending(
    data, splits: dict, utilisation, options: WorkshopOptions, *, strength_factor: float = 1.0
) -> SpliceBending:
    """The bending check of the plates where the splice plates are glued across a cut.

    A splice plate glued to both faces bends with the plate: the three layers take the
    plate's curvature κ together and their outer fibres lie ``(t + 2 t_s) / 2`` from the
    middle, so the bending stress there is ``E κ (t + 2 t_s) / 2``, the plate's times
    ``(t + 2 t_s) / t`` (same material; the layers do not slide on each other). The plate's
    utilisation is taken at every vertex within ``splice_width / 2`` of the cut's ruling.

    Parameters
    ----------
    data : FabricationData
    splits : dict
        Plate id -> the rulings its cuts follow (:func:`make_parts`).
    utilisation : (p, 2n + 2) float
        The plates' bending utilisation at every vertex (the largest along the deployment
        path, design strengths), plates in ``data`` order.
    options : WorkshopOptions
    strength_factor : float
        Design over characteristic strength (k_mod / γ_M; 1 for characteristic strengths):
        the characteristic utilisation is ``utilisation · strength_factor``.

    Returns
    -------
    SpliceBending
        ``factor`` (t + 2 t_s) / t, ``thickness`` and ``splice_thickness`` (m), ``cuts`` (per
        cut a :class:`~compas_ccu.fabrication.plan.SpliceCutBending`), ``max_utilisation`` and
        ``max_utilisation_characteristic`` (0 without cuts) and ``exceeded``.

    Examples
    --------
    A plate at utilisation 0.5 spliced with plates of its own thickness: 0.5 · 3 = 1.5.

    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> flat = np.array([[0.0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]])
    >>> data = SimpleNamespace(thickness=0.008, segments=2, plate_ids=[0], flat=[flat])
    >>> check = splice_bending(data, {0: [1]}, np.full((1, 6), 0.5), WorkshopOptions())
    >>> check.factor, check.max_utilisation, check.exceeded
    (3.0, 1.5, True)
    """
    t = float(data.thickness)
    ts = t if options.splice_thickness is None else float(options.splice_thickness)
    factor = (t + 2.0 * ts) / t
    u = np.asarray(utilisation, dtype=float)
    n = data.segments
    cuts = []
    for i, pid in enumerate(data.plate_ids):
        flat = np.asarray(data.flat[i], dtype=float)[:, :2]
        for j in splits.get(int(pid), []):
            a, b = flat[j], flat[n + 1 + j]
            d = (b - a) / np.linalg.norm(b - a)
            off = np.abs((flat - a) @ np.array([-d[1], d[0]]))
            band = off <= 0.5 * options.splice_width + ZERO_LENGTH
            plate_u = float(u[i, band].max())
            cuts.append(
                SpliceCutBending(
                    plate=int(pid),
                    ruling=int(j),
                    plate_utilisation=plate_u,
                    utilisation=plate_u * factor,
                    utilisation_characteristic=plate_u * factor * strength_factor,
                )
            )
    worst = max((c.utilisation for c in cuts), default=0.0)
    return SpliceBending(
        factor=factor,
        thickness=t,
        splice_thickness=ts,
        cuts=tuple(cuts),
        max_utilisation=worst,
        max_utilisation_characteristic=worst * strength_factor,
        exceeded=bool(worst > 1.0),
    )
