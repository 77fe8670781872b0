"""The FOLD sheet's orientation and its fold angles: the sign convention of the FOLD file.

The quads of every other plate are reversed so that the whole deployed sheet is oriented
consistently (:func:`sheet_orientation`, :func:`oriented_faces`; neighbouring plates are mirror
sheets), and a fold angle is ``atan2(-(nL x nR) . e, nL . nR)`` between the unit Newell normals
of an edge's left and right faces about its direction (:func:`fold_angles`): positive valley,
negative mountain, as in the FOLD spec. :func:`crease_fold_angles` measures every crease on the
plates' own mid-surfaces at the design state. The conventions in full:
:mod:`compas_ccu.fabrication.fold`.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.geometry import dot, unit
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "crease_fold_angles",
    "face_warp",
    "fold_angles",
    "oriented_faces",
    "quad_normals",
    "sheet_orientation",
]

_SIGN_TOL = EXACT_RELATIVE


def _traverses(faces: np.ndarray, u, v) -> np.ndarray:
    """Whether quad ``faces[k]`` (m, 4) runs ``u[k] -> v[k]`` (m,), vectorised."""
    nxt = np.roll(faces, -1, axis=1)
    return np.any((faces == np.asarray(u)[:, None]) & (nxt == np.asarray(v)[:, None]), axis=1)


def quad_normals(coords: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """(f, 3) unnormalised quad normals ``(c - a) x (d - b)`` for (f, 4) quads."""
    q = coords[quads]
    return np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])


def fold_angles(nl, nr, e) -> tuple:
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
    """:func:`fold_angles` with 0 where the sign is ambiguous (crease signs)."""
    theta, ambiguous, _ = fold_angles(nl, nr, e)
    return np.where(ambiguous, 0.0, theta)


def face_warp(coords: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """(f,) angle (deg) between the triangles ``a b c`` and ``a c d`` of every quad: 0 if planar."""
    q = coords[quads]
    n1 = unit(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]))
    n2 = unit(np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 0]))
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(n1, n2), axis=1), dot(n1, n2)))


def _segment_quads(n: int, idx: np.ndarray) -> np.ndarray:
    """Quad of every boundary segment ``idx[k] -- idx[k + 1]`` (near row j: quad j; far: j)."""
    return np.minimum(idx[:-1], idx[1:]) % (n + 1)


def sheet_orientation(data) -> tuple:
    """Per-plate flips that orient the deployed sheet consistently.

    The orientation is propagated over the creases from the first plate of every connected
    sheet, which is then flipped if its area-weighted mean normal points to world -z
    (:mod:`compas_ccu.fabrication.fold`, "Face orientation").

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
            nz = quad_normals(mid[i], faces[i])[:, 2].sum()
            up += -nz if flips[i] else nz
        if up < 0.0:
            flips[component] = ~flips[component]
    return flips, orientable


def oriented_faces(data, flips) -> np.ndarray:
    """(p, n, 4) quads of ``data.faces`` with those of the plates ``flips`` (p,) bool reversed."""
    faces = np.array(data.faces, dtype=np.int64)
    faces[flips] = faces[flips][:, :, ::-1]
    return faces


def crease_fold_angles(data) -> dict[int, np.ndarray]:
    """Signed FOLD fold angle of every crease segment, measured at the design state.

    The plates are oriented consistently (:func:`sheet_orientation`); the angle of segment ``k`` is
    ``atan2(-(nL x nR) . e, nL . nR)`` between the quad normals of plates a (left) and b along
    the segment direction ``e`` of plate a's oriented quad. It only depends on each plate's own
    mid-surface, so it does not need the hinge vertices to coincide.

    Parameters
    ----------
    data : FabricationData

    Returns
    -------
    dict of int to ndarray
        ``{crease id: (m - 1,) float}``, degrees: positive valley, negative mountain, 0 when the
        sign is ambiguous. About ``180 - fold_angle`` in magnitude.
    """
    flips, _ = sheet_orientation(data)
    faces = oriented_faces(data, flips)
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
        nl, nr = unit(quad_normals(mid[a], qa)), unit(quad_normals(mid[b], qb))
        out[c["id"]] = _signed_angle(nl, nr, unit(mid[a, v] - mid[a, u]))
    return out
