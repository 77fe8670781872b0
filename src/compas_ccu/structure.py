"""One deployed state of a CCU structure, in the SPEC §4 contract (``ccu.structure`` v1).

:class:`Structure` is a :class:`compas.data.Data`, so it serialises with ``compas.json_dump`` and
shows up in COMPAS / Rhino; :meth:`Structure.to_contract` gives the plain ``structure.json``
dictionary that other tools and the tests rely on; :meth:`Structure.to_meshes` converts the
plates to :class:`compas.datastructures.Mesh` at the boundary.
"""

from __future__ import annotations

import numpy as np
from compas.data import Data

__all__ = ["Structure", "FORMAT", "VERSION"]

FORMAT = "ccu.structure"
VERSION = 1


def _round_list(a: np.ndarray) -> list:
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
    creases : list of dict
        SPEC §4 crease records (id, plates, vertices, kind, plane, ...).
    metrics : dict
        Invariant errors and key figures.
    plate_ids : list of int, optional
    """

    def __init__(self, alpha, faces, flat, deployed, creases, metrics, plate_ids=None, name=None):
        super().__init__(name=name)
        self.alpha = float(alpha)
        self.faces = np.asarray(faces, dtype=int)
        self.flat = np.asarray(flat, dtype=float)
        self.deployed = np.asarray(deployed, dtype=float)
        self.creases = list(creases)
        self.metrics = dict(metrics)
        self.plate_ids = list(range(len(self.flat))) if plate_ids is None else list(plate_ids)

    # -- COMPAS data -------------------------------------------------------------------------
    @property
    def __data__(self) -> dict:
        return self.to_contract()

    @classmethod
    def __from_data__(cls, data: dict) -> Structure:
        return cls.from_contract(data)

    def to_contract(self) -> dict:
        """The ``structure.json`` dictionary of SPEC §4."""
        plates = [
            {"id": pid, "faces": fc.tolist(), "flat": _round_list(f), "deployed": _round_list(d)}
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

    # -- construction from a model state ---------------------------------------------------
    @classmethod
    def from_model(
        cls, model, states, k: int, alpha: float, invariants: dict, kinds: list, flat: np.ndarray
    ) -> Structure:
        """Structure of state ``k`` of a :class:`compas_ccu.model.CCUModel` placement."""
        n = model.segments
        deployed = model.state_vertices(states, k)
        creases = []
        for ci, crease in enumerate(model.mechanism.creases):
            pa = model._mech_to_out[crease.plate_a]
            pb = model._mech_to_out[crease.plate_b]
            ia = (
                list(range(n + 1)) if crease.boundary_a == "near" else list(range(n + 1, 2 * n + 2))
            )
            rel = model._relations(states, k, ci)
            kind, vertex_kinds, sectors = kinds[ci]
            origin = model._to_world(states.plane_origins[k, ci][None])[0]
            normal = model._vector_to_world(states.plane_normals[k, ci][None])[0]
            record = {
                "id": ci,
                "plates": [pa, pb],
                "vertices": [ia, list(range(n + 1))],
                "kind": kind,
                "plane": {"origin": origin.tolist(), "normal": normal.tolist()},
                "planarity": float(invariants["crease_planarity"][k, ci]),
                "alpha": np.degrees(rel.alpha).tolist(),
                "sum_beta": np.degrees(rel.sum_beta[1:-1]).tolist(),
            }
            if kind == "mixed":
                record["vertex_kinds"] = vertex_kinds
            creases.append(record)
        lead_near = states.near[k, 0]
        chord = lead_near[-1, :2] - lead_near[0, :2]
        span = float(np.linalg.norm(chord))
        normal2d = np.array([-chord[1], chord[0]]) / max(span, 1e-300)
        rise = float(np.abs((lead_near[:, :2] - lead_near[0, :2]) @ normal2d).max())
        bbox = np.ptp(deployed.reshape(-1, 3), axis=0)
        size = model.size
        metrics = {
            "alpha_limit": model.alpha_limit,
            "reference_vertex": model.reference,
            "segments": n,
            "span": span,
            "rise": rise,
            "bounding_box": bbox.tolist(),
            "size": size,
            "alpha_leading": np.degrees(
                crease_alpha_local(states.near[k, 0], states.far[k, 0] - states.near[k, 0])
            ).tolist(),
        }
        for key in ("isometry", "quad_planarity", "hinge_gap", "mirror_error", "leading_in_plane"):
            metrics[key] = float(invariants[key][k])
            metrics[key + "_relative"] = float(invariants[key][k]) / size
        cp = invariants["crease_planarity"][k]
        metrics["crease_planarity_max"] = float(cp.max()) if cp.size else 0.0
        metrics["crease_planarity_max_relative"] = metrics["crease_planarity_max"] / size
        return cls(
            alpha,
            model.faces,
            flat,
            deployed,
            creases,
            metrics,
            model.plate_ids,
            name=model.design.name,
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

    def crease_kind_counts(self) -> dict:
        """Number of creases of each kind, in the order the kinds first appear."""
        counts: dict = {}
        for c in self.creases:
            counts[c["kind"]] = counts.get(c["kind"], 0) + 1
        return counts

    def to_meshes(self, *, state: str = "deployed") -> list:
        """One :class:`compas.datastructures.Mesh` per plate (``state``: deployed or flat)."""
        from compas.datastructures import Mesh

        points = self.deployed if state == "deployed" else self.flat
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


def crease_alpha_local(near: np.ndarray, rulings: np.ndarray) -> np.ndarray:
    """Reflection angle at the vertices of the leading crease (local frame, radians)."""
    from compas_ccu.strips.rulings import vertex_reflection_angles

    return vertex_reflection_angles(near[:, :2], rulings / np.linalg.norm(rulings, axis=1)[:, None])
