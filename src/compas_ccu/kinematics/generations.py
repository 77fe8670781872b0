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
        # C order (the work arrays are xyz-major): the sums' and einsum's loops of the general loop
        hinge, away = np.ascontiguousarray(hinge), np.ascontiguousarray(away)
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
            points = np.ascontiguousarray(self.mechanism.selected_rows(rows.pick, near, far))
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
    that place them (:class:`DefaultPlacement`), planned once.

    The rows are kept xyz-major, (k, p, 3, n + 1), so that every elementwise call runs along a
    row, not over xyz; where every generation's indices allow it, the plates and creases are
    kept in generation order, so that a generation's rows are one contiguous block; the results
    are copied out in plate and crease order. Each call is an operation of
    :meth:`DefaultPlacement._place` on the same operands, so the same numbers, bit for bit:

    * a crease row's sum is the last of its cumulative sums (``numpy.add.reduce`` over the rows
      of a (k, g, n + 1, 3) array adds them one after the other, as ``accumulate`` does);
    * a dot product ``einsum("...i,...i", a, b)`` is ``((a0 b0 + a2 b2) + a1 b1) + 0`` (the
      order of NumPy's sum-of-products loop over three numbers, whose zero is +0; checked on
      import by :func:`_einsum_order`, else every generation takes the general form).

    Otherwise (a generation whose indices are not slices, closing creases) the arrays are in
    plate and crease order and such a generation takes :meth:`DefaultPlacement._place` (the
    general form) on transposed views of them.
    """

    def __init__(self, plan: DefaultPlacement, k: int):
        p, c, m = plan.plates, plan.creases, plan.vertices
        self.plan, self.k = plan, k
        self.plate_slot, self.crease_slot = _generation_order(plan)  # None: plate, crease order
        if self.plate_slot is None:
            self.plate_slot, self.crease_slot, self.ordered = np.arange(p), np.arange(c), False
        else:
            self.ordered = True
        self.rows = [np.empty((k, p, 3, m)) for _ in range(3)]  # near, far, rays: xyz-major
        self.near, self.far, self.rays = (a.transpose(0, 1, 3, 2) for a in self.rows)
        self.origins = np.zeros((k, c, 3))
        # the SVDs' right singular vectors, written in place: the normals are their last rows
        self.frames = np.zeros((k, c, 3, 3))
        self.normals = self.frames[:, :, 2]
        self.normals[:, self.crease_slot[plan.fixed]] = (0.0, 0.0, 1.0)
        self.orient = plan.orient[np.argsort(self.crease_slot)]
        self.centred_rows = np.empty((k, c, 3, m))  # the crease rows less their origins
        self.centred = self.centred_rows.transpose(0, 1, 3, 2)
        self.towards = np.empty((k, c))
        self.flipped = np.empty((k, c, 1), dtype=bool)
        self.products = np.empty((k, 3, c, m))
        self.deviation = np.empty((k, c, m))
        self.leading = plan.mechanism.leading.writer(
            self.near[:, 0], self.rays[:, 0], self.far[:, 0]
        )
        planes = (self.origins, self.normals, self.centred)
        self.calls = []
        for step in plan.steps:
            if not (_EINSUM_ORDER and self._plan_step(step)):
                args = (step, self.near, self.far, self.rays, planes)
                self.calls.append((plan._place, args, {}))
        for rows in plan.closing:
            args = (rows, None, self.near, self.far, planes)
            self.calls.append((plan._planes, args, {}))

    def _plan_step(self, step: _Step) -> bool:
        """Plan the calls of one generation on views (False: its indices are not slices)."""
        batch, calls = step.batch, []
        k, g, m = self.k, len(batch.plates), self.plan.vertices
        found = _slices(step, self.plate_slot, self.crease_slot)
        if found is None:
            return False
        parents, target, columns, rows = found
        near, far, rays = self.rows
        if not _plannable(step, found):
            return False
        negated = isinstance(parents, slice) and batch.side  # away = -rays[:, parents]
        if isinstance(parents, slice) and batch.side is not None:
            hinge, away = (far if batch.side else near)[:, parents], rays[:, parents]
        else:  # one copy of each plate's row and ray (np.where's values)
            hinge, away = np.empty((k, g, 3, m)), np.empty((k, g, 3, m))
            parents = np.arange(len(self.plate_slot))[parents]
            for j, (parent, on_far) in enumerate(zip(parents, batch.from_far)):
                calls.append((np.copyto, ((hinge[:, j], (far if on_far else near)[:, parent])), {}))
                ray = (rays[:, parent], away[:, j])
                calls.append((np.negative, ray, {}) if on_far else (np.copyto, ray[::-1], {}))
        for r, at in rows:
            points = hinge if r.hinge is None else hinge[:, r.hinge]
            if not r.fit:
                calls.append((np.copyto, (self.centred_rows[:, at], points), {}))
                continue
            calls += self._fit(points, at)
        mirrored, placed = rays[:, target], far[:, target]
        calls += self._mirror(away, self.normals[:, columns][..., None], mirrored, negated)
        calls.append((np.copyto, (near[:, target], hinge), {}))
        if batch.flip is None:
            where = batch.ccf[None, :, None, None]
            calls.append((np.negative, (mirrored, mirrored), {"where": where}))
        elif batch.flip:
            calls.append((np.negative, (mirrored, mirrored), {}))
        scale = np.ascontiguousarray(step.scale.transpose(0, 1, 3, 2))
        calls.append((np.multiply, (scale, mirrored, placed), {}))
        calls.append((np.add, (hinge, placed, placed), {}))
        self.calls += calls
        return True

    @staticmethod
    def _mirror(rays: np.ndarray, normal: np.ndarray, mirrored: np.ndarray, negated: bool):
        """The calls that write ``away - 2 dot(away, normal) normal`` to ``mirrored`` (k, g, 3,
        m), ``normal`` (k, g, 3, 1): ``away`` is ``rays`` or, ``negated``, ``-rays``.

        The dot product in einsum's order, ``d = ((a0 n0 + a2 n2) + a1 n1) + 0``. Of negated
        rays ``r`` it is ``0 - ((r0 n0 + r2 n2) + r1 n1)`` and the mirror image
        ``(-2 d) n - r``: the same numbers, signed zeros included (IEEE rounding is symmetric
        and ``x - y`` is ``x + (-y)``), without the negation."""
        k, g, _, m = rays.shape
        products = np.empty((k, 3, g, m))  # xyz-major: each component's rows one block
        dots, shift = np.empty((k, g, m)), np.empty((k, g, 3, m))
        calls = [
            (np.multiply, (rays, normal, products.transpose(0, 2, 1, 3)), {}),
            (np.add, (products[:, 0], products[:, 2], dots), {}),
            (np.add, (dots, products[:, 1], dots), {}),
        ]
        if negated:
            return calls + [
                (np.subtract, (0.0, dots, dots), {}),
                (np.multiply, (dots, -2.0, dots), {}),
                (np.multiply, (dots[:, :, None], normal, shift), {}),
                (np.subtract, (shift, rays, mirrored), {}),
            ]
        return calls + [
            (np.add, (dots, 0.0, dots), {}),
            (np.multiply, (dots, 2.0, dots), {}),
            (np.multiply, (dots[:, :, None], normal, shift), {}),
            (np.subtract, (rays, shift, mirrored), {}),
        ]

    def _fit(self, points: np.ndarray, at: slice) -> list:
        """The calls that fit the planes of crease rows ``points`` (k, h, 3, m) to columns
        ``at``: their origins, centred rows and normals (DefaultPlacement._planes)."""
        k, h, _, m = points.shape
        origin, part = self.origins[:, at], self.centred_rows[:, at]
        sums = np.empty((k, h, 3, m))
        calls = [
            (np.add.accumulate, (points, -1, None, sums), {}),
            (np.divide, (sums[..., -1], m, origin), {}),
            (np.subtract, (points, origin[..., None], part), {}),
        ]
        part = part.transpose(0, 1, 3, 2)  # (k, h, m, 3): the SVD copies it to its own order
        if _SVD is None:  # NumPy 1.x: numpy.linalg.svd
            calls.append((_svd_normals, (part, self.normals[:, at]), {}))
        else:  # numpy.linalg.svd's gufunc, its right singular vectors written in place
            u = np.empty((k, h, m, m) if m < 3 else (k, h, m, 3))
            outputs = (u, np.empty((k, h, min(m, 3))), self.frames[:, at])
            calls.append((_SVD[m >= 3], (part, *outputs), {}))  # its float64 loop
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
        normals, deviation, products = self.normals, self.deviation, self.products
        _einsum("...i,...i", normals, self.orient, out=self.towards)
        np.less(self.towards[..., None], 0.0, out=self.flipped)
        np.negative(normals, out=normals, where=self.flipped)
        # the dot products in einsum's order, each component's rows one block
        np.multiply(self.centred_rows, normals[..., None], out=products.transpose(0, 2, 1, 3))
        np.add(products[:, 0], products[:, 2], out=deviation)
        np.add(deviation, products[:, 1], out=deviation)
        planarity = np.maximum.reduce(np.abs(deviation, out=deviation), axis=-1)
        if (
            not np.maximum.reduce(planarity, axis=None, initial=0.0) < np.inf
        ):  # a row not finite (NaN, inf)
            return None
        if not self.ordered:
            near, far = self.near.copy(), self.far.copy()
            return near, far, self.origins.copy(), normals.copy(), planarity
        plates, creases = self.plate_slot, self.crease_slot  # to plate and crease order
        near, far = np.take(self.near, plates, axis=1), np.take(self.far, plates, axis=1)
        origins, normals = np.take(self.origins, creases, axis=1), np.take(normals, creases, 1)
        return near, far, origins, normals, np.take(planarity, creases, axis=1)


def _generation_order(plan: DefaultPlacement):
    """The slots (p,) and (c,) int of the plates and creases in generation order where every
    generation's parents, plates, creases and crease rows are then slices (or, for up to 8
    plates, the parents any indices) and no crease closes a loop; else None, None."""
    mechanism = plan.mechanism
    plates = np.concatenate(mechanism.generations)
    creases = np.concatenate([step.batch.creases for step in plan.steps] + [np.zeros(0, int)])
    if plan.closing or len(creases) != plan.creases:
        return None, None
    if not _EINSUM_ORDER or not np.array_equal(np.sort(creases), np.arange(plan.creases)):
        return None, None
    plate_slot, crease_slot = np.argsort(plates), np.argsort(creases)
    for step in plan.steps:
        if not _plannable(step, _slices(step, plate_slot, crease_slot)):
            return None, None
    return plate_slot, crease_slot


def _plannable(step: _Step, found) -> bool:
    """Whether :class:`_Work` plans a generation's calls on views (``found``: its
    :func:`_slices`): its parents' rows are a slice on one side, or there are at most 8."""
    if found is None:
        return False
    return (isinstance(found[0], slice) and step.batch.side is not None) or len(found[0]) <= 8


