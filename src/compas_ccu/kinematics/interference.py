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

The events of a run of states (candidate block pairs by their boxes, those with vertices on
both sides of a quad's plane near it, then the exact tests) are
:mod:`compas_ccu.kinematics.interference_events`.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import numpy as np

from compas_ccu.kinematics.interference_events import path_events
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


class PathCertificate:
    """The interpenetration certificate of one mechanism, computed as far as it is asked.

    The scan's states are fixed once for the whole range ``[0, upto]`` (:data:`_INITIAL_STATES`
    states, each step split until no vertex moves more than :data:`STEP` of the structure's
    size), so a scan asked in parts (``certify`` to the design angle, later to the limit) tests
    the same steps as one scan of the whole range and finds the same event, bit for bit.
    Threads may share a certificate (the studio's view and checks workers, and the models of
    one geometry, :func:`compas_ccu.model.self_intersection.adopt_limits`): one scans at a time.

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
        placed = vertices_at(alphas)
        move = np.linalg.norm(np.diff(placed, axis=0), axis=-1).max(axis=(1, 2))
        splits = np.clip(np.ceil(move / (STEP * size)), 1, _MAX_STATES).astype(int)
        parts = [alphas[:1]] + [
            np.linspace(alphas[i], alphas[i + 1], s + 1)[1:] for i, s in enumerate(splits)
        ]
        self.alphas = np.concatenate(parts)  #: the scan's states, radians
        # the first states are those of the scan's ends of steps (linspace ends exactly at its
        # stop): kept, not placed again (a state is placed the same, bit for bit, in any batch)
        self._placed = placed
        self._initial = np.full(len(self.alphas), -1)
        self._initial[np.concatenate([[0], np.cumsum(splits)])] = np.arange(len(alphas))
        self._done = 0  # states 0 .. _done are clear (steps between them too)
        self._scanning = threading.Lock()  # one scan at a time: two threads may ask together
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
        with self._scanning:  # a second caller waits, then finds the scan done as far
            return self._certify(alpha)

    def _certify(self, alpha: float) -> Interference | None:
        last = len(self.alphas) - 1
        goal = min(int(np.searchsorted(self.alphas, alpha - ANGLE_TOLERANCE)), last)
        while self._result is None and self._done < goal:
            stop = min(self._done + _CHUNK, last)
            vertices = self._states(self._done, stop + 1)
            self.states += len(vertices)
            events, tol = path_events(vertices, self._n, self._excluded, self._tol)
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
        if self._result is not None or self._done >= last:
            self._placed = None  # the scan is over: no state is placed again
        return self._result

    def _states(self, start, stop):
        """The vertices of the scan's states ``start .. stop - 1``: those of the first states
        kept, the others placed in one call."""
        initial = self._initial[start:stop]
        fresh = np.flatnonzero(initial < 0)
        if not len(fresh):
            return self._placed[initial]
        placed = self._vertices_at(self.alphas[start:stop][fresh])
        if len(fresh) == len(initial):
            return placed
        vertices = np.empty((stop - start,) + placed.shape[1:])
        vertices[fresh] = placed
        kept = np.flatnonzero(initial >= 0)
        vertices[kept] = self._placed[initial[kept]]
        return vertices

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
            below, _ = path_events(np.stack([vlo, vmid]), n, excluded, tol)
            if below:
                hi, vhi, event = mid, vmid, below[0]
                continue
            above, _ = path_events(np.stack([vmid, vhi]), n, excluded, tol)
            if not above:
                return None
            lo, vlo, event = mid, vmid, above[0]
        if event is None:
            found, _ = path_events(np.stack([vlo, vhi]), n, excluded, tol)
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
