"""The FE deployment against the kinematic model: node deviations in % of the span.

Every FE node has an exact kinematic position at every state (every planar quad maps rigidly,
see :mod:`compas_ccu.fea.mesh`), so the deviation is measured node by node at the same material
point, in % of the span of the leading crease of the kinematic state of that step.

How the two shapes are laid over each other is explicit, :attr:`Comparison.alignment`:

* ``"none"`` — as they are, in the model's frame. Right when the FE supports follow the
  kinematic path (displacement control): both shapes share the supports' frame.
* ``"rigid"`` — the FE shape moved first by the best-fit rotation and translation onto the
  kinematic one (:func:`compas_ccu.geometry.rigid_align`), step by step. Right when
  nothing holds the structure to the model's frame (actuation: the plate ends are free).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.problem import FEError
from compas_ccu.fea.stresses import signed_bending_stress
from compas_ccu.geometry import rigid_align

__all__ = ["Comparison", "compare", "ALIGNMENTS"]

ALIGNMENTS = ("none", "rigid")


@dataclass
class Comparison:
    """An FE deployment history compared with the kinematic model.

    Attributes
    ----------
    history : DeploymentHistory
    alignment : {"none", "rigid"}
        How the FE shape was laid onto the kinematic one before measuring (module docstring).
    deviation : (k, N) float
        Distance of every FE node from its kinematic position at every step, m.
    """

    history: DeploymentHistory
    alignment: str
    deviation: np.ndarray

    def deviation_percent(self) -> np.ndarray:
        """(k, N) deviation in % of the span at that state."""
        return 100.0 * self.deviation / self.history.spans[:, None]

    def plate_table(self, step: int = -1) -> list:
        """Per plate at one step: max and mean deviation (% span), peak bending stress (MPa)."""
        h = self.history
        d = self.deviation_percent()[step]
        bend = signed_bending_stress(h.result.forces[step], thickness=h.settings.thickness)
        rows = []
        for p in range(len(h.mesh.across)):
            nodes = h.mesh.node_plate == p
            el = h.mesh.element_plate == p
            rows.append(
                {
                    "plate": int(h.model.plate_ids[p]),
                    "deviation_max_percent": float(d[nodes].max()),
                    "deviation_mean_percent": float(d[nodes].mean()),
                    "bending_max_MPa": float(np.abs(bend[el]).max() / 1e6),
                }
            )
        return rows

    def summary(self, step: int) -> dict:
        """The deviation at ``step`` (0-based) and along the path up to it, JSON-ready."""
        d = self.deviation_percent()[: step + 1]
        return {
            "alignment": self.alignment,
            "max_percent": float(d[-1].max()),
            "mean_percent": float(d[-1].mean()),
            "max_percent_along_path": float(d.max()),
            "max_m": float(self.deviation[step].max()),
            "per_step_max_percent": d.max(axis=1).tolist(),
            "per_step_mean_percent": d.mean(axis=1).tolist(),
        }


def compare(history: DeploymentHistory, *, alignment: str = "none") -> Comparison:
    """Compare ``history`` with its kinematic states, laid over each other by ``alignment``.

    Parameters
    ----------
    history : DeploymentHistory
    alignment : {"none", "rigid"}
        See the module docstring.

    Returns
    -------
    Comparison
    """
    if alignment not in ALIGNMENTS:
        raise FEError(f"alignment must be one of {ALIGNMENTS}, got {alignment!r}")
    x, kin = history.positions, history.kinematic
    if alignment == "rigid":
        deviation = np.array(
            [np.linalg.norm(rigid_align(x[k], kin[k]) - kin[k], axis=1) for k in range(len(x))]
        )
    else:
        deviation = np.linalg.norm(x - kin, axis=2)
    return Comparison(history, alignment, deviation)
