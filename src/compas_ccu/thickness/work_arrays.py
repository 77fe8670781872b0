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

import threading

import numpy as np

__all__ = ["KEPT_SIZE", "WorkArrays", "work_arrays"]

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
        """An uninitialised C-contiguous array ``shape`` of ``dtype``, kept under ``name``
        (its content is that of the last call's; never returned to a caller)."""
        dtype = np.dtype(dtype)
        shape = tuple(int(x) for x in np.atleast_1d(shape)) if np.ndim(shape) else (int(shape),)
        size = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
        if size > 8 * KEPT_SIZE:
            return np.empty(shape, dtype)
        kept = getattr(self._local, "kept", None)
        if kept is None:
            kept = self._local.kept = {}
        buffer = kept.get(name)
        if buffer is None or buffer.size < size:
            buffer = kept[name] = np.empty(max(size, 8), dtype=np.uint8)
        return buffer[:size].view(dtype).reshape(shape)

    def clear(self) -> None:
        """Drop this thread's kept arrays."""
        self._local.kept = {}


#: The work arrays of the collision search.
work_arrays = WorkArrays()
