"""Targets and scans as points: read OBJ / STL / PLY / OFF meshes, PLY / XYZ / CSV point clouds
and Rhino ``.3dm`` meshes or point clouds into a :class:`PointSet` (docs/fit.md).

Surfaces are sampled evenly (area-weighted, with a fixed seed: the same file gives the same
points); every point keeps the normal of its face, which the design fit uses for its
plate-to-target distance. Point clouds get normals from their neighbours
(:func:`estimate_normals`). Bad input is refused in one line naming the file, the cause and the
value: an unknown format, no points, a non-finite coordinate.
"""

from __future__ import annotations

import io
import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from compas_ccu.design.units import LENGTH_UNITS
from compas_ccu.errors import GeometryError, OptionError, require

__all__ = ["PointSet", "read_points", "sample_triangles", "estimate_normals", "point_set"]
__all__ += ["MESH_SUFFIXES", "TEXT_SUFFIXES", "FORMATS", "DEFAULT_SAMPLES", "MAX_POINTS"]

#: Mesh formats read by trimesh (a PLY without faces is a point cloud).
MESH_SUFFIXES = (".obj", ".stl", ".ply", ".off")
#: Point clouds as text: x y z per line, separated by spaces, commas or semicolons.
TEXT_SUFFIXES = (".xyz", ".csv", ".txt", ".pts")
FORMATS = (*MESH_SUFFIXES, *TEXT_SUFFIXES, ".3dm")
#: Points sampled on a mesh surface unless the caller asks for another count.
DEFAULT_SAMPLES = 50_000
#: The most points a file may give (memory: 3 float64 per point and the distance arrays).
MAX_POINTS = 20_000_000


@dataclass(frozen=True)
class PointSet:
    """Points read from a target or a scan.

    Attributes
    ----------
    points : (n, 3) float64
        Coordinates, metres.
    normals : (n, 3) float64 or None
        Unit normals (the face normals of a sampled mesh), None for a point cloud until
        :func:`estimate_normals` gives them.
    source : str
        The file (or a description).
    kind : str
        ``"mesh"`` (sampled surface) or ``"points"`` (a point cloud).
    area : float or None
        Surface area of a mesh, m².
    """

    points: np.ndarray
    normals: np.ndarray | None
    source: str
    kind: str
    area: float | None = None

    def __len__(self) -> int:
        return len(self.points)

    @property
    def size(self) -> float:
        """Diagonal of the axis-aligned bounding box, m."""
        return float(np.linalg.norm(np.ptp(self.points, axis=0)))

    def with_normals(self, *, neighbours: int = 12) -> PointSet:
        """This set with normals (estimated from ``neighbours`` points if it has none)."""
        if self.normals is not None:
            return self
        normals = estimate_normals(self.points, neighbours=neighbours)
        return PointSet(self.points, normals, self.source, self.kind, self.area)

    def subset(self, index) -> PointSet:
        """The points at ``index`` (an index array or a boolean mask)."""
        normals = None if self.normals is None else self.normals[index]
        return PointSet(self.points[index], normals, self.source, self.kind, self.area)