def _slices(step: _Step, plate_slot: np.ndarray, crease_slot: np.ndarray):
    """A generation's parents (a slice, else (g,) int), plates and creases (slices) and crease
    rows (each with its crease columns, a slice) at the slots of its plates and creases; None
    where the plates, creases or rows are not slices or a crease row is picked."""
    batch = step.batch
    rows = [r for r in (step.free, step.fixed) if r is not None]
    if any(r.pick is not None or isinstance(r.hinge, np.ndarray) for r in rows):
        return None
    every = np.arange(len(crease_slot))
    target = as_slice(plate_slot[batch.plates])
    columns = as_slice(crease_slot[batch.creases])
    at = [as_slice(crease_slot[every[r.columns]]) for r in rows]
    if not all(isinstance(v, slice) for v in (target, columns, *at)):
        return None
    parents = as_slice(plate_slot[batch.parents])
    if not isinstance(parents, slice):
        parents = plate_slot[batch.parents]
    return parents, target, columns, list(zip(rows, at))


def _svd_normals(part: np.ndarray, normals: np.ndarray) -> None:
    """``numpy.linalg.svd``'s last right singular vectors of ``part`` written to ``normals``."""
    m = part.shape[-2]
    normals[...] = np.linalg.svd(part, full_matrices=m < 3)[2][..., -1, :]


def _einsum_order() -> bool:
    """Whether this NumPy's ``einsum("...i,...i")`` of 3-vectors (the dot products of the
    general loop) is ``((a0 b0 + a2 b2) + a1 b1) + 0``: the sums :class:`_Work` writes out."""
    rng = np.random.default_rng(0)
    a = rng.standard_normal((4, 257, 3)) * 10.0 ** rng.integers(-8, 8, (4, 257, 3))
    a[:, :64] = np.where(rng.random((4, 64, 3)) < 0.5, -0.0, 0.0)  # signed zeros
    a[:, 64:96, 1] = -a[:, 64:96, 0]  # cancellations
    b = rng.standard_normal((4, 1, 3))
    b[0] = (0.0, 0.0, 1.0)
    b[1] = (-0.0, 0.0, -1.0)
    p = a * b
    return (
        _einsum("...i,...i", a, b).tobytes()
        == (((p[..., 0] + p[..., 2]) + p[..., 1]) + 0.0).tobytes()
    )


_EINSUM_ORDER = _einsum_order()
