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

from compas_ccu.geometry import coordinate_cross, coordinate_dot, coordinate_unit
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
    """:func:`compas_ccu.geometry.coordinate_dot` of ``u``, ``v`` (3, ...) written to ``out``
    (``term``: an array of the shape of ``out``)."""
    return coordinate_dot(u, v, out=out, term=term)


def cross_into(u, v, out, one, two):
    """:func:`compas_ccu.geometry.coordinate_cross` of ``u``, ``v`` written to ``out`` (3,
    ...) (``one``, ``two``: arrays of the shape of ``out[0]``)."""
    return coordinate_cross(u, v, out=out, one=one, two=two)


def unit_into(v, size, term):
    """``v`` (3, ...) made :func:`compas_ccu.geometry.coordinate_unit` in place (``size``,
    ``term``: arrays of the shape of ``v[0]``)."""
    return coordinate_unit(v, in_place=True, size=size, term=term)
