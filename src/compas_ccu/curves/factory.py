"""Build a profile from a JSON-like specification."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from compas_ccu.curves.arc import ArcProfile
from compas_ccu.curves.base import Profile, require_real
from compas_ccu.curves.catenary import CatenaryProfile
from compas_ccu.curves.elastica import ElasticaProfile
from compas_ccu.curves.funicular import FunicularProfile
from compas_ccu.curves.polyline import PolylineProfile
from compas_ccu.curves.spline import SplineProfile
from compas_ccu.errors import ProfileError

__all__ = ["PROFILE_TYPES", "profile_from_dict"]

#: Profile classes by their ``name``.
PROFILE_TYPES = {
    cls.name: cls
    for cls in (
        ArcProfile,
        CatenaryProfile,
        ElasticaProfile,
        SplineProfile,
        PolylineProfile,
        FunicularProfile,
    )
}

#: Keys read by the caller, not by the factory.
IGNORED_KEYS = ("profile", "segments")

#: For each profile: the alternative sets of required keys, and the optional keys.
_REQUIRED_KEYS = {
    "arc": (("span", "rise"), ("radius", "angle")),
    "catenary": (("span", "rise"),),
    "elastica": (("span", "rise"),),
    "spline": (("points",),),
    "polyline": (("points",),),
    "funicular": (("span", "rise"),),
}
_OPTIONAL_KEYS = {"spline": ("bc_type",), "funicular": ("point_loads", "distributed_loads")}


def profile_from_dict(spec: Mapping) -> Profile:
    """Build a profile from a specification such as ``{"profile": "arc", "span": 4, "rise": 1}``.

    Keys by profile (lengths in m, angles in degrees):

    - ``"arc"``: ``span``, ``rise``; or ``radius``, ``angle`` (central angle, degrees)
    - ``"catenary"``, ``"elastica"``: ``span``, ``rise``
    - ``"spline"``: ``points`` (list of ``[x, y]``), optional ``bc_type``
      (``"natural"`` or ``"not-a-knot"``)
    - ``"polyline"``: ``points`` (list of ``[x, y]``)
    - ``"funicular"``: ``span``, ``rise``, optional ``point_loads`` (list of ``[x, P]``) and
      ``distributed_loads`` (list of ``[x0, x1, q0, q1]``); neither: a uniform load

    The keys ``"profile"`` and ``"segments"`` may be present; ``"segments"`` is ignored here
    (the caller uses it to sample the profile). ``Profile.parameters()`` plus ``"profile"``
    rebuilds an equal profile.

    Parameters
    ----------
    spec : dict
        The specification.

    Returns
    -------
    Profile
        The profile.

    Raises
    ------
    ProfileError
        If ``profile`` is missing or unknown; if a key is unknown, missing or conflicting (the
        message names it and lists the allowed keys); if a value is not a real finite number
        (``bool`` is not a number) or is otherwise invalid.

    Examples
    --------
    >>> profile = profile_from_dict({"profile": "catenary", "span": 4, "rise": 1, "segments": 32})
    >>> type(profile).__name__, profile.parameters()
    ('CatenaryProfile', {'span': 4.0, 'rise': 1.0})
    """
    if not isinstance(spec, Mapping):
        raise ProfileError(f"profile spec must be a dict, got {type(spec).__name__}")
    allowed_profiles = ", ".join(PROFILE_TYPES)
    if "profile" not in spec:
        raise ProfileError(f"missing key 'profile'; allowed profiles: {allowed_profiles}")
    kind = spec["profile"]
    if not isinstance(kind, str) or kind not in PROFILE_TYPES:
        raise ProfileError(f"profile must be one of {allowed_profiles}, got {kind!r}")

    alternatives = _REQUIRED_KEYS[kind]
    optional = _OPTIONAL_KEYS.get(kind, ())
    allowed = [key for keys in alternatives for key in keys] + list(optional)
    allowed_text = (
        f"allowed keys for profile {kind!r}: {', '.join(allowed)} "
        f"(and {', '.join(map(repr, IGNORED_KEYS))})"
    )
    given = [key for key in spec if key not in IGNORED_KEYS]
    unknown = [key for key in given if key not in allowed]
    if unknown:
        raise ProfileError(f"unknown key {unknown[0]!r}; {allowed_text}")

    required_given = {key for key in given if key not in optional}
    touched = [keys for keys in alternatives if required_given.intersection(keys)]
    if len(touched) > 1:
        choices = " or ".join(f"({', '.join(keys)})" for keys in alternatives)
        raise ProfileError(
            f"conflicting keys {', '.join(sorted(map(repr, required_given)))} for profile "
            f"{kind!r}: give either {choices}"
        )
    chosen = touched[0] if touched else alternatives[0]
    missing = [key for key in chosen if key not in spec]
    if missing:
        raise ProfileError(f"missing key {missing[0]!r}; {allowed_text}")

    values = {key: spec[key] for key in given}
    if "points" in values:
        values["points"] = _require_point_list(values["points"])
    for key in ("span", "rise", "radius", "angle"):
        if key in values:
            values[key] = require_real(key, values[key], unit="degrees" if key == "angle" else "m")

    if kind == "arc" and "radius" in values:
        return ArcProfile.from_radius_angle(**values)
    if kind in ("spline", "polyline"):
        points = values.pop("points")
        return PROFILE_TYPES[kind](points, **values)
    return PROFILE_TYPES[kind](**values)


def _require_point_list(points: object) -> np.ndarray:
    """Check a JSON-like list of ``[x, y]`` pairs of real finite numbers; return (n, 2) float."""
    if isinstance(points, np.ndarray):
        return points
    if not isinstance(points, (list, tuple)):
        raise ProfileError(
            f"points must be a list of [x, y] pairs (m), got {type(points).__name__}"
        )
    fast = _plain_pairs(points)
    if fast is not None:
        return fast
    for index, pair in enumerate(points):
        if not isinstance(pair, (list, tuple, np.ndarray)) or len(pair) != 2:
            raise ProfileError(f"points[{index}] must be a pair [x, y] (m), got {pair!r}")
        for axis, coordinate in enumerate(pair):
            require_real(f"points[{index}][{axis}]", coordinate)
    return np.array(points, dtype=float).reshape(len(points), 2)


def _plain_pairs(points):
    """``points`` as (n, 2) float if it is a list of [x, y] lists of plain finite floats and
    ints (no bool), checked in NumPy; None for anything else (the loop names the culprit)."""
    if not all(type(p) is list and len(p) == 2 for p in points):
        return None
    if not {type(c) for p in points for c in p} <= {float, int}:
        return None
    try:
        array = np.array(points, dtype=float).reshape(len(points), 2)
    except (OverflowError, ValueError):
        return None
    return array if np.isfinite(array).all() else None
