"""Writers of deployed structures: ``structure.json`` (docs/structure-json.md), OBJ, COMPAS JSON."""

from __future__ import annotations

import csv
import hashlib
import json
from pathlib import Path

import compas
import numpy as np

from compas_ccu.errors import GeometryError
from compas_ccu.outputs import name_id, write_json
from compas_ccu.structure import Structure

__all__ = [
    "write_structure_json",
    "read_structure_json",
    "write_obj",
    "write_compas_json",
    "write_path_table",
    "write_path",
    "read_values",
    "flat_footprint",
]


def write_structure_json(structure, path) -> Path:
    """Write the ``ccu.structure`` v1 contract (docs/structure-json.md)."""
    return write_json(path, structure.to_contract())


def read_structure_json(path) -> Structure:
    """Read a ``structure.json`` back into a :class:`compas_ccu.structure.Structure`."""
    return Structure.from_contract(json.loads(Path(path).read_text(encoding="utf-8")))


def write_obj(structure, path, *, state: str = "deployed") -> Path:
    """Write the plates as one OBJ with a group per plate (quads, metres)."""
    path = Path(path)
    points = structure.points(state)
    _check_finite(points, path)
    lines = [f"# compas_ccu structure, alpha = {structure.alpha:.12g} deg, units m"]
    offset = 1
    for pid, xyz, faces in zip(structure.plate_ids, points, structure.faces):
        lines.append(f"g plate_{pid}")
        lines.extend(f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in xyz)
        lines.extend("f " + " ".join(str(i + offset) for i in face) for face in faces.tolist())
        offset += len(xyz)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def write_compas_json(structure, path) -> Path:
    """Write the deployed plates as a list of COMPAS meshes (``compas.json_load`` reads it).

    Every mesh's ``guid`` is a name-based id of its name and its data (:func:`name_id`), not
    COMPAS' random one: the same structure gives the same file.
    """
    path = Path(path)
    _check_finite(structure.deployed, path)
    documents = []
    for mesh in structure.to_meshes():
        document = mesh.__jsondump__()
        data = hashlib.sha256(compas.json_dumps(document["data"]).encode()).hexdigest()
        document["guid"] = str(name_id(mesh.name, data))
        documents.append(document)
    path.write_text(compas.json_dumps(documents), encoding="utf-8")
    return path


def _check_finite(points: np.ndarray, path: Path) -> None:
    """Refuse to write coordinates that are not finite (GeometryError naming the plate)."""
    bad = ~np.isfinite(np.asarray(points, dtype=float)).all(axis=-1)
    if bad.any():
        plate, vertex = (int(i) for i in np.argwhere(bad)[0])
        raise GeometryError(
            f"{path.name} would hold non-finite coordinates (plate position {plate}, vertex "
            f"{vertex}): nothing is written"
        )


def write_path_table(structures, path) -> Path:
    """CSV: one row per state with alpha, span, rise, invariants and each crease's planarity."""
    path = Path(path)
    ncreases = len(structures[0].creases) if structures else 0
    header = [
        "state",
        "alpha_deg",
        "span_m",
        "rise_m",
        "isometry_rel",
        "quad_planarity_rel",
        "crease_planarity_max_m",
    ] + [f"crease_{i}_planarity_m" for i in range(ncreases)]
    with path.open("w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(header)
        for k, s in enumerate(structures):
            m = s.metrics
            writer.writerow(
                [
                    k,
                    f"{s.alpha:.12g}",
                    f"{m['span']:.12g}",
                    f"{m['rise']:.12g}",
                    f"{m['isometry_relative']:.3e}",
                    f"{m['quad_planarity_relative']:.3e}",
                    f"{m['crease_planarity_max']:.3e}",
                ]
                + [f"{c['planarity']:.3e}" for c in s.creases]
            )
    return path


def write_path(structures, out) -> tuple:
    """Write the states of a deployment path: ``out/states/state_NNNN.json`` (one structure
    file per state) and the table ``out/path.csv`` (:func:`write_path_table`).

    Returns
    -------
    table : Path
    states : Path
        The folder of the structure files.
    """
    out = Path(out)
    states = out / "states"
    states.mkdir(parents=True, exist_ok=True)
    for k, s in enumerate(structures):
        write_structure_json(s, states / f"state_{k:04d}.json")
    return write_path_table(structures, out / "path.csv"), states


def read_values(path) -> np.ndarray:
    """An array of numbers from a ``.npy`` file or, for any other suffix, a JSON file (nested
    lists). OSError or ValueError say what is wrong with the file."""
    path = Path(path)
    if path.suffix == ".npy":
        return np.load(path)
    return np.asarray(json.loads(path.read_text()), dtype=float)


def flat_footprint(structure) -> tuple:
    """Width and height (m) of the bounding box of the flat-folded stack in its plane."""
    flat = np.asarray(structure.flat).reshape(-1, 3)
    dx, dy = np.ptp(flat[:, 0]), np.ptp(flat[:, 1])
    return float(dx), float(dy)
