"""One FOLD frame: the plates joined at their hinges, the edges, their fold angles and kinds.

:func:`fold_frame` turns per-plate coordinates and quads into the arrays of one frame of the
``.fold`` file, in named steps: the crease vertices of the two plates of a crease merged (or
snapped onto the hinge line, :func:`_hinge_pairs`; :func:`_merge`), one edge per vertex pair
with its left and right faces (:func:`_edge_table`), the crease of every edge
(:func:`_edge_creases`), the fold angle of every edge measured on the frame's coordinates and on
the plates' own (:func:`_measure`), and the assignments (:func:`_assign`). The conventions:
:mod:`compas_ccu.fabrication.fold`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.fabrication.fold_angles import face_warp, fold_angles, quad_normals
from compas_ccu.fabrication.meshes import crease_line
from compas_ccu.geometry import unit

__all__ = ["fold_frame"]


class _Vertices(NamedTuple):
    """The frame's vertices: the plates' vertices merged at the hinges."""

    coords: np.ndarray  #: (v, d) float
    index: np.ndarray  #: (p, nv) int, the frame vertex of every plate vertex
    plate_vertices: list  #: per frame vertex, the ``[plate id, k]`` merged into it
    snapped: list  #: ``ccu:snappedCreases``
    unmerged: list  #: ``ccu:unmergedCreases``


class _Edges(NamedTuple):
    """One edge per undirected vertex pair, oriented as in its first (left) face."""

    vertices: np.ndarray  #: (e, 2) int
    left: np.ndarray  #: (e,) int, the face that runs the edge
    right: np.ndarray  #: (e,) int, the other face, -1 on the boundary
    first: np.ndarray  #: (e,) int, the edge's half-edge in the left face (``4 f + corner``)
    keys: np.ndarray  #: (e,) int, ``min(u, v) * v_count + max(u, v)``
    manifold: bool  #: no edge has more than two faces
    oriented: bool  #: no interior edge is run the same way by its two faces


def _hinge_pairs(data, coords, pos, *, hinges, merge_tol, state) -> tuple:
    """The plate-vertex pairs (flat indices ``plate * nv + k``) merged at the creases.

    Crease rows that coincide to ``merge_tol`` are merged as they are; with ``hinges="snap"``
    the others (gap up to twice the thickness) are first moved onto their hinge line in ``pos``
    (p nv, d), in place. Returns ``(pairs, snapped, unmerged)``.
    """
    nv = coords.shape[1]
    pairs, snapped, unmerged = [], [], []
    for c in data.creases if hinges else ():
        a, b = (data.index(pid) for pid in c["plates"])
        ia, ib = (np.asarray(v, dtype=np.int64) for v in c["vertices"])
        gap = float(np.linalg.norm(coords[a, ia] - coords[b, ib], axis=1).max())
        if gap > merge_tol:
            if hinges != "snap" or gap > 2.0 * float(data.thickness) + merge_tol:
                unmerged.append({"crease": c["id"], "maxDistance": gap})
                continue
            line, _, where = crease_line(data, c, state=state)
            move = max(
                float(np.linalg.norm(line - coords[a, ia], axis=1).max()),
                float(np.linalg.norm(line - coords[b, ib], axis=1).max()),
            )
            pos[a * nv + ia] = line
            pos[b * nv + ib] = line
            snapped.append({"crease": c["id"], "maxDistance": gap, "hinge": where, "maxMove": move})
        pairs += zip((a * nv + ia).tolist(), (b * nv + ib).tolist())
    return pairs, snapped, unmerged


def _roots(size: int, pairs) -> np.ndarray:
    """(size,) the lowest member of every element's class (union-find over ``pairs``)."""
    parent = np.arange(size)

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for x, y in pairs:
        rx, ry = find(x), find(y)
        if rx != ry:
            parent[max(rx, ry)] = min(rx, ry)
    return np.array([find(x) for x in range(size)])


