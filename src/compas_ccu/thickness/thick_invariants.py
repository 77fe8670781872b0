"""The invariants of thick states, and which faces each axis-shift hinge joins.

:meth:`compas_ccu.thickness.ThickModel.metrics`: the invariants of the mid-surfaces
(:meth:`compas_ccu.model.CCUModel.invariants`), the hinge gap between the facing faces' crease
edges, the offset planarity and the crease corrections (paper §5.3);
:meth:`~compas_ccu.thickness.ThickModel.pairing`: intrados or extrados, per crease.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.kinematics.mechanism import MechanismStates
from compas_ccu.kinematics.plates import stack_rows
from compas_ccu.strips.curvature import plate_curvature

__all__ = ["ThickInvariants", "thick_metrics", "hinge_pairing"]


@dataclass(frozen=True)
class ThickInvariants:
    """The invariants of ``k`` thick states (:meth:`ThickModel.metrics`), m.

    Attributes
    ----------
    isometry, quad_planarity, mirror_error : (k,) float
        Of the mid-surfaces (exact).
    hinge_gap : (k,) float
        The largest distance between the two facing faces' crease edges.
    offset_planarity : (k, c) float
        The distance of the uncorrected offset crease from its plane, per crease.
    correction : (k, c) float
        The largest correction along the rulings, per crease (paper §5.3).
    """

    isometry: np.ndarray
    quad_planarity: np.ndarray
    mirror_error: np.ndarray
    hinge_gap: np.ndarray
    offset_planarity: np.ndarray
    correction: np.ndarray


def thick_metrics(thick, st) -> ThickInvariants:
    """:meth:`ThickModel.metrics` of ``thick`` at placed states ``st``."""
    mstates = MechanismStates(
        st.near, st.far, st.hinge_origins, st.hinge_normals, st.offset_planarity, st.tilts
    )
    inv = thick.model.invariants(mstates)
    faces = thick.faces_local(st)
    index = thick.model.plates
    gaps = []
    for ci, (a, b) in enumerate(index.crease_plates):
        sa, sb = thick.sides[ci]
        rows_a, rows_b = index.crease_rows(ci)
        fa = faces[:, a, int(sa > 0), rows_a]
        fb = faces[:, b, int(sb > 0), rows_b]
        gaps.append(np.linalg.norm(fa - fb, axis=-1).max(axis=1))
    k = st.near.shape[0]
    return ThickInvariants(
        isometry=inv.isometry,
        quad_planarity=inv.quad_planarity,
        mirror_error=inv.mirror_error,
        hinge_gap=np.max(gaps, axis=0) if gaps else np.zeros(k),
        offset_planarity=st.offset_planarity,
        correction=np.abs(st.corrections).max(axis=2),
    )


def hinge_pairing(thick) -> list:
    """:meth:`ThickModel.pairing` of ``thick``."""
    st = thick.place([thick.model.alpha_design])
    kappa = plate_curvature(stack_rows(st.near, st.far)[0])
    index = thick.model.plates
    out = []
    for ci, (a, _) in enumerate(index.crease_plates):
        k = np.median(thick.sides[ci, 0] * kappa[a, index.crease_rows(ci)[0]])
        out.append("intrados" if k < 0 else ("extrados" if k > 0 else "flat"))
    return out
