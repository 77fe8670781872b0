"""A target or a scan in the studio: the structure coloured by its distance to it, and a fit.

Pure functions and records (no web page; :mod:`compas_ccu.studio.target_panel` shows them):

* :func:`load_target` reads a target surface or point cloud with the fit package's reader
  (:func:`compas_ccu.fit.read_points`) from the design folder only (a name from the page is
  checked like a design file name: no absolute path, no ``..``, no link out of the folder);
  ``ccu studio --target FILE`` names one on the command line. Its normals (a mesh's face
  normals, or estimated from 12 neighbours for a point cloud), the k-d tree of its points and
  its point spacing are made once per target (:class:`StudioTarget`).
* :func:`target_state` measures every plate vertex of the state drawn: the distance the design
  fit gives the plates (:func:`compas_ccu.fit.target_distance`: point-to-plane at the nearest
  target point, plus any tangential offset beyond twice the target's gaps, so a plate
  reaching past the target's edge counts), with the RMS, the largest and every plate's RMS;
  :func:`colour_view` colours the view's plate vertices by it (legend in mm).
* :class:`FitRequest` and :func:`fit_job` run :func:`compas_ccu.fit.fit_design` on the free keys
  chosen on the page in a background process; :func:`apply_fit` makes the fitted values one
  undoable edit of the session.
"""

from __future__ import annotations

import html
import json
import math
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from compas_ccu.design import Design
from compas_ccu.design.schema import SCHEMA
from compas_ccu.design.units import from_metres
from compas_ccu.errors import CCUError, GeometryError, OptionError
from compas_ccu.fit import (
    PointSet,
    fit_design,
    parse_free,
    read_points,
    target_distance,
    target_spacing,
)
from compas_ccu.fit.points import FORMATS
from compas_ccu.limits import raised
from compas_ccu.studio.files import atomic_write
from compas_ccu.studio.panels import STATUS_COLORS, message_html
from compas_ccu.studio.view import cmap_colors

__all__ = ["StudioTarget", "TargetState", "FitRequest", "load_target", "target_of"]
__all__ += ["target_state", "colour_view", "target_html", "suggested_free", "fit_job"]
__all__ += ["apply_fit", "fit_html", "fit_request", "distance_colors", "TARGET_COLORING"]
__all__ += ["TARGET_SAMPLES", "TARGET_POINTS"]

#: The colouring of the plates by their distance to the target (offered once one is loaded).
TARGET_COLORING = "target distance"
#: Points sampled on a target surface (a mesh).
TARGET_SAMPLES = 50_000
#: The most target points kept (a seeded subset of a larger scan).
TARGET_POINTS = 200_000
#: The colour scale spans at least 0 .. this distance, m (a state on the target stays dark).
DISTANCE_FLOOR = 0.001
#: Tangential offsets within this many times the target's gaps are not distance.
GAP_FACTOR = 2.0
#: The colour map of the distance.
DISTANCE_CMAP = "viridis"
#: Suggested bounds of a free key: its value ± this share (lengths), ± degrees (angles).
LENGTH_SHARE = 0.25
ANGLE_RANGE = 10.0
#: The free keys the page suggests (any real-valued design key may be given).
SUGGESTED_KEYS = ("crease.rise", "deployment.alpha")
#: Keys the page names as the usual free keys.
USUAL_KEYS = ("crease.span", "crease.rise", "deployment.alpha", "layout.spacing")


@dataclass(frozen=True)
class StudioTarget:
    """A target or a scan read once, ready to measure any state against.

    Attributes
    ----------
    name : str
        As given (relative to the design folder, or the command line's path).
    target : PointSet
        Its points (n, 3) and normals (n, 3), m.
    tree : scipy.spatial.cKDTree
        Of ``target.points``.
    spacing : float
        Median distance of a target point to its nearest neighbour, m.
    allowance : float
        Tangential offset from the nearest target point that is not distance, m:
        :data:`GAP_FACTOR` times the target's gaps (the 99th percentile of the nearest-neighbour
        distance), since a plate vertex on the target's edge or corner sees target points on
        one side only.
    seconds : float
        Time to read it and build the tree.
    """

    name: str
    target: PointSet
    tree: cKDTree
    spacing: float
    allowance: float
    seconds: float = 0.0

    def distances(self, vertices) -> np.ndarray:
        """Unsigned distance of every vertex to the target, m.

        Parameters
        ----------
        vertices : (..., 3) float

        Returns
        -------
        (...) float
        """
        v = np.asarray(vertices, dtype=np.float64)
        d = target_distance(v.reshape(-1, 3), self.target, self.tree, self.allowance)
        return np.abs(d).reshape(v.shape[:-1])


