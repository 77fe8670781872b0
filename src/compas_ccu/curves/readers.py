"""Curves from files: CSV / TXT points, DXF, SVG paths and Rhino 3dm curves, in metres.

:func:`read_curve` reads one curve of a file as a dense polyline of 3D points in metres;
:func:`plane_coordinates` turns it into the 2D coordinates of its plane (a crease profile).

Formats (chosen by the file suffix):

``.csv``, ``.txt``
    One point a line, ``x, y`` or ``x, y, z``, separated by commas, semicolons, tabs or spaces;
    ``#`` starts a comment and a first line that is not numbers is a header. No units in the
    file: metres unless ``units`` is given. NumPy only.
``.dxf``
    LWPOLYLINE (with bulges), POLYLINE (2D and 3D), SPLINE, ARC and chains of LINE entities
    of the model space (``ezdxf``, the ``fab`` extra). SPLINE is evaluated with ezdxf's
    B-spline construction tool, the others through ``ezdxf.path``; units from ``$INSUNITS``
    (a unitless file needs ``units``).
``.svg``
    Every ``<path>``, ``<polyline>``, ``<polygon>`` and ``<line>``, with the transforms and
    viewBox applied by ``svgelements`` (``pip install svgelements``). SVG user units are CSS
    pixels (96 per inch), so a file whose ``width`` / ``height`` carry a unit (``mm``) is read
    in that unit. SVG's y axis points down: the y coordinate is negated so that a drawing
    reads upright.
``.3dm``
    Every curve object (line, polyline, arc, NURBS, polycurve) of a Rhino file
    (``rhino3dm``, the ``fab`` extra), evaluated with ``Curve.PointAt``; units from the
    file's model unit system.

Curves are sampled until every chord lies within ``tolerance`` (relative to the curve's
bounding-box diagonal, default 1e-8) of the curve at its midpoint, so the polyline read back
is the source curve to that tolerance (docs/import.md gives the measured distances).

A file with several curves needs ``layer`` (a DXF or 3dm layer, an SVG group id or Inkscape
label), ``name`` (a DXF handle, a 3dm object name, an SVG element id) or ``index`` (among the
curves left) to choose one; the error lists the candidates.

This module reads the options, chooses the curve and samples it; the formats are read by
:mod:`.csv_curves`, :mod:`.dxf_curves`, :mod:`.svg_curves` and :mod:`.rhino_curves` into
:class:`~compas_ccu.curves.candidates.Candidate` curves; :func:`plane_coordinates` lives in
:mod:`.curve_plane`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from compas_ccu import limits
from compas_ccu.curves.candidates import UNITS, Candidate
from compas_ccu.curves.csv_curves import csv_candidates
from compas_ccu.curves.curve_plane import plane_coordinates
from compas_ccu.curves.dxf_curves import dxf_candidates, dxf_line_chains, dxf_sampler
from compas_ccu.curves.dxf_input import check_finite, extent
from compas_ccu.curves.rhino_curves import rhino_candidates
from compas_ccu.curves.svg_curves import svg_candidates
from compas_ccu.errors import ProfileError
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = [
    "dxf_sampler",
    "dxf_line_chains",
    "UNITS",
    "CURVE_SUFFIXES",
    "CurveRead",
    "read_curve",
    "plane_coordinates",
]

#: File suffixes :func:`read_curve` reads.
CURVE_SUFFIXES = (".csv", ".txt", ".dxf", ".svg", ".3dm")

#: Default chord tolerance of the sampling, relative to the curve's bounding-box diagonal.
TOLERANCE = 1e-8

#: The reader of every suffix but ``.dxf`` (which takes the units given too): ``path ->
#: (candidates, file units, metres per file unit or None)``.
_READERS = {
    ".csv": csv_candidates,
    ".txt": csv_candidates,
    ".svg": svg_candidates,
    ".3dm": rhino_candidates,
}


@dataclass(frozen=True)
class CurveRead:
    """One curve read from a file.

    Attributes
    ----------
    points : (n, 3) float
        The curve, m, as a polyline within the sampling tolerance of the source.
    source : str
        ``"path: ENTITY"``, naming the entity read (type, handle or name, layer).
    units : str
        The units of the file's numbers (a key of :data:`UNITS`).

    Examples
    --------
    >>> import numpy as np
    >>> curve = CurveRead(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), "crease.csv: 2 points", "m")
    >>> curve.points.shape, curve.units
    ((2, 3), 'm')
    """

    points: np.ndarray
    source: str
    units: str


def read_curve(
    path,
    *,
    layer: str | None = None,
    name: str | None = None,
    index: int | None = None,
    units: str | None = None,
    scale: float = 1.0,
    tolerance: float = TOLERANCE,
) -> CurveRead:
    """Read one curve of a CSV / TXT, DXF, SVG or 3dm file as 3D points in metres.

    Parameters
    ----------
    path : str or Path
        The file; its suffix chooses the reader.
    layer, name : str, optional
        Keep only the curves on this layer (DXF, 3dm; SVG: a group's id or Inkscape label) or
        of this name (DXF handle, 3dm object name, SVG element id). Case-insensitive.
    index : int, optional
        Which of the curves left (0-based, in file order); needed if more than one is left.
    units : str, optional
        Units of the file's numbers (``m``, ``cm``, ``mm``, ``in``, ``ft``): overrides the
        file's own. CSV / TXT: default ``m``.
    scale : float
        Factor applied after the unit conversion (default 1).
    tolerance : float
        Chord tolerance of the sampling, relative to the curve's size.

    Returns
    -------
    CurveRead

    Raises
    ------
    ProfileError
        The file is missing or unreadable; no curve, or several and no choice (the message
        lists them); a unit that is unknown or missing (unitless DXF); fewer than 2 points.
    MissingExtraError
        ezdxf (DXF), rhino3dm (3dm) or svgelements (SVG) is not installed.

    Examples
    --------
    >>> import tempfile, os
    >>> folder = tempfile.mkdtemp()
    >>> path = os.path.join(folder, "crease.csv")
    >>> _ = open(path, "w").write("x,y\\n0,0\\n500,250\\n1000,0\\n")
    >>> curve = read_curve(path, units="mm")
    >>> curve.points.tolist()
    [[0.0, 0.0, 0.0], [0.5, 0.25, 0.0], [1.0, 0.0, 0.0]]
    """
    path = Path(path)
    if units is not None and units not in UNITS:
        raise ProfileError(f"units must be one of {', '.join(UNITS)}, got {units!r}")
    if not (isinstance(scale, (int, float)) and math.isfinite(scale) and scale > 0):
        raise ProfileError(f"scale must be a number > 0, got {scale!r}")
    suffix = path.suffix.lower()
    if suffix not in CURVE_SUFFIXES:
        raise ProfileError(
            f"{str(path)!r}: cannot read curves from {suffix or 'a file without suffix'!r} "
            f"files; readable: {', '.join(CURVE_SUFFIXES)}"
        )
    if not path.is_file():
        raise ProfileError(f"curve file {str(path)!r} does not exist")
    if suffix == ".dxf":  # the file's $INSUNITS matters only without units
        candidates, file_units, file_factor = dxf_candidates(path, units)
    else:
        candidates, file_units, file_factor = _READERS[suffix](path)
    chosen = _choose(path, candidates, layer=layer, name=name, index=index)
    used = units or file_units
    if used is None:
        raise ProfileError(
            f"{str(path)!r} has no units we read (unitless, or a unit other than "
            f"{', '.join(UNITS)}): give units = one of {', '.join(UNITS)}"
        )
    factor = UNITS[used] if units is not None or file_factor is None else file_factor
    points = _sample(path, chosen, tolerance)
    scaled = points * (factor * scale)
    if not np.isfinite(scaled).all():
        raise ProfileError(
            f"{str(path)!r}: {chosen.label} times scale {scale:g} ({used}) is not finite"
        )
    return CurveRead(scaled, f"{path}: {chosen.label}", used)


def _sample(path: Path, chosen: Candidate, tolerance: float) -> np.ndarray:
    """The chosen curve sampled to ``tolerance`` of its size, repeated points dropped, in file
    units; refused if it has a non-finite point, is above the point limit or has fewer than 2
    distinct points."""
    rough = check_finite(chosen.sample(None), f"{str(path)!r}: {chosen.label}").reshape(-1, 3)
    size = extent(rough, f"{str(path)!r}: {chosen.label}")
    points = check_finite(chosen.sample(tolerance * size), f"{str(path)!r}: {chosen.label}")
    limits.check("points", len(points), what=f"points of {chosen.label} in {path.name}")
    if len(points) > 1:  # drop repeated points (joints of segments)
        keep = np.r_[True, np.linalg.norm(np.diff(points, axis=0), axis=1) > ZERO_LENGTH * size]
        points = points[keep]
    if len(points) < 2:
        raise ProfileError(f"{str(path)!r}: {chosen.label} has fewer than 2 distinct points")
    return points


def _choose(path: Path, candidates: list, *, layer, name, index) -> Candidate:
    left = candidates
    if layer is not None:
        left = [
            c
            for c in left
            if (c.layer is not None and c.layer.lower() == layer.lower())
            or layer.lower() in c.layers
        ]
    if name is not None:
        left = [c for c in left if c.name is not None and c.name.lower() == name.lower()]
    listing = "; ".join(f"[{k}] {c.label}" for k, c in enumerate(candidates[:20]))
    if len(candidates) > 20:
        listing += f"; ... ({len(candidates)} curves)"
    if not candidates:
        raise ProfileError(f"{str(path)!r} holds no curve")
    if not left:
        asked = ", ".join(
            f"{k} = {v!r}" for k, v in (("layer", layer), ("name", name)) if v is not None
        )
        raise ProfileError(f"{str(path)!r}: no curve with {asked}; the file holds: {listing}")
    if index is not None:
        if not 0 <= index < len(left):
            raise ProfileError(
                f"{str(path)!r}: index {index} out of range 0 ... {len(left) - 1} of the curves "
                f"{'left' if left is not candidates else 'in the file'}: "
                + "; ".join(f"[{k}] {c.label}" for k, c in enumerate(left[:20]))
            )
        return left[index]
    if len(left) > 1:
        raise ProfileError(
            f"{str(path)!r} holds {len(left)} candidate curves; choose one with layer, name or "
            "index: " + "; ".join(f"[{k}] {c.label}" for k, c in enumerate(left[:20]))
        )
    return left[0]
