"""The studio's 3D scene: a :class:`~compas_ccu.studio.view.ViewState` sent to viser.

The scene objects are created once per model and then only their vertex arrays (and colours)
are updated, so a slider step sends a few kilobytes: one mesh per plate, one line-segment set for
the creases and one for the rulings, and on demand the thick solids, the flat-folded stack, the
cut patterns on the ground and the ground grid. Names live under ``/ccu``.
"""

from __future__ import annotations

import json
import struct

import numpy as np

from compas_ccu.studio.view import ViewState
from compas_ccu.viz import colors as C
from compas_ccu.viz.patterns import pattern_layout

__all__ = ["StudioScene", "TOGGLES", "colored_glb"]

#: The layers of the view: key, label, shown at start.
TOGGLES = (
    ("creases", "creases", True),
    ("rulings", "rulings", True),
    ("solids", "thick solids", False),
    ("flat", "flat stack", False),
    ("patterns", "cut patterns", False),
    ("grid", "ground grid", True),
)
CREASE_WIDTH = 4.0  # screen pixels
RULING_WIDTH = 1.0


def _rgb(color: str) -> tuple:
    return tuple(int(round(255 * c)) for c in C.hex_to_rgb(color))


def _f32(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float32)


def _linear(colors) -> np.ndarray:
    """sRGB colours (uint8) as the linear values three.js expects for vertex colours, so a line
    is drawn in the colour its legend shows (mesh colours are converted by three.js itself)."""
    c = np.asarray(colors, dtype=float) / 255.0
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return np.ascontiguousarray(np.round(lin * 255.0), dtype=np.uint8)


def _set_faces(handle, triangles) -> None:
    """Send a mesh node's triangles only when they changed (a new model of the same layout
    has the same ones: only its vertex buffer is sent)."""
    faces = np.asarray(triangles).astype(np.uint32)
    if not np.array_equal(handle.faces, faces):
        handle.faces = faces


def _stacked(vertices: np.ndarray, triangles: np.ndarray):
    """One mesh of all plates: (p * v, 3) vertices and (p * 2n, 3) triangles."""
    offsets = (np.arange(len(vertices)) * vertices.shape[1])[:, None, None]
    return vertices.reshape(-1, 3), (triangles + offsets).reshape(-1, 3)


def colored_glb(vertices, triangles, colors) -> bytes:
    """A binary glTF (GLB) of one triangle mesh with a colour per vertex (viser 1.1's
    ``add_mesh_simple`` takes one colour per mesh; its GLB node takes ``COLOR_0``).

    Parameters
    ----------
    vertices : (n, 3) float
    triangles : (t, 3) int
    colors : (n, 3) uint8
        sRGB colours (converted to the linear values glTF holds, so the plates show the
        legend's colours).

    Returns
    -------
    bytes
    """
    v = _f32(vertices).reshape(-1, 3)
    t = np.ascontiguousarray(triangles, dtype=np.uint32).reshape(-1)
    rgba = np.full((len(v), 4), 255, dtype=np.uint8)
    rgba[:, :3] = _linear(np.asarray(colors).reshape(-1, 3))
    chunks = [v.tobytes(), rgba.tobytes(), t.tobytes()]
    offsets = np.cumsum([0] + [len(c) for c in chunks])  # each a multiple of 4 bytes
    views = [
        {"buffer": 0, "byteOffset": int(o), "byteLength": len(c), "target": target}
        for o, c, target in zip(offsets, chunks, (34962, 34962, 34963))
    ]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": len(v), "type": "VEC3",
         "min": v.min(axis=0).tolist(), "max": v.max(axis=0).tolist()},
        {"bufferView": 1, "componentType": 5121, "normalized": True, "count": len(v),
         "type": "VEC4"},
        {"bufferView": 2, "componentType": 5125, "count": len(t), "type": "SCALAR"},
    ]  # fmt: skip
    gltf = {
        "asset": {"version": "2.0", "generator": "compas_ccu studio"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1},
                                    "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
                       "metallicFactor": 0.0, "roughnessFactor": 1.0}, "doubleSided": True}],
        "buffers": [{"byteLength": int(offsets[-1])}],
        "bufferViews": views,
        "accessors": accessors,
    }  # fmt: skip
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    body = b"".join(chunks)
    head = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + 8 + len(body))
    return b"".join([head, struct.pack("<I4s", len(text), b"JSON"), text,
                     struct.pack("<I4s", len(body), b"BIN\x00"), body])  # fmt: skip