def target_of(points: PointSet, name: str, *, limit: int = TARGET_POINTS) -> StudioTarget:
    """A :class:`StudioTarget` of ``points`` (at most ``limit``: a seeded subset; normals
    estimated for a point cloud)."""
    t0 = time.perf_counter()
    if len(points) > limit:
        keep = np.sort(np.random.default_rng(0).choice(len(points), size=limit, replace=False))
        points = points.subset(keep)
    points = points.with_normals()
    tree = cKDTree(points.points)
    spacing, gaps = target_spacing(points.points, tree) if len(points) > 1 else (0.0, 0.0)
    spacing, gaps = (x if math.isfinite(x) else 0.0 for x in (spacing, gaps))
    return StudioTarget(name, points, tree, spacing, GAP_FACTOR * gaps, time.perf_counter() - t0)


def load_target(files, name, *, command_line: bool = False, units: str = "m") -> StudioTarget:
    """Read target ``name`` for the studio.

    Parameters
    ----------
    files : StudioFiles
        The studio's folders: a name from the page is read from the design folder only.
    name : str
        A file name relative to the design folder (``scan.xyz``, ``targets/roof.obj``); with
        ``command_line`` any path (``ccu studio --target FILE``: the user named it).
    units : str
        Length units of a file without units (as ``ccu fit --units``).

    Raises
    ------
    OptionError
        One line: an absolute path, a ``..``, a link out of the design folder, the studio's
        own folder, or a format the fit package does not read.
    GeometryError
        The file is missing or not readable as points (:func:`compas_ccu.fit.read_points`).
    """
    t0 = time.perf_counter()
    text = str(name).strip()
    if command_line:
        path = Path(text).expanduser().resolve()
    else:
        path = files.inside(text, suffix=None)
    if path.suffix.lower() not in FORMATS:
        raise OptionError(f"{text!r}: a target is one of {', '.join(FORMATS)}")
    if not path.is_file():
        raise GeometryError(f"{text!r}: no such file in {path.parent}")
    points = read_points(path, count=TARGET_SAMPLES, seed=0, units=units)
    target = target_of(points, text)
    return StudioTarget(target.name, target.target, target.tree, target.spacing,
                        target.allowance, time.perf_counter() - t0)  # fmt: skip


@dataclass(frozen=True)
class TargetState:
    """The distance of one drawn state to the target.

    Attributes
    ----------
    alpha : float
        Of the state, degrees.
    distance : (p, v) float
        Of every plate vertex to the target, m.
    rms, max : float
        Over all plate vertices, m.
    plates : tuple of (int, float, float)
        ``(plate id, rms, max)`` of every plate, m.
    seconds : float
        Time the distances took.
    """

    alpha: float
    distance: np.ndarray
    rms: float
    max: float
    plates: tuple
    seconds: float


def target_state(target: StudioTarget, vertices, plate_ids, alpha: float) -> TargetState:
    """The distances of the plate ``vertices`` (p, v, 3) to ``target`` (vectorised: one k-d
    tree query for all vertices).

    Parameters
    ----------
    target : StudioTarget
    vertices : (p, v, 3) float
        Plate vertices of the state drawn, m.
    plate_ids : sequence of int
        The ids of the p plates.
    alpha : float
    """
    t0 = time.perf_counter()
    d = target.distances(vertices)
    per = np.sqrt(np.mean(d**2, axis=1))
    top = d.max(axis=1)
    plates = tuple((int(i), float(r), float(m)) for i, r, m in zip(plate_ids, per, top))
    rms, largest = float(np.sqrt(np.mean(d**2))), float(d.max())
    return TargetState(float(alpha), d, rms, largest, plates, time.perf_counter() - t0)


