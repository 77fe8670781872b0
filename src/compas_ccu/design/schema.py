"""The design-file schema: every key, its type, its allowed values and its documentation.

The table :data:`SCHEMA` is the single source of truth: :func:`validate` checks a parsed TOML
document against it, and ``docs/design-files.md`` is generated from it
(``python -m compas_ccu.design.schema > docs/design-files.md``), so the documentation cannot
drift from the code.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from typing import Any, Callable

from compas_ccu.design.rules import RULES
from compas_ccu.design.units import DEFAULT_UNITS, LENGTH_UNITS, is_length, to_metres, unit_factor
from compas_ccu.errors import DesignError
from compas_ccu.materials import (
    ACTION_DURATIONS,
    LOAD_DURATIONS,
    MATERIAL_KINDS,
    MATERIALS,
    Material,
    MaterialError,
)

__all__ = [
    "Key",
    "SCHEMA",
    "MATERIAL_KEYS",
    "NAMED_SECTIONS",
    "validate",
    "file_material",
    "schema_markdown",
]


@dataclass(frozen=True)
class Key:
    """One design-file key."""

    kind: str  # "float", "int", "str", "bool", "point2", "point3", "points2", "polyline2",
    # "sizes2" (one or more [x, y] pairs), "float_or_list", "gamma", "patterns" (an array of
    # tables of PATTERN_KEYS)
    doc: str
    default: Any = None
    required: bool = False
    choices: tuple = ()
    check: Callable | None = field(default=None, compare=False)
    check_doc: str = ""
    when: str = ""  # documentation: when the key applies
    columns: int = 0  # kind "rows": numbers per row
    unit: str = ""  # "m", "deg", "1" (dimensionless) or "" (not a quantity); set from _UNITS


#: The largest length a design may give, m: beyond it the profile solvers lose their precision
#: long before a plate structure could exist.
MAX_LENGTH = 1.0e6
#: The stock sheet of a design that names none ([fabrication] sheets), m: length (along the face
#: grain) and width. ``ccu fabricate``, ``ccu scale`` and the studio all start from it.
STOCK_SHEET = (2.5, 1.25)


def _positive(v):
    return 0.0 < v <= MAX_LENGTH


def _non_negative(v):
    return 0.0 <= v <= MAX_LENGTH


def _angle_open(v):
    return 0.0 < v < 90.0


def _fraction(v):
    return 0.0 <= v <= 1.0


SCHEMA: dict = {
    "design": {
        "_doc": "Name, description and, for the rule catalog, the paper figure and the "
        "predicted global curvature class.",
        "name": Key("str", "Design name, used in file names and reports.", default=None),
        "description": Key("str", "Free text.", default=""),
        "figure": Key(
            "str",
            "Paper figure the design reproduces, e.g. '9a' (the rule catalog, "
            "docs/shape-control.md): `ccu catalog` groups its contact sheets by figure.",
            default=None,
        ),
        "expected": Key(
            "str",
            "Global curvature class the paper's rule predicts for the design; `ccu catalog` "
            "puts it beside the class measured from the deployed structure.",
            default=None,
            choices=("monoclastic", "synclastic", "anticlastic"),
        ),
        "units": Key(
            "str",
            "Length units of this file: every key of unit m (and the positions x of the "
            "crease loads) is read in these units and converted to metres; angles stay "
            "degrees, forces, pressures, densities and stiffnesses SI. Outputs are metres. "
            "A length implausible for the units (a 2500 m span) is warned about.",
            default=DEFAULT_UNITS,
            choices=tuple(LENGTH_UNITS),
        ),
    },
    "crease": {
        "_doc": "The leading crease profile, in the 2D coordinates (x, y) of the leading crease "
        "plane (see [plane]), metres. It is the 3D crease at the design reflection angle "
        '(state = "deployed") or the crease in the cut pattern (state = "flat").',
        "profile": Key(
            "str",
            "Profile type.",
            required=True,
            choices=("arc", "catenary", "elastica", "funicular", "spline", "polyline"),
        ),
        "span": Key(
            "float",
            "Distance between the end points, m.",
            check=_positive,
            check_doc="> 0 and <= 1e6",
            when="arc, catenary, elastica, funicular",
        ),
        "rise": Key(
            "float",
            "Height of the apex above the chord, m.",
            check=_positive,
            check_doc="> 0 and <= 1e6",
            when="arc, catenary, elastica, funicular",
        ),
        "point_loads": Key(
            "rows",
            "Point loads [[x, P], ...] on the span (x in profile coordinates, -span/2 < x < "
            "span/2; P > 0 downwards, any unit): the thrust line is a polygon with a kink, "
            "i.e. a crease vertex, under every load.",
            columns=2,
            when="funicular",
        ),
        "distributed_loads": Key(
            "rows",
            "Linearly varying loads [[x0, x1, q0, q1], ...] from intensity q0 at x0 to q1 at "
            "x1. Without any load the funicular is the parabola of a uniform load.",
            columns=4,
            when="funicular",
        ),
        "radius": Key(
            "float",
            "Arc radius, m (instead of span and rise).",
            check=_positive,
            check_doc="> 0 and <= 1e6",
            when="arc",
        ),
        "angle": Key(
            "float",
            "Arc central angle, degrees (with radius).",
            check=lambda v: 0.0 < v < 360.0,
            check_doc="0 < angle < 360",
            when="arc",
        ),
        "points": Key(
            "points2",
            'Control points [[x, y], ...] (at least 3), or a curve file: "crease.dxf" or '
            '{ file = "crease.dxf", layer = "CREASE", name = ..., index = ..., units = "mm", '
            "scale = 1.0 } (CSV / TXT, DXF, SVG, 3dm; a relative path is read from the design "
            "file's folder; docs/import.md). The curve becomes the polyline or spline through "
            "its dense samples, in its plane's 2D coordinates (a curve in z = const keeps x, y).",
            when="spline, polyline",
        ),
        "segments": Key(
            "int",
            "Number of equal-length crease segments (quads per plate). A polyline profile "
            "with exactly this many edges keeps its vertices as they are.",
            default=48,
            check=lambda v: 2 <= v <= 2_000_000,
            check_doc="2 ... 2e6",
        ),
        "reference": Key(
            "float",
            "Arc-length fraction of the reference vertex whose reflection "
            "angle names the actuation (the nearest vertex is used).",
            default=0.5,
            check=_fraction,
            check_doc="0 ... 1",
        ),
        "state": Key(
            "str",
            "Whether the profile is the deployed 3D crease at the design alpha "
            "or the flat crease of the cut pattern.",
            default="deployed",
            choices=("deployed", "flat"),
        ),
    },
    "rulings": {
        "_doc": "The developable type of the leading plate (docs/geometry.md §1). Directions and "
        'points are in the 2D coordinates of the leading crease plane; for state = "deployed" they '
        "are the projections of the 3D rulings, whose inclination follows from the design alpha.",
        "type": Key(
            "str",
            "Ruling field. 'explicit': the far end of every ruling is given (points), for "
            "state = 'flat' cut patterns such as those written by "
            "compas_ccu.model.flat_design.",
            required=True,
            choices=("orthogonal", "cylindrical", "conical", "angle", "explicit"),
        ),
        "side": Key(
            "str",
            "Which side of the leading crease the leading plate lies on: "
            "'inside' = towards the centre of curvature at the reference vertex (the "
            "crease is convex for the plate: synclastic CCU pair, Q2), 'outside' "
            "(anticlastic, Q4), or 'left' / 'right' of the profile direction.",
            default="inside",
            choices=("inside", "outside", "left", "right"),
        ),
        "direction": Key("point2", "Ruling direction [dx, dy].", when="cylindrical"),
        "points": Key(
            "points2",
            "Far end [x, y] of the ruling at every crease vertex, in the cut pattern (one "
            "point per vertex); the plate lies on their side of the crease and 'side' is "
            "ignored. Only with crease.state = 'flat' and layout type 'single' or 'patterns' "
            "(the plate width is given by the points).",
            when="explicit",
        ),
        "apex": Key("point2", "Apex [x, y] that all ruling lines pass through.", when="conical"),
        "gamma": Key(
            "gamma",
            "Ruling angle to the forward crease tangent, degrees: one number, "
            "or [[s, gamma], ...] with s the arc-length fraction (linear in between).",
            when="angle",
        ),
        "alpha_field": Key(
            "str",
            "'ode': alpha(s) follows alpha' = cot(gamma) kappa_2D "
            "tan(alpha) from the reference value (the only developable choice); "
            "'constant': request a constant alpha -- refused unless gamma = 90.",
            default="ode",
            choices=("ode", "constant"),
            when="angle",
        ),
    },
    "deployment": {
        "_doc": "The design state.",
        "alpha": Key(
            "float",
            "Design reflection angle at the reference vertex, degrees: that vertex's angle "
            "between its ruling and the crease tangent. The stack is flat-folded at 0. The fold "
            "a builder sets is the edges' (structure.json fold_angles / fold_alpha, ccu info): "
            "at a kink or an inflection of the crease it differs from the vertex angle.",
            required=True,
            check=_angle_open,
            check_doc="0 < alpha < 90",
        ),
    },
    "layout": {
        "_doc": "Which plates and creases the structure has.",
        "type": Key(
            "str",
            "'single': one crease with the leading plate and its mirror partner "
            "(a CCU pair); 'parallel': a corrugated multi-crease structure whose crease "
            "planes are parallel (paper Fig. 1, 10); 'inclined': crease planes given by their "
            "distances above the crease's start, reference and end vertex, i.e. inclined about "
            "the actuation rotation axis (Fig. 11) and perpendicular to it (Fig. 12a); "
            "'radial': crease planes through one axis parallel to the profile y axis, for "
            "corrugated domes and funnel columns (Fig. 12b, c). See docs/shape-control.md. "
            "'patterns': the cut patterns of a whole structure, as `ccu import` writes a "
            "folder of plate files: the leading plate as [crease] and [rulings] give it "
            "(state = 'flat', explicit rulings) and every other plate by its cut pattern "
            "(patterns, docs/import.md).",
            default="single",
            choices=("single", "parallel", "inclined", "radial", "patterns"),
        ),
        "width": Key(
            "float",
            "Ruling length of the plates of a single crease, m.",
            check=_positive,
            check_doc="> 0 and <= 1e6",
            when="single",
        ),
        "quadrants": Key(
            "bool",
            "Also build the curved-crease-folding continuations: the four "
            "quadrants of one crease (paper Fig. 2).",
            default=False,
            when="single",
        ),
        "ccf_width": Key(
            "float",
            "Ruling length of the continuation plates, m (default: width).",
            check=_positive,
            check_doc="> 0 and <= 1e6",
            when="single",
        ),
        "plates": Key(
            "int",
            "Number of plates between consecutive crease planes (at least 2: a CCU structure "
            "joins plates along creases; one plate has no crease).",
            check=lambda v: 2 <= v <= 10_000,
            check_doc="2 ... 10000",
            when="parallel, inclined, radial",
        ),
        "spacing": Key(
            "float_or_list",
            "Distance between consecutive crease planes at the "
            "design state, m: one number or one per plate (plate k lies between planes k and "
            "k + 1). For 'inclined': the distance above the crease's reference vertex (the "
            "apex of a symmetric arch), measured normal to the leading plane.",
            check=_positive,
            check_doc="> 0 and <= 1e6",
            when="parallel, inclined",
        ),
        "spacing_start": Key(
            "float_or_list",
            "Distance between consecutive crease planes above the crease's start vertex "
            "(a support), m; default: spacing. Differing from spacing inclines the plane "
            "about the actuation rotation axis.",
            check=_non_negative,
            check_doc=">= 0 and <= 1e6",
            when="inclined",
        ),
        "spacing_end": Key(
            "float_or_list",
            "Distance between consecutive crease planes above the crease's end vertex "
            "(the other support), m; default: spacing_start. Differing from spacing_start "
            "inclines the plane perpendicular to the actuation rotation axis.",
            check=_non_negative,
            check_doc=">= 0 and <= 1e6",
            when="inclined",
        ),
        "angle": Key(
            "float_or_list",
            "Angle between consecutive crease planes about the radial axis, degrees: one "
            "number or one per plate (total below 360).",
            check=lambda v: 0.0 < v < 180.0,
            check_doc="0 < angle < 180",
            when="radial",
        ),
        "axis": Key(
            "float",
            "Profile x coordinate of the radial axis (parallel to the profile y axis), m. It "
            "must lie beside the crease, e.g. at the centre of a dome or a funnel column.",
            when="radial",
        ),
        "leading": Key(
            "int",
            "Index of the plane (0 ... plates) that holds the leading crease; "
            "default: the middle plane. For 'patterns': the id of the leading plate (with an "
            "id for every pattern; default 0, the patterns 1, 2, ... in order).",
            check=lambda v: v >= 0,
            check_doc=">= 0",
            when="parallel, inclined, radial, patterns",
        ),
        "patterns": Key(
            "patterns",
            "The plates other than the leading one, in mechanism order, one table each "
            "([[layout.patterns]]): parent = the index of the plate it hangs from (0 the "
            "leading plate, k the k-th pattern; an earlier one), boundary = which boundary of "
            "the parent is the shared crease ('near': its crease row, 'far': its ruling ends), "
            "near = [[x, y], ...] the plate's crease row (one point per crease vertex, in the "
            "order of the parent's row: the rulings of both plates meet the crease at the same "
            "points), far = [[x, y], ...] the far end of every ruling, in the plate's own cut "
            "pattern coordinates, m; id = its plate id (optional). One pattern is the "
            "leading plate's partner across the leading crease (parent = 0, boundary = "
            "'near'; `ccu import` writes it first). Every plate is attached as the mechanism "
            "attaches plates: the mirror image of the parent's rulings across the crease's "
            "plane, with its own ruling lengths; its pattern must be that mirror image "
            "(segment lengths, ruling lengths and angles to 1e-6 of the plate's size).",
            when="patterns",
        ),
    },
    "target": {
        "_doc": "Inverse design of the plane layout (paper §5.5, docs/shape-control.md): target "
        "polylines along the apex and the supports, in the leading plane's frame: d is the "
        "distance from the leading plane along its normal (xaxis x yaxis), x and y are profile "
        "coordinates. The planes of the leading crease's parity (every second plane from the "
        "leading one) are solved so that their creases meet the targets exactly where the "
        "rulings reach them; the other planes keep the layout's distances. Needs layout type "
        "'parallel' or 'inclined'; the remaining fit error is reported (metrics "
        "target_fit_max).",
        "apex": Key(
            "polyline2",
            "[[d, y], ...]: height y of the reference (apex) vertex of the solved creases as a "
            "function of d (d increasing). Any [target] curve may also be a curve file, as "
            "crease.points: its x, y are read as d and the value (the curve must lie in "
            "z = const).",
        ),
        "support": Key(
            "polyline2",
            "[[d, x], ...]: profile x of the crease's start vertex (one support line in plan) "
            "as a function of d.",
        ),
        "support_end": Key(
            "polyline2",
            "[[d, x], ...]: profile x of the crease's end vertex; default: the mirror image "
            "(-x) of support.",
        ),
    },
    "plates": {
        "_doc": "Plate thickness, material and hinges (paper §5.3, docs/thickness.md): the "
        "thick solids (axis-shift hinges), the collision and bending checks and the "
        "fabrication files use them.",
        "thickness": Key(
            "float",
            "Plate thickness t, m (the flat-folded stack is plates x t high).",
            default=0.008,
            check=lambda v: 0.0 < v <= 0.1,
            check_doc="> 0 and <= 0.1",
        ),
        "material": Key(
            "str",
            "Plate material: a library material (docs/thickness.md) or one defined in this "
            "file by a [materials.NAME] table; its stiffness and strength give the curvature "
            "limit of the bending check.",
            default="plywood",
            check_doc=", ".join(f"`{name}`" for name in MATERIALS) + " or a [materials.NAME]",
        ),
        "grain": Key(
            "float",
            "Face-grain direction (material direction 1) in every cut pattern, degrees from "
            "the plane x axis; matters for the orthotropic plywoods.",
            default=0.0,
            check=lambda v: -360.0 <= v <= 360.0,
            check_doc="-360 ... 360",
        ),
        "hinge_width": Key(
            "float",
            "Width of the textile hinge strips centred on the creases, m.",
            default=0.05,
            check=_positive,
            check_doc="> 0 and <= 1e6",
        ),
    },
    "design_code": {
        "_doc": 'The basis of the bending check (docs/thickness.md, "Design values"): '
        "design strengths f_d = k_mod f_k / gamma_M (Eurocode 5 format, EN 1995-1-1 2.4.3, "
        "3.1.3) or the characteristic strengths f_k. Without this section the design values "
        "of EN 1995-1-1 apply: service class 1, permanent action (the active-bending stress "
        "of a permanently bent plate), gamma_M by material kind.",
        "code": Key(
            "str",
            "'EC5': design strengths k_mod f_k / gamma_M; 'characteristic': the "
            "characteristic strengths f_k (k_mod = gamma_M = 1).",
            default="EC5",
            choices=("EC5", "characteristic"),
        ),
        "service_class": Key(
            "int",
            "EN 1995-1-1 2.3.1.3 service class: 1 heated indoors, 2 covered, 3 outdoors "
            "(plywood EN 636-3 only). Picks k_mod and k_def.",
            default=1,
            check=lambda v: v in (1, 2, 3),
            check_doc="1, 2 or 3",
        ),
        "load_duration": Key(
            "str",
            "EN 1995-1-1 2.3.1.2 load-duration class of the action: the active bending of a "
            "permanently deployed structure is permanent.",
            default="permanent",
            choices=LOAD_DURATIONS,
        ),
        "gamma_M": Key(
            "float",
            "Partial factor of the material; default by material kind: plywood 1.2 "
            "(EN 1995-1-1 Table 2.3), aluminium 1.1 (EN 1999-1-1 6.1.3, gamma_M1); required "
            "for gfrp and kind 'other'.",
            check=lambda v: 1.0 <= v <= 10.0,
            check_doc="1 ... 10",
        ),
        "k_mod": Key(
            "float",
            "Modification factor for load duration and moisture, overriding the table "
            "(plywood: EN 1995-1-1 Table 3.1; aluminium 1.0); required for gfrp and kind "
            "'other'.",
            check=lambda v: 0.0 < v <= 1.5,
            check_doc="> 0 and <= 1.5",
        ),
        "k_def": Key(
            "float",
            "Creep factor, reported (final stiffness E / (1 + k_def)), not used by the "
            "strength check; default: plywood EN 1995-1-1 Table 3.2 (0.8 / 1.0 / 2.5 for "
            "service class 1 / 2 / 3), aluminium 0.",
            check=lambda v: 0.0 <= v <= 10.0,
            check_doc=">= 0 and <= 10",
        ),
    },
    "loads": {
        "_doc": "Load cases of the FE structural checks of the deployed state (`ccu validate`, "
        "docs/structural.md). Self-weight is always a case; every action below that is not "
        "zero adds its own: wet-concrete, construction (concrete + live, or live alone), "
        "snow, snow-half (the asymmetric case: snow on the half of the span before its "
        "middle) and wind. Characteristic values: the serviceability state (deflection) "
        "takes them as they are, the ultimate state (utilisation, buckling) multiplies them "
        "by gamma_G and gamma_Q.",
        "concrete_thickness": Key(
            "float",
            "Thickness of the wet concrete cast on the upper surface of the deployed "
            "formwork, m (0: no concrete case).",
            default=0.0,
            check=lambda v: 0.0 <= v <= 2.0,
            check_doc=">= 0 and <= 2",
        ),
        "concrete_density": Key(
            "float",
            "Density of the wet concrete, kg/m³ (normal-weight reinforced concrete, fresh: "
            "EN 1991-1-1 Table A.1, 25 kN/m³ + 1 kN/m³ fresh).",
            default=2600.0,
            check=lambda v: 100.0 <= v <= 10000.0,
            check_doc="100 ... 10000",
        ),
        "concrete_area": Key(
            "str",
            "Where the concrete weight is counted: 'projected', the thickness measured "
            "vertically (a slab with a level soffit line per plan area); 'surface', a layer "
            "of constant thickness on the plates' surface area.",
            default="projected",
            choices=("projected", "surface"),
        ),
        "live": Key(
            "float",
            "Construction live load on the projected area, N/m² (EN 1991-1-6 4.11.2: 0.75 "
            "kN/m², up to 1.5 kN/m² in the working area); with concrete it acts together "
            "with it (case construction).",
            default=0.0,
            check=lambda v: 0.0 <= v <= 1.0e5,
            check_doc=">= 0 and <= 1e5",
        ),
        "snow": Key(
            "float",
            "Snow load on the projected area, N/m² (mu_i s_k, EN 1991-1-3); also gives the "
            "asymmetric case snow-half.",
            default=0.0,
            check=lambda v: 0.0 <= v <= 1.0e5,
            check_doc=">= 0 and <= 1e5",
        ),
        "wind": Key(
            "float",
            "Wind pressure normal to the surface, Pa: positive presses onto the upper face, "
            "negative is suction (c_pe q_p, EN 1991-1-4).",
            default=0.0,
            check=lambda v: -1.0e5 <= v <= 1.0e5,
            check_doc="-1e5 ... 1e5",
        ),
        **{
            f"{action}_duration": Key(
                "str",
                f"EN 1995-1-1 load-duration class of the {what} (Table 2.2{note}): it picks "
                "the k_mod of the cases it is in (the shortest action of a case decides, "
                "3.1.3(2)).",
                default=ACTION_DURATIONS[action][0],
                choices=ACTION_DURATIONS[action][1],
            )
            for action, what, note in (
                ("concrete", "wet concrete", ""),
                ("live", "construction live load", ""),
                ("snow", "snow", "; medium-term where a heavy snow load lies long, its note"),
                ("wind", "wind", ""),
            )
        },
        "gamma_G": Key(
            "float",
            "Partial factor of the permanent actions (self-weight), EN 1990 Table A1.2(B).",
            default=1.35,
            check=lambda v: 1.0 <= v <= 3.0,
            check_doc="1 ... 3",
        ),
        "gamma_Q": Key(
            "float",
            "Partial factor of the variable actions (concrete during execution, live, snow, "
            "wind), EN 1990 Table A1.2(B).",
            default=1.5,
            check=lambda v: 1.0 <= v <= 3.0,
            check_doc="1 ... 3",
        ),
        "deflection_limit": Key(
            "float",
            "Allowed deflection under a case (serviceability), as span / this number.",
            default=500.0,
            check=lambda v: 1.0 <= v <= 1.0e5,
            check_doc="1 ... 1e5",
        ),
    },
    "supports": {
        "_doc": "How the deployed structure stands for the structural checks (`ccu "
        "validate`): the end rulings of every plate are the feet. During the deployment "
        "they follow the kinematic path; under the load cases they are held as set here.",
        "type": Key(
            "str",
            "'pinned': the feet held in place (hinges along the end rulings); 'springs': "
            "the feet on translational springs of `stiffness` in every direction.",
            default="pinned",
            choices=("pinned", "springs"),
        ),
        "stiffness": Key(
            "float",
            "Spring support stiffness per metre of foot line, N/m per m (type 'springs').",
            default=1.0e7,
            check=lambda v: 0.0 < v <= 1.0e15,
            check_doc="> 0 and <= 1e15",
            when="type = 'springs'",
        ),
        "tie": Key(
            "bool",
            "A tie between the two feet of every plate: the end foot slides along the span "
            "(held across and vertically), the tie takes the thrust.",
            default=False,
        ),
        "tie_stiffness": Key(
            "float",
            "Axial stiffness EA / L of the tie of one plate, N/m (a 12 mm steel rod over "
            "2.5 m: 9.5e6 N/m).",
            default=9.5e6,
            check=lambda v: 0.0 < v <= 1.0e15,
            check_doc="> 0 and <= 1e15",
            when="tie = true",
        ),
    },
    "hinges": {
        "_doc": "The textile hinges in the FE model (`ccu validate`): the plates' crease "
        "nodes tied in translation (rigid), or joined by springs, and free to turn, or "
        "turning against a rotational spring.",
        "eccentricity": Key(
            "str",
            "'none': the hinges join the plates' mid-surfaces; 'axis-shift': as built, on the "
            "plates' faces t/2 from the mid-surfaces (paper Fig. 8c), the plates at their thick "
            "placement (docs/structural.md).",
            default="none",
            choices=("none", "axis-shift"),
        ),
        "rotational_stiffness": Key(
            "float",
            "Rotational spring of the hinge, N m/rad per m of crease (0: free hinge).",
            default=0.0,
            check=lambda v: 0.0 <= v <= 1.0e12,
            check_doc=">= 0 and <= 1e12",
        ),
        "translational_stiffness": Key(
            "float",
            "Translational springs of the hinge in every direction, N/m per m of crease "
            "(unset: rigid ties).",
            check=lambda v: 0.0 < v <= 1.0e15,
            check_doc="> 0 and <= 1e15",
        ),
    },
    "fabrication": {
        "_doc": "The workshop (`ccu fabricate`, docs/fabrication.md): the plywood sheets in "
        "stock, the cutter, the nesting of every part onto the sheets, the textile roll of the "
        "hinge strips and the unit prices of the bill of materials. A plate longer than every "
        "sheet is split along rulings (straight lines on the plate: a splice there does not "
        "fight the bending) and joined by splice plates on both faces.",
        "sheets": Key(
            "sizes2",
            "Sheet sizes in stock, [[length, width], ...], m; the face grain runs along the "
            "length. Every part is nested onto the first size it fits (the order is the "
            "preference).",
            default=[list(STOCK_SHEET)],
            check=lambda v: all(0.0 < x <= 100.0 for p in v for x in p),
            check_doc="every size > 0 and <= 100",
        ),
        "kerf": Key(
            "float",
            "Width of the cut, m: toolpaths run kerf / 2 outside the parts; default: "
            "tool_diameter.",
            check=lambda v: 0.0 <= v <= 0.1,
            check_doc=">= 0 and <= 0.1",
        ),
        "tool_diameter": Key(
            "float",
            "Diameter of the router bit, m: the kerf when kerf is unset (a router's cut is as "
            "wide as its bit).",
            default=0.006,
            check=lambda v: 0.0 < v <= 0.1,
            check_doc="> 0 and <= 0.1",
        ),
        "bridge": Key(
            "float",
            "Least material left between the kerfs of two parts, m (parts lie at least kerf + "
            "bridge apart).",
            default=0.01,
            check=lambda v: 0.0 <= v <= 1.0,
            check_doc=">= 0 and <= 1",
        ),
        "margin": Key(
            "float",
            "Least distance from a sheet's edge to a toolpath, m.",
            default=0.01,
            check=lambda v: 0.0 <= v <= 1.0,
            check_doc=">= 0 and <= 1",
        ),
        "grain": Key(
            "str",
            "How the parts may turn on a sheet: 'along': every plate's face grain "
            "([plates] grain) along the sheet's length, turned by 0 or 180 degrees; 'across': "
            "across it; 'free': any angle (isotropic sheets).",
            default="along",
            choices=("along", "across", "free"),
        ),
        "splice_width": Key(
            "float",
            "Width of a splice plate across the cut of a split plate, m (half on each part); "
            "two splice plates per cut, one on each face.",
            default=0.15,
            check=lambda v: 0.0 < v <= 2.0,
            check_doc="> 0 and <= 2",
        ),
        "splice_thickness": Key(
            "float",
            "Thickness of the splice plates, m; default the plates' thickness. Glued across a "
            "cut, the splice plates bend with the plate: the three layers' outer fibres lie "
            "(t + 2 t_s) / 2 from the middle, so the bending utilisation there is the plate's "
            "times (t + 2 t_s) / t (checked by `ccu fabricate`). Thinner splice plates are "
            "nested on sheets of their own thickness.",
            check=lambda v: 0.0 < v <= 0.1,
            check_doc="> 0 and <= 0.1",
        ),
        "fasteners_per_splice": Key(
            "int",
            "Screws through every splice plate (bill of materials), besides the glue.",
            default=8,
            check=lambda v: 0 <= v <= 1000,
            check_doc="0 ... 1000",
        ),
        "roll_width": Key(
            "float",
            "Width of the textile roll the hinge strips are cut from, m.",
            default=1.4,
            check=lambda v: 0.0 < v <= 10.0,
            check_doc="> 0 and <= 10",
        ),
        "score_rulings": Key(
            "bool",
            "Score every interior ruling on the sheets (layer SCORE). Off by default: 8 mm "
            "plywood must bend along them, and a score weakens it; the per-plate files keep "
            "the rulings on the reference layer RULING_SCORE either way.",
            default=False,
        ),
        "nesting": Key(
            "str",
            "'spyrrow': true-shape nesting with spyrrow (sparrow); 'shelf': the parts' "
            "bounding boxes in rows (fast, wasteful; the fallback without spyrrow).",
            default="spyrrow",
            choices=("spyrrow", "shelf"),
        ),
        "nesting_time": Key(
            "float",
            "Safety limit of one packing, s: a packing that has not searched its "
            "nesting_steps by then is refused (never cut short: the files do not depend on "
            "the machine's speed or load).",
            default=600.0,
            check=lambda v: 0.0 < v <= 86400.0,
            check_doc="> 0 and <= 86400",
        ),
        "nesting_seed": Key(
            "int",
            "Random seed of the nesting search (spyrrow): the same seed and steps give the "
            "same nesting; another seed searches other layouts.",
            default=0,
            check=lambda v: 0 <= v <= 2**32 - 1,
            check_doc="0 ... 4294967295",
        ),
        "nesting_steps": Key(
            "int",
            "Steps the nesting search takes per packing (sparrow's separations; a packing "
            "stops sooner at its second failed step): more steps, shorter strips and "
            "more time.",
            default=500,
            check=lambda v: 1 <= v <= 100_000,
            check_doc="1 ... 100000",
        ),
        "currency": Key("str", "Currency of the prices below (text).", default="EUR"),
        "sheet_price": Key(
            "float",
            "Price of one sheet (every size in stock), currency per sheet.",
            default=60.0,
            check=lambda v: 0.0 <= v <= 1.0e9,
            check_doc=">= 0 and <= 1e9",
        ),
        "textile_price": Key(
            "float",
            "Price of the hinge textile, currency per metre of roll.",
            default=12.0,
            check=lambda v: 0.0 <= v <= 1.0e9,
            check_doc=">= 0 and <= 1e9",
        ),
        "glue_price": Key(
            "float",
            "Price of glue, currency per metre of glue line.",
            default=0.3,
            check=lambda v: 0.0 <= v <= 1.0e9,
            check_doc=">= 0 and <= 1e9",
        ),
        "fastener_price": Key(
            "float",
            "Price of one fastener, currency.",
            default=0.05,
            check=lambda v: 0.0 <= v <= 1.0e9,
            check_doc=">= 0 and <= 1e9",
        ),
    },
    "plane": {
        "_doc": "Placement of the leading crease plane in world coordinates (metres). Profile "
        "x runs along xaxis, profile y along yaxis; the plane normal is xaxis x yaxis.",
        "origin": Key("point3", "Origin.", default=[0.0, 0.0, 0.0]),
        "xaxis": Key("point3", "Direction of the profile x axis.", default=[1.0, 0.0, 0.0]),
        "yaxis": Key(
            "point3",
            "Direction of the profile y axis (made orthogonal to xaxis).",
            default=[0.0, 0.0, 1.0],
        ),
    },
}

#: The unit of every quantity key (lengths are metres, angles degrees at the interfaces).
_UNITS = {
    "crease": {
        "span": "m", "rise": "m", "radius": "m", "angle": "deg", "points": "m",
        "point_loads": "m, load", "distributed_loads": "m, load", "segments": "1",
        "reference": "1",
    },
    "rulings": {"direction": "1", "points": "m", "apex": "m", "gamma": "deg"},
    "deployment": {"alpha": "deg"},
    "layout": {
        "width": "m", "ccf_width": "m", "plates": "1", "spacing": "m", "spacing_start": "m",
        "spacing_end": "m", "angle": "deg", "axis": "m", "leading": "1", "patterns": "m",
    },
    "target": {"apex": "m", "support": "m", "support_end": "m"},
    "plates": {"thickness": "m", "grain": "deg", "hinge_width": "m"},
    "design_code": {"service_class": "1", "gamma_M": "1", "k_mod": "1", "k_def": "1"},
    "loads": {
        "concrete_thickness": "m", "concrete_density": "kg/m³", "live": "N/m²",
        "snow": "N/m²", "wind": "Pa", "gamma_G": "1", "gamma_Q": "1", "deflection_limit": "1",
    },
    "supports": {"stiffness": "N/m²", "tie_stiffness": "N/m"},
    "hinges": {"rotational_stiffness": "N", "translational_stiffness": "N/m²"},
    "fabrication": {
        "sheets": "m", "kerf": "m", "tool_diameter": "m", "bridge": "m", "margin": "m",
        "splice_width": "m", "splice_thickness": "m", "fasteners_per_splice": "1",
        "roll_width": "m", "nesting_time": "s", "nesting_seed": "1", "nesting_steps": "1",
        "sheet_price": "currency", "textile_price": "currency/m", "glue_price": "currency/m",
        "fastener_price": "currency",
    },
    "plane": {"origin": "m", "xaxis": "1", "yaxis": "1"},
}  # fmt: skip
for _section, _units in _UNITS.items():
    for _name, _unit in _units.items():
        SCHEMA[_section][_name] = replace(SCHEMA[_section][_name], unit=_unit)


def _pa(doc: str, **kw) -> Key:
    check_doc = "> 0 and <= 1e13 Pa"
    return Key(
        "float", doc, check=lambda v: 0.0 < v <= 1.0e13, check_doc=check_doc, unit="Pa", **kw
    )


#: The keys of one ``[materials.NAME]`` table: the values of :class:`compas_ccu.materials.
#: Material`. A file may define several materials; ``[plates] material`` names one of them or a
#: library material.
MATERIAL_KEYS: dict = {
    "_doc": "Plate materials defined in the design file, one table per material: "
    '`[materials.myply]` with `base = "plywood"` and the values to change, or every value '
    "(E1 and E2, or E for an isotropic material; G12, which E and nu12 give for an isotropic "
    'one; nu12; density; f1 and f2, or f). `[plates] material = "myply"` uses it. A name '
    "of the library (plywood, birch-plywood, ...) is refused: give the material its own name "
    "and the library one as its base. Names are letters, digits, '-' and '_'.",
    "base": Key(
        "str",
        "Library material to start from; the other keys override its values.",
        choices=tuple(MATERIALS),
    ),
    "kind": Key(
        "str",
        "What the material is, for its default design factors ([design_code]); default: "
        "the base's kind, else 'other'.",
        choices=MATERIAL_KINDS,
    ),
    "E1": _pa("Young's modulus along direction 1 (face grain), Pa."),
    "E2": _pa("Young's modulus along direction 2, Pa."),
    "E": _pa("Isotropic shortcut: E1 = E2 = E (and G12 = E / 2(1 + nu12) unless given), Pa."),
    "G12": _pa("In-plane shear modulus, Pa."),
    "nu12": Key(
        "float",
        "Poisson's ratio (strain in 2 from stress in 1); nu12^2 < E1/E2.",
        check=lambda v: -1.0 < v < 0.5,
        check_doc="-1 < nu12 < 0.5",
        unit="1",
    ),
    "density": Key(
        "float",
        "Density, kg/m³.",
        check=lambda v: 0.0 < v <= 1.0e5,
        check_doc="> 0 and <= 1e5",
        unit="kg/m³",
    ),
    "f1": _pa("Characteristic bending strength along direction 1, Pa."),
    "f2": _pa("Characteristic bending strength along direction 2, Pa."),
    "f": _pa("Isotropic shortcut: f1 = f2 = f, Pa."),
    "description": Key("str", "Free text (the source of the values)."),
}

#: Sections that hold named tables (``[materials.NAME]``), with the keys of one table.
NAMED_SECTIONS = {"materials": MATERIAL_KEYS}

_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*\Z")


def file_material(name: str, values: dict) -> Material:
    """The :class:`~compas_ccu.materials.Material` of a validated ``[materials.NAME]`` table.

    Raises
    ------
    DesignError
        A value is missing, given twice (``E`` and ``E1``) or impossible (``nu12`` against
        ``E1/E2``); the key is ``materials.NAME.KEY``.

    Examples
    --------
    >>> m = file_material("stiff", {"base": "plywood", "E": 10e9})
    >>> m.E1 == m.E2 == 10e9, round(m.G12 / 1e9, 3), m.f1 / 1e6, m.kind
    (True, 3.846, 30.0, 'plywood')
    """
    where = f"materials.{name}"
    given = {k: v for k, v in values.items() if v is not None}
    base = given.pop("base", None)
    for short, longs in (("E", ("E1", "E2")), ("f", ("f1", "f2"))):
        both = [k for k in longs if k in given]
        if short in given and both:
            raise DesignError(
                f"give {short} (isotropic) or {' and '.join(longs)}, not both",
                key=f"{where}.{both[0]}",
            )
    out = MATERIALS[base].to_dict() if base is not None else {}
    out["name"] = name
    if base is not None:
        out["description"] = f"{base} with " + ", ".join(
            f"{k} = {v:g}" for k, v in given.items() if isinstance(v, float)
        )
    if "E" in given:
        E = given.pop("E")
        nu = given.get("nu12", out.get("nu12"))
        out.update(E1=E, E2=E)
        if "G12" not in given and nu is not None:
            out["G12"] = E / (2.0 * (1.0 + nu))
    if "f" in given:
        f = given.pop("f")
        out.update(f1=f, f2=f)
    out.update(given)
    out.setdefault("kind", "other")
    missing = [k for k in ("E1", "E2", "G12", "nu12", "density", "f1", "f2") if k not in out]
    if missing:
        raise DesignError(
            f"missing {', '.join(missing)}: give every value (E or E1 and E2, G12 unless E is "
            f"given, nu12, density, f or f1 and f2), or a base = one of {', '.join(MATERIALS)}",
            key=where,
        )
    try:
        return Material(**out)
    except MaterialError as exc:
        text = str(exc)
        key = next((k for k in ("nu12", "E1", "E2", "G12", "f1", "f2") if k in text), None)
        message = text.split(": ", 1)[-1]
        raise DesignError(message, key=f"{where}.{key}" if key else where) from None


def _validate_named(section: str, given, keys: dict) -> dict:
    out = {}
    for name, table in given.items():
        where = f"{section}.{name}"
        if not isinstance(table, dict):
            raise DesignError(
                f"must be a table [{section}.NAME] of values, got {_short(table)}", key=where
            )
        if not _NAME.match(name):
            raise DesignError(
                "a name is letters, digits, '-' and '_' (starting with a letter or digit)",
                key=f"[{where}]",
            )
        if section == "materials" and name in MATERIALS:
            raise DesignError(
                f'shadows the library material {name!r}; give it another name and base = "{name}"',
                key=f"[{where}]",
            )
        allowed = [k for k in keys if not k.startswith("_")]
        for k in table:
            if k not in allowed:
                raise DesignError(
                    f"unknown key; allowed in [{section}.NAME]: {', '.join(allowed)}",
                    key=f"{where}.{k}",
                )
        values = {k: _coerce(where, k, keys[k], table[k]) if k in table else None for k in allowed}
        if section == "materials":
            file_material(name, values)  # every value together (missing, nu12 vs E1/E2)
        out[name] = values
    return out


REQUIRED_SECTIONS = ("crease", "rulings", "deployment")


def _is_number(v) -> bool:
    """A finite real number that a float holds (TOML integers may have any number of digits)."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return False
    if isinstance(v, int):
        return abs(v) <= 2**1023
    return math.isfinite(v)


