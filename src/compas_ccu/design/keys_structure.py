"""The design-file keys of the structure: plates, materials, design code, loads, supports.

The sections ``[plates]``, ``[design_code]``, ``[loads]``, ``[supports]`` and ``[hinges]`` of
:data:`compas_ccu.design.schema_table.SCHEMA`, and the keys of one ``[materials.NAME]`` table
(:data:`MATERIAL_KEYS`): what the bending, collision and FE checks of the built structure use.
"""

from __future__ import annotations

from compas_ccu.design.key import Key, positive, with_units
from compas_ccu.materials import ACTION_DURATIONS, LOAD_DURATIONS, MATERIAL_KINDS, MATERIALS

__all__ = ["STRUCTURE_SECTIONS", "MATERIAL_KEYS"]

#: The unit of every quantity key of the structure sections.
_UNITS = {
    "plates": {"thickness": "m", "grain": "deg", "hinge_width": "m"},
    "design_code": {"service_class": "1", "gamma_M": "1", "k_mod": "1", "k_def": "1"},
    "loads": {
        "concrete_thickness": "m", "concrete_density": "kg/m³", "live": "N/m²",
        "snow": "N/m²", "wind": "Pa", "gamma_G": "1", "gamma_Q": "1", "deflection_limit": "1",
    },
    "supports": {"stiffness": "N/m²", "tie_stiffness": "N/m"},
    "hinges": {"rotational_stiffness": "N", "translational_stiffness": "N/m²"},
}  # fmt: skip

#: ``{section: {name: Key}}`` of the structure sections, in the order of the documentation.
STRUCTURE_SECTIONS: dict = {
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
            check=positive,
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
}
with_units(STRUCTURE_SECTIONS, _UNITS)


def _pa(doc: str, **kw) -> Key:
    """A material stiffness or strength key, Pa."""
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
