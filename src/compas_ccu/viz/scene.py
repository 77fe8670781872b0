"""Drawable primitives of a structure: quads, crease polylines, rulings, plate outlines.

Every picture (figures, animation, viewer) draws from a :class:`Scene`, so they all show the
same thing. Plate vertex order is that of :mod:`compas_ccu.model`: near boundary ``0 .. n``, far
boundary ``n + 1 .. 2n + 1``; ruling ``j`` joins vertex ``j`` to vertex ``n + 1 + j``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.kinematics.plates import plate_rulings

__all__ = ["Scene", "scene_from_structure", "ground_offset"]


@dataclass
class Scene:
    """Geometry of one state, ready to draw.

    Attributes
    ----------
    vertices : (p, v, 3) float
        Plate vertices (``v = 2n + 2``).
    quads : (p, n, 4, 3) float
        Quad corners, counter-clockwise in the cut pattern.
    faces : (p, n, 4) int
        Quad vertex indices.
    rulings : (p, n + 1, 2, 3) float
        Ruling segments (near vertex, far vertex) of every plate.
    creases : list of dict
        ``{"id", "kind", "plates", "points": (n + 1, 3)}`` per crease (points along plate a).
    crease_alpha : list of (n + 1,) float
        Reflection angle (degrees) at the crease vertices, one array per crease.
    plate_ids : list of int
    """

    vertices: np.ndarray
    quads: np.ndarray
    faces: np.ndarray
    rulings: np.ndarray
    creases: list = field(default_factory=list)
    crease_alpha: list = field(default_factory=list)
    plate_ids: list = field(default_factory=list)

    @property
    def segments(self) -> int:
        return self.faces.shape[1]

    def subset(self, plates, creases=None) -> Scene:
        """The scene of some plates (by position) and the creases among them."""
        plates = [int(i) for i in plates]
        ids = [self.plate_ids[i] for i in plates]
        keep = [
            i
            for i, c in enumerate(self.creases)
            if (creases is None and set(c["plates"]) <= set(ids))
            or (creases is not None and c["id"] in creases)
        ]
        return Scene(
            vertices=self.vertices[plates],
            quads=self.quads[plates],
            faces=self.faces[plates],
            rulings=self.rulings[plates],
            creases=[self.creases[i] for i in keep],
            crease_alpha=[self.crease_alpha[i] for i in keep],
            plate_ids=ids,
        )

    def bounds(self) -> np.ndarray:
        """(2, 3) lower and upper corner of the bounding box."""
        pts = self.vertices.reshape(-1, 3)
        return np.array([pts.min(axis=0), pts.max(axis=0)])


def ground_offset(vertices: np.ndarray) -> np.ndarray:
    """(3,) translation that puts the lowest vertex on ``z = 0`` (presentation only)."""
    return np.array([0.0, 0.0, -float(np.min(np.asarray(vertices)[..., 2]))])


def scene_from_structure(structure, *, state: str = "deployed", ground: bool = False) -> Scene:
    """Scene of a :class:`compas_ccu.structure.Structure`.

    Parameters
    ----------
    structure : Structure
    state : {"deployed", "flat"}
        The deployed plates or the cut patterns (the flat-folded stack, z = 0).
    ground : bool
        Translate so that the lowest point stands on ``z = 0`` (the kinematics keep the crown
        of the leading crease fixed; pictures usually want the supports on the floor).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> s = load_model("examples/cone.toml").deploy()
    >>> scene = scene_from_structure(s, ground=True)
    >>> scene.quads.shape[-2:], float(scene.bounds()[0, 2])
    ((4, 3), 0.0)
    """
    if state not in ("deployed", "flat"):
        raise OptionError(f"state must be 'deployed' or 'flat', got {state!r}")
    vertices = np.array(structure.deployed if state == "deployed" else structure.flat, dtype=float)
    if ground:
        vertices = vertices + ground_offset(vertices)
    faces = np.asarray(structure.faces, dtype=int)
    p = vertices.shape[0]
    quads = vertices[np.arange(p)[:, None, None], faces]
    n = faces.shape[1]
    rulings = vertices[:, plate_rulings(n)]
    index = {pid: i for i, pid in enumerate(structure.plate_ids)}
    creases, alphas = [], []
    for c in structure.creases:
        pa = index[c["plates"][0]]
        creases.append(
            {
                "id": c["id"],
                "kind": c["kind"],
                "plates": list(c["plates"]),
                "points": vertices[pa, np.asarray(c["vertices"][0], dtype=int)],
            }
        )
        alphas.append(np.asarray(c.get("alpha", np.full(n + 1, np.nan)), dtype=float))
    return Scene(
        vertices=vertices,
        quads=quads,
        faces=faces,
        rulings=rulings,
        creases=creases,
        crease_alpha=alphas,
        plate_ids=list(structure.plate_ids),
    )
