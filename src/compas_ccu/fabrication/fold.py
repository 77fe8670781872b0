"""FOLD 1.2 output (https://github.com/edemaine/fold): :func:`fold_document`, :func:`write_fold`.

A ``.fold`` file is strict JSON (no NaN / Infinity); floats are written with Python's shortest
round-trip ``repr``, so every coordinate reads back bit-for-bit. ``file_spec`` is 1.2: boundary
edges have ``null`` as their right face in ``edges_faces`` (``[left, null]``), which FOLD allows
since version 1.2; nothing else of 1.2 (join / cut edges) is used. Three frames, all in metres,
with the same faces in the same order (face ``f = i * n + j`` is quad ``j`` of plate ``i``, array
order; a frame is built by :func:`~compas_ccu.fabrication.fold_frame.fold_frame`, the orientation
and the angles measured by :mod:`compas_ccu.fabrication.fold_angles`):

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

from compas_ccu.fabrication.fold_angles import (
    crease_fold_angles,
    oriented_faces,
    sheet_orientation,
)
from compas_ccu.fabrication.fold_frame import fold_frame
from compas_ccu.fabrication.meshes import layout_offsets
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

_HINGES = ("snap", "merge")


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
    flips, orientable = sheet_orientation(data)
    oriented = oriented_faces(data, flips)
    signs = crease_fold_angles(data)
    common = {"hinges": hinges, "merge_tol": merge_tol, "signs": signs, "flips": flips}

    key = fold_frame(data, data.deployed_mid, oriented, state="deployed", **common)
    key["frame_title"] = f"{data.name}: deployed mid-surfaces, alpha = {float(data.alpha):g} deg"
    key["frame_classes"] = ["foldedForm"]

    offsets = layout_offsets(data, gap=gap)
    cp = fold_frame(
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
    stack = fold_frame(data, stack_mid, oriented, state="stack", **common)
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
