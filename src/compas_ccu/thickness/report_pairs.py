"""What a collision report needs of a state: the height up to which contacts count.

:class:`compas_ccu.thickness.collision_check.CollisionReport` keeps per state only the largest
penetration, whether any pair crosses, the smallest clearance over the plate pairs that share
no crease and where the first interpenetration and the smallest clearance occur. In the
flat-folded stack every plate lies within the contact reach (0.1 m) of the ~17 plates above
and below it, and the full check (:func:`compas_ccu.thickness.collision.plate_contacts`)
measures every one of those gaps, while the report needs the smallest. So per state:

1. *Probes* (:func:`probe_bounds`). Of the candidate pairs (the broad phase's) that share no
   crease and no hinge, the :data:`PROBES` whose plates' centroids lie closest are tested by
   the brute force's exact tests (:mod:`compas_ccu.thickness.cells`) on every
   :data:`STRIDE`-th ruling of ``b`` against every cell of ``a``. Every gap they find is the
   gap of a real vertex over a real cell, so the smallest, ``U`` (0 if negative), bounds the
   state's smallest clearance from above; the reach if they find none.
2. *The search* (:func:`report_heights`). The candidate search boxes what a cell accepts up to
   the height ``t/2 + U`` instead of ``t/2 + reach`` (the module docstring of
   :mod:`compas_ccu.thickness.candidate_search` says why every vertex up to that height and
   every crossing is found). So every pair with a gap up to ``U`` (ties included) and every
   penetration and crossing is found with the same numbers as the full check; a pair whose
   smallest gap exceeds ``U`` reports a larger gap or none, which changes neither the report's
   largest penetration, its smallest clearance nor where they occur.
3. *Crossings.* The report gives the depth of the first bad pair, and a pair that crosses
   without a vertex inside has a positive gap that the smaller height may miss: a state in
   which a crossing is found is checked again in full
   (:func:`compas_ccu.thickness.collision.plate_contacts`).

In the stack the plates are flat and parallel, so the boxes of a plate's cells are a slab
about ``t + 2U`` thick, and only the plates next to it in the stack meet it (the 200-plate
vault at alpha = 0: 6,494 candidate pairs, of which those within ``U`` = 6 mm).
"""

from __future__ import annotations

import numpy as np

from compas_ccu.geometry import norm3
from compas_ccu.thickness.broad_phase import PairTable
from compas_ccu.thickness.cells import in_footprint, plane_heights
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["PROBES", "STRIDE", "probe_bounds", "report_heights"]

#: Candidate pairs per state whose gaps are probed, and the rulings of ``b`` they probe.
PROBES = 4
STRIDE = 4


def probe_bounds(cells, faces, table: PairTable, state, pair, marked, half):
    """(k,) an upper bound of every state's smallest gap over the ``marked`` pairs: the
    smallest gap found by the probes (module docstring); inf if they find none.

    Parameters
    ----------
    cells : tuple
        :func:`compas_ccu.thickness.cells.plate_cells` of (k, p, n) cells.
    faces : (k, p, 2, 2n + 2, 3) float
    table : PairTable
    state, pair : (N,) int
        Candidate pairs.
    marked : (P,) bool
        The pairs whose smallest gap counts.
    half : float
        Half the thickness, m.
    """
    k, p = faces.shape[:2]
    m = faces.shape[3] // 2
    bound = np.full(k, np.inf)
    use = marked[pair] & (table.hinge[pair] < 0)
    if not use.any():
        return bound
    state, pair = state[use], pair[use]
    a, b = table.pairs[pair, 0], table.pairs[pair, 1]
    # the plates' centroids (faces.mean(axis=2), its sums in turn, over the points in rows)
    flat = np.ascontiguousarray(np.moveaxis(faces.reshape(k, p, -1, 3), 2, 0))
    centroid = np.add.reduce(flat, axis=0) / flat.shape[0]
    probe = _closest(norm3(centroid[state, b] - centroid[state, a]), state)
    s, a, b = state[probe], a[probe], b[probe]
    rulings = np.unique(np.r_[np.arange(0, m, STRIDE), m - 1])
    columns = np.r_[rulings, m + rulings]
    points = faces[s, b][:, :, columns].reshape(len(s), -1, 3)  # (N, S, 3)
    mine = tuple(x[s, a] for x in cells[:2]) + tuple(
        (base[s, a], normal[s, a]) for base, normal in cells[2:]
    )
    lateral = in_footprint(points, mine, 0.0)
    d = plane_heights(points, mine[0], mine[1])
    gap = np.where(lateral, np.abs(d) - half, np.inf).min(axis=(1, 2))
    np.minimum.at(bound, s, gap)
    return bound


def _closest(score, state):
    """The :data:`PROBES` candidates of every state (``state`` sorted) with the smallest
    ``score`` (the first on a tie, NaN last), in any order: those of the stable sort by state,
    then score; with one state, those of a partition (the few up to the 4th smallest)."""
    if state[0] == state[-1] and len(score) > PROBES:
        kth = np.partition(score, PROBES - 1)[PROBES - 1]
        if not np.isnan(kth):
            few = np.flatnonzero(score <= kth)
            return few[np.argsort(score[few], kind="stable")[:PROBES]]
    order = np.lexsort((score, state))
    ranked = state[order]
    first = np.searchsorted(ranked, ranked, side="left")
    return order[np.arange(len(order)) - first < PROBES]


def report_heights(cells, faces, table: PairTable, state, pair, marked, half, reach):
    """(k, 1, 1, 1) the height over a cell's mid plane up to which the candidate search of
    each state looks: ``t/2 + U`` with ``U`` of :func:`probe_bounds` (between 0 and the reach;
    0 when no pair is ``marked``: no clearance counts, only the penetrations and crossings),
    widened by ``1e-9`` of itself for round-off.

    Parameters as :func:`probe_bounds`, and the contact reach ``reach`` (m).
    """
    if np.any(marked):
        bound = probe_bounds(cells, faces, table, state, pair, marked, half)
    else:  # no clearance counts: penetrations and crossings only, U = 0
        bound = np.zeros(faces.shape[0])
    height = half + np.clip(bound, 0.0, reach)
    height = np.where(np.isfinite(bound), height * (1.0 + EXACT_RELATIVE), half + reach)
    return height[:, None, None, None]
