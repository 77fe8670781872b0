"""The table of key figures: name, type, unit, group and meaning of every figure (the single
source of their definitions; ``docs/key-figures.md`` is generated from it)."""

from __future__ import annotations

from dataclasses import dataclass

from compas_ccu.errors import OptionError

__all__ = ["Figure", "FIGURES", "GROUPS", "figure", "figures_markdown"]


@dataclass(frozen=True)
class Figure:
    """The definition of one key figure."""

    name: str
    dtype: str  # "float", "int", "bool", "str"
    unit: str
    group: str
    doc: str


#: Groups of figures, in the order of the table.
GROUPS = ("design", "deployment", "shape", "stack", "invariants", "path", "thickness")


def _group(group, rows):
    return tuple(Figure(name, dtype, unit, group, doc) for name, dtype, unit, doc in rows)


#: Every key figure: name, type, unit, group, meaning. The single source of their definitions.
FIGURES = (
    *_group(
        "design",
        [
            ("name", "str", "", "Design name (`[design] name`, else the file name)."),
            ("description", "str", "", "`[design] description`."),
            ("layout", "str", "", "Plane layout type (`[layout] type`)."),
            ("plates", "int", "", "Number of plates."),
            ("creases", "int", "", "Number of creases."),
            (
                "crease_kinds",
                "str",
                "",
                "Creases by kind at the design state, e.g. `4 anticlastic, 5 synclastic`.",
            ),
            ("segments", "int", "", "Segments of every crease (quads per plate)."),
        ],
    ),
    *_group(
        "deployment",
        [
            (
                "alpha_design",
                "float",
                "deg",
                "Design reflection angle at the reference vertex: the per-vertex angle between "
                "the vertex's ruling and the crease tangent (the edges' folds: fold_alpha_*).",
            ),
            (
                "reference_vertex",
                "int",
                "",
                "Vertex of the leading crease whose reflection angle names the actuation.",
            ),
            (
                "alpha_min",
                "float",
                "deg",
                "Smallest reflection angle on any crease vertex at the design (leading crease "
                "included).",
            ),
            ("alpha_max", "float", "deg", "Largest reflection angle on any crease at the design."),
            (
                "fold_alpha_min",
                "float",
                "deg",
                "Smallest reflection angle of any crease edge at the design, from the geometry: "
                "half the angle between the two plates across the edge (structure.json "
                "fold_angles).",
            ),
            (
                "fold_alpha_max",
                "float",
                "deg",
                "Largest reflection angle of any crease edge at the design (half its fold).",
            ),
            (
                "reference_fold_alpha",
                "float",
                "deg",
                "Reflection angle the leading crease's edges imply at the reference vertex: half "
                "the mean fold of the edges that meet there (the fold a builder sets where "
                "alpha_design is read off; alpha_design is the vertex's angle between its ruling "
                "and the crease tangent, which differs at a kink or an inflection).",
            ),
            (
                "alpha_limit",
                "float",
                "deg",
                "Deployment limit: a crease segment, or the surface at the reference vertex "
                "(then 90 deg), stands perpendicular to its plane.",
            ),
            (
                "limit_vertex",
                "int",
                "",
                "Segment of the leading crease that stands perpendicular to its plane at the "
                "limit.",
            ),
            ("overlap_alpha", "float", "deg", "Largest alpha before a crease overlaps itself."),
            (
                "collision_free_alpha",
                "float",
                "deg",
                "Largest alpha reached from the flat stack without any two plates (zero "
                "thickness, every pair) crossing; alpha_limit if they never do (certified to "
                "1e-7 rad, docs/geometry.md).",
            ),
            (
                "limit_margin",
                "float",
                "deg",
                "min(alpha_limit, overlap_alpha, collision_free_alpha) - alpha_design: "
                "how much further the structure could open.",
            ),
        ],
    ),
    *_group(
        "shape",
        [
            ("crease_span", "float", "m", "Chord of the leading crease at the design."),
            ("crease_rise", "float", "m", "Height of the leading crease above its chord."),
            ("crease_rise_to_span", "float", "", "crease_rise / crease_span."),
            ("plan_x", "float", "m", "Extent of the deployed structure along world x."),
            ("plan_y", "float", "m", "Extent along world y."),
            ("height", "float", "m", "Extent along world z."),
            (
                "plan_diameter",
                "float",
                "m",
                "Largest distance in plan (world x-y) between two points of the deployed "
                "structure: the diameter of a dome or funnel.",
            ),
            ("plan_area", "float", "m2", "plan_x * plan_y."),
            ("plate_area", "float", "m2", "Area of all cut patterns (one face)."),
            (
                "size",
                "float",
                "m",
                "Structure size: diagonal of the bounding box of the design state (the length "
                "the relative errors refer to).",
            ),
            (
                "global_curvature",
                "str",
                "",
                "Measured global shape: synclastic, anticlastic or "
                "monoclastic (4 or more plates in a plane layout; else empty).",
            ),
            (
                "principal_curvature_1",
                "float",
                "1/m",
                "Larger principal curvature of the global surface at its centre.",
            ),
            ("principal_curvature_2", "float", "1/m", "Smaller principal curvature."),
            ("gaussian_curvature", "float", "1/m2", "Gaussian curvature of the global surface."),
            (
                "curvature_ratio",
                "float",
                "",
                "min abs(k) / max abs(k) of the global surface (monoclastic below 1e-3).",
            ),
            (
                "plane_inclination_axis",
                "float",
                "deg",
                "Largest inclination between neighbouring crease planes about the actuation axis.",
            ),
            (
                "plane_inclination_perpendicular",
                "float",
                "deg",
                "Largest inclination between neighbouring crease planes perpendicular to it.",
            ),
            (
                "target_fit_planes",
                "str",
                "",
                "Crease planes solved to meet the target curves (`[target]`), e.g. `1, 3, 7`.",
            ),
            (
                "target_fit_max",
                "float",
                "m",
                "Largest distance of a solved plane from its target curves.",
            ),
        ],
    ),
    *_group(
        "stack",
        [
            (
                "stack_x",
                "float",
                "m",
                "Flat-folded stack: extent of the cut patterns along x of the stack plane.",
            ),
            ("stack_y", "float", "m", "Flat-folded stack: extent along y of the stack plane."),
            ("stack_length", "float", "m", "Flat-folded stack: bounding box in the plane, long."),
            ("stack_width", "float", "m", "Flat-folded stack: bounding box in the plane, short."),
            (
                "plate_length",
                "float",
                "m",
                "Largest cut pattern: the longest side of the minimum-area rectangles around the "
                "plates (what a stock sheet must hold).",
            ),
            (
                "plate_width",
                "float",
                "m",
                "Largest cut pattern: the longest short side of those rectangles.",
            ),
        ],
    ),
    *_group(
        "invariants",
        [
            (
                "isometry_relative",
                "float",
                "",
                "Largest change of a quad side or diagonal from the cut pattern / size.",
            ),
            ("quad_planarity_relative", "float", "", "Largest quad non-planarity / size."),
            ("hinge_gap_relative", "float", "", "Largest gap between hinged plate edges / size."),
            (
                "mirror_error_relative",
                "float",
                "",
                "Largest violation of the mirror symmetry at a crease / size.",
            ),
            (
                "invariant_max_relative",
                "float",
                "",
                "Largest relative invariant error at the design (isometry, quad planarity, "
                "hinges, mirror symmetry), ~1e-15.",
            ),
            (
                "crease_planarity_design",
                "float",
                "m",
                "Largest distance of a crease from its plane at the design state.",
            ),
        ],
    ),
    *_group(
        "path",
        [
            (
                "path_states",
                "int",
                "",
                "States of the deployment path at which the path figures are measured.",
            ),
            (
                "crease_planarity_path",
                "float",
                "m",
                "Largest distance of a crease from its plane over the path from the flat stack "
                "to the design (0 for exact designs).",
            ),
            (
                "crease_planarity_path_relative",
                "float",
                "",
                "crease_planarity_path / size.",
            ),
            (
                "crease_planarity_path_alpha",
                "float",
                "deg",
                "Reference angle of the path state with the largest crease deviation.",
            ),
            (
                "crease_planarity_exact",
                "bool",
                "",
                "Every crease stays in its plane along the path (relative deviation <= 1e-9).",
            ),
            (
                "relaxed_alpha",
                "float",
                "deg",
                "Relaxation (on request, where not exact): the state relaxed, the worst one.",
            ),
            (
                "kinematic_isometry",
                "float",
                "m",
                "Relaxation: isometry error of the kinematic state there.",
            ),
            (
                "relaxed_strain",
                "float",
                "",
                "Relaxation: largest relative length error left in the relaxed plates.",
            ),
            ("relaxed_quad_planarity", "float", "m", "Relaxation: largest quad non-planarity."),
            (
                "relaxed_displacement",
                "float",
                "m",
                "Relaxation: largest move from the kinematic state.",
            ),
        ],
    ),
    *_group(
        "thickness",
        [
            ("thickness", "float", "m", "Plate thickness ([plates])."),
            (
                "material",
                "str",
                "",
                "Plate material ([plates]): a library name or one of the file's [materials.NAME].",
            ),
            ("stack_height", "float", "m", "Height of the flat-folded stack (sum of thicknesses)."),
            (
                "collision_free_alpha_thick",
                "float",
                "deg",
                "Largest alpha reached from the flat stack without the thick plates "
                "interpenetrating (at most collision_free_alpha; to 1/1536 of it).",
            ),
            ("mass", "float", "kg", "plate_area * thickness * density."),
            (
                "deployment_energy",
                "float",
                "J",
                "Bending energy stored in the plates at the design state, D/2 * integral of "
                "curvature squared (the work of deploying; docs/structural.md).",
            ),
            (
                "actuation_force",
                "float",
                "N",
                "Largest force between the feet (the leading crease's two ends) along the path "
                "that holds the structure: dE/dalpha / (d span/dalpha), quasi-static, no "
                "friction or self-weight (radial layouts: ring_thrust).",
            ),
            (
                "ring_radius",
                "float",
                "m",
                "Radial layouts: radius of the ring of feet about the axis at the design, "
                "sqrt(2 A / Theta) (A the plan area of the fan of the feet, Theta its angle).",
            ),
            (
                "ring_thrust",
                "float",
                "N/m",
                "Radial layouts: horizontal thrust of the feet on a ring that holds them at the "
                "design, per metre of ring, h = -dE/dalpha / (dA/dalpha): the statics of "
                "actuation_force with the ring's plan area in place of the span (positive "
                "outwards; negative: the feet pull inwards). Active bending only.",
            ),
            (
                "ring_tension",
                "float",
                "N",
                "Radial layouts: tension of that ring, h * ring_radius (negative: compression).",
            ),
            (
                "bending_utilisation",
                "float",
                "",
                "Largest abs(curvature) / (f_d (1 - nu^2) / (E t / 2)) over all plates and path "
                "states (the plate stress of a cylindrical bend), "
                "with the design strength f_d = k_mod f_k / gamma_M of [design_code] "
                "(> 1: the plates break).",
            ),
            (
                "bending_utilisation_characteristic",
                "float",
                "",
                "The same with the characteristic strength f_k (k_mod = gamma_M = 1).",
            ),
            (
                "bending_basis",
                "str",
                "",
                "Basis of the bending check, e.g. `EC5 SC1 permanent` or `characteristic`.",
            ),
            ("k_mod", "float", "", "Modification factor of the bending check ([design_code])."),
            ("gamma_M", "float", "", "Partial material factor of the bending check."),
            (
                "k_def",
                "float",
                "",
                "Creep factor (reported; final stiffness E / (1 + k_def)); None if unknown.",
            ),
            ("bending_curvature", "float", "1/m", "Largest plate curvature over the path."),
        ],
    ),
)

_BY_NAME = {f.name: f for f in FIGURES}


def figure(name: str) -> Figure:
    """The definition of figure ``name``; OptionError names the figures."""
    try:
        return _BY_NAME[name]
    except KeyError:
        raise OptionError(
            f"no key figure {name!r}; the key figures are: {', '.join(_BY_NAME)}"
        ) from None


def figures_markdown() -> str:
    """The table of ``docs/key-figures.md``."""
    lines = ["| figure | type | unit | group | meaning |", "|---|---|---|---|---|"]
    for f in FIGURES:
        lines.append(f"| `{f.name}` | {f.dtype} | {f.unit} | {f.group} | {f.doc} |")
    return "\n".join(lines)