def distance_colors(distance, hi: float) -> np.ndarray:
    """sRGB colours (``distance.shape + (3,)`` uint8) of distances on the scale 0 .. ``hi``."""
    d = np.asarray(distance, dtype=float)
    scaled = np.clip(d.reshape(-1) / hi, 0.0, 1.0)
    return cmap_colors(DISTANCE_CMAP, scaled).reshape(d.shape + (3,))


def colour_view(view, state: TargetState, name: str) -> None:
    """Colour the plate vertices of ``view`` (a :class:`~compas_ccu.studio.view.ViewState`)
    by ``state``'s distances and say so in its legend (mm; the scale spans the values drawn,
    at least 0 .. 1 mm)."""
    hi = max(state.max, DISTANCE_FLOOR)
    view.vertex_colors = distance_colors(state.distance, hi)
    rows = [
        (tuple(int(x) for x in distance_colors(r, hi)), f"plate {pid}: RMS {r * 1000:.2f} mm")
        for pid, r, _ in state.plates
    ]
    view.legend = {
        "title": f"distance to the target {name} at α = {state.alpha:.4g}°",
        "scale": (DISTANCE_CMAP, 0.0, hi * 1000.0, " mm"),
        "rows": rows,
        "note": f"every plate vertex: RMS {state.rms * 1000:.2f} mm, largest "
        f"{state.max * 1000:.2f} mm (point-to-plane at the nearest target point)",
    }


def target_html(target: StudioTarget, state: TargetState | None) -> str:
    """The target's section of the checks panel: the file, its points and the distances of
    the state drawn (RMS, largest, every plate's RMS and largest)."""
    t = target.target
    kind = "surface (sampled)" if t.kind == "mesh" else "point cloud"
    out = [
        "<div id='ccu-target' style='font-size:0.85em;margin-top:8px'>"
        f"<b>target</b> {html.escape(target.name)}: {len(t):,} points, {kind}, spacing "
        f"{target.spacing * 1000:.2f} mm (sideways allowance {target.allowance * 1000:.1f} mm)"
    ]
    if state is not None:
        c = STATUS_COLORS["info"]
        rows = "".join(
            f"<tr><td style='padding:1px 6px'>plate {pid}</td><td style='padding:1px 6px;"
            f"text-align:right'>{r * 1000:.2f}</td><td style='padding:1px 6px;"
            f"text-align:right'>{m * 1000:.2f}</td></tr>"
            for pid, r, m in state.plates
        )
        out.append(
            f"<div style='color:{c}'>distance of the plate vertices at α = {state.alpha:.2f}°: "
            f"RMS <b id='ccu-target-rms'>{state.rms * 1000:.2f} mm</b>, largest "
            f"<b>{state.max * 1000:.2f} mm</b></div><table><tr><th></th><th>RMS mm</th>"
            f"<th>max mm</th></tr>{rows}</table><div style='color:#777'>measured in "
            f"{state.seconds * 1000:.1f} ms</div>"
        )
    out.append("</div>")
    return "".join(out)


# -- the fit ---------------------------------------------------------------------------------
def suggested_free(model, keys=SUGGESTED_KEYS) -> str:
    """Free keys with bounds around the model's values, as ``ccu fit --free`` takes them:
    lengths ± :data:`LENGTH_SHARE`, angles ± :data:`ANGLE_RANGE` degrees (within 0.5° and the
    deployment limit).

    >>> from compas_ccu.model import load_model
    >>> suggested_free(load_model("examples/vault.toml"))
    'crease.rise=0.75:1.25, deployment.alpha=20:40'
    """
    out = []
    for key in keys:
        section, name = key.split(".")
        value = model.design.values[section][name]
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        if SCHEMA[section][name].unit == "deg":
            lo = max(value - ANGLE_RANGE, 0.5)
            hi = min(value + ANGLE_RANGE, math.floor(model.alpha_limit * 10) / 10)
        else:
            lo, hi = sorted((value * (1 - LENGTH_SHARE), value * (1 + LENGTH_SHARE)))
        out.append(f"{key}={lo:.6g}:{hi:.6g}")
    return ", ".join(out)


