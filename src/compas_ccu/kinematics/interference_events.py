"""The events of the interpenetration certificate in a run of placed states
(:class:`compas_ccu.kinematics.interference.PathCertificate`, whose docstring defines them):
crossings in a state and pass-throughs between neighbouring states.

The quads of every plate are grouped in blocks of :data:`BLOCK` and the vertices in blocks of
``BLOCK + 1`` rulings; a quad block and a vertex block of another plate are a candidate pair
in a step when their boxes over the step, widened by the touch tolerance and the step's largest
displacement, overlap. An event needs, for one quad, vertices of the block strictly on both
sides of its plane (in the state after the step for a crossing, one vertex in each state for a
pass-through) and a crossing point or vertex within the quad's circumradius and the step's
reach of its centre: the candidates without (almost all of them) hold no event and are left out
(:func:`compas_ccu.kinematics.interference_blocks.sided_blocks`: a bound of the heights by the
block's box first, then the heights of the pairs it keeps). The exact tests run on the others,
in the batches and the order of all candidates, with the edge planes of every quad computed
once, so the events are those of the exact tests on every candidate, bit for bit
(tests/test_kinematics_interference.py, tests/test_kinematics_interference_blocks.py).

The boxes of the blocks and the steps' displacements are written (``out=``) into the work
arrays kept per thread by :mod:`compas_ccu.kinematics.interference_blocks` (its
``work_arrays``), as its scan's are: read by this call only, never returned.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from compas_ccu.kinematics.interference_blocks import sided_blocks, work_arrays
from compas_ccu.kinematics.plates import plate_quads
from compas_ccu.work_arrays import array_maker, take_into

__all__ = ["BLOCK", "path_events"]


def _quads(vertices, n):
    """The quads of (k, p, 2n + 2, 3) plate vertices: corners (k, p, n, 4, 3), unit normals
    (k, p, n, 3), plane offsets (k, p, n), centres (k, p, n, 3) and squared circumradii
    (k, p, n) (the planes of their edges: :func:`_edge_planes`, for the quads that need them).
    The corners run counter-clockwise about the normal (the normal is the cross product of the
    diagonals)."""
    corners = vertices[:, :, plate_quads(n)]
    normal = np.cross(
        corners[..., 2, :] - corners[..., 0, :], corners[..., 3, :] - corners[..., 1, :]
    )
    length = np.linalg.norm(normal, axis=-1, keepdims=True)
    normal = normal / np.where(length > 0.0, length, 1.0)
    offset = np.einsum("...i,...i->...", normal, corners[..., 0, :])
    centre = corners.mean(axis=-2)
    radius2 = ((corners - centre[..., None, :]) ** 2).sum(axis=-1).max(axis=-1)
    return corners, normal, offset, centre, radius2


#: Quads (and rulings) per block of the candidate search.
BLOCK = 8

#: Candidate block pairs tested in one batch (bounds the memory of a scan).
_BATCH = 4096


def _blocks(n):
    """Quad blocks (J, BLOCK) and ruling blocks (I, BLOCK + 1) of a plate of ``n`` quads (the
    last block padded with its last index), and the local edges of a ruling block (E, 2)."""
    count = -(-n // BLOCK)
    start = np.arange(count)[:, None] * BLOCK
    quads = np.minimum(start + np.arange(BLOCK), n - 1)
    rulings = np.minimum(start + np.arange(BLOCK + 1), n)
    r = BLOCK + 1  # block vertices: the near row's r, then the far row's r
    j = np.arange(BLOCK)
    edges = np.concatenate(
        [np.c_[j, j + 1], np.c_[r + j, r + j + 1], np.c_[np.arange(r), r + np.arange(r)]]
    )
    return quads, rulings, edges


def _inside(points, inward, sides, tol):
    """(N,) bool: the foot of ``points`` (N, 3) inside the quads whose edge planes are
    ``inward`` (N, 4, 3) and ``sides`` (N, 4) by more than ``tol`` (float or (N,); outside by
    less than ``-tol`` if negative)."""
    tol = np.asarray(tol, dtype=float)
    return (np.einsum("nei,ni->ne", inward, points) - sides > tol[..., None]).all(axis=-1)


def _overlap(qlo, qhi, vlo, vhi):
    """(k - 1, p, J, p, I) bool: the boxes (k - 1, p, J, 3) of the quad blocks and (k - 1, p,
    I, 3) of the vertex blocks that overlap, coordinate by coordinate."""
    overlap = tmp = None
    for i in range(3):
        ql, qh = qlo[:, :, :, None, None, i], qhi[:, :, :, None, None, i]
        vl, vh = vlo[:, None, None, :, :, i], vhi[:, None, None, :, :, i]
        if overlap is None:
            overlap = np.less_equal(ql, vh)
            tmp = np.empty_like(overlap)
        else:
            overlap &= np.less_equal(ql, vh, out=tmp)
        overlap &= np.less_equal(vl, qh, out=tmp)
    return overlap


def _step_boxes(first, block, new, name):
    """Bounding boxes (lo, hi) (k - 1, p, J, 3) over each step (both states) of the blocks
    ``block`` (J, b) of points ``first`` (m, ..., k, p, 3): the point axis first, so that the
    extremes run over whole slabs. Every bound is one of the points' coordinates (min and max
    are exact: the same whatever the order). ``new(name, shape)``: the arrays written."""
    if not first.flags.c_contiguous:  # np.take would copy it afresh
        kept = new(name + ".points", first.shape)
        np.copyto(kept, first)
        first = kept
    points = take_into(first, block.T, 0, new(name, block.T.shape + first.shape[1:]))
    axes = (0,) + tuple(range(2, points.ndim - 3))  # the block's points (and their corners)
    lo, hi = np.minimum.reduce(points, axis=axes), np.maximum.reduce(points, axis=axes)
    lo = np.minimum(lo[:, :-1], lo[:, 1:])  # (J, k - 1, p, 3)
    hi = np.maximum(hi[:, :-1], hi[:, 1:])
    return np.moveaxis(lo, 0, 2), np.moveaxis(hi, 0, 2)


def path_events(vertices, n, excluded, tol):
    """Events in states (k, p, 2n + 2, 3): crossings in states ``1 .. k - 1`` and
    pass-throughs between neighbouring states, earliest first.

    Returns
    -------
    events : list of (int, str, int, int, (3,) float)
        ``(state, kind, a, b, point)``: plates ``a`` and ``b`` meet at or before ``state``.
    tolerance : float
        The largest touch tolerance used (m): ``tol``, or twice a quad's own non-planarity.
    """
    k, p = vertices.shape[:2]
    if k < 2:
        return [], tol
    new = array_maker(work_arrays, "events.")  # kept: read by this call only (module docstring)
    corners, normal, offset, centre, radius2 = _quads(vertices, n)
    # touching is within the tolerance or the quads' own planarity (radial and inclined
    # layouts mirror across fitted planes: their quads are planar to a few 1e-6 of the size)
    planarity = np.abs(np.einsum("...ci,...i->...c", corners, normal) - offset[..., None])
    touch = np.maximum(tol, 2.0 * planarity.max(axis=-1))  # (k, p, n): per quad
    # the largest displacement of a vertex in every step (np.linalg.norm of np.diff)
    step = np.subtract(vertices[1:], vertices[:-1], out=new("step", (k - 1,) + vertices.shape[1:]))
    length = np.add.reduce(
        np.multiply(step, step, out=step), axis=-1, out=new("length", step.shape[:-1])
    )
    reach = np.sqrt(length, out=length).max(axis=(1, 2))
    quad_block, ruling_block, edges = _blocks(n)
    m = n + 1
    local = np.concatenate([ruling_block, m + ruling_block], axis=1)  # (I, 2 BLOCK + 2)
    # boxes of every block over the step from state i to i + 1, widened by the touch tolerance
    qlo, qhi = _step_boxes(np.moveaxis(corners, (2, 3), (0, 1)), quad_block, new, "quads")
    vlo, vhi = _step_boxes(np.moveaxis(vertices, 2, 0), local, new, "rulings")
    widen = (touch.max() + reach)[:, None, None, None]
    qlo, vlo = qlo - widen, vlo - widen
    overlap = _overlap(qlo, qhi, vlo, vhi)  # (k - 1, p, J, p, I)
    idx = np.arange(p)
    overlap[:, idx, :, idx] = False
    candidates = np.nonzero(overlap)
    geometry = _Geometry(vertices, corners, normal, offset, centre, radius2, touch, reach)
    live = sided_blocks(geometry, candidates, overlap.shape, quad_block, local, excluded)
    found = []
    if live.any():  # the edge planes of every quad, once for all the tests that read them
        geometry = replace(geometry, edges=_edge_planes(corners, normal))
    for start in range(0, len(live), _BATCH):  # the batches of every candidate, in order
        rows = start + np.flatnonzero(live[start : start + _BATCH])
        if len(rows):
            block = tuple(c[rows] for c in candidates)
            found += _batch_events(geometry, block, quad_block, local, edges, excluded)
    found.sort(key=lambda e: e[0])
    return found, float(touch.max())


@dataclass(frozen=True)
class _Geometry:
    """The arrays of :func:`path_events` that its candidate tests read."""

    vertices: np.ndarray  # (k, p, 2n + 2, 3)
    corners: np.ndarray  # (k, p, n, 4, 3)
    normal: np.ndarray  # (k, p, n, 3)
    offset: np.ndarray  # (k, p, n)
    centre: np.ndarray  # (k, p, n, 3)
    radius2: np.ndarray  # (k, p, n)
    touch: np.ndarray  # (k, p, n)
    reach: np.ndarray  # (k - 1,)
    edges: tuple = None  # (k, p, n, 4, 3) and (k, p, n, 4): :func:`_edge_planes` of every quad


def _heights(g, states, a, quads, b, verts):
    """Heights (N, V, BLOCK) of the vertices ``verts`` (N, V) of plates ``b`` over the planes
    of the quads ``quads`` (N, BLOCK) of plates ``a`` in ``states`` (N,), and the vertices."""
    nrm = g.normal[states[:, None], a[:, None], quads]  # (N, BLOCK, 3)
    off = g.offset[states[:, None], a[:, None], quads]  # (N, BLOCK)
    x = g.vertices[states[:, None], b[:, None], verts]  # (N, V, 3)
    return x @ nrm.swapaxes(1, 2) - off[:, None, :], x


def _edge_planes(corners, normal):
    """The planes of the four edges of quads ``corners`` (..., 4, 3) with unit normals
    ``normal`` (..., 3) that contain their normals: inward unit normals (..., 4, 3) and offsets
    (..., 4), so that ``inward . x - offset`` is the distance of the foot of ``x`` inside edge
    ``i`` (the corners run counter-clockwise about the normal). Each quad's numbers are its
    own, whichever quads are computed together."""
    inward = np.cross(normal[..., None, :], np.roll(corners, -1, axis=-2) - corners)
    size = np.linalg.norm(inward, axis=-1, keepdims=True)
    inward = inward / np.where(size > 0.0, size, 1.0)
    return inward, np.einsum("...i,...i->...", inward, corners)


def _batch_events(g, block, quad_block, local, edges, excluded):
    """The events of candidate block pairs ``block`` ((N,) state, a, J, b, I) of
    :func:`path_events`: crossings, then pass-throughs, each in the order of the candidates."""
    kq, aq, jq, bq, iq = block
    p, n = g.offset.shape[1:]
    touch, radius2, reach = g.touch.ravel(), g.radius2.ravel(), g.reach
    centre = g.centre.reshape(-1, 3)
    inward, sides = g.edges[0].reshape(-1, 4, 3), g.edges[1].reshape(-1, 4)
    quads = quad_block[jq]  # (N, BLOCK)
    verts = local[iq]  # (N, V)
    skip = excluded[aq[:, None], bq[:, None], verts]  # (N, V)
    heights = []
    for step in (0, 1):
        kk = kq + step
        h, x = _heights(g, kk, aq, quads, bq, verts)  # (N, V, BLOCK), (N, V, 3)
        t = g.touch[kk[:, None], aq[:, None], quads][:, None, :]  # (N, 1, BLOCK)
        heights.append((h, x, (h > t) & ~skip[..., None], (h < -t) & ~skip[..., None]))
    (h0, x0, up0, dn0), (h1, x1, up1, dn1) = heights
    found = []
    # crossings in state k + 1: an edge of b from one side of a quad's plane to the other,
    # the crossing point inside the quad
    e0, e1 = edges[:, 0], edges[:, 1]
    nn, ee, qq = np.nonzero((up1[:, e0] & dn1[:, e1]) | (dn1[:, e0] & up1[:, e1]))
    if len(nn):
        ha, hb = h1[nn, e0[ee], qq], h1[nn, e1[ee], qq]
        pa, pb = x1[nn, e0[ee]], x1[nn, e1[ee]]
        point = pa + (ha / (ha - hb))[:, None] * (pb - pa)
        at = ((kq[nn] + 1) * p + aq[nn]) * n + quads[nn, qq]  # into (k, p, n), flat
        near = ((point - centre[at]) ** 2).sum(axis=-1) <= radius2[at]
        nn, qq, point, at = nn[near], qq[near], point[near], at[near]
        hit = _inside(point, inward[at], sides[at], -touch[at])  # the closed quad
        for i in np.flatnonzero(hit):
            found.append((int(kq[nn[i]]) + 1, "crossing", int(aq[nn[i]]), int(bq[nn[i]]), point[i]))
    # pass-throughs: a vertex over a quad in both states, on both sides of it (its height
    # changes by at most its own and the quad's displacement in the step)
    step = reach[kq][:, None, None]
    flip = ((up0 & dn1) | (dn0 & up1)) & (np.abs(h1 - h0) <= 3.0 * step)
    nn, vv, qq = np.nonzero(flip)
    if len(nn):
        at0 = (kq[nn] * p + aq[nn]) * n + quads[nn, qq]  # into (k, p, n), flat
        at1 = at0 + p * n  # the same quad in the next state
        dk = reach[kq[nn]]
        x0v, x1v = x0[nn, vv], x1[nn, vv]
        near = ((x0v - centre[at0]) ** 2).sum(axis=-1) <= (np.sqrt(radius2[at0]) + dk) ** 2
        near &= ((x1v - centre[at1]) ** 2).sum(axis=-1) <= (np.sqrt(radius2[at1]) + dk) ** 2
        nn, vv, dk, x0v, x1v = nn[near], vv[near], dk[near], x0v[near], x1v[near]
        at0, at1 = at0[near], at1[near]
        # the foot may move on to the next quad within the step: inside the quad in one
        # state, and within the step's largest displacement of it in the other
        d0 = np.einsum("nei,ni->ne", inward[at0], x0v) - sides[at0]
        d1 = np.einsum("nei,ni->ne", inward[at1], x1v) - sides[at1]
        t0, t1 = touch[at0][:, None], touch[at1][:, None]
        in0, in1 = (d0 > t0).all(axis=1), (d1 > t1).all(axis=1)
        near0, near1 = (d0 > -dk[:, None]).all(axis=1), (d1 > -dk[:, None]).all(axis=1)
        inside = (in0 & near1) | (near0 & in1)
        for i in np.flatnonzero(inside):
            found.append(
                (
                    int(kq[nn[i]]) + 1,
                    "pass-through",
                    int(aq[nn[i]]),
                    int(bq[nn[i]]),
                    x1[nn[i], vv[i]],
                )
            )
    return found
