"""Planar crease profiles: curves in the (x, y) plane, in metres, parametrised by arc length.

Every profile is a :class:`Profile`, traversed from left to right, with ``length``,
``point(s)``, ``tangent_angle(s)``, signed ``curvature(s)`` (positive turning left) and
``sample(segments)`` at equal arc length. Importing this package does not import SciPy.

Classes
-------
ArcProfile, CatenaryProfile, ElasticaProfile
    Analytic arches through ``(-span/2, 0)``, ``(0, rise)``, ``(span/2, 0)``.
FunicularProfile
    Thrust line of vertical point and distributed loads, same end points, apex height
    ``rise`` (kinks at point loads).
SplineProfile
    Cubic spline through control points (may have inflection points).
PolylineProfile
    Explicit polyline with a discrete (Menger) curvature.

Functions
---------
profile_from_dict
    Build a profile from ``{"profile": name, ...}``.
discrete_curvature
    Signed Menger curvature at the interior vertices of a polyline.
"""

from __future__ import annotations

from compas_ccu.curves.arc import ArcProfile
from compas_ccu.curves.base import Profile
from compas_ccu.curves.catenary import CatenaryProfile
from compas_ccu.curves.discrete import discrete_curvature
from compas_ccu.curves.elastica import ElasticaProfile
from compas_ccu.curves.factory import PROFILE_TYPES, profile_from_dict
from compas_ccu.curves.funicular import FunicularProfile
from compas_ccu.curves.polyline import PolylineProfile
from compas_ccu.curves.spline import SplineProfile

__all__ = [
    "PROFILE_TYPES",
    "ArcProfile",
    "CatenaryProfile",
    "ElasticaProfile",
    "FunicularProfile",
    "PolylineProfile",
    "Profile",
    "SplineProfile",
    "discrete_curvature",
    "profile_from_dict",
]
