"""Measuring the key figures of a built design: :func:`key_figures` and its groups."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from compas_ccu.analysis import global_curvature
from compas_ccu.analysis.planarity import path_alphas, planarity_along_path
from compas_ccu.analysis.plate_size import plate_rectangles
from compas_ccu.errors import OptionError
from compas_ccu.io import flat_footprint
from compas_ccu.key_figures.table import FIGURES, figure
from compas_ccu.thickness import ThickModel

__all__ = [
    "KeyFigures",
    "key_figures",
    "design_state_figures",
    "path_figures",
    "thickness_figures",
    "plate_area",
]

_BY_NAME = {f.name: f for f in FIGURES}
_CAST = {"float": float, "int": int, "bool": bool, "str": str}


class KeyFigures(Mapping):
    """The key figures of a design: a read-only mapping name -> value in :data:`FIGURES` order.

    Every figure of the table is present (None where it does not apply or was not measured) and
    readable as an attribute (``figures.crease_span``). Values are plain Python scalars.

    Parameters
    ----------
    values : mapping, optional
        Figure name -> value; names outside :data:`FIGURES` are refused.
    """

    __slots__ = ("_values",)

    def __init__(self, values: Mapping | None = None, **more):
        given = {**(values or {}), **more}
        unknown = [k for k in given if k not in _BY_NAME]
        if unknown:
            figure(unknown[0])  # raises, naming the figures
        out = {}
        for f in FIGURES:
            value = given.get(f.name)
            out[f.name] = None if value is None else _CAST[f.dtype](value)
        object.__setattr__(self, "_values", out)

    @classmethod
    def from_model(cls, model, structure=None, **options) -> KeyFigures:
        """:func:`key_figures` (same arguments)."""
        return key_figures(model, structure, **options)

    def __getitem__(self, name):
        return self._values[name]

    def __iter__(self):
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __getattr__(self, name):
        try:
            return object.__getattribute__(self, "_values")[name]
        except KeyError:
            raise AttributeError(f"KeyFigures has no figure {name!r}") from None

    def __setattr__(self, name, value):
        raise AttributeError("KeyFigures is read-only")

    def __reduce__(self):
        return (KeyFigures, (self._values,))

    def __repr__(self) -> str:
        shown = ", ".join(f"{k}={v!r}" for k, v in self._values.items() if v is not None)
        return f"KeyFigures({shown})"

    def to_dict(self) -> dict:
        """``{name: value}`` of plain JSON scalars (None where not measured), table order."""
        return dict(self._values)

    def group(self, name: str) -> dict:
        """The figures of one group of :data:`GROUPS`."""
        return {f.name: self._values[f.name] for f in FIGURES if f.group == name}

    def crease_kind_counts(self) -> dict[str, int]:
        """``crease_kinds`` as ``{kind: count}``."""
        text = self._values["crease_kinds"] or ""
        pairs = (item.split(" ", 1) for item in text.split(", ") if item)
        return {kind: int(count) for count, kind in pairs}


def key_figures(model, structure=None, *, path=None, thickness=None, relax: bool = False):
    """Measure the key figures of a built design.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    structure : compas_ccu.structure.Structure, optional
        The deployed design state (``model.deploy()``), if at hand.
    path : int or sequence of float, optional
        The deployment path of the path figures (crease planarity, bending): the number of
        states above the flat stack (``k * alpha_design / path`` for ``k = 1 .. path``, as
        :func:`compas_ccu.analysis.planarity.planarity_along_path`), or their reference angles
        in degrees. Default: no path figures.
    thickness : bool or compas_ccu.thickness.ThickModel, optional
        Also measure the thick plates (needs ``path``): True models the design's ``[plates]``;
        a ThickModel is used as it is.
    relax : bool
        Relax the worst path state of a design whose creases leave their planes and report the
        residuals (``relaxed_*``).

    Returns
    -------
    KeyFigures

    Raises
    ------
    GeometryError, MaterialError
        ``thickness=True`` and the design's plates cannot be modelled.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> figures = key_figures(load_model("examples/vault.toml"), path=8)
    >>> round(figures.crease_span, 9), round(figures.crease_rise, 9), round(figures.height, 4)
    (2.5, 1.0, 1.0456)
    >>> figures.crease_kinds, figures.crease_planarity_exact
    ('4 anticlastic, 5 synclastic', True)
    """
    values = design_state_figures(model, structure)
    if path is not None:
        values.update(path_figures(model, path, relax=relax))
    if thickness is not None and thickness is not False:
        if path is None:
            raise OptionError("thickness figures are measured along a path: give path as well")
        if thickness is True:
            thickness = ThickModel(model)
        values.update(thickness_figures(thickness, _path_alphas(model, path)))
    return KeyFigures(values)


def _path_alphas(model, path) -> np.ndarray:
    """Reference angles (degrees) of ``path``: a number of states or the angles themselves."""
    if np.ndim(path) == 0:
        return path_alphas(model, path)
    return np.atleast_1d(np.asarray(path, dtype=float))


def _empty(*groups) -> dict:
    return {f.name: None for f in FIGURES if f.group in groups}


def design_state_figures(model, structure=None) -> dict:
    """The design, deployment, shape, stack and invariant groups at the design state.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    structure : compas_ccu.structure.Structure, optional
        ``model.deploy()``, if at hand.
    """
    if structure is None:
        structure = model.deploy()
    elif structure.alpha != model.alpha_design:
        raise OptionError(
            f"key figures describe the design state (alpha = {model.alpha_design:g} deg), got a "
            f"structure at alpha = {structure.alpha:g} deg"
        )
    values = model.design.values  # the validated design document (layout type, description)
    m = structure.metrics
    shape = state_figures(structure)
    kinds = structure.crease_kind_counts()
    alphas = [a for c in structure.creases for a in c["alpha"]] + list(m["alpha_leading"])
    plan_x, plan_y, height = (float(v) for v in m["bounding_box"])
    stack_x, stack_y = flat_footprint(structure)
    overlap = float(model.overlap_alpha)
    collision_free = float(model.collision_free_alpha)
    invariants = {
        key: float(m[key])
        for key in (
            "isometry_relative",
            "quad_planarity_relative",
            "hinge_gap_relative",
            "mirror_error_relative",
        )
    }
    out = _empty("design", "deployment", "shape", "stack", "invariants")
    out.update(
        {
            "name": model.design.name,
            "description": values["design"].get("description") or "",
            "layout": values["layout"]["type"],
            "plates": len(structure.plate_ids),
            "creases": len(structure.creases),
            "crease_kinds": ", ".join(f"{v} {k}" for k, v in sorted(kinds.items())),
            "segments": model.segments,
            "alpha_design": float(model.alpha_design),
            "reference_vertex": model.reference,
            "alpha_min": float(min(alphas)),
            "alpha_max": float(max(alphas)),
            "fold_alpha_min": 0.5 * min(min(c["fold_angles"]) for c in structure.creases),
            "fold_alpha_max": 0.5 * max(max(c["fold_angles"]) for c in structure.creases),
            "reference_fold_alpha": reference_fold_alpha(model, structure),
            "alpha_limit": float(model.alpha_limit),
            "limit_vertex": model.limit_vertex,
            "overlap_alpha": overlap,
            "collision_free_alpha": collision_free,
            "limit_margin": float(
                min(model.alpha_limit, overlap, collision_free) - model.alpha_design
            ),
            **{k: v for k, v in shape.items() if k.startswith("crease_")},
            "plan_x": plan_x,
            "plan_y": plan_y,
            "height": height,
            "plan_diameter": plan_diameter(structure.points("deployed")),
            "plan_area": plan_x * plan_y,
            "plate_area": plate_area(model),
            "size": m["size"],
            "stack_x": stack_x,
            "stack_y": stack_y,
            "stack_length": max(stack_x, stack_y),
            "stack_width": min(stack_x, stack_y),
            "plate_length": shape["plate_length"],
            "plate_width": shape["plate_width"],
            **invariants,
            "invariant_max_relative": structure.max_invariant_error,
            "crease_planarity_design": m["crease_planarity_max"],
        }
    )
    out.update(_plane_figures(model))
    fit = model.target_fit  # the fit of the plane layout to [target] curves, if any
    if fit is not None:
        out["target_fit_planes"] = ", ".join(str(q) for q in fit.planes)
        out["target_fit_max"] = float(fit.max_residual)
    return out


def state_figures(structure) -> dict:
    """The shape figures of any state of the path: ``crease_span``, ``crease_rise``,
    ``crease_rise_to_span`` of the structure's state (the design values are those of
    :func:`design_state_figures`), and the cut-pattern sizes ``plate_length``, ``plate_width``
    (the same at every state). Pictures label their dimensions with these.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> f = state_figures(load_model("examples/vault.toml").deploy(10.0))
    >>> round(f["crease_span"], 3), round(f["crease_rise"], 3), round(f["plate_length"], 3)
    (2.702, 0.911, 2.723)
    """
    m = structure.metrics
    rectangles = plate_rectangles(structure.flat)
    return {
        "crease_span": float(m["span"]),
        "crease_rise": float(m["rise"]),
        "crease_rise_to_span": float(m["rise"]) / float(m["span"]),
        "plate_length": float(rectangles[:, 0].max()),
        "plate_width": float(rectangles[:, 1].max()),
    }


def _plane_figures(model) -> dict:
    """Plane inclinations and the measured global curvature of a multi-crease layout."""
    planes = model.planes
    if planes is None:
        return {}
    inc = np.abs(planes.inclinations())
    out = {
        "plane_inclination_axis": float(inc[:, 0].max()),
        "plane_inclination_perpendicular": float(inc[:, 1].max()),
    }
    if planes.plates >= 4 and model.segments >= 4:  # global_curvature's smallest grid
        states = model.mechanism.deploy(np.radians([model.alpha_design]))
        g = global_curvature(model.plane_curves(states)[0])
        out.update(
            global_curvature=g.kind,
            principal_curvature_1=float(g.principal[0]),
            principal_curvature_2=float(g.principal[1]),
            gaussian_curvature=float(g.gaussian),
            curvature_ratio=float(g.ratio),
        )
    return out


def plan_diameter(points: np.ndarray) -> float:
    """The largest distance in plan (x-y) between two of ``points``, m.

    Parameters
    ----------
    points : (..., 3) float
        The deployed vertices.

    Examples
    --------
    >>> phi = np.radians(np.arange(0.0, 330.0, 15.0))  # a ring of 22 points, 330 deg
    >>> ring = np.c_[2.0 * np.cos(phi), 2.0 * np.sin(phi), np.ones_like(phi)]
    >>> round(plan_diameter(ring), 9)
    4.0
    """
    from scipy.spatial import ConvexHull, QhullError

    xy = np.unique(np.asarray(points, dtype=float).reshape(-1, 3)[:, :2], axis=0)
    try:  # the diameter is between two corners of the convex hull
        xy = xy[ConvexHull(xy).vertices]
    except (QhullError, ValueError):  # collinear or too few points: all of them
        pass
    d = xy[:, None, :] - xy[None, :, :]
    return float(np.sqrt((d**2).sum(axis=-1)).max()) if len(xy) > 1 else 0.0


def plate_area(model) -> float:
    """Total area (m2) of the cut patterns (planar quads: half the cross product of the
    diagonals)."""
    flat, n = model.flat(), model.segments
    near, far = flat[:, : n + 1], flat[:, n + 1 :]
    d1 = far[:, 1:] - near[:, :-1]
    d2 = far[:, :-1] - near[:, 1:]
    return float(0.5 * np.linalg.norm(np.cross(d1, d2), axis=-1).sum())


def path_figures(model, path, *, relax: bool = False) -> dict:
    """The path group: crease planarity along the deployment path (see :func:`key_figures`)."""
    alphas = _path_alphas(model, path)
    report = planarity_along_path(model, alphas, relax=relax)
    s = report.summary()
    out = _empty("path")
    out.update(
        path_states=len(alphas),
        crease_planarity_path=s["planarity_max"],
        crease_planarity_path_relative=s["planarity_max_relative"],
        crease_planarity_path_alpha=s["planarity_alpha_at_max"],
        crease_planarity_exact=s["planarity_exact"],
    )
    r = s["relaxation"]
    if r is not None and not report.exact:
        out.update(
            relaxed_alpha=r["alpha"],
            kinematic_isometry=r["kinematic_isometry"],
            relaxed_strain=r["max_strain"],
            relaxed_quad_planarity=r["quad_planarity"],
            relaxed_displacement=r["displacement"],
        )
    return out


def thickness_figures(thick, alphas) -> dict:
    """The thickness group of a :class:`compas_ccu.thickness.ThickModel` over the path states
    ``alphas`` (degrees): stack, mass and the bending check."""
    alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
    bend = thick.bending(alphas)
    push = thick.actuation(alphas)
    return {
        "thickness": thick.thickness,
        "material": thick.material.name,
        "stack_height": float(thick.stack_height),
        "collision_free_alpha_thick": thick.first_collision()[0],
        "mass": plate_area(thick.model) * thick.thickness * thick.material.density,
        "deployment_energy": float(push.energy[-1]),
        "actuation_force": push.force_max,
        **_ring_figures(push),
        "bending_utilisation": float(bend.max),
        "bending_utilisation_characteristic": bend.max_characteristic,
        "bending_basis": bend.factors.label,
        "k_mod": bend.factors.k_mod,
        "gamma_M": bend.factors.gamma_M,
        "k_def": bend.factors.k_def,
        "bending_curvature": float(np.abs(bend.curvature).max()),
    }


def _ring_figures(push) -> dict:
    """The ring of feet of a radial layout at the design state (the last of the path)."""
    if push.ring_length is None:
        return {}
    return {
        "ring_radius": float(push.ring_radius[-1]),
        "ring_thrust": float(push.ring_thrust[-1]),
        "ring_tension": float(push.ring_tension[-1]),
    }


def reference_fold_alpha(model, structure) -> float | None:
    """The reflection angle the leading crease's edges imply at the reference vertex: half the
    mean fold of the one or two edges that meet there (``fold_alpha`` of structure.json), the
    fold a builder sets where the design angle is read off; None without creases.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> round(reference_fold_alpha(model, model.deploy()), 6)  # 40 deg at the vertex
    40.006437
    """
    if not structure.creases:
        return None
    lead = next(ci for ci, c in enumerate(model.mechanism.creases) if c.fixed)
    record = next(c for c in structure.creases if c["id"] == lead)
    fold = np.asarray(record["fold_angles"], dtype=float)
    r = model.reference
    edges = [j for j in (r - 1, r) if 0 <= j < len(fold)]
    return float(0.5 * fold[edges].mean())
