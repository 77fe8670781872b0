"""The generations of a mechanism's plates and their placement with the default crease planes.

A plate hangs off a crease of an already placed plate, so the plates are placed generation by
generation (:func:`placement_batches`: plate 0, then the plates whose parents are placed); all
the plates of one generation are placed together (docs/architecture.md).

:class:`DefaultPlacement` is the placement of :meth:`Mechanism.place
<compas_ccu.kinematics.mechanism.Mechanism.place>` with its default strategy
(:class:`compas_ccu.kinematics.mechanism.CreasePlanes`: the fixed leading plane, best-fit planes
elsewhere): the same arithmetic in the same order, bit for bit, with the dispatch of a redeploy
cut (docs/benchmarks.md, "The fixed cost of a redeploy"):

* every index is worked out once per mechanism: evenly spaced plates and creases are read and
  written as strided slices (views), and where a plate's crease is its parent's hinge row (every
  design the builders make) the plane is fitted to the hinge row itself;
* the planes are written straight into the crease-ordered outputs (``out=``), not gathered and
  scattered per generation;
* the fitted normals are oriented, and the planarity deviations taken, once for all the creases
  at the end: a mirror image is the same for either sign of the plane's normal, bit for bit
  (negating the normal negates every product and sum of the dot product exactly);
* a fixed crease (the leading plane, local ``z = 0``) keeps the normal ``(0, 0, 1)`` and the
  origin 0, so its deviation is the same dot product as a fitted one's: ``|z|``.

* the work arrays of a placement of ``k`` states, and every view of them the placement reads
  or writes, are made once per thread (``threading.local``: two threads may place the same
  mechanism at once) and kept while they are small; a placement is then a list of NumPy calls
  planned once (:class:`_Work`), with ``out=`` everywhere, the SVD's outputs written straight
  into the (k, c, 3, 3) array whose last rows are the normals, and the dot products by NumPy's
  C ``einsum`` without its Python wrapper. The results are copied out: nothing a call returns
  is changed by the next one.

Where a crease row is not finite or an SVD fails, :meth:`DefaultPlacement.place` returns None
and the general loop places the states instead (its masked plane fit, or
``numpy.linalg.svd``'s ``LinAlgError``).
"""

from __future__ import annotations

import threading
from typing import NamedTuple

import numpy as np

from compas_ccu.kinematics.plates import boundary_rows

try:  # the gufuncs behind numpy.linalg.svd (NumPy >= 2), called without its per-call checks
    from numpy.linalg import _umath_linalg

    _SVD = (_umath_linalg.svd_f, _umath_linalg.svd_s)
except (ImportError, AttributeError):  # pragma: no cover - NumPy 1.x names them otherwise
    _SVD = None

try:  # numpy.einsum without its Python wrapper (which calls it when optimize is False)
    from numpy._core.multiarray import c_einsum as _einsum
except ImportError:  # pragma: no cover - NumPy 1.x
    try:
        from numpy.core.multiarray import c_einsum as _einsum
    except ImportError:
        _einsum = np.einsum

#: the largest placement (states x plates x vertices x 3 numbers) whose work arrays are kept
_KEPT_SIZE = 1 << 18

__all__ = ["Batch", "DefaultPlacement", "as_slice", "placement_batches"]


class Batch(NamedTuple):
    """One generation of plates placed together (the index arrays of a placement)."""

    plates: np.ndarray  # (g,) the plates
    parents: np.ndarray  # (g,) their parents
    creases: np.ndarray  # (g,) the creases they hang on
    from_far: np.ndarray  # (g,) bool: on the parent's far boundary
    ccf: np.ndarray  # (g,) bool: folded continuation
    lengths: np.ndarray  # (g, n + 1) ruling lengths
    target: object  # the plates as a slice where they are evenly spaced, else ``plates``
    side: bool | None  # all on the parent's far (True) / near (False) boundary, None: mixed
    flip: bool | None  # all folded continuations (True) / mirror partners (False), None: mixed
    scale: np.ndarray  # (1, g, n + 1, 1) the ruling lengths, broadcast over states and xyz


