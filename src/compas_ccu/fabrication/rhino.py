"""Rhino 3DM output through rhino3dm (lazy import): :func:`write_3dm`, :func:`read_3dm_summary`.

One document in metres with six coloured layers:

========================  ===============================================================
layer                     objects
========================  ===============================================================
``plates``                deployed mid-surfaces, one quad ``Mesh`` per plate, ``plate <id>``
``creases``               deployed hinge lines, ``PolylineCurve``, ``crease <id>``: where
                          the facing faces of the two thick plates meet
                          (:func:`~compas_ccu.fabrication.meshes.crease_line`; user strings
                          ``hinge`` = faces joined, ``hinge_gap`` in m, ``kind``,
                          ``fold_angle``)
``rulings``               deployed interior rulings ``1 .. n - 1``, ``LineCurve``,
                          ``ruling <plate id>.<j>``
``solids``                closed thick plates (:func:`~compas_ccu.fabrication.meshes.solid_mesh`),
                          triangle ``Mesh``, ``solid <id>``
``cut patterns``          closed flat outlines in ``z = 0``, side by side in x
                          (:func:`~compas_ccu.fabrication.meshes.layout_offsets`),
                          ``cut <id>``; the translation is in the user strings
                          ``offset_x`` / ``offset_y`` (m, ``repr``)
``stack``                 the flat-folded stack solids, triangle ``Mesh``, ``stack <id>``
========================  ===============================================================

Every coordinate is written as a double: curves take ``Point3d`` and mesh vertices are added with
``AddPoint3d`` to double-precision vertex lists (rhino3dm's ``Vertices.Add`` would round to
float32). Plate vertex ``k`` is mesh vertex ``k`` of the ``plates`` meshes (plate vertex layout
of :mod:`compas_ccu.fabrication.data`); ``solids`` / ``stack`` meshes have the
:func:`~compas_ccu.fabrication.meshes.solid_mesh` vertex order (lower face, then upper face).
Document user text: ``design``, ``alpha`` (deg), ``thickness`` (m), ``material``,
``hinge_width`` (m), ``units``, ``creator``.

Every layer and object has a fixed id (a name-based UUID of the design's name and the
object's name, :func:`object_id`), where rhino3dm would draw a random one, so two writes of one
design give the same objects. What still differs between two writes is what rhino3dm stamps
and offers no setter for: the file's path and the minute it was created and last edited
(openNURBS' revision history).
"""

from __future__ import annotations

import uuid
from pathlib import Path

import numpy as np

from compas_ccu.fabrication.meshes import crease_line, layout_offsets, solid_mesh
from compas_ccu.kinematics.plates import plate_rulings
from compas_ccu.outputs import name_id

__all__ = ["LAYERS", "read_3dm_summary", "write_3dm"]

#: Layer names and RGBA colours, in document order.
LAYERS = {
    "plates": (214, 168, 98, 255),
    "creases": (200, 30, 30, 255),
    "rulings": (150, 150, 150, 255),
    "solids": (170, 120, 60, 255),
    "cut patterns": (0, 90, 200, 255),
    "stack": (90, 150, 70, 255),
}


def _mesh(rhino3dm, vertices, faces):
    """rhino3dm.Mesh with double-precision vertices (v, 3) and faces (f, 3 | 4)."""
    mesh = rhino3dm.Mesh()
    mesh.Vertices.UseDoublePrecisionVertices = True
    for x, y, z in np.asarray(vertices, dtype=float).tolist():
        mesh.Vertices.AddPoint3d(x, y, z)
    for f in np.asarray(faces, dtype=int).tolist():
        mesh.Faces.AddFace(*f)
    mesh.Normals.ComputeNormals()
    return mesh


def _points(rhino3dm, xyz) -> list:
    return [rhino3dm.Point3d(*p) for p in np.asarray(xyz, dtype=float).tolist()]


