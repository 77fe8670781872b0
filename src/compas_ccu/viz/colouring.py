"""The colours of a scene's faces: plywood tones by plate, or a value field.

:func:`scene_colouring` gives every painted face its colour for a ``color_by`` of
:func:`compas_ccu.viz.render.draw_scene`: the plates in plywood tones (creases by kind), the
plates by their bending curvature, the creases by the reflection angle α, or any per-vertex or
per-face array. A per-vertex field is painted on bilinear sub-quads (like Gouraud shading), as
many as its change across a quad needs (:data:`SUBDIVISIONS` at most).
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.strips.curvature import plate_curvature
from compas_ccu.tolerances import DIVISION_FLOOR, EXACT_RELATIVE
from compas_ccu.viz import colors as C
from compas_ccu.viz.colour_scale import value_mappable

__all__ = ["COLOR_MODES", "SUBDIVISIONS", "scene_colouring"]

COLOR_MODES = ("kind", "curvature", "alpha")


def _values_per(values, scene) -> tuple:
    """``("vertex", (p, v))`` or ``("face", (p, n))`` values of a colouring array."""
    p, n = scene.faces.shape[:2]
    values = np.asarray(values, dtype=float)
    if values.shape == (p, n):
        return "face", values
    if values.shape == scene.vertices.shape[:2]:
        return "vertex", values
    raise OptionError(
        f"per-vertex values must have shape {scene.vertices.shape[:2]} (plates, vertices) or "
        f"{(p, n)} (plates, faces), got {values.shape}"
    )


#: Most sub-quads per quad where a per-vertex field is painted (bilinear, like Gouraud
#: shading); they go to the quad direction(s) along which the field changes.
SUBDIVISIONS = 16
_COLOUR_STEP = 1.0 / 8.0  # largest change of a field within one sub-quad, of its colour range


def _divisions(corner_values: np.ndarray, span: float) -> tuple:
    """Sub-quads along the two quad directions (corner 0 -> 1, corner 0 -> 3): enough that no
    sub-quad spans more than 1/8 of the colour range, at most :data:`SUBDIVISIONS` in all.

    Examples
    --------
    >>> _divisions(np.array([[0.0, 0.0, 1.0, 1.0]]), 1.0)  # changes along 0 -> 3 only
    (1, 8)
    >>> _divisions(np.array([[0.0, 1.0, 2.0, 1.0]]), 1.0)
    (4, 4)
    """
    v = np.asarray(corner_values, dtype=float)
    step = _COLOUR_STEP * max(span, DIVISION_FLOOR)
    along_u = np.nanmax(np.abs(np.r_[v[:, 1] - v[:, 0], v[:, 2] - v[:, 3]]), initial=0.0)
    along_v = np.nanmax(np.abs(np.r_[v[:, 3] - v[:, 0], v[:, 2] - v[:, 1]]), initial=0.0)
    su, sv = (max(1, math.ceil(x / step - EXACT_RELATIVE)) for x in (along_u, along_v))
    while su * sv > SUBDIVISIONS:  # share the budget in proportion
        su, sv = (max(1, x - 1) if x >= y else x for x, y in ((su, sv), (sv, su)))
    return int(su), int(sv)


def _subdivide(quads: np.ndarray, corner_values: np.ndarray, su: int, sv: int) -> tuple:
    """Split quads into ``su x sv`` bilinear sub-quads with the field at their centres.

    Parameters
    ----------
    quads : (q, 4, 3) float
    corner_values : (q, 4) float
    su, sv : int
        Sub-quads along the quad directions corner 0 -> 1 and corner 0 -> 3.

    Returns
    -------
    sub : (q, su * sv, 4, 3) float
    values : (q, su * sv) float
        The bilinear interpolation of the corner values at every sub-quad's centre.
    """
    tu, tv = np.arange(su + 1) / su, np.arange(sv + 1) / sv
    i, j = np.meshgrid(np.arange(su), np.arange(sv), indexing="ij")
    i, j = i.ravel(), j.ravel()
    # (su*sv, 4) parameters (u, v) of the sub-quad corners, counter-clockwise like the quad
    u = np.stack([tu[i], tu[i + 1], tu[i + 1], tu[i]], axis=1)
    v = np.stack([tv[j], tv[j], tv[j + 1], tv[j + 1]], axis=1)

    def weights(u, v):  # bilinear weights of the quad corners 0, 1, 2, 3
        return np.stack([(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v], axis=-1)

    sub = np.einsum("kcq,fqd->fkcd", weights(u, v), quads)
    centre = weights((tu[i] + tu[i + 1]) / 2, (tv[j] + tv[j + 1]) / 2)  # (su*sv, 4)
    return sub, corner_values @ centre.T


def scene_colouring(scene, color_by, cmap, vmin, vmax, quads, normals) -> tuple:
    """The painted faces and their colours by ``color_by``.

    Parameters
    ----------
    scene : compas_ccu.viz.scene.Scene
    color_by, cmap, vmin, vmax
        As :func:`compas_ccu.viz.render.draw_scene` takes them.
    quads : (q, 4, 3) float
        The scene's quads, plate after plate.
    normals : (q, 3) float
        Their unit normals.

    Returns
    -------
    face_polys : (f, 4, 3) float
        The quads, or their sub-quads where a per-vertex field is painted.
    face_rgb : (f, 3) float
        Their colours (not yet shaded).
    normals : (f, 3) float
        Their normals.
    mappable : matplotlib.cm.ScalarMappable or None
    crease_values : list of (k_i,) float or None
        The value of every crease segment (``color_by="alpha"``).
    """
    p, n = scene.faces.shape[:2]
    mappable = None
    face_rgb = np.repeat(np.array([C.hex_to_rgb(C.plate_tone(i)) for i in range(p)]), n, axis=0)
    crease_values = None
    values = None  # (q,) per face, or (q, 4) per quad corner (painted on sub-quads)
    if isinstance(color_by, str):
        if color_by not in COLOR_MODES:
            raise OptionError(
                f"color_by must be one of {COLOR_MODES} or an array, got {color_by!r}"
            )
        if color_by == "curvature":
            corner = np.abs(plate_curvature(scene.vertices))
            values = corner[np.arange(p)[:, None, None], scene.faces].reshape(-1, 4)
            cmap = cmap or C.SEQUENTIAL_CMAP
        elif color_by == "alpha":
            crease_values = [0.5 * (a[1:] + a[:-1]) for a in scene.crease_alpha]
            cmap = cmap or C.ANGLE_CMAP
    else:
        where, given = _values_per(color_by, scene)
        if where == "vertex":
            values = given[np.arange(p)[:, None, None], scene.faces].reshape(-1, 4)
        else:
            values = given.ravel()
        cmap = cmap or C.SEQUENTIAL_CMAP
    face_polys = quads
    if values is not None:
        # the colour range is that of the values themselves (vertex values, not face means)
        mappable = value_mappable(values, vmin, vmax, cmap)
        if values.ndim == 2:
            su, sv = _divisions(values, mappable.norm.vmax - mappable.norm.vmin)
            face_polys, sub_values = _subdivide(quads, values, su, sv)
            face_rgb = mappable.to_rgba(sub_values.ravel())[:, :3]
            normals = np.repeat(normals, su * sv, axis=0)
            face_polys = face_polys.reshape(-1, 4, 3)
        else:
            face_rgb = mappable.to_rgba(values)[:, :3]
    if crease_values is not None and crease_values:
        mappable = value_mappable(np.concatenate(crease_values), vmin, vmax, cmap)
    return face_polys, face_rgb, normals, mappable, crease_values