def as_slice(indices: np.ndarray):
    """``indices`` (g,) int as a slice where they are evenly spaced and increasing (a view
    instead of a copy when read, no scatter when written), else the array itself.

    Examples
    --------
    >>> import numpy as np
    >>> as_slice(np.array([1, 5, 9])), as_slice(np.array([2])), as_slice(np.array([0, 0]))
    (slice(1, 10, 4), slice(2, 3, 1), array([0, 0]))
    """
    steps = np.diff(indices)
    if len(indices) and (len(indices) == 1 or (steps[0] > 0 and (steps == steps[0]).all())):
        step = int(steps[0]) if len(indices) > 1 else 1
        return slice(int(indices[0]), int(indices[-1]) + 1, step)
    return indices


def placement_batches(plates: list, creases: list):
    """The generations of plates (a list of (g,) int) and, per generation, its :class:`Batch`.

    Parameters
    ----------
    plates : list of PlateLink
        Plate 0 is the leading plate; every other plate comes after its parent.
    creases : list of CreaseLink
    """
    generation = np.zeros(len(plates), dtype=int)
    for i, plate in enumerate(plates[1:], start=1):
        before = [plate.parent]
        if plate.crease is not None:
            before.append(creases[plate.crease].plate_a)
        generation[i] = 1 + max(generation[b] for b in before)
    generations, batches = [np.array([0], dtype=np.intp)], []
    for g in range(1, int(generation.max(initial=0)) + 1):
        members = np.flatnonzero(generation == g)
        links = [plates[i] for i in members]
        for plate in links:
            boundary_rows(None, None, plate.boundary)  # a known boundary name
        generations.append(members)
        from_far = np.array([p.boundary == "far" for p in links], dtype=bool)
        ccf = np.array([p.relation == "ccf" for p in links], dtype=bool)
        lengths = np.stack([plates[i].intrinsics.ruling_lengths for i in members])
        batches.append(
            Batch(
                plates=members,
                parents=np.array([p.parent for p in links], dtype=np.intp),
                creases=np.array([p.crease for p in links], dtype=np.intp),
                from_far=from_far,
                ccf=ccf,
                lengths=lengths,
                target=as_slice(members),
                side=bool(from_far[0]) if (from_far == from_far[0]).all() else None,
                flip=bool(ccf[0]) if (ccf == ccf[0]).all() else None,
                scale=lengths[None, :, :, None],
            )
        )
    return generations, batches


class _Rows(NamedTuple):
    """Crease rows to fit (or, fixed, to keep) and the crease columns they are written to."""

    hinge: object  # positions in the generation's hinge rows (a slice or (h,) int; None: all)
    pick: object  # or the CreaseSelection that reads them from the placed plates (not None)
    columns: object  # the creases (a slice or (h,) int)
    fit: bool  # fitted planes (else the fixed leading plane)


class _Step(NamedTuple):
    """One generation of :class:`DefaultPlacement`."""

    batch: Batch
    parents: object  # the parents as a slice or (g,) int
    columns: object  # the generation's creases as a slice or (g,) int (their normals)
    free: _Rows | None  # the fitted creases
    fixed: _Rows | None  # the fixed creases (the leading plane)
    scale: np.ndarray  # (1, g, n + 1, 3) the ruling lengths, repeated over xyz (no broadcast)


