"""Work arrays kept per thread between calls, by name.

glibc maps every allocation above its mmap threshold afresh and unmaps it when freed, so a
temporary of a few MB costs its pages' first-touch faults on every call (docs/benchmarks.md).
A search that runs on every edit writes its largest temporaries (``out=``) into arrays kept
here instead: the thick plates' collision search (:mod:`compas_ccu.thickness.work_arrays`)
and the path certificate's scan (:mod:`compas_ccu.kinematics.interference_blocks`), each with
its own :class:`WorkArrays`.

:class:`WorkArrays` hands out arrays by name: one flat buffer per name and thread
(``threading.local``: two threads may search at once), grown to the largest size asked for
(by a quarter at least, so that sizes creeping up from call to call do not remap it each time)
and kept while it holds at most :data:`KEPT_SIZE` numbers (larger ones are made afresh every
call). A name's array is overwritten by the next call that asks for it, so a function that
takes one must never return it or a view of it to a caller outside its search: what leaves
the search is copied out or made afresh. Kept arrays are dropped when pickled.
"""

from __future__ import annotations

import math
import threading

import numpy as np

__all__ = ["KEPT_SIZE", "WorkArrays", "array_maker", "slot_maker", "take_into"]

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
        if buffer is None or len(buffer) < size:  # grown by a quarter at least: sizes creep up
            grown = 0 if buffer is None else min(len(buffer) * 5 // 4, 8 * KEPT_SIZE)
            buffer = kept[name] = np.empty(max(size, grown, 8), dtype=np.uint8)
        return buffer[:size].view(dtype).reshape(shape)

    def clear(self) -> None:
        """Drop this thread's kept arrays."""
        self._local.kept = {}


def array_maker(work, prefix: str):
    """``new(name, shape, dtype=float)``: the array ``prefix + name`` of ``work`` (a
    :class:`WorkArrays`) or, for ``work`` None, a new one."""
    if work is None:
        return lambda name, shape, dtype=np.float64: np.empty(shape, dtype)
    return lambda name, shape, dtype=np.float64: work.get(prefix + name, shape, dtype)


def slot_maker(work):
    """``new(name, shape)`` as :func:`array_maker`, but the arrays of ``work`` are the shared
    slots ``slot.0``, ``slot.1``, ... in the order asked for, whatever the name: for the
    temporaries of a function that calls no other user of the slots while it holds them and
    returns none of them to a caller that holds slots (their buffers are then shared with the
    other such functions, which keeps fewer arrays)."""
    if work is None:
        return lambda name, shape, dtype=np.float64: np.empty(shape, dtype)
    count = iter(range(1 << 30))
    return lambda name, shape, dtype=np.float64: work.get(f"slot.{next(count)}", shape, dtype)


def take_into(values, rows, axis, out):
    """``np.take(values, rows, axis=axis)`` written to ``out`` (C-contiguous): the rows must be
    in range (``mode="clip"``: with the default ``"raise"`` NumPy takes into a new buffer
    first, then copies it to ``out``). ``values`` should be C-contiguous too (else NumPy
    copies it first)."""
    return np.take(values, rows, axis=axis, out=out, mode="clip")