def _merge(data, coords, *, hinges, merge_tol, state) -> _Vertices:
    """The frame's vertices from per-plate coordinates (p, nv, d): :func:`_hinge_pairs` merged."""
    p, nv, dim = coords.shape
    pos = coords.reshape(-1, dim).copy()
    pairs, snapped, unmerged = _hinge_pairs(
        data, coords, pos, hinges=hinges, merge_tol=merge_tol, state=state
    )
    roots = _roots(p * nv, pairs)
    reps, gid = np.unique(roots, return_inverse=True)  # reps: first (lowest) plate vertex
    plate_vertices = [[] for _ in reps]
    for x, g in enumerate(gid.tolist()):
        plate_vertices[g].append([data.plate_ids[x // nv], x % nv])
    return _Vertices(pos[reps], gid.reshape(p, nv), plate_vertices, snapped, unmerged)


def _edge_table(fv: np.ndarray, nverts: int) -> _Edges:
    """The edges of the quads ``fv`` (f, 4) over ``nverts`` vertices."""
    u = fv.reshape(-1)
    v = np.roll(fv, -1, axis=1).reshape(-1)
    owner = np.repeat(np.arange(len(fv)), 4)
    key = np.minimum(u, v) * nverts + np.maximum(u, v)
    ukeys, first, inverse, counts = np.unique(
        key, return_index=True, return_inverse=True, return_counts=True
    )
    edges = np.stack([u[first], v[first]], axis=1)
    left = owner[first]
    right = np.full(len(ukeys), -1)
    second = np.flatnonzero((counts[inverse] == 2) & (np.arange(len(key)) != first[inverse]))
    right[inverse[second]] = owner[second]
    manifold = bool(counts.max() <= 2)
    oriented = not np.any(u[second] == edges[inverse[second], 0])  # same way twice
    return _Edges(edges, left, right, first, ukeys, manifold, oriented)


def _edge_creases(data, gid: np.ndarray, nverts: int, keys: np.ndarray) -> list:
    """``(crease id, segment)`` of every edge, ``(-1, -1)`` for an edge on no crease."""
    crease_of = {}
    for c in data.creases:
        for pid, idx in zip(c["plates"], c["vertices"]):
            g = gid[data.index(pid), np.asarray(idx, dtype=np.int64)]
            ends = np.minimum(g[:-1], g[1:]) * nverts + np.maximum(g[:-1], g[1:])
            for k, kk in enumerate(ends.tolist()):
                crease_of[kk] = (c["id"], k)
    return [crease_of.get(int(k), (-1, -1)) for k in keys]


def _measure(coords, faces, vertices_coords, fv, edges: _Edges) -> tuple:
    """Fold angle of every edge from the frame's own coordinates (3D frames), and the same
    angle between the plates' own (unsnapped) quads, ``coords`` (p, nv, d).

    Returns
    -------
    measured, flat_or_closed, cosine, own : (e,) arrays
        :func:`~compas_ccu.fabrication.fold_angles.fold_angles` of the frame (0, False, 1 for
        boundary edges and 2D frames) and the plates' angle (180 where folded onto each other).
    """
    p, nv, dim = coords.shape
    count = len(edges.keys)
    interior = edges.right >= 0
    fl, fr = edges.left[interior], edges.right[interior]
    measured = np.zeros(count)
    flat_or_closed = np.zeros(count, dtype=bool)
    cosine = np.ones(count)
    own = np.zeros(count)
    local = np.concatenate([faces[i] + i * nv for i in range(p)], axis=0)  # (p n, 4) plate rows
    if dim == 3 and interior.any():
        normals = unit(quad_normals(vertices_coords, fv))
        ends = edges.vertices[interior]
        ev = unit(vertices_coords[ends[:, 1]] - vertices_coords[ends[:, 0]])
        theta, ambiguous, cos = fold_angles(normals[fl], normals[fr], ev)
        measured[interior], flat_or_closed[interior], cosine[interior] = theta, ambiguous, cos
        # the plates' own mid-surfaces: the left face's plate rows of the edge
        k = edges.first[interior] % 4
        rows = coords.reshape(-1, dim)
        own_normals = unit(quad_normals(rows, local))
        eu = rows[local[fl, k]]
        ew = rows[local[fl, (k + 1) % 4]]
        own_theta, own_ambiguous, own_cos = fold_angles(
            own_normals[fl], own_normals[fr], unit(ew - eu)
        )
        own[interior] = np.where(own_ambiguous & (own_cos < 0.0), 180.0, own_theta)
    return measured, flat_or_closed, cosine, own


def _assign(interior, measured, flat_or_closed, cosine, own, located, signs) -> tuple:
    """``(assignment, fold_angle, own)`` of every edge from :func:`_measure`'s angles.

    ``"B"`` on the boundary, ``"M"`` / ``"V"`` by the sign of a measured fold, ``"F"`` where
    flat; folded through exactly 180 degrees (no sign in the coordinates) a crease keeps its
    design-state sign (``signs``), anything else is ``"U"``. ``own`` is updated in place: plates
    folded onto each other take the file's sign.
    """
    assignment = np.full(len(measured), "F", dtype="<U1")
    assignment[~interior] = "B"
    fold_angle = np.where(interior, measured, 0.0)
    folded = interior & ~flat_or_closed
    assignment[folded & (measured > 0.0)] = "V"
    assignment[folded & (measured < 0.0)] = "M"
    for e in np.flatnonzero(interior & flat_or_closed & (cosine < 0.0)):
        cid, k = located[e]
        theta = float(signs[cid][k]) if cid >= 0 else 0.0
        if theta == 0.0:
            assignment[e], fold_angle[e] = "U", 0.0
        else:
            assignment[e] = "V" if theta > 0 else "M"
            fold_angle[e] = 180.0 if theta > 0 else -180.0
    closed = interior & (own == 180.0)
    own[closed] = np.where(fold_angle[closed] < 0.0, -180.0, 180.0)
    return assignment, fold_angle, own


def fold_frame(data, coords, faces, *, hinges, merge_tol, state, signs, flips) -> dict:
    """One FOLD frame from per-plate coordinates (p, 2n + 2, d) and quads (p, n, 4).

    Parameters
    ----------
    data : FabricationData
    coords : (p, 2n + 2, d) float
        Plate vertices, d = 3 (folded forms) or 2 (crease pattern).
    faces : (p, n, 4) int
        Plate quads (oriented: :func:`~compas_ccu.fabrication.fold_angles.oriented_faces`).
    hinges : {"snap", "merge"} or None, keyword-only
        How crease rows are joined; None: never.
    merge_tol : float, keyword-only
        Crease rows closer than this (m) are merged as they are.
    state : {"deployed", "stack"}, keyword-only
        The state of the hinge lines (:func:`~compas_ccu.fabrication.meshes.crease_line`).
    signs : dict, keyword-only
        Crease id -> per-segment design-state angles
        (:func:`~compas_ccu.fabrication.fold_angles.crease_fold_angles`), the sign of a crease
        folded through exactly 180 degrees.
    flips : (p,) bool, keyword-only
        The plates whose quads ``faces`` reverses (``faces_ccu:flipped``).

    Returns
    -------
    dict
        The frame's FOLD fields (``frame_*``, ``vertices_*``, ``faces_*``, ``edges_*``) and its
        ``ccu:`` fields.
    """
    coords = np.asarray(coords, dtype=float)
    p, _, dim = coords.shape
    n = faces.shape[1]
    ids = data.plate_ids
    vertices = _merge(data, coords, hinges=hinges, merge_tol=merge_tol, state=state)
    nverts = len(vertices.coords)
    fv = np.concatenate([vertices.index[i][faces[i]] for i in range(p)], axis=0)  # (p n, 4)
    edges = _edge_table(fv, nverts)
    located = _edge_creases(data, vertices.index, nverts, edges.keys)
    edge_crease = np.array([cid for cid, _ in located], dtype=np.int64)
    interior = edges.right >= 0
    measured, flat_or_closed, cosine, own = _measure(coords, faces, vertices.coords, fv, edges)
    assignment, fold_angle, own = _assign(
        interior, measured, flat_or_closed, cosine, own, located, signs
    )
    kind = np.where(~interior, "outline", np.where(edge_crease >= 0, "crease", "ruling"))
    warp = face_warp(vertices.coords, fv) if dim == 3 else np.zeros(len(fv))

    attributes = ["3D" if dim == 3 else "2D"]
    attributes.append("manifold" if edges.manifold else "nonManifold")
    if edges.manifold:
        attributes.append("orientable" if edges.oriented else "nonOrientable")
    edges_faces = [[int(a), None if b < 0 else int(b)] for a, b in zip(edges.left, edges.right)]
    return {
        "frame_attributes": attributes,
        "frame_unit": "m",
        "vertices_coords": vertices.coords.tolist(),
        "faces_vertices": fv.tolist(),
        "edges_vertices": edges.vertices.tolist(),
        "edges_faces": edges_faces,
        "edges_assignment": assignment.tolist(),
        "edges_foldAngle": fold_angle.tolist(),
        "vertices_ccu:plateVertices": vertices.plate_vertices,
        "faces_ccu:plate": [ids[i] for i in np.repeat(np.arange(p), n).tolist()],
        "faces_ccu:quad": np.tile(np.arange(n), p).tolist(),
        "faces_ccu:flipped": np.repeat(np.asarray(flips, dtype=bool), n).tolist(),
        "edges_ccu:crease": edge_crease.tolist(),
        "edges_ccu:kind": kind.tolist(),
        "edges_ccu:plateFoldAngle": own.tolist(),
        "ccu:maxFaceWarp": float(warp.max()) if len(warp) else 0.0,
        "ccu:hinges": hinges or "separate",
        "ccu:mergeTolerance": merge_tol,
        "ccu:snappedCreases": vertices.snapped,
        "ccu:unmergedCreases": vertices.unmerged,
    }