class DefaultPlacement:
    """The placement of a mechanism with its default crease planes, planned once (module doc).

    Parameters
    ----------
    mechanism : Mechanism
    batches : list of Batch
        The generations after plate 0 (:func:`placement_batches`).
    closing : (h,) int
        The creases that attach no plate (close a loop): fitted after the last generation.
    """

    def __init__(self, mechanism, batches: list, closing: np.ndarray):
        self.mechanism = mechanism
        fixed = mechanism.crease_fixed
        self.steps = []
        for batch in batches:
            on_plate = (mechanism.crease_plate_a[batch.creases] == batch.parents).all()
            on_parent = on_plate and (mechanism.crease_far[batch.creases] == batch.from_far).all()
            parts = []
            for fit, mask in ((True, ~fixed[batch.creases]), (False, fixed[batch.creases])):
                at = np.flatnonzero(mask)
                if not len(at):
                    parts.append(None)
                    continue
                columns = batch.creases[at]
                if on_parent:
                    hinge = None if len(at) == len(mask) else as_slice(at)
                    parts.append(_Rows(hinge, None, as_slice(columns), fit))
                else:
                    pick = mechanism.crease_selection(columns)
                    parts.append(_Rows(None, pick, as_slice(columns), fit))
            parents, columns = as_slice(batch.parents), as_slice(batch.creases)
            scale = np.repeat(batch.scale, 3, axis=-1)
            self.steps.append(_Step(batch, parents, columns, *parts, scale))
        self.closing = []
        for fit, mask in ((True, ~fixed[closing]), (False, fixed[closing])):
            columns = closing[mask]
            if len(columns):
                pick = mechanism.crease_selection(columns)
                self.closing.append(_Rows(None, pick, as_slice(columns), fit))
        # the design normals that orient the fitted planes; a fixed crease keeps (0, 0, 1)
        self.orient = mechanism.crease_normals.copy()
        self.orient[fixed] = (0.0, 0.0, 1.0)
        self.fixed = np.flatnonzero(fixed)
        self.plates, self.creases = len(mechanism.plates), len(mechanism.creases)
        self.vertices = mechanism.leading.n + 1
        self._local = threading.local()

    def __getstate__(self):
        state = self.__dict__.copy()
        del state["_local"]  # the work arrays of this process's threads
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self._local = threading.local()

    def work(self, k: int) -> _Work:
        """The work arrays and the plan of a placement of ``k`` states in this thread."""
        works = getattr(self._local, "works", None)
        if works is None:
            works = self._local.works = {}
        work = works.get(k)
        if work is None:
            work = _Work(self, k)
            if k * self.plates * self.vertices * 3 <= _KEPT_SIZE:
                if len(works) >= 4:
                    works.clear()
                works[k] = work
        return work

    def place(self, lead):
        """Near and far rows (k, p, n + 1, 3), plane origins and normals (k, c, 3) and planarity
        (k, c) of every plate for the leading strip placed as ``lead`` (a LeadingPlacement), or
        None where a crease row is not finite."""
        work = self.work(lead.near.shape[0])
        work.near[:, 0], work.far[:, 0], work.rays[:, 0] = lead.near, lead.far, lead.rulings
        return work.run()

    def place_s0(self, s0: np.ndarray):
        """:meth:`place` of the leading strip at ``s0`` (k,) float, written where it is kept
        (:meth:`LeadingStrip.writer <compas_ccu.kinematics.leading.LeadingStrip.writer>`); the
        leading strip's tilts (k, n) last. None where a crease row is not finite."""
        work = self.work(len(s0))
        tilts = work.leading.place(s0)
        placed = work.run()
        return None if placed is None else (*placed, tilts)

    def _place(self, step: _Step, near, far, rays, planes) -> None:
        """Fit the planes of one generation's creases and place its plates (the general form of
        the planned calls, for indices that are not slices)."""
        batch, parents = step.batch, step.parents
        if batch.side is None:
            on_far = batch.from_far[None, :, None, None]
            hinge = np.where(on_far, far[:, parents], near[:, parents])
            ray = rays[:, parents]
            away = np.where(on_far, -ray, ray)
        else:
            hinge = (far if batch.side else near)[:, parents]  # (k, g, n + 1, 3)
            away = -rays[:, parents] if batch.side else rays[:, parents]
        for rows in (step.free, step.fixed):
            if rows is not None:
                self._planes(rows, hinge, near, far, planes)
        normal = planes[1][:, step.columns][:, :, None]  # unoriented: the same mirror image
        shift = 2.0 * _einsum("...i,...i", away, normal)[..., None] * normal  # geometry.dot
        mirrored = away - shift
        if batch.flip is None:
            mirrored = np.where(batch.ccf[None, :, None, None], -mirrored, mirrored)
        elif batch.flip:
            mirrored = -mirrored
        near[:, batch.target] = hinge
        rays[:, batch.target] = mirrored
        far[:, batch.target] = hinge + step.scale * mirrored

    def _planes(self, rows: _Rows, hinge, near, far, planes) -> None:
        """Fit (free) or keep (fixed) the planes of crease rows: their origins, normals and
        centred rows written to the crease columns of ``planes`` (the general form)."""
        origins, normals, centred = planes
        if rows.pick is not None:
            points = self.mechanism.selected_rows(rows.pick, near, far)
        else:
            points = hinge if rows.hinge is None else hinge[:, rows.hinge]
        at = rows.columns
        if not rows.fit:  # origin 0 and normal (0, 0, 1) kept: the deviation is |z|
            centred[:, at] = points
            return
        m = points.shape[-2]
        origin = np.add.reduce(points, axis=-2)
        origin /= m
        part = points - origin[..., None, :]
        origins[:, at], centred[:, at] = origin, part
        if _SVD is None:  # NumPy 1.x
            normals[:, at] = np.linalg.svd(part, full_matrices=m < 3)[2][..., -1, :]
        else:  # numpy.linalg.svd's gufunc: the same LAPACK call on the same rows
            normals[:, at] = _SVD[m >= 3](part, signature="d->ddd")[2][..., -1, :]


