"""The scene data of the viewer: the arrays of every state drawn, before any plotly object.

:func:`path_data` computes the deployment path once and keeps, for every grounded state, the
coordinates of its plates, plate edges, creases (one polyline set per kind) and rulings
(:class:`ViewerData`); :func:`cut_pattern_places` lays the flat-folded plates on the ground
behind the structure and :func:`sheet_places` the fabrication's sheets around it. The traces
drawn from these arrays are :mod:`compas_ccu.viz.viewer_traces`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.kinematics.plates import plate_rulings
from compas_ccu.viz.colors import plate_tone
from compas_ccu.viz.scene import Scene, scene_from_structure
from compas_ccu.viz.viewer_ground import cut_pattern_layout, sheet_grid_layout

__all__ = [
    "ViewerData",
    "path_data",
    "cut_pattern_places",
    "sheet_places",
    "polylines",
    "KIND_ORDER",
    "MAX_RULINGS",
]

#: Order of the crease kinds (their traces and legend entries); other kinds follow, sorted.
KIND_ORDER = ("synclastic", "anticlastic", "ccf", "mixed")
#: Rulings drawn per plate (every k-th ruling, both ends always).
MAX_RULINGS = 32


# -- geometry helpers (vectorised) -----------------------------------------------------------
def polylines(lines) -> np.ndarray:
    """(m, 3) points of several polylines, each followed by a NaN row (a gap in the line).

    Parameters
    ----------
    lines : sequence of (k_i, 3) float, or (q, k, 3) float

    Returns
    -------
    (sum(k_i + 1), 3) float
    """
    if isinstance(lines, np.ndarray) and lines.ndim == 3:
        q, k, _ = lines.shape
        out = np.full((q, k + 1, 3), np.nan)
        out[:, :k] = lines
        return out.reshape(-1, 3)
    if len(lines) == 0:
        return np.zeros((0, 3))
    gap = np.full((1, 3), np.nan)
    return np.concatenate([np.concatenate([np.asarray(pts, float), gap]) for pts in lines])


def _ruling_index(n: int) -> np.ndarray:
    """Rulings drawn: at most ``MAX_RULINGS`` per plate, evenly spaced, both ends included."""
    count = min(n + 1, MAX_RULINGS)
    return np.unique(np.round(np.linspace(0, n, count)).astype(int))


def _triangles(faces: np.ndarray, v: int) -> np.ndarray:
    """(2 p n, 3) triangle indices into the (p v,) stacked vertices, two per quad.

    Parameters
    ----------
    faces : (p, n, 4) int
        Quad vertex indices per plate.
    v : int
        Vertices per plate.
    """
    p = faces.shape[0]
    glob = faces + (np.arange(p) * v)[:, None, None]
    tri = np.stack([glob[..., [0, 1, 2]], glob[..., [0, 2, 3]]], axis=2)  # (p, n, 2, 3)
    return tri.reshape(-1, 3)


def _edge_index(structure, n: int) -> np.ndarray:
    """(m,) gather index of the plate edges that no crease line draws, ``-1`` for a gap.

    Free boundaries (a near or far boundary that is not a crease) and the two end rulings of
    every plate, as polylines into the ``(p v, 3)`` stacked vertices.
    """
    p = len(structure.plate_ids)
    rulings = plate_rulings(n)
    v = rulings.size  # vertices of one plate
    index = {pid: i for i, pid in enumerate(structure.plate_ids)}
    near, far = rulings.T
    creased = set()
    for c in structure.creases:
        for plate, verts in zip(c["plates"], c["vertices"]):
            creased.add((index[plate], "near" if int(verts[0]) == 0 else "far"))
    parts = []
    for i in range(p):
        lines = [rulings[0], rulings[-1]]  # the two end rulings
        lines += [b for name, b in (("near", near), ("far", far)) if (i, name) not in creased]
        parts += [np.r_[i * v + line, -1] for line in lines]
    return np.concatenate(parts)


def _gather(points: np.ndarray, index: np.ndarray) -> np.ndarray:
    """(m, 3) rows ``points[index]``, NaN where ``index < 0``."""
    out = points[np.maximum(index, 0)].astype(float)
    out[index < 0] = np.nan
    return out


def _state_data(scene, edges: np.ndarray, rulings_at: np.ndarray, kinds: list) -> dict:
    """Coordinates of the state-dependent traces of one grounded scene.

    Parameters
    ----------
    scene : compas_ccu.viz.scene.Scene
    edges : (m,) int
        :func:`_edge_index` of the structure.
    rulings_at : (r,) int
        Rulings drawn per plate.
    kinds : list of str
        Crease kinds, one trace each.

    Returns
    -------
    dict
        ``plates`` (p v, 3), ``edges`` (m, 3), ``rulings`` (3 p r, 3) and one ``(.., 3)`` array
        per crease kind (NaN rows separate polylines).
    """
    p, v, _ = scene.vertices.shape
    stacked = scene.vertices.reshape(p * v, 3)
    out = {
        "plates": stacked,
        "edges": _gather(stacked, edges),
        "rulings": polylines(scene.rulings[:, rulings_at].reshape(-1, 2, 3)),
    }
    for kind in kinds:
        out[kind] = polylines([c["points"] for c in scene.creases if c["kind"] == kind])
    return out


@dataclass
class ViewerData:
    """The arrays of the viewer: every state of a deployment path, grounded.

    Attributes
    ----------
    alphas : (m,) float
        The states' reference reflection angles, degrees.
    structures : list of compas_ccu.structure.Structure
        One per state.
    scenes : list of compas_ccu.viz.scene.Scene
        The grounded scenes of the states (lowest point on ``z = 0``).
    flat : compas_ccu.viz.scene.Scene
        The flat-folded stack of the last state (the cut patterns).
    kinds : list of str
        The crease kinds present, in :data:`KIND_ORDER`: one trace each.
    counts : dict
        Creases per kind.
    rulings_at : (r,) int
        The rulings drawn of every plate.
    states : list of dict
        Per state: ``plates`` (p v, 3), ``edges`` (m, 3), ``rulings`` and one array per crease
        kind (NaN rows separate polylines).
    lo, hi : (3,) float
        The box over all states.
    size : float
        Its diagonal, m.
    tones : list of str
        The plates' colours.
    triangles : (2 p n, 3) int
        Two triangles per quad into the ``(p v,)`` stacked vertices.
    facecolor : (2 p n,) str
        The colour of every triangle (its plate's tone).
    plate_text : (p v,) str
        The hover text of every vertex (``"plate <id>"``).
    """

    alphas: np.ndarray
    structures: list
    scenes: list
    flat: Scene
    kinds: list
    counts: dict
    rulings_at: np.ndarray
    states: list
    lo: np.ndarray
    hi: np.ndarray
    size: float
    tones: list
    triangles: np.ndarray
    facecolor: np.ndarray
    plate_text: np.ndarray

    @property
    def segments(self) -> int:
        """Segments per plate."""
        return self.scenes[-1].segments

    @property
    def plate_ids(self) -> list:
        """The plates' ids, in plate order."""
        return self.scenes[-1].plate_ids


def path_data(model, alphas) -> ViewerData:
    """The arrays of the states ``alphas`` of a model's deployment path.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    alphas : (m,) float
        Reference reflection angles, degrees, increasing from 0.

    Returns
    -------
    ViewerData

    Raises
    ------
    compas_ccu.errors.DeploymentLimitError, compas_ccu.errors.SelfIntersectionError
        A state is beyond the deployment limit, or a crease overlaps itself on the way.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> data = path_data(load_model("examples/cone.toml"), np.linspace(0.0, 40.0, 3))
    >>> len(data.states), data.kinds, data.triangles.shape[1]
    (3, ['synclastic'], 3)
    """
    structures = model.path(alphas)
    scenes = [scene_from_structure(s, ground=True) for s in structures]
    flat = scene_from_structure(structures[-1], state="flat")
    last = scenes[-1]
    p, v, _ = last.vertices.shape
    n = last.segments
    counts = structures[-1].crease_kind_counts()
    kinds = [k for k in KIND_ORDER if k in counts] + sorted(
        k for k in counts if k not in KIND_ORDER
    )
    rulings_at = _ruling_index(n)
    edges = _edge_index(structures[-1], n)
    states = [_state_data(s, edges, rulings_at, kinds) for s in scenes]
    # a fixed box over all states
    allv = np.stack([s.vertices for s in scenes]).reshape(-1, 3)
    lo, hi = allv.min(axis=0), allv.max(axis=0)
    tones = [plate_tone(i) for i in range(p)]
    return ViewerData(
        alphas=alphas,
        structures=structures,
        scenes=scenes,
        flat=flat,
        kinds=kinds,
        counts=counts,
        rulings_at=rulings_at,
        states=states,
        lo=lo,
        hi=hi,
        size=float(np.linalg.norm(hi - lo)),
        tones=tones,
        triangles=_triangles(last.faces, v),
        facecolor=np.repeat(tones, 2 * n),
        plate_text=np.repeat([f"plate {pid}" for pid in last.plate_ids], v),
    )


def cut_pattern_places(data: ViewerData, pattern_offsets=None) -> np.ndarray:
    """(p, v, 3) cut patterns on the ground (z = 0) behind the structure (+y), centred in x.

    Parameters
    ----------
    data : ViewerData
    pattern_offsets : (p, 2) float, optional
        Translations of the flat-folded stack's plates; default :func:`cut_pattern_layout`
        (gap: 2 % of the structure's size, the block beside its plan).

    Raises
    ------
    compas_ccu.errors.OptionError
        ``pattern_offsets`` is not one translation per plate.
    """
    lo, hi, size = data.lo, data.hi, data.size
    fv = data.flat.vertices
    p, n = len(fv), data.segments
    if pattern_offsets is None:
        beside = (float(hi[0] - lo[0]), float(hi[1] - lo[1]))
        pattern_offsets = cut_pattern_layout(fv, n, gap=0.02 * size, beside=beside)
    pattern_offsets = np.asarray(pattern_offsets, dtype=float)
    if pattern_offsets.shape != (p, 2):
        raise OptionError(
            f"pattern_offsets must have shape {(p, 2)} (one translation per plate), got "
            f"{pattern_offsets.shape}"
        )
    pattern = fv.copy()
    pattern[..., :2] += pattern_offsets[:, None, :]
    centre = 0.5 * (pattern[..., 0].min() + pattern[..., 0].max())
    shift = np.array(
        [0.5 * (lo[0] + hi[0]) - centre, hi[1] + 0.04 * size - pattern[..., 1].min(), 0.0]
    )
    pattern = pattern + shift
    pattern[..., 2] = 0.0
    return pattern


def sheet_places(data: ViewerData, doc: dict) -> tuple:
    """The sheets of a nesting document in a grid around the structure's plan.

    Parameters
    ----------
    data : ViewerData
    doc : dict
        :func:`compas_ccu.viz.viewer_ground.sheet_document`.

    Returns
    -------
    sizes : (s, 2) float
        Sheet length and width, m.
    corners : (s, 2) float
        Where each sheet's corner lies (:func:`sheet_grid_layout`, gap 4 % of the size).
    """
    lo, hi = data.lo, data.hi
    sizes = np.array([s["size"] for s in doc["sheets"]], dtype=float).reshape(-1, 2)
    corners = sheet_grid_layout(sizes, gap=0.04 * data.size, structure=(lo[0], lo[1], hi[0], hi[1]))
    return sizes, corners
