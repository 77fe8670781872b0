"""The curves of a Rhino 3dm file (``rhino3dm``, the ``fab`` extra), as candidates.

Every curve object (line, polyline, arc, NURBS, polycurve), evaluated with ``Curve.PointAt``
(the knots of a NURBS curve sampled exactly: possible kinks); units from the file's model unit
system.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from compas_ccu.curves.candidates import UNITS, Candidate, adaptive, need_module
from compas_ccu.errors import ProfileError

__all__ = ["rhino_candidates"]


_RHINO_UNITS = {
    "Meters": "m",
    "Millimeters": "mm",
    "Centimeters": "cm",
    "Inches": "in",
    "Feet": "ft",
}


def rhino_candidates(path: Path):
    """The curve objects of a Rhino 3dm file, its units and no unit factor.

    Returns
    -------
    candidates : list of Candidate
        Every curve object (line, polyline, arc, NURBS, polycurve) in file order.
    units : str or None
        The file's model unit system (None: unset).
    factor : None

    Raises
    ------
    ProfileError
        The file is not a 3dm file, or its model units are none of :data:`UNITS`.
    MissingExtraError
        rhino3dm is not installed.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import rhino3dm
    >>> model = rhino3dm.File3dm()
    >>> model.Settings.ModelUnitSystem = rhino3dm.UnitSystem.Millimeters
    >>> _ = model.Objects.AddLine(rhino3dm.Point3d(0, 0, 0), rhino3dm.Point3d(1000, 0, 0))
    >>> path = Path(tempfile.mkdtemp()) / "crease.3dm"
    >>> model.Write(str(path), 7)
    True
    >>> candidates, units, factor = rhino_candidates(path)
    >>> len(candidates), units, factor, candidates[0].sample(None).round(6).tolist()
    (1, 'mm', None, [[0.0, 0.0, 0.0], [1000.0, 0.0, 0.0]])
    """
    rhino3dm = need_module("rhino3dm", "fab", "3dm files")
    model = rhino3dm.File3dm.Read(str(path))
    if model is None:
        raise ProfileError(f"cannot read 3dm file {str(path)!r}")
    unit_name = str(model.Settings.ModelUnitSystem).split(".")[-1]
    file_units = _RHINO_UNITS.get(unit_name)
    if file_units is None and unit_name not in ("None", "Unset"):
        raise ProfileError(
            f"{str(path)!r}: model units {unit_name} are not supported; give units = one of "
            f"{', '.join(UNITS)}"
        )
    layers = {k: model.Layers[k] for k in range(len(model.Layers))}
    candidates = []
    for obj in model.Objects:
        geometry = obj.Geometry
        if not isinstance(geometry, rhino3dm.Curve):
            continue
        attrs = obj.Attributes
        layer = layers.get(attrs.LayerIndex)
        layer_name = layer.Name if layer is not None else None
        kind = type(geometry).__name__
        name = attrs.Name or None
        label = f"{kind} {name or str(attrs.Id)[:8]!r} on layer {layer_name}"
        candidates.append(Candidate(label, layer_name, name, _rhino_sampler(rhino3dm, geometry)))
    return candidates, file_units, None


def _rhino_sampler(rhino3dm, curve):
    if isinstance(curve, rhino3dm.PolylineCurve):
        pts = np.array([[p.X, p.Y, p.Z] for p in (curve.Point(k) for k in range(curve.PointCount))])
        return lambda tol: pts
    if isinstance(curve, rhino3dm.LineCurve):
        a, b = curve.PointAtStart, curve.PointAtEnd
        pts = np.array([[a.X, a.Y, a.Z], [b.X, b.Y, b.Z]])
        return lambda tol: pts
    domain = curve.Domain
    breaks = ()
    nurbs = curve.ToNurbsCurve()
    if nurbs is not None:  # knots of multiplicity >= degree: possible kinks, sampled exactly
        knots = [nurbs.Knots[k] for k in range(len(nurbs.Knots))]
        breaks = tuple(sorted(set(knots)))

    def evaluate(ts):
        out = []
        for t in ts:
            p = curve.PointAt(float(t))
            out.append((p.X, p.Y, p.Z))
        return np.array(out, dtype=float)

    return lambda tol: adaptive(evaluate, domain.T0, domain.T1, tol, breaks=breaks)
