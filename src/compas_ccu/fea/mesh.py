"""Shell meshes of CCU structures: the planar-quad strips refined to a chosen element size.

Every plate of a model is a strip of planar quads between two boundary curves, one quad per crease
segment. Each quad is divided into ``along × across[p]`` bilinear sub-quads; because every quad is
planar and congruent to its cut quad at every state (docs/geometry.md §3), a material point keeps
its bilinear parameters exactly, and :meth:`ShellMesh.kinematic` gives the exact kinematic position
of every FE node at any reflection angle. Hinge nodes are duplicated: plate a and plate b have their
own node at every crease point; :attr:`ShellMesh.ties` pairs them.

>>> from compas_ccu.design import load_design
>>> from compas_ccu.model import CCUModel
>>> from compas_ccu.fea.mesh import mesh_model
>>> mesh = mesh_model(CCUModel(load_design("examples/vault.toml")), element_size=0.1)
>>> mesh.elements.shape, mesh.ties.shape
((1920, 4), (585, 2))
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.fea.problem import FEError
from compas_ccu.kinematics.plates import plate_quads
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["ShellMesh", "mesh_model"]


@dataclass
class ShellMesh:
    """A quad-shell mesh of a CCU model.

    Attributes
    ----------
    nodes : (N, 3) float
        Reference coordinates: the flat-folded stack (alpha = 0), world frame.
    elements : (E, 4) int
        Counter-clockwise in the cut pattern (the model's face orientation).
    element_plate : (E,) int
        Plate of every element (output order of the model).
    node_plate, node_quad : (N,) int
        Plate and crease-segment quad of every node.
    node_uv : (N, 2) float
        Bilinear parameters of every node in its quad (u along the crease, v across).
    ties : (T, 2) int
        Hinge node pairs (plate a, plate b) along every crease.
    tie_crease : (T,) int
        Crease id of every tie.
    tie_lengths : (T,) float
        Crease length belonging to every tie node, m.
    supports : (F,) int
        The nodes on the end rulings of every plate (where the corrugation meets the ground).
    free_edges : (G,) int
        The nodes on the two outer long boundaries of the stack (not on a crease).
    directions : (E, 3) float
        Unit direction along the crease in every element at the reference (plywood face grain).
    along : int
        Elements per crease segment.
    across : (P,) int
        Elements across every plate.
    """

    nodes: np.ndarray
    elements: np.ndarray
    element_plate: np.ndarray
    node_plate: np.ndarray
    node_quad: np.ndarray
    node_uv: np.ndarray
    ties: np.ndarray
    tie_crease: np.ndarray
    tie_lengths: np.ndarray
    supports: np.ndarray
    free_edges: np.ndarray
    directions: np.ndarray
    along: int
    across: np.ndarray
    segments: int

    @property
    def element_size(self) -> float:
        """Largest element edge length at the reference, m."""
        q = self.nodes[self.elements]
        return float(np.linalg.norm(q - np.roll(q, 1, axis=1), axis=2).max())

    def kinematic(self, vertices: np.ndarray) -> np.ndarray:
        """Exact kinematic positions of the nodes.

        Parameters
        ----------
        vertices : (k, p, 2n + 2, 3) or (p, 2n + 2, 3) float
            Plate vertices of the model (output order), e.g. ``Structure.deployed``.

        Returns
        -------
        (k, N, 3) or (N, 3) float
        """
        v = np.asarray(vertices, dtype=float)
        single = v.ndim == 3
        v = v[None] if single else v
        q = plate_quads(self.segments)[self.node_quad]  # (nodes, 4) corners a, b, c, d
        p = self.node_plate
        u, w = self.node_uv[:, 0:1], self.node_uv[:, 1:2]
        a, b, c, d = (v[:, p, q[:, i]] for i in range(4))
        x = (1 - u) * (1 - w) * a + u * (1 - w) * b + u * w * c + (1 - u) * w * d
        return x[0] if single else x

    def element_normals(self, positions: np.ndarray) -> np.ndarray:
        """(..., E, 3) unit normals ``(x2 - x0) × (x3 - x1)`` of the elements at ``positions``."""
        q = np.asarray(positions)[..., self.elements, :]
        n = np.cross(q[..., 2, :] - q[..., 0, :], q[..., 3, :] - q[..., 1, :])
        return n / np.linalg.norm(n, axis=-1, keepdims=True)

    def element_areas(self) -> np.ndarray:
        """(E,) reference areas of the elements, m²."""
        q = self.nodes[self.elements]
        n = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
        return 0.5 * np.linalg.norm(n, axis=1)


def mesh_model(model, *, element_size: float = 0.05) -> ShellMesh:
    """Refine the plates of ``model`` into quad shells of about ``element_size``.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    element_size : float
        Target element edge length, m. Along the crease an element is never longer than a crease
        segment (the strips' quads are kept as they are); across, every plate gets as many
        elements as its longest ruling needs.

    Returns
    -------
    ShellMesh
    """
    if not (isinstance(element_size, (int, float)) and element_size > 0.0):
        raise FEError(f"element_size must be > 0 m, got {element_size!r}")
    n = model.segments
    flat = model.flat()
    structure = model.path([0.0], check=False)[0]  # the flat-folded stack
    stack = structure.deployed  # (p, 2n + 2, 3)
    p_count = len(flat)
    near, far = flat[:, : n + 1, :2], flat[:, n + 1 :, :2]
    seg = np.linalg.norm(np.diff(near, axis=1), axis=2).max()
    seg = max(seg, np.linalg.norm(np.diff(far, axis=1), axis=2).max())
    along = max(1, math.ceil(seg / element_size - EXACT_RELATIVE))
    rulings = np.linalg.norm(far - near, axis=2).max(axis=1)
    across = np.maximum(1, np.ceil(rulings / element_size - EXACT_RELATIVE).astype(int))
    if p_count * (n * along + 1) * (across.max() + 1) > 2_000_000:
        raise FEError(
            f"element_size {element_size} m gives more than 2 million nodes; use a larger size"
        )

    nodes_plate, nodes_quad, nodes_uv, elements, element_plate = [], [], [], [], []
    offsets = np.zeros(p_count + 1, dtype=int)
    a_count = n * along + 1
    for p in range(p_count):
        r = int(across[p])
        a_idx, c_idx = np.meshgrid(np.arange(a_count), np.arange(r + 1), indexing="ij")
        a_idx, c_idx = a_idx.ravel(), c_idx.ravel()
        quad = np.minimum(a_idx // along, n - 1)
        nodes_plate.append(np.full(a_idx.size, p))
        nodes_quad.append(quad)
        nodes_uv.append(np.c_[(a_idx - quad * along) / along, c_idx / r])
        offsets[p + 1] = offsets[p] + a_idx.size
        ai, ci = np.meshgrid(np.arange(a_count - 1), np.arange(r), indexing="ij")
        k = (ai * (r + 1) + ci).ravel()
        quads = np.c_[k, k + (r + 1), k + (r + 1) + 1, k + 1]
        if model.faces[p, 0, 0] != 0:  # the model's faces run the other way round
            quads = quads[:, ::-1]
        elements.append(quads + offsets[p])
        element_plate.append(np.full(len(quads), p))

    mesh = ShellMesh(
        nodes=np.zeros((offsets[-1], 3)),
        elements=np.concatenate(elements),
        element_plate=np.concatenate(element_plate),
        node_plate=np.concatenate(nodes_plate),
        node_quad=np.concatenate(nodes_quad),
        node_uv=np.concatenate(nodes_uv),
        ties=np.zeros((0, 2), dtype=int),
        tie_crease=np.zeros(0, dtype=int),
        tie_lengths=np.zeros(0),
        supports=np.zeros(0, dtype=int),
        free_edges=np.zeros(0, dtype=int),
        directions=np.zeros((0, 3)),
        along=along,
        across=across,
        segments=n,
    )
    mesh.nodes = mesh.kinematic(stack)

    def node(p, a, c):
        return offsets[p] + a * (across[p] + 1) + c

    a_all = np.arange(a_count)
    # hinges: crease vertices of plate a (near or far row) against plate b's near row
    ties, tie_crease, tie_lengths = [], [], []
    on_crease = np.zeros(offsets[-1], dtype=bool)
    for crease in structure.creases:
        pa, pb = crease["plates"]
        ca = 0 if crease["vertices"][0][0] == 0 else across[pa]
        cb = 0 if crease["vertices"][1][0] == 0 else across[pb]
        na, nb = node(pa, a_all, ca), node(pb, a_all, cb)
        gap = np.linalg.norm(mesh.nodes[na] - mesh.nodes[nb], axis=1).max()
        if gap > EXACT_RELATIVE * model.size:
            raise FEError(f"crease {crease['id']}: hinge nodes do not coincide (gap {gap:.3g} m)")
        edge = np.linalg.norm(np.diff(mesh.nodes[na], axis=0), axis=1)
        length = 0.5 * (np.r_[0.0, edge] + np.r_[edge, 0.0])
        ties.append(np.c_[na, nb])
        tie_crease.append(np.full(a_count, crease["id"]))
        tie_lengths.append(length)
        on_crease[na] = on_crease[nb] = True
    if ties:
        mesh.ties = np.concatenate(ties)
        mesh.tie_crease = np.concatenate(tie_crease)
        mesh.tie_lengths = np.concatenate(tie_lengths)
    ends = [node(p, a, np.arange(across[p] + 1)) for p in range(p_count) for a in (0, a_count - 1)]
    mesh.supports = np.unique(np.concatenate(ends))
    edges = [node(p, a_all, c) for p in range(p_count) for c in (0, across[p])]
    edges = np.unique(np.concatenate(edges))
    mesh.free_edges = edges[~on_crease[edges]]
    # material direction 1: along the crease (u) in every element
    q = mesh.nodes[mesh.elements]
    u = mesh.node_uv[mesh.elements, 0]
    a_ = mesh.node_quad[mesh.elements] + u
    du = (q * (a_ - a_.mean(axis=1, keepdims=True))[..., None]).sum(axis=1)
    mesh.directions = du / np.linalg.norm(du, axis=1, keepdims=True)
    return mesh
