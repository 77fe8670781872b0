"""Design by fitting a target (``ccu fit``, docs/fit.md): free design keys, within bounds, so
that the deployed design meets a target surface or point cloud.

Every evaluation builds the exact forward model (a :class:`~compas_ccu.model.CCUModel` of the
base design document with the free keys set) and deploys it to its design angle. The residuals
are two-sided: the signed distance of a fixed, seeded subset of the target points to the plates
(the target is covered) and the distance of fixed points on every plate triangle (barycentric
lattice, the same in every evaluation) to the target (the plates stay on it): point-to-plane at
the nearest target point, plus any tangential offset beyond the target's point spacing (a plate
reaching past the target's edge). ``scipy.optimize.least_squares`` (trf, bounds, loss
``soft_l1``) starts from the base design and stops after at most ``max_evaluations`` models:
the result depends on the seed, never on a clock.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial import cKDTree

from compas_ccu.design import Design
from compas_ccu.design.schema import SCHEMA
from compas_ccu.errors import CCUError, DesignError, FitError, OptionError
from compas_ccu.fit.distance import PlateSurface, plate_triangles
from compas_ccu.model import CCUModel
from compas_ccu.tolerances import EXACT_RELATIVE, FIT_OBJECTIVE

__all__ = ["FreeKey", "DesignFit", "fit_design", "parse_free", "free_keys", "TARGET_SIZE_FACTOR"]
__all__ += ["target_distance", "target_spacing"]

#: A target whose bounding box diagonal exceeds this many times the largest design size within
#: the bounds is refused: no deployable design of this base can reach it.
TARGET_SIZE_FACTOR = 2.0
#: Residual (m) of an evaluation whose design cannot be built (beyond a limit).
FAILED_RESIDUAL = 1.0
#: Barycentric points on every plate triangle for the plates -> target term.
_BARY = np.array([[1 / 3, 1 / 3], [2 / 3, 1 / 6], [1 / 6, 2 / 3], [1 / 6, 1 / 6]])


@dataclass(frozen=True)
class FreeKey:
    """A design key the fit may change.

    Attributes
    ----------
    key : str
        ``section.name`` of the design schema, e.g. ``crease.rise``.
    lower, upper : float
        Bounds, in the key's schema unit (m for lengths, degrees for angles).
    """

    key: str
    lower: float
    upper: float

    @property
    def section(self) -> str:
        return self.key.split(".", 1)[0]

    @property
    def name(self) -> str:
        return self.key.split(".", 1)[1]


def _check_key(key: str, lower, upper) -> FreeKey:
    section, _, name = key.partition(".")
    if not name or section not in SCHEMA or name not in SCHEMA[section]:
        raise DesignError(
            "not a design key (free keys are section.name, e.g. crease.rise)", key=key
        )
    spec = SCHEMA[section][name]
    if spec.kind not in ("float", "float_or_list"):
        raise DesignError(f"a free key must be a real number, this one is {spec.kind}", key=key)
    if lower is None or upper is None:
        raise OptionError(f"{key}: a free key needs bounds, e.g. {key}=LOWER:UPPER")
    try:
        lo, hi = float(lower), float(upper)
    except (TypeError, ValueError):
        raise OptionError(f"{key}: bounds must be numbers, got {lower!r}:{upper!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise OptionError(f"{key}: bounds must be finite with lower < upper, got {lo:g}:{hi:g}")
    return FreeKey(key, lo, hi)


def parse_free(text: str) -> list:
    """Free keys from ``KEY=LOWER:UPPER[,KEY=LOWER:UPPER ...]``.

    Examples
    --------
    >>> parse_free("crease.rise=0.5:1.5,layout.spacing=0.1:0.2")[0]
    FreeKey(key='crease.rise', lower=0.5, upper=1.5)
    >>> parse_free("crease.rise")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    compas_ccu.errors.OptionError: crease.rise: a free key needs bounds, e.g. ...
    """
    out = []
    for item in (s.strip() for s in str(text).split(",")):
        if not item:
            continue
        key, _, bounds = item.partition("=")
        lower, _, upper = bounds.partition(":")
        out.append(_check_key(key.strip(), lower.strip() or None, upper.strip() or None))
    return free_keys(out)


def free_keys(items) -> list:
    """Checked free keys from :class:`FreeKey` records or ``{key: [lower, upper]}``."""
    if isinstance(items, dict):
        out = []
        for key, bounds in items.items():
            if not isinstance(bounds, (list, tuple)) or len(bounds) != 2:
                raise OptionError(f"{key}: a free key needs bounds [lower, upper], got {bounds!r}")
            out.append(_check_key(key, *bounds))
        items = out
    items = list(items)
    if not items:
        raise OptionError("no free keys: give --free KEY=LOWER:UPPER or a [free] table")
    keys = [f.key for f in items]
    if len(set(keys)) != len(keys):
        raise OptionError(f"a free key is given twice: {', '.join(keys)}")
    return items


@dataclass(frozen=True)
class DesignFit:
    """The result of :func:`fit_design`.

    Attributes
    ----------
    design : Design
        The fitted design (the base document with the free keys set), in the base's units.
    parameters : dict
        ``{key: value}`` fitted, schema units (m, degrees).
    start : dict
        The base design's values.
    rms, max : float
        RMS and largest distance of all target points to the fitted plates, m.
    hausdorff : float
        The larger of ``max`` and the largest distance of the plates to the target, m.
    plates : tuple of dict
        ``{"id", "points", "rms", "max"}`` of the target points nearest to each plate.
    evaluations : int
        Models built by the least-squares solver.
    status : int
        ``least_squares``' status; message : str.
    signed : (n,) float
        Signed distance of every target point to the fitted plates.
    plate_row : (n,) int
    """

    design: Design
    parameters: dict
    start: dict
    rms: float
    max: float
    hausdorff: float
    plates: tuple
    evaluations: int
    status: int
    message: str
    bounds: dict
    signed: np.ndarray = field(repr=False)
    plate_row: np.ndarray = field(repr=False)

    def to_dict(self) -> dict:
        """The ``ccu.fit`` record (docs/fit.md), lengths m, angles degrees."""
        return {
            "format": "ccu.fit",
            "version": 1,
            "units": "m",
            "design": self.design.name,
            "parameters": self.parameters,
            "start": self.start,
            "bounds": self.bounds,
            "rms": self.rms,
            "max": self.max,
            "hausdorff": self.hausdorff,
            "evaluations": self.evaluations,
            "status": self.status,
            "message": self.message,
            "plates": list(self.plates),
        }


def _design(document: dict, free, values, base: Design, name: str) -> Design:
    doc = {k: dict(v) if isinstance(v, dict) else v for k, v in document.items()}
    for f, value in zip(free, values):
        doc.setdefault(f.section, {})[f.name] = float(value)
    doc.setdefault("design", {})["name"] = name
    return Design.from_metric(doc, units=base.units, base=base.base)


def _plates(design: Design):
    model = CCUModel(design)
    return model, model.vertices([model.alpha_design])[0]


def fit_design(
    base: Design,
    target,
    free,
    *,
    points: int = 3000,
    seed: int = 0,
    max_evaluations: int = 100,
    f_scale: float | None = None,
    name: str | None = None,
) -> DesignFit:
    """Fit the free keys of ``base`` to a target (module docstring).

    Parameters
    ----------
    base : Design
        The start; its other keys stay as they are.
    target : compas_ccu.fit.points.PointSet
        Target points, m, in the design's world frame (normals estimated if it has none).
    free : list of FreeKey
    points : int
        Target points and plate points of the residuals (seeded subsets).
    seed : int
    max_evaluations : int
        The most models the solver builds; not converged within them: FitError.
    f_scale : float, optional
        Soft-l1 scale, m; default 1/200 of the target size.
    name : str, optional
        Name of the fitted design (default ``<base name>-fit``).

    Returns
    -------
    DesignFit

    Raises
    ------
    DesignError, OptionError
        A free key that is not a real design key, or without bounds; a base value outside them.
    FitError
        The target is far larger than any design within the bounds, the base design cannot
        be built, or the fit did not converge within ``max_evaluations``.
    """
    free = free_keys(free)
    document = base.metric_document()
    start = _start_values(base, free)
    name = name or f"{base.name}-fit"
    target = target.with_normals()
    tsize = target.size
    _check_reach(document, free, start, base, tsize)

    rng = np.random.default_rng(seed)
    sub = np.sort(rng.choice(len(target), size=min(int(points), len(target)), replace=False))
    ttree = cKDTree(target.points)
    # the target's point spacing: tangential offsets within it are not distance (the median
    # nearest-neighbour distance in the fit; the 99th percentile, random samples leave gaps,
    # for the Hausdorff distance)
    spacing, gaps = target_spacing(target.points, ttree)
    f_scale = float(f_scale) if f_scale is not None else tsize / 200.0
    fixed = (target.points[sub], rng, int(points))
    residuals = _Residuals(document, free, start, base, name, target, ttree, spacing, *fixed)
    res = _solve(residuals, free, max_evaluations, f_scale)
    bounds = ([f.lower for f in free], [f.upper for f in free])
    values = np.clip(residuals.x0 + res.x * residuals.scale, *bounds)
    design = _design(document, free, values, base, name)
    d, back, plates = _measured_fit(design, target, ttree, gaps)
    return DesignFit(
        design=design,
        parameters={f.key: float(v_) for f, v_ in zip(free, values)},
        start=start,
        rms=float(np.sqrt(np.mean(d.distance**2))),
        max=float(d.distance.max()),
        hausdorff=float(max(d.distance.max(), np.abs(back).max())),
        plates=plates,
        evaluations=int(residuals.count),
        status=int(res.status),
        message=str(res.message),
        bounds={f.key: [f.lower, f.upper] for f in free},
        signed=d.signed,
        plate_row=d.plate,
    )


def _start_values(base: Design, free) -> dict:
    """``{key: value}`` of the free keys in the base design; DesignError if the base does not
    set one or sets it to something else than a number, OptionError if it lies outside its
    bounds."""
    start = {}
    for f in free:
        value = base.values[f.section][f.name]
        if value is None:
            raise DesignError(f"the base design does not set it; add it to {f.section}", key=f.key)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise DesignError(f"a free key must be one number, the base gives {value!r}", key=f.key)
        if not f.lower <= float(value) <= f.upper:
            raise OptionError(
                f"{f.key}: the base value {float(value):g} lies outside the bounds "
                f"{f.lower:g}:{f.upper:g}"
            )
        start[f.key] = float(value)
    return start


class _Residuals:
    """The residuals of :func:`fit_design` at the free values ``x0 + u * scale`` (``u`` the
    solver's variables, scaled to the bounds): the target points' distance to the deployed
    plates, then the fixed plate points' distance to the target (module docstring).

    ``tpts`` are the target points of the first term; the plate points of the second (at most
    ``points`` of the barycentric points of every triangle) are drawn from ``rng`` (after the
    target subset: the seed gives both). Every evaluation samples the plates on the lattice
    plan of the start's triangles; ``count`` counts the evaluations."""

    def __init__(
        self, document, free, start, base, name, target, ttree, spacing, tpts, rng, points
    ):
        self.document, self.free, self.base, self.name = document, free, base, name
        self.target, self.ttree, self.spacing, self.tpts = target, ttree, spacing, tpts
        model0, v0 = _plates(_design(document, free, start.values(), base, name))
        tri0, _ = plate_triangles(v0, model0.faces)
        self.spacing0 = model0.size / 100.0
        zeros = np.zeros(len(tri0), dtype=np.int64)
        self.plan = PlateSurface(tri0, zeros, spacing=self.spacing0).plan
        self.nplate = min(points, len(tri0) * len(_BARY))
        self.pick = np.sort(rng.choice(len(tri0) * len(_BARY), size=self.nplate, replace=False))
        self.x0 = np.array(list(start.values()))
        self.scale = np.array([max(f.upper - f.lower, EXACT_RELATIVE) for f in free])
        self.count = 0

    def __call__(self, u):
        self.count += 1
        values = self.x0 + u * self.scale
        try:
            model, v = _plates(_design(self.document, self.free, values, self.base, self.name))
        except CCUError:
            return np.full(len(self.tpts) + self.nplate, FAILED_RESIDUAL)
        surf = PlateSurface.from_vertices(v, model.faces, spacing=self.spacing0, plan=self.plan)
        # unsigned (the sign flips where the nearest plate changes side; for Gauss-Newton
        # |s| and s are the same)
        r1 = surf.query(self.tpts, candidates=8, max_candidates=64).distance
        tri = surf.triangles
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
        pts = (
            a[:, None]
            + _BARY[None, :, :1] * (b - a)[:, None]
            + _BARY[None, :, 1:] * (c - a)[:, None]
        )
        pts = pts.reshape(-1, 3)[self.pick]
        r2 = target_distance(pts, self.target, self.ttree, self.spacing)
        return np.concatenate([r1, r2])


def _solve(residuals: _Residuals, free, max_evaluations: int, f_scale: float):
    """``least_squares`` (trf, the bounds, soft-l1) from the base design; FitError if it did
    not converge within ``max_evaluations``."""
    x0, scale = residuals.x0, residuals.scale
    lower = np.array([(f.lower - s) / w for f, s, w in zip(free, x0, scale)])
    upper = np.array([(f.upper - s) / w for f, s, w in zip(free, x0, scale)])
    res = least_squares(
        residuals,
        np.zeros(len(free)),
        bounds=(lower, upper),
        loss="soft_l1",
        f_scale=f_scale,
        max_nfev=int(max_evaluations),
        diff_step=1e-6,
        xtol=1e-8,
        ftol=FIT_OBJECTIVE,
    )
    if res.status <= 0:
        raise FitError(
            f"the fit did not converge within {max_evaluations} evaluations "
            f"({res.message.rstrip('.')}; RMS {1000 * math.sqrt(np.mean(res.fun**2)):.1f} mm): "
            "raise max_evaluations or narrow the bounds"
        )
    return res


def _measured_fit(design: Design, target, ttree, gaps: float):
    """Every target point's distance to the fitted design's plates, the plates' samples'
    distance to the target (the Hausdorff distance's other side) and every plate's record."""
    model, v = _plates(design)
    surf = PlateSurface.from_vertices(v, model.faces, spacing=model.size / 150.0)
    d = surf.query(target.points)
    back = target_distance(surf.samples, target, ttree, gaps)
    rows = d.plate
    ids = model.plate_ids
    cnt = np.bincount(rows, minlength=len(ids))
    sq = np.bincount(rows, weights=d.distance**2, minlength=len(ids))
    top = np.zeros(len(ids))
    np.maximum.at(top, rows, d.distance)
    plates = tuple(
        {
            "id": int(pid),
            "points": int(cnt[i]),
            "rms": float(np.sqrt(sq[i] / cnt[i])) if cnt[i] else None,
            "max": float(top[i]) if cnt[i] else None,
        }
        for i, pid in enumerate(ids)
    )
    return d, back, plates


def target_distance(pts, target, tree, spacing):
    """Signed distance of points to a target: point-to-plane at the nearest target point, plus
    the tangential offset beyond the target's point spacing (a point past the target's edge).

    The plates-to-target term of :func:`fit_design`, and the distance the studio colours the
    plates by (docs/studio.md).

    Parameters
    ----------
    pts : (m, 3) float
        Points, m.
    target : PointSet
        The target, with normals (:meth:`PointSet.with_normals`).
    tree : scipy.spatial.cKDTree
        Of ``target.points``.
    spacing : float
        The target's point spacing, m (:func:`target_spacing`): tangential offsets within it
        are not distance.

    Returns
    -------
    (m,) float
        Signed by the side of the nearest target point's normal, m.
    """
    dist, idx = tree.query(pts)
    delta = pts - target.points[idx]
    normal = (delta * target.normals[idx]).sum(axis=1)
    tangential = np.sqrt(np.maximum(dist**2 - normal**2, 0.0))
    excess = np.maximum(tangential - spacing, 0.0)
    return np.sign(normal) * np.sqrt(normal**2 + excess**2)


def target_spacing(points, tree) -> tuple:
    """The point spacing of a target: the median and the 99th percentile of the distance of
    (at most 20,000 of) its points to their nearest neighbour, m.

    Parameters
    ----------
    points : (n, 3) float
    tree : scipy.spatial.cKDTree
        Of ``points``.

    Returns
    -------
    median, p99 : float
    """
    probe = points[:: max(1, len(points) // 20000)]
    nn = tree.query(probe, k=2)[0][:, 1]
    return float(np.median(nn)), float(np.quantile(nn, 0.99))


def _check_reach(document, free, start, base, target_size) -> None:
    """FitError if the target is far larger than the base design at any single bound."""
    sizes = []
    cases = [list(start.values())]
    for i, f in enumerate(free):
        for bound in (f.lower, f.upper):
            values = list(start.values())
            values[i] = bound
            cases.append(values)
    for values in cases:
        try:
            sizes.append(CCUModel(_design(document, free, values, base, base.name)).size)
        except CCUError:
            continue
    if not sizes:
        raise FitError(f"the base design {base.name} cannot be built at its start or its bounds")
    largest = max(sizes)
    if target_size > TARGET_SIZE_FACTOR * largest:
        raise FitError(
            f"the target ({target_size:.2f} m across) is far larger than any design of "
            f"{base.name} within the bounds (at most {largest:.2f} m across, factor "
            f"{TARGET_SIZE_FACTOR:g}): widen the bounds or check the target's units"
        )
