"""The design-file keys of the shape: the crease, the rulings, the deployment, the layout.

The sections ``[design]``, ``[crease]``, ``[rulings]``, ``[deployment]``, ``[layout]``,
``[target]`` and ``[plane]`` of :data:`compas_ccu.design.schema_table.SCHEMA`: what the
structure is, where it stands and how far it is deployed.
"""

from __future__ import annotations

from compas_ccu.design.key import Key, angle_open, fraction, non_negative, positive, with_units
from compas_ccu.design.units import DEFAULT_UNITS, LENGTH_UNITS

__all__ = ["SHAPE_SECTIONS"]

#: The unit of every quantity key of the shape sections.
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
    "plane": {"origin": "m", "xaxis": "1", "yaxis": "1"},
}  # fmt: skip

#: ``{section: {name: Key}}`` of the shape sections, in the order of the documentation.
SHAPE_SECTIONS: dict = {
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
            check=positive,
            check_doc="> 0 and <= 1e6",
            when="arc, catenary, elastica, funicular",
        ),
        "rise": Key(
            "float",
            "Height of the apex above the chord, m.",
            check=positive,
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
            check=positive,
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
            check=fraction,
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
            check=angle_open,
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
            check=positive,
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
            check=positive,
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
            check=positive,
            check_doc="> 0 and <= 1e6",
            when="parallel, inclined",
        ),
        "spacing_start": Key(
            "float_or_list",
            "Distance between consecutive crease planes above the crease's start vertex "
            "(a support), m; default: spacing. Differing from spacing inclines the plane "
            "about the actuation rotation axis.",
            check=non_negative,
            check_doc=">= 0 and <= 1e6",
            when="inclined",
        ),
        "spacing_end": Key(
            "float_or_list",
            "Distance between consecutive crease planes above the crease's end vertex "
            "(the other support), m; default: spacing_start. Differing from spacing_start "
            "inclines the plane perpendicular to the actuation rotation axis.",
            check=non_negative,
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
with_units(SHAPE_SECTIONS, _UNITS)
