"""FOLD 1.2 output (https://github.com/edemaine/fold): :func:`fold_document`, :func:`write_fold`.

A ``.fold`` file is strict JSON (no NaN / Infinity); floats are written with Python's shortest
round-trip ``repr``, so every coordinate reads back bit-for-bit. ``file_spec`` is 1.2: boundary
edges have ``null`` as their right face in ``edges_faces`` (``[left, null]``), which FOLD allows
since version 1.2; nothing else of 1.2 (join / cut edges) is used. Three frames, all in metres,
with the same faces in the same order (face ``f = i * n + j`` is quad ``j`` of plate ``i``, array
order):

0. key frame, ``["foldedForm"]`` / ``"3D"``: the deployed mid-surfaces at the design state
   (``data.deployed_mid``), the two plates of every crease sharing its hinge vertices (see
   *Hinges* below) so that each crease is a FOLD crease: one edge with two faces.
1. ``file_frames[0]``, ``["creasePattern"]`` / ``"2D"``: the flat cut patterns laid side by side
   in x (:func:`~compas_ccu.fabrication.meshes.layout_offsets`, translations in
   ``"ccu:offsets"``), faces counter-clockwise as cut (``data.faces``). Vertices are NOT merged
   across plates: a CCU crease joins two *mirror* sheets (each plate is cut on its own and the
   neighbour is the reflection of its bending across the crease plane), so the plates do not
   unfold into one flat sheet and no single-sheet crease pattern exists. Crease edges are
   therefore boundaries (``"B"``) of their sheets, tagged with their crease id in
   ``"edges_ccu:crease"``.
2. ``file_frames[1]``, ``["foldedForm"]`` / ``"3D"``: the flat-folded stack, mid-surfaces of
   ``data.stack_solids`` (mean of the lower and upper faces), hinges as in frame 0, every crease
   folded nearly through 180 degrees (the snapped hinge vertices tilt the hinge quads: 176 to
   177 degrees for the vault).

Hinges. The crease vertices of the two plates of a crease are merged into one vertex when their
mid-surface rows coincide to ``merge_tol`` (1e-9 m). Thick plates do not do that: their hinge
lies on the two *facing faces*, which meet exactly, while the mid-surfaces are up to a thickness
apart there (``t cos(fold_angle / 2)`` at the design state, ``t`` in the stack). With
``hinges="snap"`` (default) such a crease is merged onto its hinge line
(:func:`~compas_ccu.fabrication.meshes.crease_line`, exact face vertices of ``data.solids`` /
``data.stack_solids``), so only its crease vertices leave the mid-surface (by about ``t / 2``);
every snap is listed in ``"ccu:snappedCreases"`` (crease, ``maxDistance`` between the two
mid-surface rows, ``hinge`` faces, ``maxMove`` of a vertex). With ``hinges="merge"`` (strict)
only coinciding creases are merged; the others stay two separate boundaries (``"B"``, with their
crease id) and are listed in ``"ccu:unmergedCreases"`` with their largest gap. Gaps larger than
twice the thickness are never snapped (a broken model, not a hinge).

Face orientation of the 3D frames. ``data.faces`` are counter-clockwise in each cut pattern, and
since neighbouring plates are mirror sheets this orientation flips across every crease. FOLD's
mountain/valley needs one consistent orientation, so the 3D frames reverse the quads of every
other plate (``"faces_ccu:flipped"``): the orientation is propagated over the creases from the
first plate and then the whole connected sheet is flipped if needed so that the area-weighted mean
normal of the design state points to world +z (the outside / top of a vault). The stack frame uses
the same flips, so a face shows the same side of the material in both 3D frames.

Fold angles and mountain / valley. Every edge's ``edges_foldAngle`` is measured on the frame's
own ``vertices_coords``, so the file agrees with itself: a reader (or a folding simulator) that
recomputes the angles from the coordinates finds the written ones (to round-off, 3e-14 deg). For
an interior edge ``u -> v`` with its left face ``L`` (the face that runs ``u -> v``, first in
``edges_faces``) and right face ``R``, their unit Newell normals ``nL``, ``nR`` (for a quad
``a b c d``: ``(c - a) x (d - b)``) and ``e = (v - u) / |v - u|``, the fold angle is
``theta = atan2(-(nL x nR) . e, nL . nR)`` in degrees: FOLD's deviation from flatness, positive
when the normals point into each other (valley), negative when they point away (mountain), as in
the FOLD spec. Assignment: ``"V"`` if ``theta > 0``, ``"M"`` if ``theta < 0``, ``"B"`` (angle 0)
for outline edges. When ``|(nL x nR) . e| < 1e-9`` (``EXACT_RELATIVE``, the sign test margin of
unit vectors) the two faces are coplanar: the edge is ``"F"`` with angle 0 if they lie side by
side, and if they lie on each other (folded through exactly 180 degrees: thin plates in the
stack) a crease keeps the sign it has at the design state (:func:`crease_fold_angles`, measured
on the plates' own mid-surfaces) with ``+-180``, anything else is ``"U"`` (angle 0).

Rulings are edges too: a ruling is where the smoothly bent plate is sampled, and the quads on
either side of it meet at a small angle (1.24 to 1.28 degrees for the vault at the design
state). They are therefore ``"M"`` / ``"V"`` with their measured angle, like the creases, and
``"F"`` only where the plate is flat to the tolerance above (the 2D crease-pattern frame). What
an edge is in the design is in ``"edges_ccu:kind"``: ``"crease"``, ``"ruling"`` or ``"outline"``.
The crease-pattern frame is flat: its rulings are ``"F"`` and its crease edges ``"B"``.

The snapped hinge vertices are not on the plates' mid-surfaces, so the file's crease angles are
not the plates' dihedral: ``"edges_ccu:plateFoldAngle"`` is the same signed angle measured
between the two faces' own (unsnapped) mid-surface quads, the fold angle of the thick model
(119.989 degrees for the vault's 2 alpha = 60 degree creases, whose file angles are 116.2 to
117.1 degrees). Snapping also warps quads whose two crease rows move to different faces of a
plate (any non-orthogonal layout); ``"ccu:maxFaceWarp"`` is the largest angle between the two
triangles ``a b c`` / ``a c d`` of a quad of the frame (0 for the vault, 0.53 degrees for the
fig12c funnel), which a simulator that triangulates the quads sees as a small facet fold.

Custom fields (``ccu:`` namespace): ``faces_ccu:plate`` (plate id), ``faces_ccu:quad`` (quad
index ``j``), ``faces_ccu:flipped``, ``edges_ccu:crease`` (crease id or -1),
``edges_ccu:kind``, ``edges_ccu:plateFoldAngle`` (deg), ``ccu:maxFaceWarp`` (deg),
``vertices_ccu:plateVertices`` (``[plate id, k]`` pairs of
the plate vertices merged into each vertex), ``ccu:snappedCreases``, ``ccu:unmergedCreases``,
``ccu:hinges``, ``ccu:mergeTolerance``, ``ccu:offsets`` and, at file level, ``ccu:design``,
``ccu:alpha``, ``ccu:thickness``, ``ccu:material``, ``ccu:plateIds``, ``ccu:segments``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from compas_ccu.fabrication.meshes import crease_line, layout_offsets
from compas_ccu.geometry import dot, unit
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "ASSIGNMENTS",
    "crease_fold_angles",
    "fold_document",
    "fold_json",
    "read_fold",
    "write_fold",
]

#: The edge assignments this writer uses.
ASSIGNMENTS = ("B", "M", "V", "F", "U")

_SIGN_TOL = EXACT_RELATIVE
_HINGES = ("snap", "merge")


def _traverses(faces: np.ndarray, u, v) -> np.ndarray:
    """Whether quad ``faces[k]`` (m, 4) runs ``u[k] -> v[k]`` (m,), vectorised."""
    nxt = np.roll(faces, -1, axis=1)
    return np.any((faces == np.asarray(u)[:, None]) & (nxt == np.asarray(v)[:, None]), axis=1)


def _quad_normals(coords: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """(f, 3) unnormalised quad normals ``(c - a) x (d - b)`` for (f, 4) quads."""
    q = coords[quads]
    return np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])


def _fold_angles(nl, nr, e) -> tuple:
    """FOLD fold angles (deg) between left / right unit normals about the unit edges ``e``.

    Returns
    -------
    theta : (m,) float
        ``atan2(-(nL x nR) . e, nL . nR)``: positive valley, negative mountain.
    ambiguous : (m,) bool
        ``|(nL x nR) . e| < EXACT_RELATIVE``: the faces are coplanar (flat, ``theta`` = 0) or
        folded onto each other (``theta`` = +-180 with no sign in the geometry).
    cosine : (m,) float
        ``nL . nR``.
    """
    s = -np.einsum("ij,ij->i", np.cross(nl, nr), e)
    c = np.einsum("ij,ij->i", nl, nr)
    ambiguous = np.abs(s) < _SIGN_TOL
    theta = np.where(ambiguous & (c > 0.0), 0.0, np.degrees(np.arctan2(s, c)))
    return theta, ambiguous, c


def _signed_angle(nl, nr, e) -> np.ndarray:
    """:func:`_fold_angles` with 0 where the sign is ambiguous (crease signs)."""
    theta, ambiguous, _ = _fold_angles(nl, nr, e)
    return np.where(ambiguous, 0.0, theta)


def _face_warp(coords: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """(f,) angle (deg) between the triangles ``a b c`` and ``a c d`` of every quad: 0 if planar."""
    q = coords[quads]
    n1 = unit(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]))
    n2 = unit(np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 0]))
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(n1, n2), axis=1), dot(n1, n2)))


def _segment_quads(n: int, idx: np.ndarray) -> np.ndarray:
    """Quad of every boundary segment ``idx[k] -- idx[k + 1]`` (near row j: quad j; far: j)."""
    return np.minimum(idx[:-1], idx[1:]) % (n + 1)


def _orientation(data) -> tuple:
    """Per-plate flips that orient the deployed sheet consistently; see the module docstring.

    Returns
    -------
    flips : (p,) bool
    orientable : bool
    """
    p, n = len(data.plate_ids), data.segments
    faces = np.asarray(data.faces)
    mid = np.asarray(data.deployed_mid, dtype=float)
    adjacency = {i: [] for i in range(p)}
    for c in data.creases:
        a, b = (data.index(pid) for pid in c["plates"])
        ia, ib = (np.asarray(v, dtype=np.int64) for v in c["vertices"])
        qa, qb = _segment_quads(n, ia)[:1], _segment_quads(n, ib)[:1]
        ta = bool(_traverses(faces[a][qa], ia[:1], ia[1:2])[0])
        tb = bool(_traverses(faces[b][qb], ib[:1], ib[1:2])[0])
        # consistent when the two plates run the shared edge in opposite directions
        adjacency[a].append((b, ta == tb))
        adjacency[b].append((a, ta == tb))
    flips = np.zeros(p, dtype=bool)
    seen = np.zeros(p, dtype=bool)
    orientable = True
    for root in range(p):
        if seen[root]:
            continue
        seen[root] = True
        component, todo = [root], [root]
        while todo:
            a = todo.pop()
            for b, differ in adjacency[a]:
                want = flips[a] ^ differ
                if not seen[b]:
                    seen[b], flips[b] = True, want
                    component.append(b)
                    todo.append(b)
                elif flips[b] != want:
                    orientable = False
        up = 0.0
        for i in component:
            nz = _quad_normals(mid[i], faces[i])[:, 2].sum()
            up += -nz if flips[i] else nz
        if up < 0.0:
            flips[component] = ~flips[component]
    return flips, orientable


def _oriented_faces(data, flips) -> np.ndarray:
    faces = np.array(data.faces, dtype=np.int64)
    faces[flips] = faces[flips][:, :, ::-1]
    return faces


def crease_fold_angles(data) -> dict:
    """Signed FOLD fold angle of every crease segment, measured at the design state.

    The plates are oriented consistently (module docstring); the angle of segment ``k`` is
    ``atan2(-(nL x nR) . e, nL . nR)`` between the quad normals of plates a (left) and b along
    the segment direction ``e`` of plate a's oriented quad. It only depends on each plate's own
    mid-surface, so it does not need the hinge vertices to coincide.

    Parameters
    ----------
    data : FabricationData

    Returns
    -------
    dict
        ``{crease id: (m - 1,) float}``, degrees: positive valley, negative mountain, 0 when the
        sign is ambiguous. About ``180 - fold_angle`` in magnitude.
    """
    flips, _ = _orientation(data)
    faces = _oriented_faces(data, flips)
    mid = np.asarray(data.deployed_mid, dtype=float)
    n = data.segments
    out = {}
    for c in data.creases:
        a, b = (data.index(pid) for pid in c["plates"])
        ia, ib = (np.asarray(v, dtype=np.int64) for v in c["vertices"])
        qa, qb = faces[a][_segment_quads(n, ia)], faces[b][_segment_quads(n, ib)]
        forward = _traverses(qa, ia[:-1], ia[1:])
        u = np.where(forward, ia[:-1], ia[1:])
        v = np.where(forward, ia[1:], ia[:-1])
        nl, nr = unit(_quad_normals(mid[a], qa)), unit(_quad_normals(mid[b], qb))
        out[c["id"]] = _signed_angle(nl, nr, unit(mid[a, v] - mid[a, u]))
    return out


def _frame(data, coords, faces, *, hinges, merge_tol, state, signs, flips) -> dict:
    """One FOLD frame from per-plate coordinates (p, 2n + 2, d) and quads (p, n, 4).

    ``hinges``: "snap" | "merge" | None (never merge); ``state`` for the hinge lines;
    ``signs``: crease id -> per-segment design-state angles (:func:`crease_fold_angles`), the
    sign of a crease folded through exactly 180 degrees.
    """
    coords = np.asarray(coords, dtype=float)
    p, nv, dim = coords.shape
    n = faces.shape[1]
    ids = data.plate_ids
    pos = coords.reshape(-1, dim).copy()

    # --- vertices: union-find over the crease vertex pairs that are merged
    parent = np.arange(p * nv)

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    snapped, unmerged = [], []
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
        for x, y in zip((a * nv + ia).tolist(), (b * nv + ib).tolist()):
            rx, ry = find(x), find(y)
            if rx != ry:
                parent[max(rx, ry)] = min(rx, ry)
    roots = np.array([find(x) for x in range(p * nv)])
    reps, gid = np.unique(roots, return_inverse=True)  # reps: first (lowest) plate vertex
    vertices_coords = pos[reps]
    plate_vertices = [[] for _ in reps]
    for x, g in enumerate(gid.tolist()):
        plate_vertices[g].append([ids[x // nv], x % nv])
    gid = gid.reshape(p, nv)
    nverts = len(reps)

    # --- faces
    fv = np.concatenate([gid[i][faces[i]] for i in range(p)], axis=0)  # (p n, 4)
    face_plate = np.repeat(np.arange(p), n)

    # --- edges: one per undirected vertex pair, oriented as in its first (left) face
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

    crease_of = {}
    for c in data.creases:
        for pid, idx in zip(c["plates"], c["vertices"]):
            g = gid[data.index(pid), np.asarray(idx, dtype=np.int64)]
            keys = np.minimum(g[:-1], g[1:]) * nverts + np.maximum(g[:-1], g[1:])
            for k, kk in enumerate(keys.tolist()):
                crease_of[kk] = (c["id"], k)
    located = [crease_of.get(int(k), (-1, -1)) for k in ukeys]
    edge_crease = np.array([cid for cid, _ in located], dtype=np.int64)

    # --- fold angle of every edge, from this frame's own coordinates (3D frames); the same
    # angle between the plates' own (unsnapped) quads, ``coords``
    interior = right >= 0
    fl, fr = left[interior], right[interior]
    measured = np.zeros(len(ukeys))
    flat_or_closed = np.zeros(len(ukeys), dtype=bool)
    cosine = np.ones(len(ukeys))
    own = np.zeros(len(ukeys))
    local = np.concatenate([faces[i] + i * nv for i in range(p)], axis=0)  # (p n, 4) plate rows
    if dim == 3 and interior.any():
        normals = unit(_quad_normals(vertices_coords, fv))
        ev = unit(vertices_coords[edges[interior, 1]] - vertices_coords[edges[interior, 0]])
        theta, ambiguous, cos = _fold_angles(normals[fl], normals[fr], ev)
        measured[interior], flat_or_closed[interior], cosine[interior] = theta, ambiguous, cos
        # the plates' own mid-surfaces: the left face's plate rows of the edge
        k = first[interior] % 4
        rows = coords.reshape(-1, dim)
        own_normals = unit(_quad_normals(rows, local))
        eu = rows[local[fl, k]]
        ew = rows[local[fl, (k + 1) % 4]]
        own_theta, own_ambiguous, own_cos = _fold_angles(
            own_normals[fl], own_normals[fr], unit(ew - eu)
        )
        own[interior] = np.where(own_ambiguous & (own_cos < 0.0), 180.0, own_theta)

    assignment = np.full(len(ukeys), "F", dtype="<U1")
    assignment[~interior] = "B"
    fold_angle = np.where(interior, measured, 0.0)
    folded = interior & ~flat_or_closed
    assignment[folded & (measured > 0.0)] = "V"
    assignment[folded & (measured < 0.0)] = "M"
    # folded through 180 degrees exactly (no sign in the coordinates): the crease keeps the sign
    # it has at the design state; anything else is "U"
    for e in np.flatnonzero(interior & flat_or_closed & (cosine < 0.0)):
        cid, k = located[e]
        theta = float(signs[cid][k]) if cid >= 0 else 0.0
        if theta == 0.0:
            assignment[e], fold_angle[e] = "U", 0.0
        else:
            assignment[e] = "V" if theta > 0 else "M"
            fold_angle[e] = 180.0 if theta > 0 else -180.0
    # plates folded onto each other: the sign is the file's
    closed = interior & (own == 180.0)
    own[closed] = np.where(fold_angle[closed] < 0.0, -180.0, 180.0)
    kind = np.where(~interior, "outline", np.where(edge_crease >= 0, "crease", "ruling"))
    warp = _face_warp(vertices_coords, fv) if dim == 3 else np.zeros(len(fv))

    attributes = ["3D" if dim == 3 else "2D"]
    attributes.append("manifold" if manifold else "nonManifold")
    if manifold:
        attributes.append("orientable" if oriented else "nonOrientable")
    edges_faces = [[int(a), None if b < 0 else int(b)] for a, b in zip(left, right)]
    return {
        "frame_attributes": attributes,
        "frame_unit": "m",
        "vertices_coords": vertices_coords.tolist(),
        "faces_vertices": fv.tolist(),
        "edges_vertices": edges.tolist(),
        "edges_faces": edges_faces,
        "edges_assignment": assignment.tolist(),
        "edges_foldAngle": fold_angle.tolist(),
        "vertices_ccu:plateVertices": plate_vertices,
        "faces_ccu:plate": [ids[i] for i in face_plate.tolist()],
        "faces_ccu:quad": np.tile(np.arange(n), p).tolist(),
        "faces_ccu:flipped": np.repeat(np.asarray(flips, dtype=bool), n).tolist(),
        "edges_ccu:crease": edge_crease.tolist(),
        "edges_ccu:kind": kind.tolist(),
        "edges_ccu:plateFoldAngle": own.tolist(),
        "ccu:maxFaceWarp": float(warp.max()) if len(warp) else 0.0,
        "ccu:hinges": hinges or "separate",
        "ccu:mergeTolerance": merge_tol,
        "ccu:snappedCreases": snapped,
        "ccu:unmergedCreases": unmerged,
    }


def fold_document(
    data, *, hinges: str = "snap", merge_tol: float = EXACT_RELATIVE, gap: float = 0.1
) -> dict:
    """The design as a FOLD 1.2 document (a JSON-ready dict); see the module docstring.

    Parameters
    ----------
    data : FabricationData
    hinges : {"snap", "merge"}, keyword-only
        How the 3D frames join the plates of a crease whose mid-surface rows do not coincide:
        merge them onto the hinge line (``"snap"``) or keep them apart (``"merge"``: only
        coinciding rows are merged).
    merge_tol : float, keyword-only
        Crease rows closer than this (m) coincide and are merged as they are.
    gap : float, keyword-only
        Clear distance between the cut patterns of the crease-pattern frame, m.

    Returns
    -------
    dict
        Key frame (deployed) at the top level, ``file_frames`` = [crease pattern, flat-folded
        stack].
    """
    if hinges not in _HINGES:
        raise ValueError(f"hinges must be one of {_HINGES}, got {hinges!r}")
    flips, orientable = _orientation(data)
    oriented = _oriented_faces(data, flips)
    signs = crease_fold_angles(data)
    common = {"hinges": hinges, "merge_tol": merge_tol, "signs": signs, "flips": flips}

    key = _frame(data, data.deployed_mid, oriented, state="deployed", **common)
    key["frame_title"] = f"{data.name}: deployed mid-surfaces, alpha = {float(data.alpha):g} deg"
    key["frame_classes"] = ["foldedForm"]

    offsets = layout_offsets(data, gap=gap)
    cp = _frame(
        data,
        np.asarray(data.flat, dtype=float) + offsets[:, None, :],
        np.asarray(data.faces, dtype=np.int64),
        hinges=None,
        merge_tol=merge_tol,
        state="deployed",
        signs=signs,
        flips=np.zeros(len(data.plate_ids), dtype=bool),
    )
    cp.update(
        {
            "frame_title": f"{data.name}: cut patterns (separate sheets, side by side)",
            "frame_classes": ["creasePattern"],
            "frame_parent": 0,
            "frame_inherit": False,
            "ccu:offsets": offsets.tolist(),
        }
    )

    stack_mid = np.asarray(data.stack_solids, dtype=float).mean(axis=1)
    stack = _frame(data, stack_mid, oriented, state="stack", **common)
    stack.update(
        {
            "frame_title": f"{data.name}: flat-folded stack (alpha = 0)",
            "frame_classes": ["foldedForm"],
            "frame_parent": 0,
            "frame_inherit": False,
        }
    )

    doc = {
        "file_spec": 1.2,
        "file_creator": "compas_ccu",
        "file_title": data.name,
        "file_classes": ["singleModel"],
        "ccu:design": data.name,
        "ccu:alpha": float(data.alpha),
        "ccu:thickness": float(data.thickness),
        "ccu:material": str(data.material),
        "ccu:plateIds": list(data.plate_ids),
        "ccu:segments": data.segments,
        "ccu:orientable": orientable,
    }
    doc.update(key)
    doc["file_frames"] = [cp, stack]
    return doc


def fold_json(doc: dict, *, indent=None) -> str:
    """A FOLD document as strict JSON text (``ValueError`` on NaN / inf, which JSON lacks).

    Parameters
    ----------
    doc : dict
        :func:`fold_document`.
    indent : int or None, keyword-only
        JSON indentation (None: compact).
    """
    separators = (",", ":") if indent is None else None
    return json.dumps(doc, indent=indent, separators=separators, allow_nan=False)


def write_fold(
    data,
    path,
    *,
    hinges: str = "snap",
    merge_tol: float = EXACT_RELATIVE,
    gap: float = 0.1,
    indent=None,
) -> Path:
    """Write :func:`fold_document` as a ``.fold`` file (strict JSON, :func:`fold_json`).

    Parameters
    ----------
    data : FabricationData
    path : str or Path
    hinges, merge_tol, gap : keyword-only
        See :func:`fold_document`.
    indent : int or None, keyword-only
        JSON indentation (None: compact).

    Returns
    -------
    Path
    """
    path = Path(path)
    doc = fold_document(data, hinges=hinges, merge_tol=merge_tol, gap=gap)
    path.write_text(fold_json(doc, indent=indent), encoding="utf-8")
    return path


def read_fold(path) -> dict:
    """Read a ``.fold`` file.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    dict
        The parsed JSON (key frame at the top level, further frames in ``file_frames``).

    Raises
    ------
    ValueError
        If the JSON is not a dictionary with FOLD keys.
    """
    doc = json.loads(Path(path).read_text(encoding="utf-8"))
    if not isinstance(doc, dict) or not any(
        k.startswith(("file_", "vertices_", "faces_", "edges_")) for k in doc
    ):
        raise ValueError(f"{path} is not a FOLD file")
    return doc
