"""How the deployed structure stands under the load cases: pinned feet, springs, a tie.

During the deployment the feet (the end rulings of every plate, :attr:`ShellMesh.supports`)
follow the kinematic path. For the load cases the design's ``[supports]`` section decides:

* ``pinned`` — the feet stay where the deployment put them (translations held, free to turn);
* ``springs`` — the feet are released and held by translational springs of ``stiffness``
  (N/m per m of foot line) in every direction;
* ``tie`` — the feet at the end of every plate slide along the span (held across and
  vertically) and a tie of axial stiffness ``tie_stiffness`` (N/m per plate) joins them to
  the start feet.

A spring joins a foot to a *ground node* at the same place that follows the foot's kinematic
path for the whole analysis, so it is slack until the load cases start. The tie of a plate is a
spring along the span from each end foot to its ground node: the start feet are held, so a tie
anchored there and a spring to the ground are the same thing; the tie's ground force is counted
in the start side's reaction (the tie pulls the start feet, not the ground).

>>> import numpy as np
>>> share = foot_lengths(np.array([[0, 0, 0], [0.5, 0, 0], [1.0, 0, 0]]), [[0, 1, 2]])
>>> share.tolist()
[0.25, 0.5, 0.25]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.fea.mesh import ShellMesh
from compas_ccu.fea.problem import FEError
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["SupportModel", "support_model", "foot_lengths", "SUPPORT_TYPES"]

SUPPORT_TYPES = ("pinned", "springs")


def foot_lengths(nodes: np.ndarray, lines) -> np.ndarray:
    """(len(nodes),) the foot-line length belonging to every node of ``lines`` (half of each
    neighbouring segment; zero for nodes on no line)."""
    x = np.asarray(nodes, dtype=float)
    out = np.zeros(len(x))
    for line in lines:
        line = np.asarray(line, dtype=int)
        edge = np.linalg.norm(np.diff(x[line], axis=0), axis=1)
        out[line] += 0.5 * (np.r_[0.0, edge] + np.r_[edge, 0.0])
    return out


@dataclass
class SupportModel:
    """The supports of the load cases, as arrays an :class:`FEProblem` takes.

    Attributes
    ----------
    kind : str
        ``pinned`` or ``springs``.
    tie : bool
    side : (F,) int
        0 for a foot at the start of its plate, 1 at the end (``mesh.supports`` order).
    released : (F, 3) bool
        The feet's translations left free during the load cases.
    ground : (G,) int
        The foot every ground node stands under (an index into ``mesh.supports``).
    stiffness : (G, 3) float
        The spring from every ground node to its foot along x, y, z, N/m.
    tie_stiffness : (G, 3) float
        The part of ``stiffness`` that is the tie.
    """

    kind: str
    tie: bool
    side: np.ndarray
    released: np.ndarray
    ground: np.ndarray
    stiffness: np.ndarray
    tie_stiffness: np.ndarray

    def to_dict(self) -> dict:
        return {
            "type": self.kind,
            "tie": self.tie,
            "feet": int(len(self.side)),
            "ground_springs": int(len(self.ground)),
            "released_dofs": int(self.released.sum()),
        }


def _foot_lines(mesh: ShellMesh) -> tuple:
    """The feet's side (0 start, 1 end) and the lines of nodes along every plate's feet."""
    a = mesh.node_quad + mesh.node_uv[:, 0]
    feet = mesh.supports
    side = (a[feet] > 0.5 * mesh.segments).astype(int)
    lines = []
    for p in np.unique(mesh.node_plate[feet]):
        for s in (0, 1):
            sel = feet[(mesh.node_plate[feet] == p) & (side == s)]
            lines.append(sel[np.argsort(mesh.node_uv[sel, 1])])
    return side, lines


def support_model(
    mesh: ShellMesh,
    deployed: np.ndarray,
    *,
    kind: str = "pinned",
    stiffness: float = 1.0e7,
    tie: bool = False,
    tie_stiffness: float = 9.5e6,
    span_axis: np.ndarray = (1.0, 0.0, 0.0),
) -> SupportModel:
    """The supports of ``mesh`` for the load cases (see the module notes).

    Parameters
    ----------
    mesh : ShellMesh
    deployed : (N, 3) float
        The deployed node positions (the foot lines' lengths), m.
    kind : {"pinned", "springs"}
    stiffness : float
        Springs: N/m per m of foot line, every direction.
    tie : bool
    tie_stiffness : float
        The tie of one plate, N/m, shared among its end feet by foot length.
    span_axis : (3,) float
        The span direction: a tie needs it along a global axis (the sliding feet are free along
        it).

    Raises
    ------
    FEError
        An unknown kind, a stiffness that is not positive, or a tie along a span that is not a
        global axis.
    """
    if kind not in SUPPORT_TYPES:
        raise FEError(f"supports.type must be one of {SUPPORT_TYPES}, got {kind!r}")
    for name, value in (("stiffness", stiffness), ("tie_stiffness", tie_stiffness)):
        if not (np.isfinite(value) and value > 0.0):
            raise FEError(f"supports.{name} must be > 0, got {value!r}")
    side, lines = _foot_lines(mesh)
    feet = mesh.supports
    length = foot_lengths(deployed, lines)[feet]
    released = np.zeros((len(feet), 3), dtype=bool)
    k = np.zeros((len(feet), 3))
    k_tie = np.zeros((len(feet), 3))
    if kind == "springs":
        released[:] = True
        k += stiffness * length[:, None]
    if tie:
        axis = np.asarray(span_axis, dtype=float)
        j = int(np.argmax(np.abs(axis)))
        if abs(abs(axis[j]) - 1.0) > EXACT_RELATIVE:
            raise FEError(
                f"a tie needs the span along a global axis (the end feet slide along it); the "
                f"span runs along {np.round(axis, 6).tolist()}: set [plane] xaxis to a "
                "coordinate axis"
            )
        end = side == 1
        released[end, j] = True
        plate = mesh.node_plate[feet]
        per_plate = np.bincount(plate[end], weights=length[end], minlength=plate.max() + 1)
        share = np.where(end, length / np.maximum(per_plate[plate], np.finfo(float).tiny), 0.0)
        k_tie[:, j] = tie_stiffness * share
        k += k_tie
    ground = np.flatnonzero(np.any(k > 0.0, axis=1))
    return SupportModel(kind, bool(tie), side, released, ground, k[ground], k_tie[ground])
