"""One deployed state of a CCU structure: the ``ccu.structure`` contract (docs/structure-json.md).

:class:`Structure` is a :class:`compas.data.Data`, so it serialises with ``compas.json_dump`` and
shows up in COMPAS / Rhino; :meth:`Structure.to_contract` gives the plain ``structure.json``
dictionary that other tools and the tests rely on; :meth:`Structure.to_meshes` converts the
plates to :class:`compas.datastructures.Mesh` at the boundary.
"""

from __future__ import annotations

import numpy as np
from compas.data import Data
from compas.datastructures import Mesh

__all__ = ["Structure", "FORMAT", "VERSION", "STATES"]

FORMAT = "ccu.structure"
VERSION = 1


#: The two states of a structure's plates: the deployed geometry and the cut pattern.
STATES = ("deployed", "flat")


def _as_lists(a: np.ndarray) -> list:
    return np.asarray(a, dtype=float).tolist()


class Structure(Data):
    """A deployed CCU structure.

    Parameters
    ----------
    alpha : float
        Reference reflection angle, degrees.
    faces : (p, n, 4) int
        Quad faces of every plate, counter-clockwise in the cut pattern.
    flat, deployed : (p, v, 3) float
        Cut patterns (z = 0) and deployed vertices of every plate, same vertex order.
    creases : list of dict, or a callable that returns it
        crease records (docs/structure-json.md) (id, plates, vertices, kind, plane, ...).
    metrics : dict, or a callable that returns it
        Invariant errors and key figures.
    plate_ids : list of int, optional

    Notes
    -----
    A callable is called once, on the first read of :attr:`creases` / :attr:`metrics` (or of
    the contract): a redeployed model builds its structures with lazy records
    (:class:`compas_ccu.model.records.StateRecords`), so a caller that reads only the vertices
    does not pay for them.
    """

    def __init__(self, alpha, faces, flat, deployed, creases, metrics, plate_ids=None, name=None):
        super().__init__(name=name)
        self.alpha = float(alpha)
        self.faces = np.asarray(faces, dtype=int)
        self.flat = np.asarray(flat, dtype=float)
        self.deployed = np.asarray(deployed, dtype=float)
        self._creases = creases if callable(creases) else list(creases)
        self._metrics = metrics if callable(metrics) else dict(metrics)
        self.plate_ids = list(range(len(self.flat))) if plate_ids is None else list(plate_ids)

    @property
    def creases(self) -> list:
        """crease records (docs/structure-json.md), computed on first read if lazy."""
        if callable(self._creases):
            self._creases = list(self._creases())
        return self._creases

    @creases.setter
    def creases(self, value) -> None:
        self._creases = list(value)

    @property
    def metrics(self) -> dict:
        """Invariant errors and key figures, computed on first read if lazy."""
        if callable(self._metrics):
            self._metrics = dict(self._metrics())
        return self._metrics

    @metrics.setter
    def metrics(self, value) -> None:
        self._metrics = dict(value)

    # -- COMPAS data -------------------------------------------------------------------------
    @property
    def __data__(self) -> dict:
        return self.to_contract()

    @classmethod
    def __from_data__(cls, data: dict) -> Structure:
        return cls.from_contract(data)

    def to_contract(self) -> dict:
        """The ``structure.json`` dictionary (docs/structure-json.md)."""
        plates = [
            {"id": pid, "faces": fc.tolist(), "flat": _as_lists(f), "deployed": _as_lists(d)}
            for pid, fc, f, d in zip(self.plate_ids, self.faces, self.flat, self.deployed)
        ]
        return {
            "format": FORMAT,
            "version": VERSION,
            "units": "m",
            "alpha": self.alpha,
            "plates": plates,
            "creases": self.creases,
            "metrics": self.metrics,
        }

    @classmethod
    def from_contract(cls, data: dict) -> Structure:
        """Read a ``structure.json`` dictionary back."""
        if data.get("format") != FORMAT or data.get("version") != VERSION:
            raise ValueError(
                f"not a {FORMAT} v{VERSION} document: format={data.get('format')!r}, "
                f"version={data.get('version')!r}"
            )
        plates = data["plates"]
        return cls(
            data["alpha"],
            [p["faces"] for p in plates],
            [p["flat"] for p in plates],
            [p["deployed"] for p in plates],
            data["creases"],
            data.get("metrics", {}),
            [p["id"] for p in plates],
        )

    # -- key figures -------------------------------------------------------------------------
    @property
    def max_invariant_error(self) -> float:
        """Largest relative invariant error (isometry, planarity, hinge, mirror)."""
        keys = (
            "isometry_relative",
            "quad_planarity_relative",
            "hinge_gap_relative",
            "mirror_error_relative",
        )
        return max(self.metrics[k] for k in keys)

    def crease_kind_counts(self) -> dict[str, int]:
        """Number of creases of each kind, in the order the kinds first appear."""
        counts: dict[str, int] = {}
        for c in self.creases:
            counts[c["kind"]] = counts.get(c["kind"], 0) + 1
        return counts

    def points(self, state: str = "deployed") -> np.ndarray:
        """(p, v, 3) plate vertices of ``state``: ``"deployed"`` or ``"flat"`` (cut patterns).

        Raises
        ------
        ValueError
            ``state`` is neither.
        """
        if state not in STATES:
            raise ValueError(f"state must be one of {', '.join(map(repr, STATES))}, got {state!r}")
        return self.deployed if state == "deployed" else self.flat

    def to_meshes(self, *, state: str = "deployed") -> list:
        """One :class:`compas.datastructures.Mesh` per plate (``state``: deployed or flat)."""
        points = self.points(state)
        meshes = []
        for pid, xyz, faces in zip(self.plate_ids, points, self.faces):
            mesh = Mesh.from_vertices_and_faces(xyz.tolist(), faces.tolist())
            mesh.name = f"plate_{pid}"
            mesh.attributes["plate"] = pid
            mesh.attributes["alpha"] = self.alpha
            meshes.append(mesh)
        return meshes

    def __repr__(self) -> str:
        return (
            f"Structure(alpha={self.alpha:g} deg, plates={len(self.flat)}, "
            f"creases={len(self.creases)})"
        )