@dataclass(frozen=True)
class FitRequest:
    """A fit asked for from the page: the valid design it starts from, the free keys and the
    target (:func:`fit_request` checks the keys at once)."""

    document: dict
    name: str
    base: object
    free: str
    target: StudioTarget
    options: dict

    def job(self, limits: dict) -> dict:
        """The keyword arguments of :func:`fit_job` (arrays and plain values: picklable)."""
        t = self.target.target
        return dict(document=self.document, name=self.name, base=self.base, free=self.free,
                    points=t.points, normals=t.normals, kind=t.kind, source=self.target.name,
                    options=self.options, limits=limits)  # fmt: skip


def fit_request(session, target: StudioTarget, free: str, **options) -> FitRequest:
    """A :class:`FitRequest` of the session's valid design.

    Raises
    ------
    CCUError
        One line: no valid design, no target, free keys that are not real design keys or have
        no bounds (as ``ccu fit --free``).
    """
    if target is None:
        raise OptionError("load a target before fitting")
    parse_free(free)
    with session.lock:
        model = session.model
        if model is None:
            raise OptionError("the design has no valid model to fit")
        design = model.design
        return FitRequest(session.valid_document, design.name, design.base, str(free), target,
                          dict(options))  # fmt: skip


def fit_job(document, *, name, base, free, points, normals, kind, source, options,
            limits) -> dict:  # fmt: skip
    """Fit the free keys of design ``document`` to the target points (what the background
    process runs; :func:`compas_ccu.fit.fit_design`).

    Returns
    -------
    dict
        ``pid``, and ``record`` (``fit.json``'s record) or ``error`` (the one line of a
        refused or failed fit).
    """
    target = PointSet(np.asarray(points), normals, source, kind)
    try:
        with raised(**limits):
            design = Design(document, name=name, base=base)
            result = fit_design(design, target, parse_free(free), **options)
    except CCUError as exc:
        return {"pid": os.getpid(), "error": str(exc)}
    return {"pid": os.getpid(), "record": result.to_dict()}


def apply_fit(session, request: FitRequest, outcome: dict, *, out=None):
    """Make the fitted values an edit of the session (one undo step) and write ``fit.json``
    into ``out`` (the output folder's ``<design>/fit/``) if given.

    Raises
    ------
    OptionError
        The fit failed, or the design changed since the fit started.
    """
    if "error" in outcome:
        raise OptionError(f"the fit failed: {outcome['error']}")
    record = outcome["record"]
    with session.lock:
        if session.valid_document != request.document:
            raise OptionError("the design changed while fitting: fit again")
        document = session.valid_document
        units = document.get("design", {}).get("units", "m")
        for key, value in record["parameters"].items():
            section, name = key.split(".")
            spec = SCHEMA[section][name]
            document.setdefault(section, {})[name] = from_metres(spec.kind, spec.unit, value,
                                                                 units)  # fmt: skip
        problem = session.replace(document)
    if problem is not None:
        raise OptionError(f"the fitted design does not build: {problem.message}")
    if out is not None:
        folder = Path(out) / request.name / "fit"
        folder.mkdir(parents=True, exist_ok=True)
        text = json.dumps({"target": request.target.name, **record}, indent=1) + "\n"
        return atomic_write(folder / "fit.json", text)
    return None


def fit_html(outcome: dict) -> str:
    """The figures of a fit (``fit.json``): parameters from → to, RMS, largest, Hausdorff,
    models built; or why it failed."""
    if "error" in outcome:
        return message_html(f"the fit failed: {outcome['error']}", "fail", id="ccu-fit")
    r = outcome["record"]
    rows = "".join(
        f"<tr><td style='padding:1px 6px'>{html.escape(k)}</td><td style='padding:1px 6px'>"
        f"{r['start'][k]:.6g} → <b>{v:.6g}</b></td></tr>"
        for k, v in r["parameters"].items()
    )
    return (
        f"<div id='ccu-fit' style='font-size:0.85em'><table>{rows}</table>"
        f"RMS {r['rms'] * 1000:.2f} mm, largest {r['max'] * 1000:.2f} mm, Hausdorff "
        f"{r['hausdorff'] * 1000:.2f} mm (target points to the plates); {r['evaluations']} "
        f"models built ({html.escape(r['message'])})</div>"
    )
