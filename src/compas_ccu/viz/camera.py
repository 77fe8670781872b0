"""The cameras of the pictures: a view by name, the projection, and the framing of several states.

A :class:`Camera` looks at the scene from an azimuth and an elevation, orthographic or in
perspective; :func:`camera` reads a view name or ``"azimuth,elevation"``. Several scenes drawn at
one scale (a deployment sequence, the frames of an animation) share the limits of
:func:`projected_limits`; :func:`path_frames` gives the grounded states of a path so framed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.tolerances import EXACT_RELATIVE
from compas_ccu.viz.scene import scene_from_structure

__all__ = ["Camera", "VIEWS", "camera", "projected_limits", "path_frames", "PathFrames"]


@dataclass(frozen=True)
class Camera:
    """A view of the scene.

    Parameters
    ----------
    azimuth, elevation : float
        Direction from the scene towards the eye, degrees (azimuth from +x in the xy plane,
        elevation above it).
    distance : float or None
        Eye distance in units of the scene size for a perspective view; None: orthographic.
    """

    azimuth: float = -60.0
    elevation: float = 28.0
    distance: float | None = 3.0

    def axes(self) -> np.ndarray:
        """(3, 3) rows: screen right, screen up, towards the eye."""
        az, el = math.radians(self.azimuth), math.radians(self.elevation)
        eye = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
        right = np.array([-math.sin(az), math.cos(az), 0.0])
        up = np.cross(eye, right)
        return np.array([right, up, eye])

    def project(self, points, centre, size: float) -> tuple:
        """Project points.

        Parameters
        ----------
        points : (..., 3) float
        centre : (3,) float
            The point the camera looks at.
        size : float
            Scene size (sets the eye distance of a perspective view).

        Returns
        -------
        xy : (..., 2) float
            Screen coordinates (metres at the centre's depth).
        depth : (...,) float
            Towards the eye: larger is nearer.
        """
        rel = np.asarray(points, dtype=float) - np.asarray(centre, dtype=float)
        screen = rel @ self.axes().T
        xy, depth = screen[..., :2], screen[..., 2]
        if self.distance is not None:
            eye = self.distance * size
            xy = xy * (eye / np.maximum(eye - depth, EXACT_RELATIVE * eye))[..., None]
        return xy, depth


VIEWS = {
    "perspective": Camera(-60.0, 28.0, 3.0),
    "plan": Camera(-90.0, 90.0, None),
    "elevation": Camera(-90.0, 0.0, None),
    "side": Camera(0.0, 0.0, None),
    "top": Camera(-90.0, 90.0, None),
    "front": Camera(-90.0, 0.0, None),
    "iso": Camera(-45.0, math.degrees(math.atan(1.0 / math.sqrt(2.0))), None),
}


def camera(view) -> Camera:
    """A :class:`Camera` from a view name or ``"azimuth,elevation"`` (degrees, orthographic).

    Names: ``perspective``, ``plan`` (= ``top``), ``elevation`` (= ``front``), ``side``,
    ``iso`` (the isometric view, orthographic, elevation 35.26°).

    Examples
    --------
    >>> camera("iso").azimuth, round(camera("iso").elevation, 2), camera("iso").distance
    (-45.0, 35.26, None)
    >>> camera("30,20")
    Camera(azimuth=30.0, elevation=20.0, distance=None)
    """
    if isinstance(view, Camera):
        return view
    if isinstance(view, str) and "," in view:
        try:
            az, el = (float(x) for x in view.split(","))
        except ValueError:
            raise OptionError(
                f"a view 'azimuth,elevation' needs two numbers of degrees, got {view!r}"
            ) from None
        if not (math.isfinite(az) and math.isfinite(el) and -90.0 <= el <= 90.0):
            raise OptionError(f"view elevation must be within -90 to 90 degrees, got {view!r}")
        return Camera(az, el, None)
    try:
        return VIEWS[view]
    except (KeyError, TypeError):
        raise OptionError(
            f"unknown view {view!r}; expected one of {sorted(VIEWS)} or 'azimuth,elevation'"
        ) from None


@dataclass
class PathFrames:
    """The grounded states of a deployment path, framed by one camera at one scale."""

    alphas: np.ndarray
    structures: list
    scenes: list
    centre: np.ndarray
    size: float
    limits: tuple


def path_frames(model, count, alpha=None, view="perspective", *, what="count") -> PathFrames:
    """``count`` states from α = 0 to ``alpha`` (default: the design α), framed together.

    Raises OptionError naming ``what`` for a count below 2 and for ``alpha <= 0``.
    """

    if int(count) != count or count < 2:
        raise OptionError(f"{what} must be an integer >= 2, got {count!r}")
    target = model.alpha_design if alpha is None else float(alpha)
    if not target > 0.0:
        raise OptionError(f"alpha must be > 0 degrees, got {target!r}")
    alphas = np.linspace(0.0, target, int(count))
    structures = model.path(alphas)
    scenes = [scene_from_structure(s, ground=True) for s in structures]
    pts = np.concatenate([s.vertices.reshape(-1, 3) for s in scenes])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    size = float(np.linalg.norm(np.ptp(pts, axis=0)))
    limits = projected_limits(scenes, view, centre=centre, size=size)
    return PathFrames(alphas, structures, scenes, centre, size, limits)


def projected_limits(scenes, view="perspective", *, centre=None, size=None, pad=0.04) -> tuple:
    """Common axes limits ``(xmin, xmax, ymin, ymax)`` of several scenes in one view."""
    cam = camera(view)
    pts = np.concatenate([s.vertices.reshape(-1, 3) for s in scenes])
    if centre is None:
        centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    if size is None:
        size = float(np.linalg.norm(np.ptp(pts, axis=0))) or 1.0
    xy, _ = cam.project(pts, centre, size)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    m = pad * max(hi - lo)
    return (lo[0] - m, hi[0] + m, lo[1] - m, hi[1] + m)
