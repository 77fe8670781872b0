"""Curve files in a design: read the ``crease.points`` and ``[target]`` curves a design names.

The schema (:mod:`compas_ccu.design.schema`) accepts a curve file where a key takes points:
``points = "crease.dxf"`` or ``points = { file = "crease.dxf", layer = "CREASE", units = "mm" }``.
:func:`read_curve_files` reads them (:func:`compas_ccu.curves.readers.read_curve`) and puts the
points in their place, so the rest of compas_ccu sees ordinary point lists.
"""

from __future__ import annotations

import copy
from pathlib import Path

from compas_ccu.curves.readers import plane_coordinates, read_curve
from compas_ccu.design.schema import CURVE_FILE_PLACES
from compas_ccu.errors import DesignError, MissingExtraError, ProfileError
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["read_curve_files", "absolute_curve_files"]

_PLACES = tuple(tuple(place.split(".")) for place in CURVE_FILE_PLACES)


def _is_file(value) -> bool:
    return isinstance(value, dict) and "file" in value


def _file_units(spec: dict, path: Path, values: dict):
    """The units a curve file is read in: its table's ``units``; for a CSV / TXT file (no
    units of its own) the design's ``[design] units``; else the file's own (None)."""
    if spec["units"] is not None:
        return spec["units"]
    if path.suffix.lower() in (".csv", ".txt"):
        return (values.get("design") or {}).get("units") or "m"
    return None


def read_curve_files(values: dict, base=None, *, plane_given: bool = True) -> dict:
    """Replace every curve-file reference of validated design ``values`` by the points read.

    Parameters
    ----------
    values : dict
        :func:`compas_ccu.design.schema.validate` output; changed in place and returned.
    base : str or Path, optional
        Folder that relative paths are read from (the design file's); default: the current one.
    plane_given : bool
        Whether the design gives its ``[plane]``. If not, and the crease curve does not lie in
        a plane z = const, the plane is taken from the file: ``values["plane"]`` becomes the
        curve's plane (origin at its chord's midpoint, x along the chord, y towards its bulge),
        so the structure stands where the curve was drawn.

    Returns
    -------
    dict
        ``values``, with ``crease.points`` the curve's 2D coordinates in its plane (m) and every
        ``[target]`` curve its x, y.

    Raises
    ------
    DesignError
        A missing or unreadable file, no or several candidate curves, a non-planar crease curve
        or a target curve off z = const; the key is the one that names the file, the message
        names the file and the entity.

    Examples
    --------
    >>> import os, tempfile
    >>> from compas_ccu.design.schema import validate
    >>> folder = tempfile.mkdtemp()
    >>> _ = open(os.path.join(folder, "c.csv"), "w").write("-1 0\\n0 0.5\\n1 0\\n")
    >>> values = validate({"crease": {"profile": "polyline", "points": "c.csv"},
    ...                    "rulings": {"type": "orthogonal"}, "deployment": {"alpha": 30.0},
    ...                    "layout": {"width": 0.3}})
    >>> read_curve_files(values, folder)["crease"]["points"]
    [[-1.0, 0.0], [0.0, 0.5], [1.0, 0.0]]
    """
    base = Path(base) if base is not None else Path.cwd()
    for section, key in _PLACES:
        spec = values.get(section, {}).get(key)
        if not _is_file(spec):
            continue
        where = f"{section}.{key}"
        path = Path(spec["file"])
        if not path.is_absolute():
            path = base / path
        if not path.is_file():
            raise DesignError(f"curve file {str(path)!r} does not exist", key=where)
        try:
            curve = read_curve(
                path,
                layer=spec["layer"],
                name=spec["name"],
                index=spec["index"],
                units=_file_units(spec, path, values),
                scale=spec["scale"],
            )
            if section == "crease":
                points, frame, _ = plane_coordinates(curve.points, source=curve.source)
                in_xy = frame["xaxis"] == [1.0, 0.0, 0.0] and frame["yaxis"] == [0.0, 1.0, 0.0]
                if not plane_given and not in_xy:
                    values["plane"] = frame
            else:
                z = curve.points[:, 2]
                size = float(abs(curve.points).max()) or 1.0
                if float(z.max() - z.min()) > EXACT_RELATIVE * size:
                    raise ProfileError(
                        f"{curve.source}: a target curve is drawn in a plane z = const (its "
                        f"x, y are d and the value); z varies by {float(z.max() - z.min()):.6g} m"
                    )
                points = curve.points[:, :2]
        except (ProfileError, MissingExtraError) as exc:
            raise DesignError(str(exc), key=where) from None
        values[section][key] = points.tolist()
    return values


def absolute_curve_files(document: dict, base) -> dict:
    """A copy of a design document whose curve-file paths are absolute (resolved against
    ``base``), for documents that leave the design file's folder (sweep variants on workers).

    Examples
    --------
    >>> doc = {"crease": {"profile": "polyline", "points": {"file": "c.dxf", "layer": "A"}}}
    >>> absolute_curve_files(doc, "/data")["crease"]["points"]
    {'file': '/data/c.dxf', 'layer': 'A'}
    """
    out = copy.deepcopy(document)
    for section, key in _PLACES:
        table = out.get(section)
        value = table.get(key) if isinstance(table, dict) else None
        if isinstance(value, str):
            value = table[key] = {"file": value}
        if isinstance(value, dict) and isinstance(value.get("file"), str):
            path = Path(value["file"])
            if not path.is_absolute():
                value["file"] = str(Path(base).resolve() / path)
    return out
