"""Closed triangle meshes of the thick plates, and OBJ / binary glTF writers.

Every plate of a :class:`~compas_ccu.fabrication.data.FabricationData` is a thick solid bounded
by its lower and upper faces (``data.solids[i, 0]`` / ``[i, 1]``, plate vertex layout of
:mod:`compas_ccu.fabrication.data`), the near- and far-boundary side strips and the two end caps
(rulings ``0`` and ``n``). :func:`solid_mesh` closes it into a watertight, outward-oriented
triangle mesh; :func:`write_obj` and :func:`write_gltf` write one named mesh per plate.

Units: metres. OBJ keeps doubles (``%.17g``: the file round-trips every coordinate exactly);
glTF stores vertex positions as float32 by specification (about 0.1 µm at a few metres, ample
for viewing, not for fabrication: use the OBJ or the 3DM for that).

Axes. The OBJ files keep the design's world coordinates (Z up, as Rhino). glTF is Y up by
specification, so :func:`write_gltf` rotates every vertex by -90 degrees about X
(:data:`Z_UP_TO_Y_UP`: glTF ``(x, y, z)`` = world ``(x, z, -y)``): a proper rotation, so the
triangles stay outward-oriented, and a viewer shows the vault standing upright.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from compas_ccu.kinematics.plates import plate_quads

__all__ = [
    "Z_UP_TO_Y_UP",
    "boundary_loop",
    "crease_line",
    "layout_offsets",
    "plate_solids",
    "signed_volume",
    "solid_mesh",
    "write_gltf",
    "write_obj",
]

_STATES = ("deployed", "stack")

#: World (Z up) to glTF (Y up): -90 degrees about X, ``(x, y, z) -> (x, z, -y)``; row-vector
#: points are mapped by ``points @ Z_UP_TO_Y_UP.T``.
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


def boundary_loop(n: int) -> np.ndarray:
    """(2n + 2,) int: plate vertex indices around the outline, near row then far row back.

    ``0, 1, .., n, 2n + 1, 2n, .., n + 1``: the same order as
    :meth:`FabricationData.outline <compas_ccu.fabrication.data.FabricationData.outline>`.
    """
    return np.r_[np.arange(n + 1), np.arange(2 * n + 1, n, -1)]


def _split(quads: np.ndarray) -> np.ndarray:
    """(2q, 3) int: every quad ``[a, b, c, d]`` as ``[a, b, c]`` and ``[a, c, d]``."""
    return np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]], axis=0)


def signed_volume(vertices: np.ndarray, triangles: np.ndarray) -> float:
    """Signed volume of a closed triangle mesh (positive when oriented outward).

    Parameters
    ----------
    vertices : (v, 3) float
    triangles : (t, 3) int

    Returns
    -------
    float
        ``sum(det[a, b, c]) / 6`` (m³ for vertices in m).
    """
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def solid_mesh(lower, upper) -> tuple:
    """Closed, outward-oriented triangle mesh of one thick plate.

    Parameters
    ----------
    lower, upper : (2n + 2, 3) float
        The two face vertex arrays of the plate (plate vertex layout: near boundary ``0 .. n``,
        far boundary ``n + 1 .. 2n + 1``). ``upper`` may lie on either side of ``lower``.

    Returns
    -------
    vertices : (4n + 4, 3) float
        ``lower`` then ``upper`` (vertex ``k`` of the upper face is ``2n + 2 + k``).
    triangles : (8n + 4, 3) int
        ``2n`` triangles per face (quad ``j`` split along its ``j -- n + 2 + j`` diagonal),
        then the side band around the outline (near strip, end cap at ruling ``n``, far strip,
        end cap at ruling ``0``), two triangles per outline edge. Every edge is shared by
        exactly two triangles traversing it in opposite directions, and the orientation is
        chosen so that the signed volume is positive (normals point out of the solid).

    Raises
    ------
    ValueError
        If the arrays do not have the plate layout or the solid has zero volume.

    Examples
    --------
    >>> import numpy as np
    >>> lower = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> v, t = solid_mesh(lower, lower + [0, 0, 0.01])
    >>> v.shape, t.shape, round(signed_volume(v, t), 6)
    ((8, 3), (12, 3), 0.01)
    >>> v, t = solid_mesh(lower, lower - [0, 0, 0.01])
    >>> round(signed_volume(v, t), 6)
    0.01
    """
    lower = np.asarray(lower, dtype=float)
    upper = np.asarray(upper, dtype=float)
    if lower.ndim != 2 or lower.shape[1] != 3 or lower.shape != upper.shape:
        raise ValueError(
            f"lower and upper must both be (2n + 2, 3), got {lower.shape}, {upper.shape}"
        )
    v = lower.shape[0]
    if v < 4 or v % 2:
        raise ValueError(f"a plate has 2n + 2 >= 4 vertices, got {v}")
    n = v // 2 - 1
    quads = plate_quads(n)
    faces = np.concatenate([_split(quads), _split(quads[:, ::-1] + v)], axis=0)
    # side band: for every directed outline edge a -> b of the lower face (the lower quads run
    # along the outline in this order), the side quad [b, a, v + a, v + b] traverses it the
    # other way, and its neighbours' shared vertical edges cancel too.
    loop = boundary_loop(n)
    a, b = loop, np.roll(loop, -1)
    sides = _split(np.stack([b, a, a + v, b + v], axis=1))
    triangles = np.concatenate([faces, sides], axis=0).astype(np.int64)
    vertices = np.concatenate([lower, upper], axis=0)
    vol = signed_volume(vertices, triangles)
    if not vol:
        raise ValueError("the solid has zero volume (upper == lower?)")
    if vol < 0.0:
        triangles = triangles[:, ::-1].copy()
    return vertices, triangles


def plate_solids(data, *, state: str = "deployed") -> list:
    """Closed solid meshes of every plate.

    Parameters
    ----------
    data : FabricationData
    state : {"deployed", "stack"}
        ``"deployed"``: ``data.solids`` (design state); ``"stack"``: ``data.stack_solids``
        (flat-folded stack).

    Returns
    -------
    list of (str, (4n + 4, 3) float, (t, 3) int)
        ``("plate_<id>", vertices, triangles)`` per plate, in array order.
    """
    if state not in _STATES:
        raise ValueError(f"state must be one of {_STATES}, got {state!r}")
    solids = np.asarray(data.solids if state == "deployed" else data.stack_solids, dtype=float)
    out = []
    for i, pid in enumerate(data.plate_ids):
        vertices, triangles = solid_mesh(solids[i, 0], solids[i, 1])
        out.append((f"plate_{pid}", vertices, triangles))
    return out


def crease_line(data, crease: dict, *, state: str = "deployed") -> tuple:
    """Where the two plates of a crease meet: the hinge line.

    Thick plates do not meet along their mid-surfaces: the hinge lies on the two facing faces,
    which share their crease edge (:mod:`compas_ccu.thickness.axis_shift`), while the
    mid-surfaces are up to a thickness apart there. Of the five candidate pairs of crease rows
    (lower / upper face of either plate, and the two mid-surfaces), the closest pair is taken
    and the line is their mean (exactly the shared edge when the faces meet).

    Parameters
    ----------
    data : FabricationData
    crease : dict
        One of ``data.creases``.
    state : {"deployed", "stack"}, keyword-only

    Returns
    -------
    points : (m, 3) float
        The hinge line, in the order of ``crease["vertices"]``.
    gap : float
        Largest distance between the two chosen rows, m (0 when the faces meet).
    where : str
        ``"lower-upper"`` style face names of plates a and b, or ``"mid-mid"``.
    """
    if state not in _STATES:
        raise ValueError(f"state must be one of {_STATES}, got {state!r}")
    solids = np.asarray(data.solids if state == "deployed" else data.stack_solids, dtype=float)
    a, b = (data.index(pid) for pid in crease["plates"])
    ia, ib = (np.asarray(v, dtype=np.int64) for v in crease["vertices"])
    rows_a = {"lower": solids[a, 0, ia], "upper": solids[a, 1, ia]}
    rows_b = {"lower": solids[b, 0, ib], "upper": solids[b, 1, ib]}
    candidates = [(f"{fa}-{fb}", rows_a[fa], rows_b[fb]) for fa in rows_a for fb in rows_b]
    candidates.append(
        (
            "mid-mid",
            0.5 * (rows_a["lower"] + rows_a["upper"]),
            0.5 * (rows_b["lower"] + rows_b["upper"]),
        )
    )
    gaps = [float(np.linalg.norm(pa - pb, axis=1).max()) for _, pa, pb in candidates]
    k = int(np.argmin(gaps))
    where, pa, pb = candidates[k]
    return 0.5 * (pa + pb), gaps[k], where


def layout_offsets(data, *, gap: float = 0.1) -> np.ndarray:
    """Offsets that lay the cut patterns side by side in x without overlap.

    Plate ``i`` (array order) is drawn at ``data.flat[i] + offsets[i]``: its bounding box starts
    at ``y = 0`` and ``gap`` after the previous plate's box in x (the first box starts at
    ``x = 0``).

    Parameters
    ----------
    data : FabricationData
    gap : float, keyword-only
        Clear distance between consecutive bounding boxes, m.

    Returns
    -------
    (p, 2) float
        Translation of every plate, m.
    """
    flat = np.asarray(data.flat, dtype=float)
    lo, hi = flat.min(axis=1), flat.max(axis=1)
    width = hi[:, 0] - lo[:, 0]
    start = np.r_[0.0, np.cumsum(width + gap)[:-1]]
    return np.stack([start - lo[:, 0], -lo[:, 1]], axis=1)


def write_obj(data, path, *, state: str = "deployed") -> Path:
    """Write the closed plate solids as a Wavefront OBJ, one object per plate.

    Each plate is ``o plate_<id>`` (and group ``g plate_<id>``) with its ``4n + 4`` vertices
    (:func:`solid_mesh` order: lower face then upper face) and outward triangles; coordinates in
    metres, ``%.17g`` (exact round trip of the doubles).

    Parameters
    ----------
    data : FabricationData
    path : str or Path
    state : {"deployed", "stack"}, keyword-only
        Design state (``data.solids``) or flat-folded stack (``data.stack_solids``).

    Returns
    -------
    Path
    """
    path = Path(path)
    meshes = plate_solids(data, state=state)
    lines = [
        f"# compas_ccu: {data.name}, state {state}, alpha {data.alpha!r} deg",
        f"# thickness {data.thickness!r} m, material {data.material}; units: metres",
        f"# {len(meshes)} closed plate solids, outward-oriented triangles",
    ]
    base = 1
    for name, vertices, triangles in meshes:
        lines += [f"o {name}", f"g {name}"]
        lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in vertices.tolist()]
        lines += [f"f {a} {b} {c}" for a, b, c in (triangles + base).tolist()]
        base += len(vertices)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963


def _buffer_view_targets(tree: dict) -> None:
    """Set every mesh buffer view's ``target`` (vertex / index data) in a glTF JSON tree.

    Optional in glTF, but the Khronos validator hints at every view without it; trimesh leaves
    it out (its ``tree_postprocessor`` hook calls this before packing the GLB).
    """
    views = tree.get("bufferViews", [])
    accessors = tree.get("accessors", [])
    for mesh in tree.get("meshes", []):
        for primitive in mesh.get("primitives", []):
            for accessor in primitive.get("attributes", {}).values():
                views[accessors[accessor]["bufferView"]]["target"] = _ARRAY_BUFFER
            if "indices" in primitive:
                views[accessors[primitive["indices"]]["bufferView"]]["target"] = (
                    _ELEMENT_ARRAY_BUFFER
                )


def write_gltf(data, path, *, state: str = "deployed") -> Path:
    """Write the closed plate solids as a binary glTF (``.glb``) through trimesh.

    One scene node and one mesh per plate, both named ``plate_<id>``, identity transforms.
    glTF is metres and Y up by specification: the vertices are the world coordinates rotated by
    :data:`Z_UP_TO_Y_UP` (glTF ``(x, y, z)`` = world ``(x, z, -y)``; world = glTF
    ``(x, -z, y)``). Vertex positions are float32 (about 1e-7 relative, so ~0.3 µm at 2.5 m):
    fine for viewing and AR, not a fabrication reference.

    Parameters
    ----------
    data : FabricationData
    path : str or Path
    state : {"deployed", "stack"}, keyword-only

    Returns
    -------
    Path
    """
    import trimesh

    path = Path(path)
    scene = trimesh.Scene()
    for name, vertices, triangles in plate_solids(data, state=state):
        mesh = trimesh.Trimesh(vertices=vertices @ Z_UP_TO_Y_UP.T, faces=triangles, process=False)
        scene.add_geometry(mesh, node_name=name, geom_name=name)
    scene.metadata.update(
        {
            "name": data.name,
            "state": state,
            "alpha": float(data.alpha),
            "thickness": float(data.thickness),
            "material": data.material,
            "unit": "m",
            "up": "+Y (world +Z; glTF (x, y, z) = world (x, z, -y))",
        }
    )
    path.write_bytes(scene.export(file_type="glb", tree_postprocessor=_buffer_view_targets))
    return path