def write_3dm(data, path, *, gap: float = 0.1, version: int = 8) -> Path:
    """Write the design as a Rhino 3DM document (metres, six layers, see the module docstring).

    Parameters
    ----------
    data : FabricationData
    path : str or Path
    gap : float, keyword-only
        Clear distance between consecutive cut patterns on the ``cut patterns`` layer, m.
    version : int, keyword-only
        3DM archive version (8 = Rhino 8; 7 for older Rhinos).

    Returns
    -------
    Path
    """
    import rhino3dm

    path = Path(path)
    model = rhino3dm.File3dm()
    model.Settings.ModelUnitSystem = rhino3dm.UnitSystem.Meters
    for key, value in (
        ("design", data.name),
        ("alpha", repr(float(data.alpha))),
        ("thickness", repr(float(data.thickness))),
        ("material", str(data.material)),
        ("hinge_width", repr(float(data.hinge_width))),
        ("units", "m, deg"),
        ("creator", "compas_ccu"),
    ):
        model.Strings[key] = value

    layer = {}
    for name, colour in LAYERS.items():
        lay = rhino3dm.Layer()
        lay.Name = name
        lay.Color = colour
        lay.Id = object_id(data.name, f"layer {name}")
        layer[name] = model.Layers.Add(lay)

    def attributes(layer_name, name, **strings):
        att = rhino3dm.ObjectAttributes()
        att.LayerIndex = layer[layer_name]
        att.Name = name
        att.Id = object_id(data.name, name)
        for k, v in strings.items():
            att.SetUserString(k, str(v))
        return att

    n = data.segments
    mid = np.asarray(data.deployed_mid, dtype=float)
    solids = np.asarray(data.solids, dtype=float)
    stack = np.asarray(data.stack_solids, dtype=float)
    offsets = layout_offsets(data, gap=gap)
    for i, pid in enumerate(data.plate_ids):
        model.Objects.AddMesh(
            _mesh(rhino3dm, mid[i], data.faces[i]),
            attributes("plates", f"plate {pid}", plate=pid, stack_position=data.stack_position[i]),
        )
        for j, ends in enumerate(plate_rulings(n)[1:-1], start=1):
            line = rhino3dm.LineCurve(*_points(rhino3dm, mid[i, ends]))
            model.Objects.AddCurve(line, attributes("rulings", f"ruling {pid}.{j}", plate=pid))
        v, t = solid_mesh(solids[i, 0], solids[i, 1])
        model.Objects.AddMesh(
            _mesh(rhino3dm, v, t), attributes("solids", f"solid {pid}", plate=pid)
        )
        v, t = solid_mesh(stack[i, 0], stack[i, 1])
        model.Objects.AddMesh(_mesh(rhino3dm, v, t), attributes("stack", f"stack {pid}", plate=pid))
        outline = data.outline(i) + offsets[i]
        closed = np.concatenate([outline, outline[:1]], axis=0)
        xyz = np.column_stack([closed, np.zeros(len(closed))])
        model.Objects.AddCurve(
            rhino3dm.PolylineCurve(_points(rhino3dm, xyz)),
            attributes(
                "cut patterns",
                f"cut {pid}",
                plate=pid,
                offset_x=repr(float(offsets[i, 0])),
                offset_y=repr(float(offsets[i, 1])),
            ),
        )
    for c in data.creases:
        a, b = c["plates"]
        pts, gap, where = crease_line(data, c)
        model.Objects.AddCurve(
            rhino3dm.PolylineCurve(_points(rhino3dm, pts)),
            attributes(
                "creases",
                f"crease {c['id']}",
                plates=f"{a} {b}",
                kind=c["kind"],
                fold_angle=repr(float(c["fold_angle"])),
                hinge=where,
                hinge_gap=repr(gap),
            ),
        )
    path.parent.mkdir(parents=True, exist_ok=True)
    if not model.Write(str(path), version):
        raise OSError(f"rhino3dm could not write {path}")
    return path


def object_id(design: str, name: str) -> uuid.UUID:
    """The fixed id of object (or layer) ``name`` of design ``design`` in a 3DM file.

    >>> str(object_id("vault", "plate 0")) == str(object_id("vault", "plate 0"))
    True
    >>> object_id("vault", "plate 0") == object_id("dome", "plate 0")
    False
    """
    return name_id(design, name)


def read_3dm_summary(path) -> dict:
    """What a 3DM file holds, for tests and users.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    dict
        ``units`` (e.g. ``"Meters"``), ``user_text`` (document user text, dict), and ``layers``:
        ``{layer name: {"count": int, "names": [object names], "types": [geometry class
        names], "color": (r, g, b, a)}}`` in layer order.
    """
    import rhino3dm

    model = rhino3dm.File3dm.Read(str(path))
    if model is None:
        raise OSError(f"rhino3dm could not read {path}")
    layers = {}
    by_index = {}
    for k in range(len(model.Layers)):
        lay = model.Layers[k]
        entry = {"count": 0, "names": [], "types": [], "color": tuple(lay.Color)}
        layers[lay.Name] = entry
        by_index[lay.Index] = entry
    for obj in model.Objects:
        entry = by_index.get(obj.Attributes.LayerIndex)
        if entry is None:
            continue
        entry["count"] += 1
        entry["names"].append(obj.Attributes.Name)
        entry["types"].append(type(obj.Geometry).__name__)
    user_text = dict(model.Strings[k] for k in range(len(model.Strings)))
    units = str(model.Settings.ModelUnitSystem).split(".")[-1]
    return {"units": units, "user_text": user_text, "layers": layers}
