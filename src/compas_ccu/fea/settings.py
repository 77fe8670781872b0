"""The options of an FE validation: one dataclass, checked on construction.

>>> s = FESettings(engine="opensees", steps=4)
>>> s.mode, s.material.name
('displacement', 'plywood')
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from compas_ccu.fea.eccentric import ECCENTRICITIES
from compas_ccu.fea.loads import CASE_NAMES, GRAVITY, load_cases
from compas_ccu.fea.problem import FEError
from compas_ccu.fea.supports import SUPPORT_TYPES
from compas_ccu.materials import DesignFactors, design_factors
from compas_ccu.materials import material as get_material

__all__ = ["FESettings", "MODES", "CONTROLS", "DRIVES", "GRAVITY", "DEFAULT_AREA_LOAD"]

MODES = ("displacement", "actuation")
CONTROLS = ("supports", "edges")
#: Which plates the displacement mode drives: every plate's end rulings, or the leading
#: crease's two plates alone after pre-bending (:mod:`compas_ccu.fea.leading`).
DRIVES = ("all", "leading")
#: The ``area-load`` case of a design without a ``[loads]`` action, N/m².
DEFAULT_AREA_LOAD = 1500.0
_VARIABLE = ("concrete_thickness", "live", "snow", "wind")
_SUPPORT_KEYS = {"type": "pinned", "stiffness": 1.0e7, "tie": False, "tie_stiffness": 9.5e6}


@dataclass
class FESettings:
    """Options of an FE validation (SI units; angles in degrees).

    Attributes
    ----------
    engine : {"kratos", "opensees"}
    mode : {"displacement", "actuation"}
        The deployment strategy: :mod:`compas_ccu.fea.displacement` or
        :mod:`compas_ccu.fea.actuation`.
    element_size : float
        Target element edge length, m.
    steps : int
        Deployment increments from the flat stack to the target.
    alpha : float or None
        Target reference reflection angle, degrees (None: the design's).
    material : str or dict
        A name of :data:`compas_ccu.materials.MATERIALS` or a dict of values.
    design_code : dict or DesignFactors or None
        The basis of the strength check (:func:`compas_ccu.materials.design_factors`): keys
        of a design file's ``[design_code]`` section or the factors; None: the EC5 defaults of
        the material. Becomes a :class:`~compas_ccu.materials.DesignFactors`.
    thickness : float
        m (default 8 mm plywood).
    orthotropic : bool
        E1 along the crease, E2 across (else the isotropic equivalent).
    hinge_stiffness : float
        Rotational hinge spring, N m / rad per m of crease (0: free hinges).
    hinge_translational_stiffness : float or None
        Displacement mode: in-plane / out-of-plane hinge springs, N/m per m, instead of rigid
        ties.
    hinge_eccentricity : {"none", "axis-shift"}
        Displacement mode: hinges on the mid-surfaces, or on the plates' faces with the plates
        at their thick placement (:mod:`compas_ccu.fea.eccentric`).
    control : {"supports", "edges"}
        Displacement mode: which nodes follow the kinematic path.
    drive : {"all", "leading"}
        Displacement mode: the end rulings of every plate follow the kinematic path (``all``),
        or, after pre-bending to ``prebend`` and a release, those of the leading crease's two
        plates alone (``leading``: does one crease drive all? :mod:`compas_ccu.fea.leading`;
        no load cases are run).
    self_weight : bool
        Displacement mode: self-weight during the deployment too.
    checks : bool
        Displacement mode: run the load cases on the deployed state (deflection, utilisation,
        linear buckling factor, reactions, hinge forces; :mod:`compas_ccu.fea.checks`).
    loads : dict or None
        The keys of a design file's ``[loads]`` section (:mod:`compas_ccu.fea.loads`); None:
        self-weight and the ``area-load`` case only.
    load_cases : sequence of str or None
        The cases to run (names of :data:`compas_ccu.fea.loads.CASE_NAMES`); None: all that
        the loads define.
    area_load : float or None
        A uniform load on the plate surface, Pa: the ``area-load`` case (0: none). None: 1.5
        kN/m² if ``loads`` has no action of its own, else none.
    supports : dict or None
        The keys of a design file's ``[supports]`` section (:mod:`compas_ccu.fea.supports`);
        None: pinned feet.
    deflection_limit : float
        Allowed deflection as a fraction of the span (1/500).
    prebend : float
        Actuation mode and ``drive="leading"``: pre-bending angle, degrees (default: a quarter
        of the target under actuation, an eighth with the leading drive).
    actuator_stiffness : float
        Actuation mode: stiffness of the actuator at every crease end, N/m.
    tolerance, max_cuts, max_iterations
        Newton options of the engine.
    """

    engine: str = "kratos"
    mode: str = "displacement"
    element_size: float = 0.1
    steps: int = 8
    alpha: float | None = None
    material: object = "plywood"
    design_code: object = None
    thickness: float = 0.008
    orthotropic: bool = False
    hinge_stiffness: float = 0.0
    hinge_translational_stiffness: float | None = None
    hinge_eccentricity: str = "none"
    control: str = "supports"
    drive: str = "all"
    self_weight: bool = False
    checks: bool = True
    loads: dict | None = None
    load_cases: tuple | None = None
    area_load: float | None = None
    supports: dict | None = None
    deflection_limit: float = 1.0 / 500.0
    prebend: float | None = None
    actuator_stiffness: float = 2.0e5
    tolerance: float = 1e-6
    max_cuts: int = 6
    max_iterations: int = 30

    def __post_init__(self):
        if self.mode not in MODES:
            raise FEError(f"mode must be one of {MODES}, got {self.mode!r}")
        if self.hinge_eccentricity not in ECCENTRICITIES:
            raise FEError(
                f"hinge_eccentricity must be one of {ECCENTRICITIES}, got "
                f"{self.hinge_eccentricity!r}"
            )
        if self.hinge_eccentricity != "none" and self.engine != "kratos":
            raise FEError(
                f"hinge_eccentricity {self.hinge_eccentricity!r} needs engine 'kratos' (eccentric "
                f"shell sections); engine {self.engine!r} models hinges on the mid-surfaces only"
            )
        if self.hinge_eccentricity != "none" and self.mode != "displacement":
            raise FEError(
                "axis-shift hinges are modelled in the displacement mode only, not in "
                f"mode {self.mode!r}"
            )
        if self.control not in CONTROLS:
            raise FEError(f"control must be one of {CONTROLS}, got {self.control!r}")
        self._check_drive()
        if not (isinstance(self.steps, int) and self.steps >= 1):
            raise FEError(f"steps must be an integer >= 1, got {self.steps!r}")
        for key in ("thickness", "element_size"):
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0.0):
                raise FEError(f"{key} must be > 0, got {v!r}")
        if self.area_load is None:
            variable = any((self.loads or {}).get(k) for k in _VARIABLE)
            self.area_load = 0.0 if variable else DEFAULT_AREA_LOAD
        if self.area_load < 0.0 or not (0.0 < self.deflection_limit < 1.0):
            raise FEError(
                f"area_load must be >= 0 Pa and deflection_limit in (0, 1), got "
                f"{self.area_load!r} and {self.deflection_limit!r}"
            )
        self.material = get_material(self.material)
        if not isinstance(self.design_code, DesignFactors):
            self.design_code = design_factors(self.material, **(self.design_code or {}))
        supports = dict(self.supports or {})
        unknown = sorted(set(supports) - set(_SUPPORT_KEYS))
        if unknown:
            raise FEError(f"unknown supports key(s) {unknown}; known: {sorted(_SUPPORT_KEYS)}")
        self.supports = {**_SUPPORT_KEYS, **supports}
        if self.supports["type"] not in SUPPORT_TYPES:
            raise FEError(
                f"supports.type must be one of {SUPPORT_TYPES}, got {self.supports['type']!r}"
            )
        if self.load_cases is not None:
            self.load_cases = tuple(self.load_cases)
            names = [c.name for c in self.cases(select=False)]
            missing = [c for c in self.load_cases if c not in names]
            if missing:
                known = [c for c in CASE_NAMES if c in names]
                raise FEError(
                    f"load case(s) {missing} are not defined: the loads give {known} (set the "
                    "action in the design's [loads] section, or --area-load)"
                )

    def _check_drive(self) -> None:
        """The leading drive is a displacement-mode deployment on the supports alone."""
        if self.drive not in DRIVES:
            raise FEError(f"drive must be one of {DRIVES}, got {self.drive!r}")
        if self.drive == "all":
            return
        clash = {
            "mode": (self.mode, "displacement"),
            "control": (self.control, "supports"),
            "hinge_eccentricity": (self.hinge_eccentricity, "none"),
            "self_weight": (self.self_weight, False),
        }
        for key, (value, needed) in clash.items():
            if value != needed:
                raise FEError(
                    f"drive {self.drive!r} needs {key} = {needed!r} (the supports of the "
                    f"leading plates drive a displacement-mode deployment), got {value!r}"
                )

    def cases(self, *, select: bool = True) -> list:
        """The :class:`~compas_ccu.fea.loads.LoadCase` list of the checks (``load_cases``
        only, unless ``select`` is False); empty without ``checks``."""
        if not self.checks and select:
            return []
        weight = self.material.density * GRAVITY * self.thickness
        out = load_cases(self.loads or {}, self_weight=weight, area_load=self.area_load)
        if select and self.load_cases is not None:
            out = [c for c in out if c.name in self.load_cases]
        return out

    @classmethod
    def from_options(cls, options: dict) -> FESettings:
        """Settings from keyword options; an unknown key raises :class:`FEError` naming it."""
        known = cls.__dataclass_fields__
        unknown = sorted(set(options) - set(known))
        if unknown:
            raise FEError(f"unknown FE option(s) {unknown}; known: {sorted(known)}")
        return cls(**options)
