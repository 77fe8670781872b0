"""What the fabrication writers need, as plain arrays: :class:`FabricationData`.

Every writer in :mod:`compas_ccu.fabrication` is a pure function of a :class:`FabricationData`;
:func:`compas_ccu.fabrication.fabrication_data` builds one from a model and its thickness.

Units: metres and degrees (the DXF writer converts to millimetres itself). Plate vertex layout
(docs/geometry.md §2, :mod:`compas_ccu.kinematics.plates`): near boundary ``0 .. n``, far boundary
``n + 1 .. 2n + 1``; quad ``j`` = ``[j, j + 1, n + 2 + j, n + 1 + j]``; ruling ``j`` joins vertex
``j`` and ``n + 1 + j``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["FabricationData"]


@dataclass
class FabricationData:
    """A design ready for the workshop.

    Attributes
    ----------
    name : str
        Design name (file stems, labels).
    alpha : float
        Design reflection angle, degrees (the state of ``deployed_mid`` and ``solids``).
    thickness : float
        Plate thickness, m.
    material : str
        Material name (labels).
    plate_ids : list of int
        Plate ``i`` of every array below has id ``plate_ids[i]``.
    faces : (p, n, 4) int
        Quads of every plate, counter-clockwise in its cut pattern.
    flat : (p, 2n + 2, 2) float
        Cut patterns, m, in the plane coordinates of the flat-folded stack seen from above
        (from the stack's top): cut every plate with this side up and stack it as drawn.
    deployed_mid : (p, 2n + 2, 3) float
        Mid-surface vertices at the design state, world coordinates, m.
    solids : (p, 2, 2n + 2, 3) float
        Lower (index 0) and upper (index 1) face vertices of every thick plate at the design
        state: the closed solid is the two faces, the crease-side and far-side strips and the
        two end caps.
    stack_solids : (p, 2, 2n + 2, 3) float
        The same solids in the flat-folded stack (alpha = 0).
    creases : list of dict
        docs/structure-json.md crease records: ``id``, ``plates`` [a, b] (plate ids), ``vertices``
        [[ia ...], [ib ...]] (vertex indices in plates a and b, same order along the crease),
        ``kind`` ("synclastic" | "anticlastic" | "ccf" | "mixed" | "straight"), and
        ``fold_angle`` (degrees, the angle between the two plates' surfaces at the design
        state, 0 = closed flat: the mean of the crease record's per-edge ``fold_angles``).
    stack_position : list of int
        Per plate: 0 for the bottom plate of the flat-folded stack, p - 1 for the top one.
    hinge_width : float
        Width of the textile hinge strips, m (centred on each crease).
    """

    name: str
    alpha: float
    thickness: float
    material: str
    plate_ids: list
    faces: np.ndarray
    flat: np.ndarray
    deployed_mid: np.ndarray
    solids: np.ndarray
    stack_solids: np.ndarray
    creases: list
    stack_position: list
    hinge_width: float = 0.05
    metadata: dict = field(default_factory=dict)

    @property
    def segments(self) -> int:
        """Crease segments ``n`` per plate."""
        return self.flat.shape[1] // 2 - 1

    def outline(self, i: int) -> np.ndarray:
        """(2n + 2, 2) closed cut outline of plate ``i`` (array index): near row, far row back."""
        n = self.segments
        order = np.r_[np.arange(n + 1), np.arange(2 * n + 1, n, -1)]
        return self.flat[i, order]

    def plate_creases(self, i: int) -> list:
        """Creases of plate ``i`` (array index): list of (crease id, other plate id, indices)."""
        pid = self.plate_ids[i]
        out = []
        for c in self.creases:
            a, b = c["plates"]
            if a == pid:
                out.append((c["id"], b, list(c["vertices"][0])))
            elif b == pid:
                out.append((c["id"], a, list(c["vertices"][1])))
        return out

    def index(self, plate_id: int) -> int:
        """Array index of a plate id."""
        return self.plate_ids.index(plate_id)
