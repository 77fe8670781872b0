"""The collision check of thick plates along a deployment path, and its report.

:meth:`compas_ccu.thickness.ThickModel.collisions` tests every ordered plate pair in every state
(:func:`compas_ccu.thickness.collision.plate_contacts`) and keeps, per state, the largest
penetration and the smallest clearance between plates that share no crease:
:class:`CollisionReport`, worded by :func:`collision_text`. :func:`scan_first_collision` scans and
bisects for the first state from the flat stack in which the thick plates interpenetrate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import SelfIntersectionError
from compas_ccu.thickness.axis_shift import offset_faces
from compas_ccu.thickness.collision import plate_contacts

__all__ = [
    "CollisionReport",
    "collision_text",
    "ordered_pairs",
    "path_collisions",
    "checked_collisions",
    "scan_first_collision",
    "first_contact",
]


@dataclass
class CollisionReport:
    """Interpenetration check along a deployment path.

    Attributes
    ----------
    alphas : (k,) float
        Checked reference angles, degrees.
    penetration : (k,) float
        Largest penetration depth of a face vertex into another plate, m (<= tolerance: none).
    clearance : (k,) float
        Smallest gap between plates that share no crease, m; inf where no vertex of such a pair
        lies over the other plate (there is no such pair, or they are more than the contact
        reach apart).
    crossing : (k,) bool
        A plate passes through another one.
    first : dict or None
        The first state that interpenetrates: alpha, plates, vertex, point, depth.
    closest : dict or None
        Where the smallest clearance occurs: alpha, plates, vertex, point, clearance; None if
        the clearance is inf in every state.
    tolerance : float
    clearance_pairs : int
        Plate pairs that share no crease: the pairs the clearance is measured over (0 for a
        single crease between two plates).
    """

    alphas: np.ndarray
    penetration: np.ndarray
    clearance: np.ndarray
    crossing: np.ndarray
    first: dict | None
    closest: dict | None
    tolerance: float
    clearance_pairs: int = 0

    @property
    def ok(self) -> bool:
        return self.first is None

    def summary(self) -> dict:
        """Plain data (strict JSON: no inf / NaN); :func:`collision_text` words it.

        ``min_clearance`` (m) and ``closest`` are None when no clearance was measured: no plate
        pair shares no crease (``clearance_pairs`` = 0), or no vertex of such a pair lies over
        the other plate anywhere on the path.
        """
        clearance = float(self.clearance.min())
        return {
            "alphas": [float(self.alphas[0]), float(self.alphas[-1]), len(self.alphas)],
            "interpenetration": not self.ok,
            "max_penetration": float(self.penetration.max()),
            "min_clearance": clearance if math.isfinite(clearance) else None,
            "clearance_pairs": int(self.clearance_pairs),
            "first": self.first,
            "closest": self.closest,
            "tolerance": self.tolerance,
        }


def collision_text(summary: dict, *, degree: str = " deg") -> str:
    """One line on a :meth:`CollisionReport.summary`: the first interpenetration or "none"."""
    first = summary["first"]
    if first is not None:
        return (
            f"plates {first['plates'][0]} and {first['plates'][1]} interpenetrate at alpha "
            f"{first['alpha']:.4g}{degree} by {first['depth'] * 1e3:.3g} mm near "
            f"{[round(v, 3) for v in first['point']]} m"
        )
    if summary["min_clearance"] is None:
        if not summary.get("clearance_pairs"):
            return "none; no plate pair to check (every pair of plates shares a crease)"
        return "none; no plate lies over another one it shares no crease with"
    closest = summary["closest"]
    where = (
        f" (plates {closest['plates'][0]}/{closest['plates'][1]} at alpha "
        f"{closest['alpha']:.3g}{degree})"
        if closest and "plates" in closest
        else ""
    )
    return f"none; min clearance {summary['min_clearance'] * 1e3:.3g} mm{where}"


def ordered_pairs(index, joined) -> tuple:
    """The plate pairs of :meth:`ThickModel.contact_pairs` (mechanism order).

    Parameters
    ----------
    index : compas_ccu.kinematics.plates.PlateIndex
    joined : set of (int, int)
        The plate pairs ``(a, b)``, ``a < b``, joined by a crease.
    """
    p = index.count
    first, second = np.divmod(np.arange(p * p), p)
    pairs = np.c_[first, second][first != second]
    rows = {}
    for ci, (a, b) in enumerate(index.crease_plates):
        on_a = np.zeros(index.vertex_count, dtype=bool)
        on_b = np.zeros(index.vertex_count, dtype=bool)
        on_a[index.crease_rows(ci)[0]] = True
        on_b[index.crease_rows(ci)[1]] = True
        # vertices of b on the hinge with a, and of a on the hinge with b (both faces)
        rows[(a, b)] = np.concatenate([on_b, on_b])
        rows[(b, a)] = np.concatenate([on_a, on_a])
    joined = [a * p + b for a, b in joined]
    neighbours = np.isin(np.minimum(*pairs.T) * p + np.maximum(*pairs.T), joined)
    return pairs, rows, neighbours


def _contacts(thick, alphas, method: str, smallest):
    """:func:`compas_ccu.thickness.collision.plate_contacts` of ``thick`` at ``alphas``
    (degrees): the placed faces (k, p, 2, 2n + 2, 3), the pairs and ``depth, clear,
    crossing, where`` (k, P)."""
    st = thick.place(alphas)
    mid_near, mid_far = thick.corrected_boundaries(st)
    faces = offset_faces(mid_near, mid_far, st.offsets, thick.thickness)  # thick.faces_local(st)
    pairs, rows, _ = thick.contact_pairs()
    found = plate_contacts(
        mid_near,
        mid_far,
        st.offsets,
        faces,
        thick.thickness,
        pairs=pairs,
        hinged=rows,
        method=method,
        smallest=smallest,
    )
    return faces, pairs, found


def _located(thick, alphas, faces, pairs, where, k, q, what, value) -> dict:
    """The record of pair ``q`` in state ``k``: alpha, plates (ids), vertex, point (world)."""
    a, b = (int(x) for x in pairs[q])
    index = thick.model.plates
    v = int(where[k, q])
    point = thick.model.to_world(faces[k, b].reshape(-1, 3)[v][None])[0]
    return {
        "alpha": float(alphas[k]),
        "plates": [index.output_id(a), index.output_id(b)],
        "vertex": v,
        "point": point.tolist(),
        what: float(value),
    }


def _first(thick, alphas, faces, pairs, found, tolerance) -> dict | None:
    """The first pair of the first state in which two plates interpenetrate (deeper than
    ``tolerance``) or cross, or None."""
    depth, _, crossing, where = found
    bad = (depth > tolerance) | crossing
    if not bad.any():
        return None
    k = int(np.flatnonzero(bad.any(axis=1))[0])
    q = int(np.flatnonzero(bad[k])[0])
    first = _located(thick, alphas, faces, pairs, where, k, q, "depth", depth[k, q])
    first["crossing"] = bool(crossing[k, q])
    return first


def path_collisions(thick, alphas, tolerance: float, method: str) -> CollisionReport:
    """The :class:`CollisionReport` of ``thick`` (a ThickModel) at reference angles ``alphas``
    (degrees; :meth:`ThickModel.collisions`)."""
    alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
    neighbours = thick.contact_pairs()[2]
    faces, pairs, found = _contacts(thick, alphas, method, ~neighbours)
    depth, clear, crossing, where = found
    penetration = np.maximum(depth.max(axis=1), 0.0)
    others = clear[:, ~neighbours] if (~neighbours).any() else np.full((len(alphas), 1), np.inf)
    clearance = others.min(axis=1)
    first = _first(thick, alphas, faces, pairs, found, tolerance)
    closest = None
    if np.isfinite(clearance).any():
        masked = np.where(neighbours[None], np.inf, clear)
        k, q = np.unravel_index(np.argmin(masked), masked.shape)
        closest = _located(
            thick, alphas, faces, pairs, where, int(k), int(q), "clearance", masked[k, q]
        )
    return CollisionReport(
        alphas,
        penetration,
        clearance,
        crossing.any(axis=1),
        first,
        closest,
        tolerance,
        clearance_pairs=int((~neighbours).sum()) // 2,
    )


def first_contact(thick, alphas, tolerance: float = 1e-6, method: str = "cells") -> dict | None:
    """The ``first`` of :func:`path_collisions` (the first state in which the thick plates
    interpenetrate or cross, and where), the same bit for bit, without the clearances: the
    candidate search looks only up to half the thickness over a cell, where every penetration
    and crossing lies (:mod:`compas_ccu.thickness.report_pairs`, with no pair whose clearance
    counts)."""
    alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
    none = np.zeros(len(thick.contact_pairs()[0]), dtype=bool)
    faces, pairs, found = _contacts(thick, alphas, method, none)
    return _first(thick, alphas, faces, pairs, found, tolerance)


def checked_collisions(thick, alphas=None, **options) -> CollisionReport:
    """:meth:`ThickModel.collisions`, raising :class:`SelfIntersectionError` on
    interpenetration (:meth:`ThickModel.check_collisions`)."""
    report = thick.collisions(alphas, **options)
    if report.first is not None:
        f = report.first
        how = (
            "pass through each other"
            if f.get("crossing")
            else (f"interpenetrate by {f['depth'] * 1000:.3g} mm")
        )
        raise SelfIntersectionError(
            f"thick plates {f['plates'][0]} and {f['plates'][1]} {how} at alpha = "
            f"{f['alpha']:.6g} deg, near {np.round(f['point'], 4).tolist()} m "
            f"(thickness {thick.thickness * 1000:.4g} mm)",
            alpha=f["alpha"],
            crease=None,
        )
    return report


def scan_first_collision(thick, upto, states: int, bisections: int) -> tuple:
    """The scan and the bisections of :meth:`ThickModel.first_collision`."""
    if upto is None:
        upto = min(thick.model.alpha_limit, thick.model.collision_free_alpha)
    alphas = np.linspace(0.0, float(upto), states)
    first = first_contact(thick, alphas)
    if first is None:
        return float(upto), None
    k = int(np.searchsorted(alphas, first["alpha"]))
    lo, hi = (alphas[k - 1] if k > 0 else 0.0), first["alpha"]
    for _ in range(bisections if k > 0 else 0):
        mid = 0.5 * (lo + hi)
        hit = first_contact(thick, [mid])
        if hit is None:
            lo = mid
        else:
            hi, first = mid, hit
    return float(lo), first