class StudioScene:
    """The scene of one viser server.

    Parameters
    ----------
    scene : viser.SceneApi
    """

    def __init__(self, scene):
        self.scene = scene
        self._handles: dict = {}
        self._shape = None
        self._key = None
        self._stale: set = set()  # the nodes of a model not redrawn since it changed
        self.added = 0  #: scene nodes added so far (a new model of the same shape adds none)

    def draw(self, view: ViewState, model, key, layers: dict) -> None:
        """Draw ``view`` of ``model``; ``key`` identifies the model.

        A new model of the same shape (plates, vertices and triangles per plate: an edit of a
        dimension, a material, a load) updates the vertex buffers of the nodes already in the
        scene; only a new shape rebuilds them. ``layers`` maps the :data:`TOGGLES` keys to
        whether they are shown.
        """
        p, v = view.vertices.shape[:2]
        shape = (p, v, view.triangles.shape)
        if shape != self._shape:
            self.clear()
            self._shape = shape
        if key != self._key:
            self._key = key
            self._ground = float(model.vertices([model.alpha_design])[0][..., 2].min())
            self._stale = {"faces", "/ccu/flat", "/ccu/patterns", "/ccu/grid"}
        faces = "faces" in self._stale
        self._stale.discard("faces")
        h = self._handles
        for i in range(p):
            name = f"/ccu/plates/{i}"
            color = tuple(int(x) for x in view.plate_colors[i])
            if name not in h:
                h[name] = self._add(
                    self.scene.add_mesh_simple,
                    name, _f32(view.vertices[i]), view.triangles[i].astype(np.uint32),
                    color=color, side="double", cast_shadow=False, receive_shadow=False,
                )  # fmt: skip
            else:
                h[name].vertices = _f32(view.vertices[i])
                if faces:
                    _set_faces(h[name], view.triangles[i])
                if tuple(h[name].color) != color:
                    h[name].color = color
        creases = view.creases.reshape(-1, 2, 3)
        colors = np.repeat(view.crease_colors.reshape(-1, 1, 3), 2, axis=1)
        self._lines("/ccu/creases", creases, colors, layers["creases"], CREASE_WIDTH)
        rulings = view.rulings.reshape(-1, 2, 3)
        tone = np.broadcast_to(np.array(_rgb(C.RULING_COLOR), np.uint8), rulings.shape)
        self._lines("/ccu/rulings", rulings, tone, layers["rulings"], RULING_WIDTH)
        self._solids(view, layers["solids"], faces)
        self._colored(view, layers["solids"])
        self._flat_stack(model, view, layers["flat"])
        self._patterns(model, view, layers["patterns"])
        self._grid(view, layers["grid"])

    def clear(self) -> None:
        for handle in self._handles.values():
            handle.remove()
        self._handles = {}
        self._shape = None

    def _add(self, add, name, *args, **options):
        self.added += 1
        return add(name, *args, **options)

    def _mesh(self, name, verts, tris, visible, **options) -> None:
        """Node ``name`` shows the mesh ``verts``, ``tris`` (its buffers updated in place when
        it is in the scene with as many vertices and triangles, else added anew)."""
        h = self._handles
        self._stale.discard(name)
        if name in h and (h[name].vertices.shape, h[name].faces.shape) == (verts.shape, tris.shape):
            h[name].vertices = _f32(verts)
            _set_faces(h[name], tris)
        else:
            if name in h:
                h.pop(name).remove()
            h[name] = self._add(
                self.scene.add_mesh_simple, name, _f32(verts), tris.astype(np.uint32), **options
            )
        h[name].visible = visible

    def _lines(self, name, points, colors, visible, width) -> None:
        h = self._handles
        if name in h and h[name].points.shape != points.shape:
            h.pop(name).remove()
        if name not in h:
            h[name] = self._add(
                self.scene.add_line_segments, name, _f32(points), _linear(colors),
                thickness=width, thickness_units="screen",
            )  # fmt: skip
        elif visible:
            h[name].points = _f32(points)
            h[name].colors = _linear(colors)
        h[name].visible = visible

    def _solids(self, view, visible, faces=False) -> None:
        h = self._handles
        if faces:  # a new model: its solids get new buffers when next shown
            self._stale.update(n for n in h if n.startswith("/ccu/solids/"))
        for i, (verts, tris) in enumerate(view.solids if visible else []):
            name = f"/ccu/solids/{i}"
            if name in h and name in self._stale:
                self._mesh(name, verts, np.asarray(tris), True)
            elif name in h:
                h[name].vertices = _f32(verts)
            else:
                h[name] = self._add(
                    self.scene.add_mesh_simple, name, _f32(verts), np.asarray(tris, np.uint32),
                    color=tuple(int(x) for x in view.plate_colors[i]),
                )  # fmt: skip
        for name, handle in h.items():
            if name.startswith("/ccu/solids/"):
                handle.visible = visible
        # the mid-surfaces would show through the solids; coloured vertices draw them instead
        plates = not visible and view.vertex_colors is None
        for i in range(len(view.vertices)):
            if f"/ccu/plates/{i}" in h:
                h[f"/ccu/plates/{i}"].visible = plates

    def _colored(self, view, solids) -> None:
        """The plates in their vertex colours (one GLB node), when the view has them."""
        h, name = self._handles, "/ccu/colored"
        visible = view.vertex_colors is not None and not solids
        if visible:
            verts, tris = _stacked(view.vertices, view.triangles)
            data = colored_glb(verts, tris, view.vertex_colors.reshape(-1, 3))
            if name in h:
                h[name].glb_data = data
            else:
                h[name] = self._add(
                    self.scene.add_glb, name, data, cast_shadow=False, receive_shadow=False
                )
        if name in h:
            h[name].visible = visible

    def _flat_stack(self, model, view, visible) -> None:
        h, name = self._handles, "/ccu/flat"
        if visible and (name not in h or name in self._stale):
            verts, tris = _stacked(model.vertices([0.0])[0], view.triangles)
            self._mesh(
                name, verts, tris, visible, color=(120, 120, 120), opacity=0.35, side="double"
            )
        if "/ccu/flat" in h:
            h["/ccu/flat"].visible = visible

    def _patterns(self, model, view, visible) -> None:
        """The cut patterns on the ground beside the structure, laid out in rows."""
        h = self._handles
        if visible and ("/ccu/patterns" not in h or "/ccu/patterns" in self._stale):
            flat = model.flat()
            xy = flat[..., :2] + pattern_layout(flat)[:, None]
            v = view.vertices.reshape(-1, 3)
            lo, hi = v.min(axis=0), v.max(axis=0)
            shift = np.array([hi[0] + 0.2 * (hi[0] - lo[0]), lo[1]]) - xy.reshape(-1, 2).min(0)
            xyz = np.concatenate([xy + shift, np.full(xy.shape[:-1] + (1,), self._ground)], -1)
            verts, tris = _stacked(xyz, view.triangles)
            self._mesh(
                "/ccu/patterns", verts, tris, visible, color=_rgb(C.PLATE_TONES[0]), side="double"
            )
        if "/ccu/patterns" in h:
            h["/ccu/patterns"].visible = visible

    def _grid(self, view, visible) -> None:
        h = self._handles
        if "/ccu/grid" not in h or "/ccu/grid" in self._stale:
            self._stale.discard("/ccu/grid")
            v = view.vertices.reshape(-1, 3)
            lo, hi = v.min(axis=0), v.max(axis=0)
            size = float(max(hi - lo))
            cell = 0.5 * 10.0 ** np.floor(np.log10(max(size, 1e-6)))  # 0.5 m cells at 1-10 m
            props = dict(
                width=4 * size, height=4 * size, cell_size=float(cell), section_size=2 * float(cell)
            )
            position = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), self._ground)
            if "/ccu/grid" in h:  # a new model: the grid's properties, no new node
                grid = h["/ccu/grid"]
                for name, value in props.items():
                    if getattr(grid, name) != value:
                        setattr(grid, name, value)
                if tuple(grid.position) != position:
                    grid.position = position
            else:
                h["/ccu/grid"] = self._add(
                    self.scene.add_grid, "/ccu/grid", **props,
                    cell_color=(228, 228, 228), section_color=(190, 190, 190), position=position,
                )  # fmt: skip
        h["/ccu/grid"].visible = visible