class _Work:
    """The arrays of one thread's placements of ``k`` states and the NumPy calls on their views
    that place them (:class:`DefaultPlacement`): a generation whose indices are slices is ~15
    calls with ``out=``, planned once; any other is :meth:`DefaultPlacement._place` on the
    same arrays."""

    def __init__(self, plan: DefaultPlacement, k: int):
        p, c, m = plan.plates, plan.creases, plan.vertices
        self.plan, self.k = plan, k
        self.near, self.far, self.rays = (np.empty((k, p, m, 3)) for _ in range(3))
        self.origins = np.zeros((k, c, 3))
        # the SVDs' right singular vectors, written in place: the normals are their last rows
        self.frames = np.zeros((k, c, 3, 3))
        self.normals = self.frames[:, :, 2]
        self.normals[:, plan.fixed] = (0.0, 0.0, 1.0)
        self.centred = np.empty((k, c, m, 3))  # the crease rows less their origins
        self.towards = np.empty((k, c))
        self.flipped = np.empty((k, c, 1), dtype=bool)
        self.deviation = np.empty((k, c, m))
        self.leading = plan.mechanism.leading.writer(
            self.near[:, 0], self.rays[:, 0], self.far[:, 0]
        )
        planes = (self.origins, self.normals, self.centred)
        self.calls = []
        for step in plan.steps:
            if not self._plan_step(step):
                self.calls.append((plan._place, (step, self.near, self.far, self.rays, planes), {}))
        for rows in plan.closing:
            args = (rows, None, self.near, self.far, planes)
            self.calls.append((plan._planes, args, {}))

    def _plan_step(self, step: _Step) -> bool:
        """Plan the calls of one generation on views (False: its indices are not slices)."""
        batch, parents, calls = step.batch, step.parents, []
        k, g, m = self.k, len(batch.plates), self.near.shape[2]
        target, columns = batch.target, step.columns
        rows = [r for r in (step.free, step.fixed) if r is not None]
        views = [target, columns] + [r.columns for r in rows]
        views += [r.hinge for r in rows if r.hinge is not None]
        if any(r.pick is not None for r in rows) or not all(isinstance(v, slice) for v in views):
            return False
        near, far, rays = self.near, self.far, self.rays
        if isinstance(parents, slice) and batch.side is not None:
            hinge = (far if batch.side else near)[:, parents]
            away = rays[:, parents]
            if batch.side:
                away = np.empty((k, g, m, 3))
                calls.append((np.negative, (rays[:, parents], away), {}))
        elif g <= 8:  # one copy of each plate's row and ray (np.where's values)
            hinge, away = np.empty((k, g, m, 3)), np.empty((k, g, m, 3))
            for j, (parent, on_far) in enumerate(zip(batch.parents, batch.from_far)):
                calls.append((np.copyto, ((hinge[:, j], (far if on_far else near)[:, parent])), {}))
                ray = (rays[:, parent], away[:, j])
                calls.append((np.negative, ray, {}) if on_far else (np.copyto, ray[::-1], {}))
        else:
            return False
        for r in rows:
            points = hinge if r.hinge is None else hinge[:, r.hinge]
            if not r.fit:
                calls.append((np.copyto, (self.centred[:, r.columns], points), {}))
                continue
            calls += self._fit(points, r.columns)
        normal = self.normals[:, columns][:, :, None]  # unoriented: the same mirror image
        dots, shift = np.empty((k, g, m)), np.empty((k, g, m, 3))
        mirrored, placed = rays[:, target], far[:, target]
        calls += [
            (_einsum, ("...i,...i", away, normal), {"out": dots}),  # geometry.dot
            (np.multiply, (dots, 2.0, dots), {}),
            (np.multiply, (dots[..., None], normal, shift), {}),
            (np.copyto, (near[:, target], hinge), {}),
            (np.subtract, (away, shift, mirrored), {}),
        ]
        if batch.flip is None:
            where = batch.ccf[None, :, None, None]
            calls.append((np.negative, (mirrored, mirrored), {"where": where}))
        elif batch.flip:
            calls.append((np.negative, (mirrored, mirrored), {}))
        calls.append((np.multiply, (step.scale, mirrored, placed), {}))
        calls.append((np.add, (hinge, placed, placed), {}))
        self.calls += calls
        return True

    def _fit(self, points: np.ndarray, at: slice) -> list:
        """The calls that fit the planes of crease rows ``points`` (k, h, m, 3) to columns
        ``at``: their origins, centred rows and normals (DefaultPlacement._planes)."""
        k, h, m = points.shape[:3]
        origin, part = self.origins[:, at], self.centred[:, at]
        calls = [
            (np.add.reduce, (points, -2, None, origin), {}),
            (np.divide, (origin, m, origin), {}),
            (np.subtract, (points, origin[..., None, :], part), {}),
        ]
        if _SVD is None:  # NumPy 1.x: numpy.linalg.svd
            calls.append((_svd_normals, (part, self.normals[:, at]), {}))
        else:  # numpy.linalg.svd's gufunc, its right singular vectors written in place
            u = np.empty((k, h, m, m) if m < 3 else (k, h, m, 3))
            outputs = (u, np.empty((k, h, min(m, 3))), self.frames[:, at])
            calls.append((_SVD[m >= 3], (part, *outputs), {"signature": "d->ddd"}))
        return calls

    def run(self):
        """Run the planned calls: near, far (k, p, m, 3), origins, normals (k, c, 3) and
        planarity (k, c), copies of the work arrays; None where a crease row is not finite."""
        try:
            with np.errstate(invalid="raise"):  # an SVD that fails (numpy.linalg.svd's check)
                for call, args, keywords in self.calls:
                    call(*args, **keywords)
        except (FloatingPointError, np.linalg.LinAlgError):
            return None
        normals, deviation = self.normals, self.deviation
        _einsum("...i,...i", normals, self.plan.orient, out=self.towards)
        np.less(self.towards[..., None], 0.0, out=self.flipped)
        np.negative(normals, out=normals, where=self.flipped)
        _einsum("...ni,...i->...n", self.centred, normals, out=deviation)
        planarity = np.maximum.reduce(np.abs(deviation, out=deviation), axis=-1)
        if not np.isfinite(planarity).all():  # a crease row that is not finite
            return None
        return self.near.copy(), self.far.copy(), self.origins.copy(), normals.copy(), planarity


def _svd_normals(part: np.ndarray, normals: np.ndarray) -> None:
    """``numpy.linalg.svd``'s last right singular vectors of ``part`` written to ``normals``."""
    m = part.shape[-2]
    normals[...] = np.linalg.svd(part, full_matrices=m < 3)[2][..., -1, :]
