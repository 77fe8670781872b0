"""Checks and fast paths of DXF input shared by the curve reader and the plate importer.

* :func:`dxf_units`: the unit of ``$INSUNITS``, refusing a code outside the ones understood;
* :func:`check_dxf_points`: the point limit (:data:`compas_ccu.limits.LIMITS` ``points``)
  checked on the file's bytes before ezdxf parses it;
* :func:`spline_sampler`: a SPLINE's points, with coincident fit points dropped and a SPLINE
  that no curve can be built from refused by name;
* :func:`straight_polyline_points`: the vertices of an LWPOLYLINE without arcs, vectorised.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from compas_ccu import limits
from compas_ccu.errors import ProfileError
from compas_ccu.tolerances import ZERO_LENGTH

__all__ = [
    "DXF_UNITS",
    "dxf_units",
    "dxf_point_count",
    "check_dxf_points",
    "check_finite",
    "extent",
    "ocs_to_wcs",
    "one_line",
    "spline_sampler",
    "straight_polyline_points",
]

#: The ``$INSUNITS`` codes the readers understand: code -> unit (0: unitless).
DXF_UNITS = {0: None, 1: "in", 2: "ft", 4: "mm", 5: "cm", 6: "m"}


def _understood() -> str:
    return ", ".join(f"{c} ({u or 'unitless'})" for c, u in DXF_UNITS.items())


def dxf_units(doc, path) -> str | None:
    """The unit of a DXF document's ``$INSUNITS`` (None: unitless).

    Raises
    ------
    ProfileError
        The code is none of :data:`DXF_UNITS` (the message names the code and the codes
        understood).

    Examples
    --------
    >>> import ezdxf
    >>> doc = ezdxf.new()
    >>> doc.header["$INSUNITS"] = 4
    >>> dxf_units(doc, "crease.dxf")
    'mm'
    """
    code = doc.header.get("$INSUNITS", 0)
    if code is None or code == "":
        code = 0
    if isinstance(code, bool) or not isinstance(code, int) or code not in DXF_UNITS:
        raise ProfileError(
            f"{str(path)!r}: $INSUNITS = {code!r} is a unit code not understood; understood: "
            f"{_understood()}; or give the file's units (m, cm, mm, in, ft)"
        )
    return DXF_UNITS[code]


def dxf_point_count(data: bytes) -> int:
    """An upper bound of the points a DXF file holds: its group-code 10 tags (x coordinates).

    Examples
    --------
    >>> dxf_point_count(b"0\\nLINE\\n 10\\n0.0\\n 20\\n0.0\\n 11\\n1.0\\n 21\\n0.0\\n")
    1
    """
    text = data.replace(b"\r\n", b"\n")
    count = text.count(b"\n 10\n") + text.count(b"\n10\n") + text.count(b"\n  10\n")
    return count + int(text.startswith(b"10\n") or text.startswith(b" 10\n"))


def check_dxf_points(path) -> None:
    """Refuse a DXF file with more coordinate tags than the ``points`` limit, before parsing.

    Raises
    ------
    LimitError
        Names the file, the count and how to raise the limit.

    Examples
    --------
    A small file is let through without being read:

    >>> import tempfile
    >>> from pathlib import Path
    >>> path = Path(tempfile.mkdtemp()) / "small.dxf"
    >>> _ = path.write_bytes(b"0\\nEOF\\n")
    >>> check_dxf_points(path) is None
    True
    """
    path = Path(path)
    try:
        size = path.stat().st_size
    except OSError:
        return  # the reader names the problem
    if size < 12 * limits.LIMITS.points:  # every point takes at least 12 bytes
        return
    count = dxf_point_count(path.read_bytes())
    limits.check("points", count, what=f"points (coordinate tags) in {path.name}")


def check_finite(points, label: str):
    """``points`` as a float array, or a ProfileError naming the first non-finite coordinate.

    Examples
    --------
    >>> check_finite([[0, 1, 2]], "LINE #1").tolist()
    [[0.0, 1.0, 2.0]]
    >>> check_finite([[0, 1, 2], [0, float("nan"), 0]], "LINE #1")
    Traceback (most recent call last):
    ...
    compas_ccu.errors.ProfileError: LINE #1 has a non-finite coordinate at point 1: [0.0, nan, 0.0]
    """
    pts = np.asarray(points, dtype=float)
    bad = ~np.isfinite(pts)
    if bad.any():
        k = int(np.flatnonzero(bad.any(axis=-1) if pts.ndim > 1 else bad)[0])
        raise ProfileError(f"{label} has a non-finite coordinate at point {k}: {pts[k].tolist()}")
    return pts


def one_line(exc) -> str:
    """An exception's message on one line (ezdxf's can hold the offending line's newline).

    Examples
    --------
    >>> one_line(ValueError("bad tag\\n  on line 12"))
    'bad tag on line 12'
    """
    return " ".join(str(exc).split())


def extent(points, label: str) -> float:
    """The bounding-box diagonal of finite ``points`` (k, 3), or a ProfileError if it exceeds
    what a float holds (coordinates near 1e308).

    Examples
    --------
    >>> extent([[0.0, 0.0, 0.0], [3.0, 4.0, 0.0]], "LINE #1")
    5.0
    """
    if not len(points):
        return 0.0
    with np.errstate(over="ignore", invalid="ignore"):
        size = float(np.linalg.norm(np.ptp(points, axis=0)))
    if not math.isfinite(size):
        raise ProfileError(
            f"{label}: its extent overflows a float (coordinates up to "
            f"{float(np.abs(points).max()):g})"
        )
    return size


def spline_sampler(e):
    """A function ``tolerance -> (n, 3) points`` of a DXF SPLINE (file units).

    A SPLINE of fit points is interpolated through its distinct fit points (a fit point that
    repeats its predecessor within 1e-12 of their extent is dropped: ezdxf's interpolation
    divides by the distance between them); a SPLINE of control points is ezdxf's B-spline of
    them. The checks run when the curve is sampled, so a broken SPLINE elsewhere in a file does
    not stop reading another curve.

    Raises (when called)
    ------
    ProfileError
        The SPLINE has fewer than 2 distinct fit points and no control points, a non-finite
        coordinate, or ezdxf cannot build a curve of its data (the message names the handle).

    Examples
    --------
    >>> import ezdxf
    >>> spline = ezdxf.new().modelspace().add_spline(fit_points=[(0, 0), (1, 1), (2, 0)])
    >>> points = spline_sampler(spline)(1e-3)
    >>> len(points) > 10, (points[[0, -1]].round(6) + 0.0).tolist()
    (True, [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    """
    label = f"SPLINE #{e.dxf.handle}"
    state: dict = {}

    def tool():
        if "tool" in state:
            return state["tool"]
        from ezdxf.math import fit_points_to_cad_cv

        try:
            if e.control_point_count():
                check_finite(np.asarray(e.control_points, dtype=float), label)
                made = e.construction_tool()
            elif e.fit_point_count():
                fit = check_finite(np.asarray(e.fit_points, dtype=float), label)
                extent = float(np.linalg.norm(np.ptp(fit, axis=0)))
                step = np.linalg.norm(np.diff(fit, axis=0), axis=1)
                distinct = fit[np.r_[True, step > ZERO_LENGTH * extent]]
                if len(distinct) < 2:
                    raise ProfileError(
                        f"{label}: its {len(fit)} fit points coincide (fewer than 2 distinct "
                        "points) and it has no control points"
                    )
                tangents = None
                if e.dxf.hasattr("start_tangent") and e.dxf.hasattr("end_tangent"):
                    tangents = [e.dxf.start_tangent, e.dxf.end_tangent]
                    if not all(math.isfinite(c) for t in tangents for c in t):
                        raise ProfileError(f"{label}: a non-finite end tangent {tangents}")
                    if min(math.hypot(*t) for t in tangents) == 0.0:
                        tangents = None  # a zero tangent: no tangent given
                made = fit_points_to_cad_cv(distinct, tangents=tangents)
            else:
                raise ProfileError(f"{label} has neither control points nor fit points")
        except ProfileError:
            raise
        except (ValueError, ArithmeticError, IndexError, np.linalg.LinAlgError) as exc:
            raise ProfileError(f"{label}: no curve can be built of its data ({exc})") from None
        state["tool"] = made
        return made

    def sample(tol):
        spline = tool()
        try:
            if tol is None:
                return np.array([tuple(v) for v in spline.control_points], dtype=float)
            return np.array([tuple(v) for v in spline.flattening(tol, segments=16)], dtype=float)
        except (
            ValueError,
            ArithmeticError,
            IndexError,
            np.linalg.LinAlgError,
            RecursionError,
        ) as exc:
            raise ProfileError(f"{label}: its curve cannot be evaluated ({exc})") from None

    return sample


def straight_polyline_points(e):
    """The WCS vertices of an LWPOLYLINE without arcs ((n, 3) float, the first repeated at
    the end if it is closed), or None if it has an arc (bulge) segment.

    Examples
    --------
    >>> import ezdxf
    >>> msp = ezdxf.new().modelspace()
    >>> straight_polyline_points(msp.add_lwpolyline([(0, 0), (1, 1), (2, 0)])).tolist()
    [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 0.0, 0.0]]
    >>> print(straight_polyline_points(msp.add_lwpolyline([(0, 0, 0, 0, 1.0), (1, 1)])))  # a bulge
    None
    """
    data = np.asarray(list(e.lwpoints), dtype=float).reshape(-1, 5)
    if np.any(data[:, 4] != 0.0):
        return None
    ocs = e.ocs()
    elevation = float(e.dxf.get("elevation", 0.0) or 0.0)
    local = np.c_[data[:, :2], np.full(len(data), elevation)]
    if e.closed and len(local) > 1:
        local = np.r_[local, local[:1]]
    return ocs_to_wcs(ocs, local)


def ocs_to_wcs(ocs, local: np.ndarray) -> np.ndarray:
    """World coordinates of points given in an entity's object coordinate system: ezdxf's
    ``OCS.to_wcs`` of every point at once, the same operations in the same order
    (``x ux + y uy + z uz``), so the same numbers; the points themselves where the OCS is the
    world's.

    Parameters
    ----------
    ocs : ezdxf.math.OCS
    local : (m, 3) float

    Returns
    -------
    (m, 3) float

    Examples
    --------
    >>> from ezdxf.math import OCS
    >>> ocs_to_wcs(OCS((0, 0, -1)), np.array([[1.0, 2.0, 3.0]])).tolist()  # a mirrored arc's
    [[-1.0, 2.0, -3.0]]
    >>> tuple(OCS((0, 0, -1)).to_wcs((1.0, 2.0, 3.0)))
    (-1.0, 2.0, -3.0)
    """
    if not ocs.transform:
        return local
    ux, uy, uz = (np.array(tuple(axis), dtype=float) for axis in (ocs.ux, ocs.uy, ocs.uz))
    return local[:, :1] * ux + local[:, 1:2] * uy + local[:, 2:3] * uz
