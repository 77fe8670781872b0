"""The work arrays of the collision search, kept per thread between calls.

glibc maps every allocation above its mmap threshold afresh and unmaps it when freed, so a
temporary of a few MB costs its pages' first-touch faults on every call (docs/benchmarks.md:
~3,800 page faults per studio rise edit in the thick plates' candidate search). The largest
temporaries of :mod:`compas_ccu.thickness.candidate_search`, :mod:`compas_ccu.thickness.cells`
and :mod:`compas_ccu.thickness.box_trees` are written (``out=``) into arrays kept here instead,
as :mod:`compas_ccu.kinematics.generations` keeps the redeploy's.

:class:`WorkArrays` hands out arrays by name: one flat buffer per name and thread
(``threading.local``: two threads may search at once), grown to the largest size asked for
and kept while it holds at most :data:`KEPT_SIZE` numbers (larger ones are made afresh every
call). A name's array is overwritten by the next call that asks for it, so a function that
takes one must never return it or a view of it: what leaves the collision search is copied
out (the caller's arrays are made afresh). Kept arrays are dropped when pickled.
"""

from __future__ import annotations

import math
import threading

import numpy as np

__all__ = [
    "KEPT_SIZE",
    "WorkArrays",
    "work_arrays",
    "array_maker",
    "slot_maker",
    "dot_into",
    "cross_into",
    "unit_into",
]

#: The largest buffer (in numbers of 8 bytes) kept between calls: 4 MB.
KEPT_SIZE = 1 << 19


class WorkArrays:
    """Named work arrays of this thread, kept between calls (module docstring)."""

    def __init__(self):
        self._local = threading.local()

    def __getstate__(self):
        return {}  # the work arrays of this process's threads

    def __setstate__(self, state):
        self._local = threading.local()

    def get(self, name: str, shape, dtype=np.float64) -> np.ndarray:
        """An uninitialised C-contiguous array ``shape`` (an int or a tuple of ints) of
        ``dtype``, kept under ``name`` (its content is that of the last call's; never returned
        to a caller)."""
        shape = (shape,) if isinstance(shape, (int, np.integer)) else shape
        size = math.prod(shape) * np.dtype(dtype).itemsize
        if size > 8 * KEPT_SIZE:
            return np.empty(shape, dtype)
        try:
            kept = self._local.kept
        except AttributeError:
            kept = self._local.kept = {}
        buffer = kept.get(name)
        if buffer is None or len(buffer) < size:
            buffer = kept[name] = np.empty(max(size, 8), dtype=np.uint8)
        return buffer[:size].view(dtype).reshape(shape)

    def clear(self) -> None:
        """Drop this thread's kept arrays."""
        self._local.kept = {}


#: The work arrays of the collision search.
work_arrays = WorkArrays()


def array_maker(work, prefix: str):
    """``new(name, shape)``: the float array ``prefix + name`` of ``work`` (a
    :class:`WorkArrays`) or, for ``work`` None, a new one."""
    if work is None:
        return lambda name, shape: np.empty(shape)
    return lambda name, shape: work.get(prefix + name, shape)


def slot_maker(work):
    """``new(name, shape)`` as :func:`array_maker`, but the arrays of ``work`` are the shared
    slots ``slot.0``, ``slot.1``, ... in the order asked for, whatever the name: for the
    temporaries of a function that calls no other user of the slots while it holds them and
    returns none of them to a caller that holds slots (their buffers are then shared with the
    other such functions, which keeps fewer arrays)."""
    if work is None:
        return lambda name, shape: np.empty(shape)
    count = iter(range(1 << 30))
    return lambda name, shape: work.get(f"slot.{next(count)}", shape)


def dot_into(u, v, out, term):
    """:func:`compas_ccu.geometry.coordinate_dot` of ``u``, ``v`` (3, ...) written to ``out``,
    the same sums in the same order (``term``: an array of the shape of ``out``)."""
    np.multiply(u[0], v[0], out=out)
    out += np.multiply(u[2], v[2], out=term)
    out += np.multiply(u[1], v[1], out=term)
    return out


def cross_into(u, v, out, one, two):
    """:func:`compas_ccu.geometry.coordinate_cross` of ``u``, ``v`` written to ``out`` (3,
    ...) (``one``, ``two``: arrays of the shape of ``out[0]``)."""
    for i, j, c in ((1, 2, 0), (2, 0, 1), (0, 1, 2)):
        np.subtract(np.multiply(u[i], v[j], out=one), np.multiply(u[j], v[i], out=two), out=out[c])
    return out


def unit_into(v, size, term):
    """``v`` (3, ...) made :func:`compas_ccu.geometry.coordinate_unit` in place (``size``,
    ``term``: arrays of the shape of ``v[0]``)."""
    np.multiply(v[0], v[0], out=size)
    size += np.multiply(v[1], v[1], out=term)
    size += np.multiply(v[2], v[2], out=term)
    return np.divide(v, np.sqrt(size, out=size), out=v)