def _short(value, limit: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= limit else f"{text[: limit - 3]}..."


#: The keys of a curve-file table (``points = { file = ..., layer = ... }``), and their types.
CURVE_FILE_KEYS = {
    "file": str,
    "layer": str,
    "name": str,
    "index": int,
    "units": str,
    "scale": float,
}
CURVE_FILE_UNITS = ("m", "cm", "mm", "in", "ft", "px")
#: The keys that take a curve file instead of a list of points.
CURVE_FILE_PLACES = ("crease.points", "target.apex", "target.support", "target.support_end")


def _curve_file(where: str, value) -> dict:
    """A curve-file reference (a path, or a table with ``file``), checked and completed."""
    table = {"file": value} if isinstance(value, str) else dict(value)
    for k, v in table.items():
        if k not in CURVE_FILE_KEYS:
            raise DesignError(
                f"unknown key in a curve file table; allowed: {', '.join(CURVE_FILE_KEYS)}",
                key=f"{where}.{k}",
            )
        want = CURVE_FILE_KEYS[k]
        if want is float and _is_number(v):
            v = table[k] = float(v)
        if not isinstance(v, want) or isinstance(v, bool):
            raise DesignError(f"must be a {want.__name__}, got {_short(v)}", key=f"{where}.{k}")
    if not table.get("file"):
        raise DesignError("a curve file table needs file = PATH", key=f"{where}.file")
    if table.get("units") is not None and table["units"] not in CURVE_FILE_UNITS:
        raise DesignError(
            f"must be one of {', '.join(CURVE_FILE_UNITS)}, got {table['units']!r}",
            key=f"{where}.units",
        )
    if table.get("index") is not None and table["index"] < 0:
        raise DesignError(f"must be >= 0, got {table['index']}", key=f"{where}.index")
    if "scale" in table and not 0.0 < table["scale"] <= MAX_LENGTH:
        raise DesignError(f"must be > 0 and <= 1e6, got {table['scale']}", key=f"{where}.scale")
    return {k: table.get(k, 1.0 if k == "scale" else None) for k in CURVE_FILE_KEYS}


#: The keys of one ``[[layout.patterns]]`` table: (required, documentation).
PATTERN_KEYS = {
    "parent": (True, "index of the plate it hangs from (0: the leading plate)"),
    "boundary": (True, "'near' or 'far': the parent's boundary that is the shared crease"),
    "near": (True, "[[x, y], ...]: the crease row, in the parent's row order"),
    "far": (True, "[[x, y], ...]: the far end of every ruling"),
    "id": (False, "the plate id"),
}


def _patterns(where: str, value) -> list:
    """The ``[[layout.patterns]]`` tables, each checked on its own (types, at least two
    points, finite numbers); how they fit together is checked when the design is built
    (:mod:`compas_ccu.design.patterns`)."""
    if not isinstance(value, list) or not value:
        raise DesignError(
            f"must be a non-empty array of tables [[layout.patterns]], got {_short(value)}",
            key=where,
        )
    out = []
    for i, table in enumerate(value):
        at = f"{where}[{i}]"
        if not isinstance(table, dict):
            raise DesignError(f"must be a table (parent, boundary, near, far, id), got "
                              f"{_short(table)}", key=at)  # fmt: skip
        for k in table:
            if k not in PATTERN_KEYS:
                raise DesignError(
                    f"unknown key; allowed in a pattern: {', '.join(PATTERN_KEYS)}",
                    key=f"{at}.{k}",
                )
        for k, (required, doc) in PATTERN_KEYS.items():
            if required and k not in table:
                raise DesignError(f"missing required key ({doc})", key=f"{at}.{k}")
        for k in ("parent", "id"):
            v = table.get(k, 0)
            if not isinstance(v, int) or isinstance(v, bool) or v < 0:
                raise DesignError(f"must be an integer >= 0, got {_short(v)}", key=f"{at}.{k}")
        if table["boundary"] not in ("near", "far"):
            raise DesignError(
                f"must be 'near' or 'far', got {_short(table['boundary'])}", key=f"{at}.boundary"
            )
        rows = {}
        for k in ("near", "far"):
            v = table[k]
            ok = isinstance(v, list) and all(
                isinstance(p, list) and len(p) == 2 and all(map(_is_number, p)) for p in v
            )
            if not ok:
                raise DesignError(
                    f"must be a list of [x, y] pairs of finite numbers, got {_short(v)}",
                    key=f"{at}.{k}",
                )
            if len(v) < 2:
                raise DesignError(
                    f"needs at least 2 points (one per crease vertex), got {len(v)}",
                    key=f"{at}.{k}",
                )
            rows[k] = [[float(x), float(y)] for x, y in v]
        if len(rows["near"]) != len(rows["far"]):
            raise DesignError(
                f"{len(rows['far'])} ruling ends for {len(rows['near'])} crease points: one "
                "far end per crease vertex",
                key=f"{at}.far",
            )
        out.append(
            {
                "parent": table["parent"],
                "boundary": table["boundary"],
                "near": rows["near"],
                "far": rows["far"],
                "id": table.get("id"),
            }
        )
    return out


def _coerce(section: str, name: str, key: Key, value, units: str = DEFAULT_UNITS):
    where = f"{section}.{name}"
    # the value as the message shows it: a number of a float key as a float (-1 -> -1.0)
    given = float(value) if key.kind == "float" and _is_number(value) else value
    length = is_length(key.unit)

    def fail(what, hint=""):
        shown = _short(given)
        if length and units != DEFAULT_UNITS:
            shown = f"{shown} {units}"
        raise DesignError(f"{what}, got {shown}{hint}", key=where)

    if key.kind == "float":
        if not _is_number(value):
            fail("must be a finite number")
        value = float(value)
    elif key.kind == "int":
        if not isinstance(value, int) or isinstance(value, bool):
            fail("must be an integer")
    elif key.kind == "str":
        if not isinstance(value, str):
            fail("must be a string")
        if key.choices and value not in key.choices:
            fail(f"must be one of {', '.join(repr(c) for c in key.choices)}")
    elif key.kind == "bool":
        if not isinstance(value, bool):
            fail("must be true or false")
    elif key.kind in ("point2", "point3"):
        dim = 2 if key.kind == "point2" else 3
        if not (isinstance(value, list) and len(value) == dim and all(map(_is_number, value))):
            fail(f"must be a list of {dim} numbers")
        value = [float(v) for v in value]
    elif where in CURVE_FILE_PLACES and isinstance(value, (str, dict)):
        value = _curve_file(where, value)
    elif key.kind in ("points2", "polyline2", "sizes2"):
        ok = isinstance(value, list) and all(
            isinstance(p, list) and len(p) == 2 and all(map(_is_number, p)) for p in value
        )
        if not ok:
            fail("must be a list of [x, y] number pairs")
        least = {"points2": 3, "polyline2": 2}.get(key.kind, 1)
        if len(value) < least:
            fail(f"needs at least {least} points")
        value = [[float(x), float(y)] for x, y in value]
    elif key.kind == "rows":
        ok = isinstance(value, list) and all(
            isinstance(p, list) and len(p) == key.columns and all(map(_is_number, p)) for p in value
        )
        if not ok or not value:
            fail(f"must be a non-empty list of rows of {key.columns} numbers")
        value = [[float(v) for v in p] for p in value]
    elif key.kind == "patterns":
        value = _patterns(where, value)
    elif key.kind == "float_or_list":
        if _is_number(value):
            value = float(value)
        elif isinstance(value, list) and value and all(map(_is_number, value)):
            value = [float(v) for v in value]
        else:
            fail("must be a number or a non-empty list of numbers")
    elif key.kind == "gamma":
        if _is_number(value):
            value = float(value)
        elif (
            isinstance(value, list)
            and len(value) >= 2
            and all(isinstance(p, list) and len(p) == 2 and all(map(_is_number, p)) for p in value)
        ):
            value = [[float(s), float(g)] for s, g in value]
            s = [p[0] for p in value]
            if s[0] != 0.0 or s[-1] != 1.0 or any(b <= a for a, b in zip(s, s[1:])):
                fail("must have increasing arc-length fractions from 0 to 1")
        else:
            fail("must be a number or a list of [s, gamma] pairs")
        values = [value] if isinstance(value, float) else [g for _, g in value]
        if not all(0.0 < g < 180.0 for g in values):
            fail("ruling angles must be in (0, 180) degrees")
    if length and not isinstance(value, dict):  # a curve file has its own units
        value = to_metres(key.kind, key.unit, value, units)
    if key.check is not None:
        values = value if isinstance(value, list) and key.kind == "float_or_list" else [value]
        for v in values:
            if not key.check(v):
                if not length:
                    fail(f"must be {key.check_doc}")
                metres = "" if units == DEFAULT_UNITS else " m"
                fail(f"must be {key.check_doc}{metres}", _units_hint(key, v, units))
    return value


def _units_hint(key: Key, metres: float, units: str) -> str:
    """``(= 0.2 m): did you mean units = "mm"?`` for a length that fails its check in
    ``units`` but would pass in other units."""
    if isinstance(metres, list):  # a list of sizes: no single value to convert
        return ""
    given = metres / unit_factor(units)
    note = "" if units == DEFAULT_UNITS else f" (= {metres:.6g} m)"
    fits = [u for u, f in LENGTH_UNITS.items() if u != units and key.check(given * f)]
    if fits:
        note += f': did you mean units = "{fits[0]}"?'
    return note


def _units(document: dict) -> str:
    """The ``[design] units`` of a document, checked first: every length depends on it."""
    table = document.get("design")
    if not isinstance(table, dict) or "units" not in table:
        return DEFAULT_UNITS
    return _coerce("design", "units", SCHEMA["design"]["units"], table["units"])


def design_sheet(values: dict) -> tuple:
    """The preferred stock sheet (length, width) m of validated design ``values``: the first
    of [fabrication] sheets (:data:`STOCK_SHEET` by default)."""
    sheets = (values.get("fabrication") or {}).get("sheets") or [STOCK_SHEET]
    return tuple(float(x) for x in sheets[0])


def validate(document: dict) -> dict:
    """Validate a parsed design document and fill in defaults.

    Parameters
    ----------
    document : dict
        The parsed TOML.

    Returns
    -------
    dict
        ``{section: {key: value}}`` with every key of :data:`SCHEMA` present (None if unset),
        and ``{"materials": {name: {key: value}}}`` for the ``[materials.NAME]`` tables.
        Lengths are metres: a document with ``[design] units`` other than ``"m"`` is
        converted (:mod:`compas_ccu.design.units`); ``design.units`` keeps the file's units.

    Raises
    ------
    DesignError
        Unknown section or key, wrong type, value out of range, missing required key. The
        message starts with the dotted key name.
    """
    if not isinstance(document, dict):
        raise DesignError(f"a design must be a table, got {type(document).__name__}")
    out: dict = {}
    units = _units(document)
    for section in document:
        if section not in SCHEMA and section not in NAMED_SECTIONS:
            raise DesignError(
                f"unknown section; allowed: {', '.join([*SCHEMA, *NAMED_SECTIONS])}",
                key=f"[{section}]",
            )
        if not isinstance(document[section], dict):
            raise DesignError("must be a table", key=f"[{section}]")
    for section, keys in NAMED_SECTIONS.items():
        out[section] = _validate_named(section, document.get(section, {}), keys)
    for section, keys in SCHEMA.items():
        given = document.get(section, {})
        if section in REQUIRED_SECTIONS and section not in document:
            raise DesignError("missing required section", key=f"[{section}]")
        allowed = [k for k in keys if not k.startswith("_")]
        for name in given:
            if name not in allowed:
                raise DesignError(
                    f"unknown key; allowed in [{section}]: {', '.join(allowed)}",
                    key=f"{section}.{name}",
                )
        values = {}
        for name in allowed:
            key = keys[name]
            if name in given:
                values[name] = _coerce(section, name, key, given[name], units)
            elif key.required:
                raise DesignError("missing required key", key=f"{section}.{name}")
            else:
                values[name] = key.default
        out[section] = values
    for rule in RULES:
        if rule.applies(out) and not rule.holds(out):
            message = rule.message(out) if callable(rule.message) else rule.message
            raise DesignError(message, key=rule.key)
    return out


def schema_markdown() -> str:
    """The design-file reference as Markdown, generated from :data:`SCHEMA`."""
    lines = [
        "# Design files",
        "",
        "Designs are TOML files. Every key is listed here (this page is generated from",
        "`compas_ccu.design.schema.SCHEMA`; regenerate it with",
        "`python -m compas_ccu.design.schema > docs/design-files.md`).",
        "Lengths are metres, angles degrees. An unknown section or key, a wrong type or an",
        "impossible value is an error that names the key, the value and what is allowed.",
        "",
        "**Units.** `[design] units` (`m` default, `mm`, `cm`, `ft`, `in`) sets the units of",
        "every length of the file: the keys whose unit below is `m`, and the positions x of",
        "the crease loads (unit `m, load`). They are converted to metres when the file is read;",
        "inside compas_ccu and in every output (structure.json, reports, `ccu info`) lengths are",
        "metres. Angles stay degrees; forces, pressures, densities and stiffnesses stay SI",
        "(N, Pa, kg/m³), whatever the units. The allowed ranges and the defaults below are in",
        "metres (a file in mm without `[plates] thickness` has 8 mm plates). A length",
        "that is implausible for a curved-crease structure (a crease span outside 0.05 ... 200 m,",
        "a plate thinner than 0.2 mm, ...) is a warning that names the key, the value and the",
        'units that fit (`crease.span = 2500 m is implausible ...: did you mean units = "mm"`).',
        "Writing a design back (`compas_ccu.design.inverse.write_design`) keeps its units;",
        "sweep and study parameters that set a length of a base design are in its units.",
        "`ccu new --preset vault|dome|funnel|cone|quadrants NAME.toml` writes a commented",
        "template to start from.",
        "",
    ]
    for section, keys in [*SCHEMA.items(), *NAMED_SECTIONS.items()]:
        req = " (required)" if section in REQUIRED_SECTIONS else ""
        title = f"[{section}.NAME]" if section in NAMED_SECTIONS else f"[{section}]"
        lines += [
            f"## {title}{req}",
            "",
            keys["_doc"],
            "",
            "| key | type | unit | default | allowed | applies to | meaning |",
            "|---|---|---|---|---|---|---|",
        ]
        for name, key in keys.items():
            if name.startswith("_"):
                continue
            allowed = ", ".join(f"`{c}`" for c in key.choices) or key.check_doc
            default = (
                "required"
                if key.required
                else ("" if key.default is None else f"`{key.default!r}`".replace("'", '"'))
            )
            lines.append(
                f"| `{name}` | {key.kind} | {key.unit} | {default} | {allowed} | "
                f"{key.when or 'all'} | "
                f"{key.doc} |"
            )
        lines.append("")
    lines += [
        "## Rules between keys",
        "",
        "Checked in this order once every key is valid on its own; the error names the key.",
        "",
        "| key | rule |",
        "|---|---|",
    ]
    lines += [f"| `{rule.key}` | {rule.doc} |" for rule in RULES]
    lines.append("")
    return "\n".join(lines)


if __name__ == "__main__":  # pragma: no cover
    print(schema_markdown())
