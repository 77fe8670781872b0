"""The logic of the Grasshopper components, as plain functions (tested on CPython).

Each component's ``code.py`` (``components/<Name>/code.py``) converts its Grasshopper inputs,
calls one function here and passes the result's fields to its outputs. Geometry goes out
through :mod:`compas_ccu.ghpython.convert`: Rhino geometry inside Rhino, COMPAS geometry
elsewhere. Lengths: the design is in metres; ``unit_scale`` is metres per document unit
(1 for a document in metres, 0.001 in millimetres), applied to curves coming in and to
geometry going out.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import NamedTuple

import numpy as np
from compas.geometry import Line, Polyline, Scale

from compas_ccu.design import Design, load_design
from compas_ccu.errors import CCUError, CCUWarning, OptionError
from compas_ccu.fabrication import fabrication_data
from compas_ccu.fabrication.dxf import PLATE_LAYERS
from compas_ccu.fabrication.fabricate import fabricate
from compas_ccu.fabrication.hinge_dxf import strip_layout
from compas_ccu.ghpython.convert import crease_plane, curve_points, to_host, to_host_surface
from compas_ccu.key_figures.text import utilisation_text
from compas_ccu.kinematics.plates import plate_rulings
from compas_ccu.model import CCUModel
from compas_ccu.scene.draw import draw_items, item_structure, ruling_lines
from compas_ccu.thickness import ThickModel
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = [
    "as_model",
    "crease_design",
    "design_component",
    "deploy_component",
    "checks_component",
    "cut_patterns_component",
    "fabricate_component",
    "DesignResult",
    "DeployResult",
    "ChecksResult",
    "CutPatternsResult",
    "FabricateResult",
    "CUT_LAYERS",
    "INVARIANT_TOLERANCE",
]

#: The layers of the cut patterns: those of the DXF plate files.
CUT_LAYERS = tuple(k for k in PLATE_LAYERS if k != "LABEL")
#: Largest relative invariant error (isometry, planarity, hinge, mirror) a check passes.
INVARIANT_TOLERANCE = EXACT_RELATIVE


def _unit_scale(unit_scale) -> float:
    if isinstance(unit_scale, bool) or not isinstance(unit_scale, (int, float)):
        raise OptionError(f"unit_scale must be metres per document unit, got {unit_scale!r}")
    if not (math.isfinite(unit_scale) and unit_scale > 0.0):
        raise OptionError(f"unit_scale must be a finite number > 0, got {unit_scale!r}")
    return float(unit_scale)


def _to_document(geometry, unit_scale: float):
    if unit_scale != 1.0:
        geometry = geometry.transformed(Scale.from_factors([1.0 / unit_scale] * 3))
    return geometry


def as_model(item) -> CCUModel:
    """A :class:`CCUModel` from a model, a :class:`Design` or a design file path.

    Raises
    ------
    OptionError
        Anything else (None: the input is not connected).
    """
    if isinstance(item, CCUModel):
        return item
    if isinstance(item, Design):
        return CCUModel(item)
    if isinstance(item, (str, Path)) and str(item).strip():
        return CCUModel(load_design(str(item).strip()))
    raise OptionError(
        f"expected a CCU model, a design or a design file path, got {type(item).__name__}"
    )


def crease_design(
    crease,
    *,
    name: str = "grasshopper",
    segments: int = 48,
    rulings: str = "orthogonal",
    side: str = "inside",
    width: float = 0.3,
    plates: int | None = None,
    spacing: float | None = None,
    alpha: float = 30.0,
    count: int = 64,
    unit_scale: float = 1.0,
) -> dict:
    """A design document whose leading crease is a planar curve (a ``polyline`` profile).

    Parameters
    ----------
    crease
        A Rhino curve, a polyline or a list of points (:func:`curve_points`): the deployed
        crease at the design angle, in document units.
    name, segments, rulings, side, width, alpha
        ``design.name``, ``crease.segments``, ``rulings.type``, ``rulings.side``,
        ``layout.width`` (m, a single crease), ``deployment.alpha`` (degrees).
    plates, spacing : optional
        A corrugated structure (``layout.type = "parallel"``): number of plates and crease
        plane spacing, m.
    count : int
        Segments to sample a curve with (polylines keep their vertices).
    unit_scale : float
        Metres per document unit.

    Returns
    -------
    dict
        The design document (the same as a TOML file's), validated by :class:`Design`.

    Examples
    --------
    >>> doc = crease_design([[0, 0, 0], [1, 0, 0.4], [2, 0, 0]], segments=8)
    >>> doc["crease"]["points"], doc["plane"]["yaxis"]
    ([[0.0, 0.0], [1.0, 0.4], [2.0, 0.0]], [0.0, 0.0, 1.0])
    """
    scale = _unit_scale(unit_scale)
    points = curve_points(crease, count=count) * scale
    origin, xaxis, yaxis, profile = crease_plane(points)
    layout: dict = {"type": "single", "width": float(width)}
    if plates is not None:
        if spacing is None:
            raise OptionError(f"plates={plates!r} needs a crease plane spacing (m)")
        layout = {"type": "parallel", "plates": int(plates), "spacing": float(spacing)}
    return {
        "design": {"name": str(name)},
        "crease": {
            "profile": "polyline",
            "points": profile.tolist(),
            "segments": int(segments),
            "state": "deployed",
        },
        "rulings": {"type": rulings, "side": side},
        "deployment": {"alpha": float(alpha)},
        "layout": layout,
        "plane": {
            "origin": [float(v) for v in origin],
            "xaxis": [float(v) for v in xaxis],
            "yaxis": [float(v) for v in yaxis],
        },
    }


class DesignResult(NamedTuple):
    """Outputs of the Design component."""

    design: Design
    model: CCUModel
    info: str


def _info(model: CCUModel) -> str:
    structure = model.deploy()
    kinds = ", ".join(f"{k} {v}" for k, v in structure.crease_kind_counts().items())
    return "\n".join(
        [
            f"design {model.design.name}: {len(model.plate_ids)} plates, "
            f"{model.segments} segments per crease",
            f"creases: {kinds or 'none'}",
            f"design angle {model.alpha_design:g} deg; limit {model.alpha_limit:.4g} deg; "
            f"plates overlap from {model.overlap_alpha:.4g} deg; plates cross from "
            f"{model.collision_free_alpha:.4g} deg",
        ]
    )


def design_component(path=None, crease=None, **options) -> DesignResult:
    """The Design component: from a design file, or from a crease curve and options.

    Parameters
    ----------
    path : str, optional
        A design TOML file; when given, ``crease`` and the options are not used.
    crease : optional
        The deployed crease (see :func:`crease_design` for it and the ``options``).

    Raises
    ------
    OptionError
        Neither a path nor a crease.
    CCUError
        The design is impossible (the message names the cause and the value).
    """
    if path is not None and str(path).strip():
        design = load_design(str(path).strip())
    elif crease is not None:
        design = Design(crease_design(crease, **options))
    else:
        raise OptionError("connect a design file path or a crease curve")
    model = CCUModel(design)
    return DesignResult(design, model, _info(model))


class DeployResult(NamedTuple):
    """Outputs of the Deploy component (lists in the structure's plate / crease order)."""

    structure: object
    plates: list
    creases: list
    rulings: list
    plate_colors: list
    crease_colors: list
    info: str


def deploy_component(
    model,
    alpha=None,
    *,
    surfaces: bool = False,
    state: str = "deployed",
    rulings: bool = True,
    unit_scale: float = 1.0,
) -> DeployResult:
    """The Deploy component: the plates at reflection angle ``alpha``.

    Parameters
    ----------
    model : CCUModel, Design or path
    alpha : float, optional
        Reference reflection angle, degrees (the slider); default: the design angle.
    surfaces : bool
        Plates as ruled NURBS surfaces (inside Rhino) instead of meshes.
    state : {"deployed", "flat"}
    rulings : bool
    unit_scale : float
        Metres per document unit (the output is in document units).

    Returns
    -------
    DeployResult
        Colours are ``(r, g, b)`` 0..255 (the crease kind palette of the figures).
    """
    model = as_model(model)
    scale = _unit_scale(unit_scale)
    structure = item_structure(model, alpha=alpha)
    items = draw_items(structure, state=state, rulings=rulings)
    out: dict = {"plate": [], "crease": [], "ruling": []}
    colors: dict = {"plate": [], "crease": []}
    points = structure.points(state)
    n = structure.faces.shape[1]
    for item in items:
        if item.role == "ruling":  # one output line per ruling (a plate's graph of rulings)
            for line in ruling_lines(item.geometry):
                out["ruling"].append(to_host(_to_document(line, scale), color=item.color))
            continue
        geometry = _to_document(item.geometry, scale)
        host = None
        if item.role == "plate" and surfaces:
            xyz = points[structure.plate_ids.index(item.attributes["plate"])] / scale
            host = to_host_surface(xyz[: n + 1], xyz[n + 1 :])
        if host is None:
            host = to_host(geometry, color=item.color)
        out[item.role].append(host)
        if item.role in colors:
            colors[item.role].append(item.color.rgb255)
    info = f"alpha {structure.alpha:g} deg ({state}); max invariant error " + (
        f"{structure.max_invariant_error:.2e}"
    )
    return DeployResult(
        structure,
        out["plate"],
        out["crease"],
        out["ruling"],
        colors["plate"],
        colors["crease"],
        info,
    )


class ChecksResult(NamedTuple):
    """Outputs of the Checks component."""

    ok: bool
    report: str
    values: dict


def checks_component(model, alpha=None, *, thickness=None) -> ChecksResult:
    """The Checks component: kinematics, overlap, thick plates (collisions, bending).

    ``ok`` is False when a check fails: the deployment is refused (beyond the limit, a crease
    overlapping itself), an invariant error above :data:`INVARIANT_TOLERANCE`, plates that
    overlap at ``alpha``, or thick plates that interpenetrate on the way. The bending check
    (EC5 design values) is reported; a utilisation above 1 is a warning, not a failure
    (the thickness / material are the designer's choice).
    """
    model = as_model(model)
    alpha = model.alpha_design if alpha is None else float(alpha)
    lines, values, ok = [], {"alpha": alpha}, True
    values["alpha_limit"] = model.alpha_limit
    values["overlap_alpha"] = model.overlap_alpha
    values["collision_free_alpha"] = model.collision_free_alpha
    try:
        structure = model.deploy(alpha)
    except CCUError as exc:
        return ChecksResult(False, f"FAIL deployment: {exc}", {**values, "error": str(exc)})
    error = structure.max_invariant_error
    values["max_invariant_error"] = error
    passed = error <= INVARIANT_TOLERANCE
    ok &= passed
    lines.append(f"{'ok  ' if passed else 'FAIL'} invariants: max relative error {error:.2e}")
    passed = alpha < model.overlap_alpha
    ok &= passed
    lines.append(
        f"{'ok  ' if passed else 'FAIL'} overlap: plates overlap from "
        f"{model.overlap_alpha:.4g} deg (alpha {alpha:g} deg, limit {model.alpha_limit:.4g})"
    )
    passed = alpha <= model.collision_free_alpha
    ok &= passed
    lines.append(
        f"{'ok  ' if passed else 'FAIL'} crossing: no two plates cross from the flat stack to "
        f"{model.collision_free_alpha:.4g} deg (alpha {alpha:g} deg)"
    )
    kinds = structure.crease_kind_counts()
    values["crease_kinds"] = kinds
    if "ccf" in kinds:
        lines.append("--   thick plates: not checked (CCF creases have no thick model)")
        return ChecksResult(bool(ok), "\n".join(lines), values)
    try:
        summary = ThickModel(model, thickness=thickness).summary()
    except CCUError as exc:
        lines.append(f"FAIL thick plates: {exc}")
        return ChecksResult(False, "\n".join(lines), {**values, "error": str(exc)})
    values["thick"] = summary
    collisions = summary["collisions"]
    passed = not collisions["interpenetration"]
    ok &= passed
    first = collisions["first"]
    lines.append(
        f"{'ok  ' if passed else 'FAIL'} collisions (flat stack to design angle): "
        + ("none" if first is None else f"plates {first['plates']} at {first['alpha']:.4g} deg")
    )
    bending = summary["bending"]
    lines.append(
        f"{'WARN' if bending['exceeded'] else 'ok  '} bending ({bending['basis']['basis']}, "
        f"{summary['thickness'] * 1000:g} mm {summary['material']}): max utilisation "
        f"{utilisation_text(bending['max_utilisation'])}"
    )
    return ChecksResult(bool(ok), "\n".join(lines), values)


class CutPatternsResult(NamedTuple):
    """Outputs of the Cut patterns component: ``curves[i]`` is on layer ``layers[i]``."""

    curves: list
    layers: list
    plates: list
    by_layer: dict


def cut_patterns_component(
    model, *, thickness=None, gap: float = 0.05, unit_scale: float = 1.0
) -> CutPatternsResult:
    """The Cut patterns component: every plate's cut pattern on the XY plane, by layer.

    The thick plates' cut patterns (crease corrections of the design state, as in the DXF
    files), laid out top to bottom ``gap`` (m) apart. Layers: ``CUT`` (closed outline),
    ``CREASE`` (the crease edges), ``RULING_SCORE`` (interior rulings).
    """
    model = as_model(model)
    scale = _unit_scale(unit_scale)
    if not gap > 0.0:
        raise OptionError(f"gap must be > 0 m, got {gap!r}")
    data = fabrication_data(model, thickness=thickness)
    outlines = [data.outline(i) for i in range(len(data.plate_ids))]
    shifts = strip_layout(outlines, gap=float(gap))
    n = data.segments
    curves, layers, plates = [], [], []
    by_layer: dict = {name: [] for name in CUT_LAYERS}

    def emit(geometry, layer, pid):
        host = to_host(_to_document(geometry, scale))
        curves.append(host)
        layers.append(layer)
        plates.append(pid)
        by_layer[layer].append(host)

    for i, pid in enumerate(data.plate_ids):
        flat = np.c_[np.asarray(data.flat[i], dtype=float) + shifts[i], np.zeros(2 * n + 2)]
        outline = np.c_[outlines[i] + shifts[i], np.zeros(2 * n + 2)]
        emit(Polyline(np.r_[outline, outline[:1]].tolist()), "CUT", pid)
        for _cid, _other, idx in data.plate_creases(i):
            emit(Polyline(flat[idx].tolist()), "CREASE", pid)
        for a, b in plate_rulings(n)[1:-1]:
            emit(Line(flat[a].tolist(), flat[b].tolist()), "RULING_SCORE", pid)
    return CutPatternsResult(curves, layers, plates, by_layer)


class FabricateResult(NamedTuple):
    """Outputs of the Fabricate component, and the warnings its ``code.py`` turns into
    runtime messages (a nester missing: the shelves nested the parts)."""

    files: list
    info: str
    warnings: tuple = ()


def fabricate_component(model, folder, *, run: bool = False, **options) -> FabricateResult:
    """The Fabricate component: write the fabrication files into ``folder`` when ``run``.

    ``options``: ``thickness``, ``material``, ``grain``, ``hinge_width``, ``allow_collisions``
    (:func:`compas_ccu.fabrication.fabricate.fabricate`). compas_ccu's warnings are not
    shown as Python warnings but returned (``warnings``): the component shows each as a
    runtime message, and ``info`` lists them.
    """
    if not run:
        return FabricateResult([], "set run to True to write the files")
    if folder is None or not str(folder).strip():
        raise OptionError("connect a folder to write the fabrication files into")
    model = as_model(model)
    out = Path(str(folder).strip())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        manifest = fabricate(model, out, **options)
    notes = [str(n) for n in (manifest.get("workshop") or {}).get("warnings") or []]
    for w in caught:
        if not issubclass(w.category, CCUWarning):  # others as Python shows them
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        elif str(w.message) not in notes:
            notes.append(str(w.message))
    files = [str(out / f) for f in manifest["files"]] if "files" in manifest else []
    info = "\n".join([f"wrote {len(files)} files into {out}", *(f"warning: {n}" for n in notes)])
    return FabricateResult(files, info, tuple(notes))
