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

Nothing is kept between calls (every array is allocated per call): two threads may place the
same mechanism at once. Where a crease row is not finite or an SVD fails,
:meth:`DefaultPlacement.place` returns None and the general loop places the states instead (its
masked plane fit, or ``numpy.linalg.svd``'s ``LinAlgError``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.geometry import dot
from compas_ccu.kinematics.plates import boundary_rows

try:  # the gufuncs behind numpy.linalg.svd (NumPy >= 2), called without its per-call checks
    from numpy.linalg import _umath_linalg

    _SVD = (_umath_linalg.svd_f, _umath_linalg.svd_s)
except (ImportError, AttributeError):  # pragma: no cover - NumPy 1.x names them otherwise
    _SVD = None

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

    def place(self, lead):
        """Near and far rows (k, p, n + 1, 3), plane origins and normals (k, c, 3) and planarity
        (k, c) of every plate for the leading strip placed as ``lead`` (a LeadingPlacement), or
        None where a crease row is not finite."""
        k, m = lead.near.shape[0], lead.near.shape[1]
        p, c = self.plates, self.creases
        near = np.empty((k, p, m, 3))
        far = np.empty((k, p, m, 3))
        rays = np.empty((k, p, m, 3))  # unit ruling directions near -> far (Mechanism.place)
        near[:, 0], far[:, 0], rays[:, 0] = lead.near, lead.far, lead.rulings
        origins = np.zeros((k, c, 3))
        normals = np.empty((k, c, 3))
        centred = np.empty((k, c, m, 3))  # the crease rows less their origins
        if len(self.fixed):
            normals[:, self.fixed] = (0.0, 0.0, 1.0)
        planes = (origins, normals, centred)
        try:
            with np.errstate(invalid="raise"):  # an SVD that fails (numpy.linalg.svd's check)
                for step in self.steps:
                    self._place(step, near, far, rays, planes)
                for rows in self.closing:
                    self._planes(rows, None, near, far, planes)
        except (FloatingPointError, np.linalg.LinAlgError):
            return None
        if not np.isfinite(centred).all():  # every crease row, checked once
            return None
        towards = dot(normals, self.orient)
        np.negative(normals, out=normals, where=(towards < 0.0)[..., None])
        deviation = np.abs(np.einsum("...ni,...i->...n", centred, normals))
        return near, far, origins, normals, np.maximum.reduce(deviation, axis=-1)

    def _place(self, step: _Step, near, far, rays, planes) -> None:
        """Fit the planes of one generation's creases and place its plates."""
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
        shift = 2.0 * np.einsum("...i,...i", away, normal)[..., None] * normal  # geometry.dot
        target = batch.target
        near[:, target] = hinge
        if isinstance(target, slice) and batch.flip is False:  # written where it is kept
            mirrored = rays[:, target]
            np.subtract(away, shift, out=mirrored)
            placed = far[:, target]
            np.multiply(step.scale, mirrored, out=placed)
            np.add(hinge, placed, out=placed)
            return
        mirrored = away - shift
        if batch.flip is None:
            mirrored = np.where(batch.ccf[None, :, None, None], -mirrored, mirrored)
        elif batch.flip:
            mirrored = -mirrored
        rays[:, target] = mirrored
        far[:, target] = hinge + step.scale * mirrored

    def _planes(self, rows: _Rows, hinge, near, far, planes) -> None:
        """Fit (free) or keep (fixed) the planes of crease rows: their origins, normals and
        centred rows written to the crease columns of ``planes``."""
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
        if isinstance(at, slice):
            origin = origins[:, at]
            np.add.reduce(points, axis=-2, out=origin)
            origin /= m
            part = centred[:, at]
            np.subtract(points, origin[..., None, :], out=part)
        else:
            origin = np.add.reduce(points, axis=-2)
            origin /= m
            part = points - origin[..., None, :]
            origins[:, at], centred[:, at] = origin, part
        if _SVD is None:  # NumPy 1.x
            normals[:, at] = np.linalg.svd(part, full_matrices=m < 3)[2][..., -1, :]
        else:  # numpy.linalg.svd's gufunc: the same LAPACK call on the same rows
            normals[:, at] = _SVD[m >= 3](part, signature="d->ddd")[2][..., -1, :]