def point_set(points, *, normals=None, source: str = "points", kind: str = "points") -> PointSet:
    """A checked :class:`PointSet` from arrays (the refusals of :func:`read_points`).

    Raises
    ------
    GeometryError
        Not (n, 3), no points, or a non-finite coordinate.

    Examples
    --------
    >>> point_set([[0, 0, 0], [1, 0, 0]]).points.dtype
    dtype('float64')
    >>> point_set([[0, 0, float("nan")]])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    compas_ccu.errors.GeometryError: points: 1 non-finite coordinate (first: point 0 = ...)
    """
    p = np.asarray(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 3:
        raise GeometryError(f"{source}: points must be (n, 3), got shape {p.shape}")
    _check_points(p, source)
    n = None
    if normals is not None:
        n = np.asarray(normals, dtype=np.float64).reshape(p.shape)
    return PointSet(np.ascontiguousarray(p), n, source, kind)


def _check_points(p: np.ndarray, source: str) -> None:
    if len(p) == 0:
        raise GeometryError(f"{source}: no points (an empty file or mesh)")
    if len(p) > MAX_POINTS:
        raise GeometryError(f"{source}: {len(p)} points, more than the {MAX_POINTS} allowed")
    bad = ~np.isfinite(p).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        count = int((~np.isfinite(p)).sum())
        raise GeometryError(
            f"{source}: {count} non-finite coordinate{'s' if count > 1 else ''} "
            f"(first: point {i} = {p[i].tolist()})"
        )


def sample_triangles(vertices, triangles, count: int, *, seed: int = 0):
    """``count`` points spread evenly (area-weighted) over a triangle mesh, reproducibly.

    Parameters
    ----------
    vertices : (v, 3) float
    triangles : (t, 3) int
    count : int
    seed : int
        Seed of the generator (the same seed gives the same points).

    Returns
    -------
    points : (count, 3) float64
    normals : (count, 3) float64
        Unit normals of the faces the points lie on.
    area : float
        Total area, m².

    Raises
    ------
    GeometryError
        The mesh has no area.
    """
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    cross = np.cross(b - a, c - a)
    double = np.linalg.norm(cross, axis=1)
    area = 0.5 * float(double.sum())
    if not len(t) or not area > 0.0 or not math.isfinite(area):
        raise GeometryError(f"the mesh has no area to sample (area {area:g} m2, {len(t)} faces)")
    rng = np.random.default_rng(seed)
    face = rng.choice(len(t), size=int(count), p=double / double.sum())
    u, w = rng.random((2, int(count)))
    flip = u + w > 1.0
    u, w = np.where(flip, 1.0 - u, u), np.where(flip, 1.0 - w, w)
    points = a[face] + u[:, None] * (b - a)[face] + w[:, None] * (c - a)[face]
    normals = cross[face] / np.where(double[face] > 0.0, double[face], 1.0)[:, None]
    return points, normals, area


def estimate_normals(points, *, neighbours: int = 12, chunk: int = 200_000) -> np.ndarray:
    """(n, 3) unit normals of a point cloud: the smallest principal axis of each point's
    ``neighbours`` nearest points (orientation arbitrary).

    Parameters
    ----------
    points : (n, 3) float
    neighbours : int
    chunk : int
        Points per batch (memory).
    """
    p = np.asarray(points, dtype=np.float64)
    k = int(min(max(3, neighbours), len(p)))
    if k < 3:
        return np.tile([0.0, 0.0, 1.0], (len(p), 1))
    tree = cKDTree(p)
    out = np.empty_like(p)
    for s in range(0, len(p), chunk):
        _, idx = tree.query(p[s : s + chunk], k=k)
        nb = p[idx]
        nb = nb - nb.mean(axis=1, keepdims=True)
        cov = np.einsum("nki,nkj->nij", nb, nb)
        _, vec = np.linalg.eigh(cov)
        out[s : s + chunk] = vec[:, :, 0]
    return out


def read_points(path, *, count: int = DEFAULT_SAMPLES, seed: int = 0, units: str = "m") -> PointSet:
    """Read a target or a scan as points.

    Parameters
    ----------
    path : path-like
        ``.obj``, ``.stl``, ``.ply``, ``.off`` (a mesh: sampled; a PLY without faces: its
        points), ``.xyz`` / ``.csv`` / ``.txt`` / ``.pts`` (x y z per line, spaces, commas or
        semicolons; a header line and ``#`` comments are skipped; further columns ignored),
        ``.3dm`` (every mesh, Brep render mesh or point cloud of the file).
    count : int
        Points to sample on a mesh surface (keyword-only).
    seed : int
        Seed of the sampling.
    units : str
        Length units of the file's coordinates: ``m``, ``mm``, ``cm``, ``ft``, ``in`` (a
        ``.3dm`` file is read in its own model units).

    Returns
    -------
    PointSet

    Raises
    ------
    GeometryError
        Missing or unreadable file, an unknown format, no points, a non-finite coordinate.
    MissingExtraError
        A mesh or ``.3dm`` file without trimesh / rhino3dm installed (the fab extra).
    OptionError
        Unknown ``units``, a sample count below 1.
    """
    path = Path(path)
    source = str(path)
    if units not in LENGTH_UNITS:
        raise OptionError(f"units must be one of {', '.join(LENGTH_UNITS)}, got {units!r}")
    if not isinstance(count, (int, np.integer)) or not 1 <= count <= MAX_POINTS:
        raise OptionError(f"the sample count must be 1 to {MAX_POINTS}, got {count!r}")
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise GeometryError(
            f"{source}: unknown format {suffix or '(no suffix)'!r}; allowed: {', '.join(FORMATS)}"
        )
    if not path.is_file():
        raise GeometryError(f"{source}: no such file")
    if suffix in TEXT_SUFFIXES:
        result = PointSet(_read_text(path), None, source, "points")
    elif suffix == ".3dm":
        result = _read_3dm(path, count, seed)
    else:
        result = _read_mesh(path, count, seed)
    _check_points(result.points, source)
    f = LENGTH_UNITS[units]
    if f != 1.0 and suffix != ".3dm":  # a .3dm file names its own units
        area = None if result.area is None else result.area * f * f
        result = PointSet(result.points * f, result.normals, source, result.kind, area)
    return result


def _read_text(path: Path) -> np.ndarray:
    text = path.read_text(encoding="utf-8", errors="replace")
    text = text.replace(",", " ").replace(";", " ").replace("\t", " ")
    lines = text.splitlines()
    skip = 0
    for line in lines:
        body = line.split("#", 1)[0].split()
        if not body:
            skip += 1
            continue
        try:
            float(body[0])
        except ValueError:
            skip += 1  # a header line
        break
    try:
        with warnings.catch_warnings():  # an empty file: refused below as "no points"
            warnings.simplefilter("ignore", UserWarning)
            data = np.loadtxt(
                io.StringIO("\n".join(lines[skip:])), comments="#", usecols=(0, 1, 2), ndmin=2
            )
    except (ValueError, IndexError) as exc:
        raise GeometryError(f"{path}: not x y z rows of numbers ({exc})") from None
    return data.astype(np.float64).reshape(-1, 3)


def _trimesh():
    require("trimesh", "fab", what="reading meshes")
    import trimesh

    return trimesh


def _read_mesh(path: Path, count: int, seed: int) -> PointSet:
    trimesh = _trimesh()
    try:
        loaded = trimesh.load(str(path), process=False)
    except Exception as exc:  # noqa: BLE001 - any reader failure is the file's fault
        raise GeometryError(f"{path}: cannot read it as {path.suffix.lower()} ({exc})") from None
    if isinstance(loaded, trimesh.Scene):
        geometries = list(loaded.dump()) if loaded.geometry else []
    else:
        geometries = [loaded]
    faces = [g for g in geometries if getattr(g, "faces", None) is not None and len(g.faces)]
    if faces:
        vertices, triangles, offset = [], [], 0
        for g in faces:
            vertices.append(np.asarray(g.vertices, dtype=np.float64))
            triangles.append(np.asarray(g.faces, dtype=np.int64) + offset)
            offset += len(g.vertices)
        v = np.concatenate(vertices)
        _check_points(v, str(path))
        points, normals, area = sample_triangles(v, np.concatenate(triangles), count, seed=seed)
        return PointSet(points, normals, str(path), "mesh", area)
    vertices = [
        np.asarray(g.vertices, dtype=np.float64) for g in geometries if hasattr(g, "vertices")
    ]
    v = np.concatenate(vertices) if vertices else np.zeros((0, 3))
    return PointSet(v.reshape(-1, 3), None, str(path), "points")


def _read_3dm(path: Path, count: int, seed: int) -> PointSet:
    require("rhino3dm", "fab", what="reading .3dm files")
    import rhino3dm

    model = rhino3dm.File3dm.Read(str(path))
    if model is None:
        raise GeometryError(f"{path}: cannot read it as a Rhino .3dm file")
    vertices, triangles, clouds, offset = [], [], [], 0
    for obj in model.Objects:
        geometry = obj.Geometry
        meshes = []
        if isinstance(geometry, rhino3dm.Mesh):
            meshes = [geometry]
        elif isinstance(geometry, rhino3dm.Brep):
            meshes = [f.GetMesh(rhino3dm.MeshType.Any) for f in geometry.Faces]
        elif isinstance(geometry, rhino3dm.PointCloud):
            clouds.append(np.array([[p.X, p.Y, p.Z] for p in geometry.GetPoints()], float))
        for mesh in meshes:
            if mesh is None:
                continue
            mesh.Faces.ConvertQuadsToTriangles()
            v = np.array([[p.X, p.Y, p.Z] for p in mesh.Vertices], dtype=np.float64)
            f = np.array([list(mesh.Faces[i])[:3] for i in range(len(mesh.Faces))], np.int64)
            if len(v) and len(f):
                vertices.append(v)
                triangles.append(f.reshape(-1, 3) + offset)
                offset += len(v)
    factor = _rhino_unit(model)
    if vertices:
        v = np.concatenate(vertices) * factor
        _check_points(v, str(path))
        points, normals, area = sample_triangles(v, np.concatenate(triangles), count, seed=seed)
        return PointSet(points, normals, str(path), "mesh", area)
    p = np.concatenate(clouds) * factor if clouds else np.zeros((0, 3))
    return PointSet(p.reshape(-1, 3), None, str(path), "points")


def _rhino_unit(model) -> float:
    """Metres per model unit of a .3dm file (its ModelUnitSystem; metres if unknown)."""
    factors = {"Millimeters": 1e-3, "Centimeters": 1e-2, "Meters": 1.0, "Feet": 0.3048}
    factors["Inches"] = 0.0254
    name = str(getattr(model.Settings, "ModelUnitSystem", "Meters")).split(".")[-1]
    return factors.get(name, 1.0)
