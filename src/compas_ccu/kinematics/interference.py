"""Plates passing through each other along the path from the flat stack: the certificate.

Every state the library returns must be free of interpenetration: no two plates (zero
thickness, every pair, hinged neighbours away from their hinge) cross. A test of single states
is not enough: two nearly parallel plates — a radial ring whose last plate reaches round to its
first, two stacked plates of a wide layout — can pass through each other *whole* between two
samples, and are clear again at both. So the certificate follows the path from the flat stack
(docs/geometry.md, "Interpenetration certificate") and watches two events:

* **crossing** (in one state): an edge of one plate (a ruling or a boundary edge) passes strictly
  through a quad of another plate: the edge's ends lie on both sides of the quad's plane (by
  more than ``tolerance``) and the crossing point lies in the closed quad (within
  ``tolerance`` of it: two mirror images that straddle their mirror plane meet exactly on
  their edges). Two planar quads that intersect transversally always have such an edge.
* **pass-through** (between two neighbouring states): a vertex of one plate lies over a quad of
  another (its foot along the quad's normal inside the quad) in both states, on opposite sides
  of it (by more than ``tolerance`` in both). The plates were stacked in one order and are in the
  other: they passed through each other in between, even if neither state shows a crossing.

The scan samples the whole range ``[0, alpha_limit]`` with steps small enough that no vertex
moves more than :data:`STEP` of the structure's size, tests both events on every state and step,
and bisects the first step with an event down to :data:`ANGLE_TOLERANCE` (radians). What it
returns: the largest angle known clear (``clear``, the certificate: every state from the flat
stack to it is free of both events at the sampled and bisected states) and the first event
(``hit``, its plates, kind and point). The flat stack itself (α = 0: every plate in one plane,
touching face on face) is no crossing: nothing is strictly on either side.

Candidate pairs (a quad of one plate, a vertex or edge of another) come from a k-d tree over
the quads' centres (:class:`scipy.spatial.cKDTree`), within the quad's circumradius plus the
edge's half length plus the step's largest displacement: the work per state is linear in the
vertices away from the flat stack. A vertex that passes through a quad within one step is within
that distance of the quad's centre at the step's start, so no pass-through is lost to the
pruning; nor is a crossing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.kinematics.plates import plate_quads
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "ANGLE_TOLERANCE",
    "Interference",
    "PathCertificate",
    "STEP",
    "TOUCH_RELATIVE",
    "describe",
]

#: The largest vertex displacement between two scanned states, relative to the structure size.
STEP = 0.05

#: The bisection of the first step with an event stops when the step is below this (radians):
#: the certified angle lies within it below the first event.
ANGLE_TOLERANCE = 1e-7

#: A point within this fraction of the structure size of a plane (or of a quad's edge) is on it:
#: touching is not crossing. Where a quad is planar only to a larger distance (layouts whose
#: creases leave their planes), twice that distance is its tolerance.
TOUCH_RELATIVE = EXACT_RELATIVE

_INITIAL_STATES = 33
_CHUNK = 16
_MAX_STATES = 4096


@dataclass(frozen=True)
class Interference:
    """The first state on the path from the flat stack in which two plates cross.

    Attributes
    ----------
    clear : float
        Largest reference angle (radians) known free of interpenetration from the flat stack.
    hit : float or None
        Reference angle (radians) of the first event (``clear < hit <= clear +
        ANGLE_TOLERANCE`` after the bisection), None if the plates stay clear to ``upto``.
    plates : tuple of int or None
        The two plates (mechanism order) of the first event.
    kind : str or None
        "crossing" (an edge through a quad in one state) or "pass-through" (a vertex from one
        side of a quad to the other between two states).
    point : (3,) float or None
        Where (local coordinates): the crossing point or the vertex.
    states : int
        States placed and tested (the scan and the bisection).
    tolerance : float
        The largest touch tolerance used, m: within it of a quad's plane or edge is touching,
        not crossing (:data:`TOUCH_RELATIVE` of the size, or twice the quad's own
        non-planarity, whichever is larger).

    Examples
    --------
    The cone pair of ``examples/cone.toml`` stays clear up to its deployment limit:

    >>> import math
    >>> from compas_ccu.model import load_model
    >>> result = load_model("examples/cone.toml").interference
    >>> result.clear_to_end, result.plates, round(math.degrees(result.clear), 6)
    (True, None, 89.0625)
    """

    clear: float
    hit: float | None
    plates: tuple | None
    kind: str | None
    point: np.ndarray | None
    states: int
    tolerance: float = 0.0

    @property
    def clear_to_end(self) -> bool:
        return self.hit is None


def _quads(vertices, n):
    """The quads of (k, p, 2n + 2, 3) plate vertices: corners (k, p, n, 4, 3), unit normals
    (k, p, n, 3), plane offsets (k, p, n), centres (k, p, n, 3), squared circumradii
    (k, p, n), and the planes of their four edges that contain the normal: inward unit normals
    (k, p, n, 4, 3) and offsets (k, p, n, 4), so that ``inward . x - offset`` is the distance
    of the foot of ``x`` inside edge ``i``. The corners run counter-clockwise about the normal
    (the normal is the cross product of the diagonals)."""
    corners = vertices[:, :, plate_quads(n)]
    normal = np.cross(
        corners[..., 2, :] - corners[..., 0, :], corners[..., 3, :] - corners[..., 1, :]
    )
    length = np.linalg.norm(normal, axis=-1, keepdims=True)
    normal = normal / np.where(length > 0.0, length, 1.0)
    offset = np.einsum("...i,...i->...", normal, corners[..., 0, :])
    centre = corners.mean(axis=-2)
    radius2 = ((corners - centre[..., None, :]) ** 2).sum(axis=-1).max(axis=-1)
    inward = np.cross(normal[..., None, :], np.roll(corners, -1, axis=-2) - corners)
    size = np.linalg.norm(inward, axis=-1, keepdims=True)
    inward = inward / np.where(size > 0.0, size, 1.0)
    sides = np.einsum("...i,...i->...", inward, corners)
    return corners, normal, offset, centre, radius2, inward, sides


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


def _boxes(points, axis):
    """Bounding boxes (lo, hi) of ``points`` over ``axis`` (and the last but one axis)."""
    return points.min(axis=axis), points.max(axis=axis)


def _events(vertices, n, excluded, tol):
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
    corners, normal, offset, centre, radius2, inward, sides = _quads(vertices, n)
    # touching is within the tolerance or the quads' own planarity (radial and inclined
    # layouts mirror across fitted planes: their quads are planar to a few 1e-6 of the size)
    planarity = np.abs(np.einsum("...ci,...i->...c", corners, normal) - offset[..., None])
    touch = np.maximum(tol, 2.0 * planarity.max(axis=-1))  # (k, p, n): per quad
    # the largest displacement of a vertex in every step
    reach = np.linalg.norm(np.diff(vertices, axis=0), axis=-1).max(axis=(1, 2))
    quad_block, ruling_block, edges = _blocks(n)
    m = n + 1
    local = np.concatenate([ruling_block, m + ruling_block], axis=1)  # (I, 2 BLOCK + 2)
    # boxes of every block over the step from state i to i + 1, widened by the touch tolerance
    qc = corners[:, :, quad_block].reshape(k, p, len(quad_block), -1, 3)
    qlo, qhi = _boxes(np.concatenate([qc[:-1], qc[1:]], axis=3), axis=3)
    vc = vertices[:, :, local]
    vlo, vhi = _boxes(np.concatenate([vc[:-1], vc[1:]], axis=3), axis=3)
    widen = (touch.max() + reach)[:, None, None, None]
    qlo, vlo = qlo - widen, vlo - widen
    overlap = np.all(
        (qlo[:, :, :, None, None] <= vhi[:, None, None])
        & (vlo[:, None, None] <= qhi[:, :, :, None, None]),
        axis=-1,
    )  # (k - 1, p, J, p, I)
    idx = np.arange(p)
    overlap[:, idx, :, idx] = False
    ks, a, jb, b, ib = np.nonzero(overlap)
    found = []
    for start in range(0, len(ks), _BATCH):
        part = slice(start, start + _BATCH)
        kq, aq, jq, bq, iq = ks[part], a[part], jb[part], b[part], ib[part]
        quads = quad_block[jq]  # (N, BLOCK)
        verts = local[iq]  # (N, V)
        skip = excluded[aq[:, None], bq[:, None], verts]  # (N, V)
        heights = []
        for step in (0, 1):
            kk = kq + step
            nrm = normal[kk[:, None], aq[:, None], quads]  # (N, BLOCK, 3)
            off = offset[kk[:, None], aq[:, None], quads]  # (N, BLOCK)
            x = vertices[kk[:, None], bq[:, None], verts]  # (N, V, 3)
            h = x @ nrm.swapaxes(1, 2) - off[:, None, :]  # (N, V, BLOCK)
            t = touch[kk[:, None], aq[:, None], quads][:, None, :]  # (N, 1, BLOCK)
            heights.append((h, x, (h > t) & ~skip[..., None], (h < -t) & ~skip[..., None]))
        (h0, x0, up0, dn0), (h1, x1, up1, dn1) = heights
        # crossings in state k + 1: an edge of b from one side of a quad's plane to the other,
        # the crossing point inside the quad
        e0, e1 = edges[:, 0], edges[:, 1]
        nn, ee, qq = np.nonzero((up1[:, e0] & dn1[:, e1]) | (dn1[:, e0] & up1[:, e1]))
        if len(nn):
            ha, hb = h1[nn, e0[ee], qq], h1[nn, e1[ee], qq]
            pa, pb = x1[nn, e0[ee]], x1[nn, e1[ee]]
            point = pa + (ha / (ha - hb))[:, None] * (pb - pa)
            at = (kq[nn] + 1, aq[nn], quads[nn, qq])
            near = ((point - centre[at]) ** 2).sum(axis=-1) <= radius2[at]
            nn, qq, point = nn[near], qq[near], point[near]
            at = (kq[nn] + 1, aq[nn], quads[nn, qq])
            hit = _inside(point, inward[at], sides[at], -touch[at])  # the closed quad
            for i in np.flatnonzero(hit):
                found.append(
                    (int(kq[nn[i]]) + 1, "crossing", int(aq[nn[i]]), int(bq[nn[i]]), point[i])
                )
        # pass-throughs: a vertex over a quad in both states, on both sides of it (its height
        # changes by at most its own and the quad's displacement in the step)
        step = reach[kq][:, None, None]
        flip = ((up0 & dn1) | (dn0 & up1)) & (np.abs(h1 - h0) <= 3.0 * step)
        nn, vv, qq = np.nonzero(flip)
        if len(nn):
            at0 = (kq[nn], aq[nn], quads[nn, qq])
            at1 = (kq[nn] + 1, aq[nn], quads[nn, qq])
            dk = reach[kq[nn]]
            x0v, x1v = x0[nn, vv], x1[nn, vv]
            near = ((x0v - centre[at0]) ** 2).sum(axis=-1) <= (np.sqrt(radius2[at0]) + dk) ** 2
            near &= ((x1v - centre[at1]) ** 2).sum(axis=-1) <= (np.sqrt(radius2[at1]) + dk) ** 2
            nn, vv, qq, dk, x0v, x1v = nn[near], vv[near], qq[near], dk[near], x0v[near], x1v[near]
            at0 = (kq[nn], aq[nn], quads[nn, qq])
            at1 = (kq[nn] + 1, aq[nn], quads[nn, qq])
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
    found.sort(key=lambda e: e[0])
    return found, float(touch.max())


class PathCertificate:
    """The interpenetration certificate of one mechanism, computed as far as it is asked.

    The scan's states are fixed once for the whole range ``[0, upto]`` (:data:`_INITIAL_STATES`
    states, each step split until no vertex moves more than :data:`STEP` of the structure's
    size), so a scan asked in parts (``certify`` to the design angle, later to the limit) tests
    the same steps as one scan of the whole range and finds the same event, bit for bit.

    Parameters
    ----------
    vertices_at : callable
        ``vertices_at(alphas)`` → (k, p, 2n + 2, 3) plate vertices (near row, then far row) at
        reference angles ``alphas`` (radians), in any fixed frame.
    upto : float
        The end of the range, radians (the deployment limit).
    segments : int
        ``n``: quads per plate.
    hinges : list of (int, int, (n + 1,) int, (n + 1,) int)
        Per crease: plate a, plate b and their vertex rows on the hinge.
    size : float
        The structure's size, m: the scale of :data:`TOUCH_RELATIVE`.
    plates : int

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> model.interference.hit is None, model.interference.clear == model.mechanism.alpha_limit
    (True, True)
    """

    def __init__(self, vertices_at, *, upto, segments, hinges, size, plates):
        n = segments
        excluded = np.zeros((plates, plates, 2 * n + 2), dtype=bool)
        for a, b, rows_a, rows_b in hinges:
            excluded[a, b, rows_b] = True
            excluded[b, a, rows_a] = True
        self._vertices_at = vertices_at
        self._n, self._excluded = n, excluded
        self._tol = TOUCH_RELATIVE * size
        self.upto = float(upto)
        alphas = np.linspace(0.0, self.upto, _INITIAL_STATES)
        move = np.linalg.norm(np.diff(vertices_at(alphas), axis=0), axis=-1).max(axis=(1, 2))
        splits = np.clip(np.ceil(move / (STEP * size)), 1, _MAX_STATES).astype(int)
        parts = [alphas[:1]] + [
            np.linspace(alphas[i], alphas[i + 1], s + 1)[1:] for i, s in enumerate(splits)
        ]
        self.alphas = np.concatenate(parts)  #: the scan's states, radians
        self._done = 0  # states 0 .. _done are clear (steps between them too)
        self._result = None
        self.states = 0  #: states placed and tested so far
        self.tolerance = self._tol  #: the largest touch tolerance used so far, m

    def certify(self, alpha: float) -> Interference | None:
        """Scan the steps up to the first state at or beyond ``alpha`` (radians).

        Returns
        -------
        Interference or None
            The first event if the scan has found one (at any angle), else None: the plates
            are clear from the flat stack to at least ``alpha``.
        """
        last = len(self.alphas) - 1
        goal = min(int(np.searchsorted(self.alphas, alpha - ANGLE_TOLERANCE)), last)
        while self._result is None and self._done < goal:
            stop = min(self._done + _CHUNK, last)
            vertices = self._vertices_at(self.alphas[self._done : stop + 1])
            self.states += len(vertices)
            events, tol = _events(vertices, self._n, self._excluded, self._tol)
            self.tolerance = max(self.tolerance, tol)
            for k in sorted({e[0] for e in events}):
                k += self._done
                found = self._refine(k, vertices[k - 1 - self._done], vertices[k - self._done])
                if found is not None:
                    lo, hi, (_, kind, a, b, point) = found
                    self._result = Interference(
                        float(lo),
                        float(hi),
                        (a, b),
                        kind,
                        np.asarray(point),
                        self.states,
                        self.tolerance,
                    )
                    break
            else:
                self._done = stop
        return self._result

    def result(self) -> Interference:
        """The whole range: the first event, or clear to ``upto``."""
        found = self.certify(self.upto)
        if found is None:
            return Interference(self.upto, None, None, None, None, self.states, self.tolerance)
        return found

    def _refine(self, k, vlo, vhi):
        """Bisect the step into state ``k`` down to :data:`ANGLE_TOLERANCE`: ``(lo, hi,
        event)``, or None when neither half of a step shows the event (it came from the coarse
        step: a vertex that passed round a plate's edge, not through it)."""
        lo, hi = self.alphas[k - 1], self.alphas[k]
        n, excluded, tol = self._n, self._excluded, self._tol
        event = None
        while hi - lo > ANGLE_TOLERANCE:
            mid = 0.5 * (lo + hi)
            vmid = self._vertices_at(np.array([mid]))[0]
            self.states += 1
            below, _ = _events(np.stack([vlo, vmid]), n, excluded, tol)
            if below:
                hi, vhi, event = mid, vmid, below[0]
                continue
            above, _ = _events(np.stack([vmid, vhi]), n, excluded, tol)
            if not above:
                return None
            lo, vlo, event = mid, vmid, above[0]
        if event is None:
            found, _ = _events(np.stack([vlo, vhi]), n, excluded, tol)
            if not found:
                return None
            event = found[0]
        return lo, hi, event


def describe(result: Interference, ids) -> str:
    """One line: which plates (by ``ids``: mechanism plate → id) meet where, in degrees.

    Examples
    --------
    >>> import math
    >>> hit = Interference(
    ...     clear=math.radians(50.0), hit=math.radians(50.01), plates=(1, 2), kind="crossing",
    ...     point=None, states=12,
    ... )
    >>> for part in describe(hit, ids=[5, 6, 7]).split("; "):
    ...     print(part)
    plates 6 and 7 cross at alpha = 50.01 deg
    the largest alpha reached from the flat stack without any two plates crossing is 50 deg
    """
    a, b = (ids[i] for i in result.plates)
    how = "pass through each other" if result.kind == "pass-through" else "cross"
    return (
        f"plates {a} and {b} {how} at alpha = {math.degrees(result.hit):.6g} deg; the largest "
        f"alpha reached from the flat stack without any two plates crossing is "
        f"{math.degrees(result.clear):.6g} deg"
    )
