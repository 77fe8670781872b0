"""The splice plates of thick plates: the flat stack with them, their gaps along the path.

:meth:`compas_ccu.thickness.ThickModel.splice_stack` and
:meth:`~compas_ccu.thickness.ThickModel.splice_collisions` put the splice plates
(:class:`compas_ccu.thickness.splices.Splice`) of a model's plates into its flat-folded stack
(the highest pile, :func:`~compas_ccu.thickness.splices.max_pile`) and test them against the
neighbouring plates of the stack in every state of the path
(:func:`~compas_ccu.thickness.splices.splice_gaps`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from compas_ccu.thickness.splices import (
    SpliceGaps,
    gap_summary,
    max_pile,
    slab_points,
    splice_gaps,
)

__all__ = ["SpliceStack", "stack_with_splices", "splice_path_gaps"]


@dataclass(frozen=True)
class SpliceStack:
    """The flat-folded stack with splice plates (:meth:`ThickModel.splice_stack`).

    Attributes
    ----------
    stack_height : float
        The plates' stack height plus :attr:`max_pile`, m.
    stack_height_plates : float
        The plates' own :attr:`ThickModel.stack_height`, m.
    max_pile : float
        The highest pile of splice plates over one point of the plan, m.
    pile_point : list of float or None
        Where ([x, y], cut-pattern coordinates, m); None without splice plates.
    count : int
        The number of splice plates.
    area : float
        Their footprints' area, m².
    mass : float
        Their mass (the plates' material), kg.
    """

    stack_height: float
    stack_height_plates: float
    max_pile: float
    pile_point: list | None
    count: int
    area: float
    mass: float

    def to_dict(self) -> dict:
        """Plain data (strict JSON), the fields in order (copies)."""
        return asdict(self)


def stack_with_splices(thick, splices) -> SpliceStack:
    """The flat stack of ``thick`` (a ThickModel) with ``splices``
    (:meth:`ThickModel.splice_stack`)."""
    quads = np.array([sp.footprint for sp in splices], dtype=float).reshape(-1, 4, 2)
    pile, point = max_pile(quads, [sp.thickness for sp in splices])
    plates = thick.stack_height
    return SpliceStack(
        stack_height=plates + pile,
        stack_height_plates=plates,
        max_pile=pile,
        pile_point=None if point is None else [float(v) for v in point],
        count=len(splices),
        area=float(sum(sp.area for sp in splices)),
        mass=float(sum(sp.area * sp.thickness for sp in splices) * thick.material.density),
    )


def splice_path_gaps(thick, splices, alphas, tolerance: float) -> SpliceGaps:
    """Splice plates against the neighbouring plates of the stack of ``thick`` (a ThickModel)
    at reference angles ``alphas`` (degrees; :meth:`ThickModel.splice_collisions`)."""
    if not len(splices):
        return gap_summary([], [], alphas, np.full((len(alphas), 0), np.inf), tolerance)
    st = thick.place(alphas)
    mid_near, mid_far = thick.corrected_boundaries(st)
    index = thick.model.plates
    mech = {pid: i for i, pid in enumerate(index.ids)}
    row = {pid: r for r, pid in enumerate(index.output_ids)}
    by_position = {int(k): pid for pid, k in zip(index.output_ids, thick.stack_position)}
    cut = thick.cut_patterns()
    n = index.segments
    up = np.sign(thick.place([0.0]).offsets[0, :, :, 2].mean(axis=1))  # ν to the stack top
    plates = [mech[int(sp.plate)] for sp in splices]
    neighbours = [
        by_position.get(
            thick.stack_position[row[int(sp.plate)]] + (1 if sp.face == "upper" else -1)
        )
        for sp in splices
    ]
    rows = [row[int(sp.plate)] for sp in splices]
    points = slab_points(
        splices,
        cut[rows, : n + 1],
        cut[rows, n + 1 :],
        mid_near[:, plates],
        mid_far[:, plates],
        st.offsets[:, plates],
        thick.thickness,
        up[plates],
    )
    targets = [-1 if b is None else mech[b] for b in neighbours]
    gaps = splice_gaps(points, targets, mid_near, mid_far, st.offsets, thick.thickness)
    return gap_summary(splices, neighbours, alphas, gaps, tolerance)
