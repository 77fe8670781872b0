"""The plate material library: :class:`Material` (stiffness in two directions, density, bending
strength, the plate moduli and curvature limits derived from them), the named materials of
:data:`MATERIALS` and :func:`material`, which makes one of a name, a dict or a Material.

Values are typical (rounded) mean stiffnesses and characteristic bending strengths; direction 1
is the face-grain direction of plywood, direction 2 the cross direction; SI units (Pa, kg/m³).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace

from compas_ccu.errors import MaterialError
from compas_ccu.tolerances import EXACT_RELATIVE, ZERO_LENGTH

__all__ = ["Material", "MATERIALS", "MATERIAL_KINDS", "material", "MaterialError"]

#: What a material is, for its design factors (docs/thickness.md, "Design values"): plywood
#: (EN 1995-1-1), gfrp, aluminium (EN 1999-1-1) or other.
MATERIAL_KINDS = ("plywood", "gfrp", "aluminium", "other")


@dataclass(frozen=True)
class Material:
    """A plate material: in-plane stiffness in two directions, density and bending strength.

    Parameters
    ----------
    name : str
    E1, E2 : float
        Young's moduli along direction 1 (face grain) and 2, Pa.
    G12 : float
        In-plane shear modulus, Pa; also used for the transverse shear (G13 = G23 = G12).
    nu12 : float
        Poisson's ratio (strain in 2 from stress in 1).
    density : float
        kg/m³.
    f1, f2 : float
        Bending (or yield) strength along 1 and 2, Pa.
    description : str
    kind : str
        One of :data:`MATERIAL_KINDS`: which default design factors apply
        (:func:`compas_ccu.materials.design_factors`).
    """

    name: str
    E1: float
    E2: float
    G12: float
    nu12: float
    density: float
    f1: float
    f2: float
    description: str = ""
    kind: str = "other"

    def __post_init__(self):
        if self.kind not in MATERIAL_KINDS:
            raise MaterialError(
                f"material {self.name!r}: kind must be one of {', '.join(MATERIAL_KINDS)}, "
                f"got {self.kind!r}"
            )
        for key in ("E1", "E2", "G12", "density", "f1", "f2"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise MaterialError(f"material {self.name!r}: {key} must be > 0, got {value!r}")
        # positive definite plane-stress compliance: nu12^2 < E1 / E2
        if not (
            -1.0 < self.nu12 and self.nu12**2 < self.E1 / self.E2 and self.nu12 < 0.5 + ZERO_LENGTH
        ):
            raise MaterialError(
                f"material {self.name!r}: nu12 = {self.nu12!r} gives no positive definite "
                "stiffness (need -1 < nu12 < 0.5 and nu12^2 < E1/E2)"
            )

    @classmethod
    def isotropic(cls, name: str, E: float, nu: float, density: float, strength: float, **kw):
        """An isotropic material (G = E / 2(1 + ν))."""
        return cls(name, E, E, E / (2.0 * (1.0 + nu)), nu, density, strength, strength, **kw)

    @property
    def is_isotropic(self) -> bool:
        return (
            self.E1 == self.E2
            and self.f1 == self.f2
            and abs(self.G12 - self.E1 / (2.0 * (1.0 + self.nu12))) <= EXACT_RELATIVE * self.E1
        )

    @property
    def nu21(self) -> float:
        return self.nu12 * self.E2 / self.E1

    @property
    def E(self) -> float:
        """Isotropic-equivalent modulus: the mean of E1 and E2, Pa."""
        return 0.5 * (self.E1 + self.E2)

    @property
    def strength(self) -> float:
        """The smaller bending strength, Pa (conservative for an unknown direction)."""
        return min(self.f1, self.f2)

    def isotropic_equivalent(self) -> Material:
        """The isotropic material with the mean modulus and the smaller strength."""
        if self.is_isotropic:
            return self
        return Material.isotropic(
            self.name + " (isotropic)",
            self.E,
            self.nu12,
            self.density,
            self.strength,
            description=self.description,
            kind=self.kind,
        )

    @property
    def plate_factor(self) -> float:
        """``1 - ν12 ν21``: a plate bent to a cylinder is ``1 / (1 - ν12 ν21)`` stiffer than a beam.

        The plate's reduced stiffness along direction i is ``Q_ii = E_i / (1 - ν12 ν21)``
        (docs/thickness.md, "Bending check"); isotropic: ``1 - ν²``.

        >>> round(material("plywood").plate_factor, 4)
        0.91
        """
        return 1.0 - self.nu12 * self.nu21

    def plate_modulus(self, angle):
        """Plate modulus ``Q̄11(φ)`` of a cylindrical bend at ``angle`` φ (radians) to direction 1,
        Pa: the stress per strain along the bending direction when the strain across it is 0.

        ``Q̄11 = Q11 cos⁴φ + 2 (Q12 + 2 Q66) sin²φ cos²φ + Q22 sin⁴φ`` with
        ``Q11 = E1 / (1 - ν12 ν21)``, ``Q22 = E2 / (1 - ν12 ν21)``, ``Q12 = ν12 Q22``,
        ``Q66 = G12`` (classical lamination theory; Timoshenko & Woinowsky-Krieger §1-2 for the
        isotropic ``E / (1 - ν²)``). Scalars or arrays.

        >>> m = material("plywood")
        >>> round(float(m.plate_modulus(0.3)) / 1e9, 4), round(9.0 / (1 - 0.3**2), 4)
        (9.8901, 9.8901)
        """
        import numpy as np

        c2, s2 = np.cos(angle) ** 2, np.sin(angle) ** 2
        q11 = self.E1 / self.plate_factor
        q22 = self.E2 / self.plate_factor
        q12 = self.nu12 * q22
        return q11 * c2 * c2 + 2.0 * (q12 + 2.0 * self.G12) * s2 * c2 + q22 * s2 * s2

    def curvature_limit(self, thickness: float, direction: int | None = None) -> float:
        """Largest curvature before the outer fibre reaches the strength, 1/m:
        ``κ = f (1 - ν12 ν21) / (E t / 2)``, the plate (plane-strain) stress of a wide plate bent
        to a cylinder (:meth:`plate_modulus`; Lienhard 2014's beam formula without the factor
        is up to 10 % unconservative against the FE, docs/thickness.md).

        ``direction`` 1 or 2 picks that direction's E and f, ``None`` the conservative smaller
        value of the two.
        """
        if not (thickness > 0.0):
            raise MaterialError(f"thickness must be > 0, got {thickness!r}")
        if direction is None:
            return min(self.curvature_limit(thickness, 1), self.curvature_limit(thickness, 2))
        if direction not in (1, 2):
            raise MaterialError(f"direction must be 1, 2 or None, got {direction!r}")
        E, f = (self.E1, self.f1) if direction == 1 else (self.E2, self.f2)
        return f * self.plate_factor / (E * thickness / 2.0)

    def off_axis_modulus(self, angle):
        """Young's modulus at ``angle`` (radians, scalar or array) from direction 1, Pa.

        ``1/E(φ) = cos⁴φ/E1 + (1/G12 - 2ν12/E1) sin²φ cos²φ + sin⁴φ/E2`` (plane stress: a
        strip free to contract across; the plate check uses :meth:`plate_modulus`).
        """
        import numpy as np

        c2, s2 = np.cos(angle) ** 2, np.sin(angle) ** 2
        return 1.0 / (
            c2 * c2 / self.E1
            + (1.0 / self.G12 - 2.0 * self.nu12 / self.E1) * s2 * c2
            + s2 * s2 / self.E2
        )

    def off_axis_strength(self, angle):
        """Bending strength at ``angle`` (radians) from direction 1 (Hankinson's formula), Pa.

        ``f(φ) = f1 f2 / (f1 sin²φ + f2 cos²φ)``, the standard off-grain rule for wood.
        """
        import numpy as np

        return self.f1 * self.f2 / (self.f1 * np.sin(angle) ** 2 + self.f2 * np.cos(angle) ** 2)

    def curvature_limit_at(self, thickness: float, angle):
        """Curvature limit ``f(φ) / (Q̄11(φ) t / 2)`` for bending at ``angle`` (radians) to 1, 1/m.

        >>> m = material("birch-plywood")
        >>> limit = float(m.curvature_limit_at(0.008, 0.0))
        >>> round(limit, 4) == round(m.curvature_limit(0.008, 1), 4)
        True
        """
        if not (thickness > 0.0):
            raise MaterialError(f"thickness must be > 0, got {thickness!r}")
        return self.off_axis_strength(angle) / (self.plate_modulus(angle) * thickness / 2.0)

    def plate_rigidity(self, thickness: float, angle=0.0):
        """Bending rigidity ``D(φ) = Q̄11(φ) t³ / 12`` of a cylindrical bend, N m (isotropic:
        ``E t³ / 12 (1 - ν²)``).

        >>> round(float(material("plywood").plate_rigidity(0.008)), 2)
        421.98
        """
        if not (thickness > 0.0):
            raise MaterialError(f"thickness must be > 0, got {thickness!r}")
        return self.plate_modulus(angle) * thickness**3 / 12.0

    def to_dict(self) -> dict:
        return asdict(self)

    def with_values(self, **values) -> Material:
        """A copy with some values replaced (unknown keys are refused)."""
        unknown = sorted(set(values) - set(self.to_dict()))
        if unknown:
            raise MaterialError(
                f"unknown material key(s) {unknown}; known: {sorted(self.to_dict())}"
            )
        return replace(self, **values)


MATERIALS = {
    m.name: m
    for m in (
        Material.isotropic(
            "plywood",
            9.0e9,
            0.3,
            600.0,
            30.0e6,
            description="generic 8 mm plywood as an isotropic plate, E = 9 GPa (paper's scale)",
            kind="plywood",
        ),
        Material(
            "birch-plywood",
            11.0e9,
            6.0e9,
            0.6e9,
            0.05,
            680.0,
            45.0e6,
            35.0e6,
            description="birch plywood, 7 plies at 9 mm: bending E and f_m,k along / across grain",
            kind="plywood",
        ),
        Material(
            "poplar-plywood",
            6.5e9,
            2.5e9,
            0.4e9,
            0.05,
            450.0,
            30.0e6,
            18.0e6,
            description="poplar plywood (light, flexible): bending E, f_m,k along / across grain",
            kind="plywood",
        ),
        Material.isotropic(
            "gfrp",
            20.0e9,
            0.25,
            1900.0,
            200.0e6,
            description="glass-fibre reinforced polymer sheet, quasi-isotropic laminate",
            kind="gfrp",
        ),
        Material.isotropic(
            "aluminium",
            70.0e9,
            0.33,
            2700.0,
            130.0e6,
            description="aluminium sheet EN AW-5754 H22, f = 0.2 % proof strength",
            kind="aluminium",
        ),
    )
}


def material(spec) -> Material:
    """A :class:`Material` from a library name, a Material, or a dict of values.

    A dict may name a library ``base`` and override some values:
    ``{"base": "birch-plywood", "E1": 12e9}``; without ``base`` it must give every value.
    """
    if isinstance(spec, Material):
        return spec
    if isinstance(spec, str):
        if spec not in MATERIALS:
            raise MaterialError(f"unknown material {spec!r}; known: {sorted(MATERIALS)}")
        return MATERIALS[spec]
    if isinstance(spec, dict):
        values = dict(spec)
        base = values.pop("base", None)
        if base is not None:
            return material(base).with_values(**values)
        try:
            return Material(**values)
        except TypeError as exc:
            raise MaterialError(f"material values {sorted(values)}: {exc}") from None
    raise MaterialError(f"a material is a name, a dict or a Material, got {spec!r}")
