"""The work arrays of the collision search, kept per thread between calls.

glibc maps every allocation above its mmap threshold afresh and unmaps it when freed, so a
temporary of a few MB costs its pages' first-touch faults on every call (docs/benchmarks.md:
~3,800 page faults per studio rise edit in the thick plates' candidate search). The largest
temporaries of :mod:`compas_ccu.thickness.candidate_search`, :mod:`compas_ccu.thickness.cells`
and :mod:`compas_ccu.thickness.box_trees` are written (``out=``) into arrays kept here instead,
as :mod:`compas_ccu.kinematics.generations` keeps the redeploy's.

:class:`WorkArrays` (:mod:`compas_ccu.work_arrays`, re-exported here with its makers) hands
out arrays by name, one flat buffer per name and thread. A name's array is overwritten by the
next call that asks for it, so a function that takes one must never return it or a view of
it: what leaves the collision search is copied out (the caller's arrays are made afresh).
"""

from __future__ import annotations

import numpy as np

from compas_ccu.work_arrays import KEPT_SIZE, WorkArrays, array_maker, slot_maker

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

#: The work arrays of the collision search.
work_arrays = WorkArrays()


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
