"""The typed results of the structural checks (:mod:`compas_ccu.fea.checks`).

:func:`~compas_ccu.fea.checks.hinge_line_forces` returns a :class:`HingeLineForces`,
:func:`~compas_ccu.fea.checks.structural_checks` a :class:`StructuralChecks`; their
``to_dict()`` is what ``validation.json`` holds (``checks``, and ``hinges_uls`` of every case),
key for key and in the same order.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

__all__ = ["HingeExtremes", "CreaseHingeForces", "HingeLineForces", "StructuralChecks"]


def _plain(record) -> dict:
    """The fields of a dataclass in order, the values as they are (strict JSON already)."""
    return {f.name: getattr(record, f.name) for f in fields(record)}


@dataclass(frozen=True)
class HingeExtremes:
    """The hinge line forces over a set of hinge nodes, in the crease's frame, N/m.

    Attributes
    ----------
    tension_max_N_per_m : float
        The largest in-plane tension across a crease (0 if none).
    compression_max_N_per_m : float
        The largest in-plane compression across a crease (positive; 0 if none).
    out_of_plane_max_N_per_m : float
        The largest out-of-plane shear.
    along_crease_max_N_per_m : float
        The largest shear along the crease.
    line_mean_N_per_m : float
        The mean line force (length-weighted).
    interior_max_N_per_m : float or None
        The largest line force away from the feet (the middle 80 % of every crease); None if
        no hinge node lies there.
    """

    tension_max_N_per_m: float
    compression_max_N_per_m: float
    out_of_plane_max_N_per_m: float
    along_crease_max_N_per_m: float
    line_mean_N_per_m: float
    interior_max_N_per_m: float | None

    def to_dict(self) -> dict:
        """Plain data, the fields in order."""
        return _plain(self)


@dataclass(frozen=True)
class CreaseHingeForces:
    """The hinge line forces of one crease (:class:`HingeLineForces`).

    Attributes
    ----------
    crease : int
        The crease's index.
    extremes : HingeExtremes
        Over its hinge nodes, N/m.
    resultant_N : list of float
        (3,) the resultant force its hinge passes to plate b, N (rounded to 1e-6 N).
    """

    crease: int
    extremes: HingeExtremes
    resultant_N: list

    def to_dict(self) -> dict:
        """Plain data: ``crease``, the :class:`HingeExtremes` keys, ``resultant_N``."""
        return {"crease": self.crease, **self.extremes.to_dict(), "resultant_N": self.resultant_N}


@dataclass(frozen=True)
class HingeLineForces:
    """The hinge line forces of one step (:func:`~compas_ccu.fea.checks.hinge_line_forces`).

    Attributes
    ----------
    overall : HingeExtremes or None
        Over every hinge node, N/m; None if the problem has no hinges.
    creases : tuple of CreaseHingeForces
        Per crease, by crease index (empty without hinges).
    """

    overall: HingeExtremes | None
    creases: tuple = ()

    def to_dict(self) -> dict:
        """Plain data (a case's ``hinges_uls``): the :class:`HingeExtremes` keys of
        :attr:`overall` (none without hinges), then ``creases`` (a list of dicts)."""
        head = {} if self.overall is None else self.overall.to_dict()
        return {**head, "creases": [c.to_dict() for c in self.creases]}


@dataclass(frozen=True)
class StructuralChecks:
    """Every load case's checks and the governing values
    (:func:`~compas_ccu.fea.checks.structural_checks`; ``validation.json`` ``checks``).

    The governing values carry the keys of one case, so readers of ``validation.json`` read
    either. Deflections in m, stresses in MPa, forces in N, line forces in N/m.

    Attributes
    ----------
    load : dict
        ``self_weight_N_per_m2`` and ``area_load_N_per_m2`` (0 without an area-load case), N/m².
    supports : dict
        The supports (:meth:`compas_ccu.fea.supports.SupportModel.to_dict`; ``{"type": "pinned"}``
        without).
    cases : list of dict
        One row per load case (its :class:`~compas_ccu.fea.loads.LoadCase` keys, then its
        checks: ``deflection_*``, ``utilisation_*``, ``strength_*``, ``basis``, ``stiffness``,
        ``buckling_*``, ``reactions_sls`` / ``reactions_uls``, ``hinges_uls``
        (:meth:`HingeLineForces.to_dict`) and ``steps``).
    governing : dict
        The case name governing ``deflection``, ``utilisation`` and ``buckling`` (None where
        no case has the value).
    deflection_max_m : float
        The largest instantaneous deflection of a case at the SLS, m.
    deflection_limit_m : float
        ``deflection_limit`` × span, m.
    deflection_ratio : float or None
        The largest deflection over the limit.
    deflection_ok : bool
        Every case within the limit.
    utilisation_max : float or None
        The largest ULS stress over the design strength.
    utilisation_max_characteristic : float
        The largest ULS stress over the characteristic strength.
    utilisation_plate : int
        The plate of the governing utilisation (plate id).
    strength_MPa, strength_characteristic_MPa : float
        The governing case's design and characteristic strength, MPa.
    basis : dict
        The governing case's design factors (:meth:`~compas_ccu.materials.DesignFactors.to_dict`).
    utilisation_ok : bool
        Every case at a utilisation of 1 or less.
    reaction_total_N : list of float
        (3,) the largest total reaction of the characteristic loads (the heaviest case), N.
    buckling_factor : float or None
        The smallest design buckling factor of a case; None without a buckling analysis.
    buckling_ok : bool or None
        ``buckling_factor >= 1``; None without one.
    buckling_factor_mean : float or None
        The buckling case's factor with E_mean.
    stiffness : dict or None
        The stiffness basis of the buckling case (else the governing case's).
    deflection_final_max_m : float or None
        The largest final deflection with creep, m; None without k_def.
    buckling_note : str
        The first case's note on its buckling factor ("" if none).
    hinge_tension_max_N_per_m : float
        The largest hinge tension across a crease of a case at the ULS, N/m.
    hinge_mean_N_per_m : float or None
        The governing case's mean hinge line force, N/m; None without hinges.
    hinge_shear_max_N_per_m : float
        The largest out-of-plane hinge shear of a case at the ULS, N/m.
    """

    load: dict
    supports: dict
    cases: list
    governing: dict
    deflection_max_m: float
    deflection_limit_m: float
    deflection_ratio: float | None
    deflection_ok: bool
    utilisation_max: float | None
    utilisation_max_characteristic: float
    utilisation_plate: int
    strength_MPa: float
    strength_characteristic_MPa: float
    basis: dict
    utilisation_ok: bool
    reaction_total_N: list
    buckling_factor: float | None
    buckling_ok: bool | None
    buckling_factor_mean: float | None
    stiffness: dict | None
    deflection_final_max_m: float | None
    buckling_note: str
    hinge_tension_max_N_per_m: float
    hinge_mean_N_per_m: float | None
    hinge_shear_max_N_per_m: float

    def to_dict(self) -> dict:
        """Plain data (strict JSON, ``validation.json`` ``checks``), the fields in order."""
        return _plain(self)
