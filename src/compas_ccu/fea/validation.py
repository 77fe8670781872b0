"""FE validation of a deployment: mesh, deploy, compare with the kinematics, summarise, write.

:func:`validate` puts the jobs of :mod:`compas_ccu.fea` together:

1. the options become :class:`~compas_ccu.fea.settings.FESettings`;
2. the target state is checked (deployment limit, self-intersection) and the plates meshed
   (:mod:`compas_ccu.fea.mesh`);
3. the structure is deployed by the strategy of ``mode`` — ``displacement``
   (:mod:`compas_ccu.fea.displacement`; with ``drive="leading"`` the leading crease's plates
   alone, :mod:`compas_ccu.fea.leading`) or ``actuation`` (:mod:`compas_ccu.fea.actuation`) —
   into a :class:`~compas_ccu.fea.history.DeploymentHistory`;
4. the history is compared with the kinematic model (:mod:`compas_ccu.fea.comparison`), after a
   rigid alignment under actuation only (:data:`ALIGNMENT`), and checked under load
   (:mod:`compas_ccu.fea.checks`, displacement mode);
5. the :class:`Validation` summarises all of it (:meth:`Validation.summary`) and writes it
   (:mod:`compas_ccu.fea.output`).
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field

import numpy as np

from compas_ccu.fea.actuation import actuate
from compas_ccu.fea.checks import StructuralChecks, structural_checks
from compas_ccu.fea.comparison import Comparison, compare
from compas_ccu.fea.displacement import deploy_by_displacement, deployment_problem
from compas_ccu.fea.history import DeploymentHistory
from compas_ccu.fea.leading import deploy_by_leading_crease
from compas_ccu.fea.mesh import ShellMesh, mesh_model
from compas_ccu.fea.output import write_figures, write_results
from compas_ccu.fea.problem import FEProblem, FEResult
from compas_ccu.fea.settings import CONTROLS, DRIVES, MODES, FESettings
from compas_ccu.fea.stresses import stress_summary
from compas_ccu.materials import DesignFactors

__all__ = [
    "FESettings",
    "Validation",
    "validate",
    "deployment_problem",
    "MODES",
    "CONTROLS",
    "DRIVES",
    "STRATEGIES",
    "ALIGNMENT",
]

#: The deployment strategy of every mode (the displacement mode with ``drive="leading"``:
#: :func:`~compas_ccu.fea.leading.deploy_by_leading_crease`).
STRATEGIES = {"displacement": deploy_by_displacement, "actuation": actuate}

#: How :func:`validate` lays the FE shape onto the kinematic one in every mode: under
#: displacement control the supports hold both in the same frame; under actuation the plate
#: ends are free, so the FE shape is rigidly aligned first (see :mod:`compas_ccu.fea.comparison`).
ALIGNMENT = {"displacement": "none", "actuation": "rigid"}


@dataclass
class Validation:
    """The outcome of :func:`validate`: the FE history, its comparison, checks and summary.

    Attributes
    ----------
    history : DeploymentHistory
        The FE deployment step by step (what the strategy returned).
    comparison : Comparison
        The history against the kinematic model, with its ``alignment``.
    extra : dict
        JSON-ready run record added to the summary (``wall_time_total_s``).
    """

    history: DeploymentHistory
    comparison: Comparison
    extra: dict = field(default_factory=dict)

    # -- the history's fields -----------------------------------------------------------------
    @property
    def model(self):
        return self.history.model

    @property
    def mesh(self) -> ShellMesh:
        return self.history.mesh

    @property
    def settings(self) -> FESettings:
        return self.history.settings

    @property
    def problem(self) -> FEProblem:
        return self.history.problem

    @property
    def result(self) -> FEResult:
        return self.history.result

    @property
    def alphas(self) -> np.ndarray:
        """(k,) reference angle of the kinematic state of every step, degrees."""
        return self.history.alphas

    @property
    def kinematic(self) -> np.ndarray:
        """(k, N, 3) kinematic node positions at every step."""
        return self.history.kinematic

    @property
    def spans(self) -> np.ndarray:
        """(k,) span of the leading crease of the kinematic state at every step, m."""
        return self.history.spans

    @property
    def deployment_steps(self) -> int:
        return self.history.deployment_steps

    @property
    def positions(self) -> np.ndarray:
        """(k, N, 3) FE node positions at every step."""
        return self.history.positions

    def work(self) -> np.ndarray:
        """(k,) work of the supports up to every step, J (:meth:`DeploymentHistory.work`)."""
        return self.history.work()

    def load_path(self) -> dict:
        """The load–deployment curve (:meth:`DeploymentHistory.load_path`)."""
        return self.history.load_path()

    def hinge_forces(self, step: int = -1) -> list:
        """Per crease hinge line forces (:meth:`DeploymentHistory.hinge_forces`)."""
        return self.history.hinge_forces(step)

    # -- comparison and checks ----------------------------------------------------------------
    @property
    def alignment(self) -> str:
        """``"none"`` or ``"rigid"``: how :attr:`deviation` was measured."""
        return self.comparison.alignment

    @property
    def deviation(self) -> np.ndarray:
        """(k, N) distance of every FE node from its kinematic position, m, after
        :attr:`alignment`."""
        return self.comparison.deviation

    def deviation_percent(self) -> np.ndarray:
        """(k, N) deviation in % of the span at that state."""
        return self.comparison.deviation_percent()

    def plate_table(self, step: int = -1) -> list:
        """Per plate at one step: max and mean deviation (% span), peak bending stress (MPa)."""
        return self.comparison.plate_table(step)

    def structural_checks(self) -> StructuralChecks | None:
        """Deflection and utilisation under the check loads (:mod:`compas_ccu.fea.checks`;
        None without load-case steps)."""
        return structural_checks(self.history)

    # -- summary and output -------------------------------------------------------------------
    def summary(self) -> dict:
        """Everything a report needs, JSON-ready (what ``validation.json`` holds)."""
        h = self.history
        s, r, k = h.settings, h.result, h.deployment_steps - 1
        checks = structural_checks(h)
        settings = asdict(s)
        settings["material"] = s.material.to_dict()
        return {
            "format": "ccu.validation",
            "version": 1,
            "design": h.model.design.name,
            "engine": r.engine,
            "mode": s.mode,
            "converged": r.converged,
            "alpha": float(h.alphas[k]),
            "span": float(h.spans[k]),
            "mesh": {
                "nodes": len(h.mesh.nodes),
                "elements": len(h.mesh.elements),
                "ties": len(h.problem.ties),
                "element_size": h.mesh.element_size,
                "along": h.mesh.along,
                "across": h.mesh.across.tolist(),
            },
            "deviation": self.comparison.summary(k),
            "plates": self.comparison.plate_table(k),
            "stresses": stress_summary(r.forces[k], thickness=s.thickness).to_dict(),
            "hinges": h.hinge_forces(k),
            "load_path": h.load_path(),
            "checks": None if checks is None else checks.to_dict(),
            "solver": {
                "steps": int(h.problem.steps),
                "iterations": r.iterations.tolist() if r.iterations is not None else [],
                "cuts": int(r.cuts),
                "wall_time_s": float(r.wall_time),
                "message": r.message,
            },
            "settings": settings,
            **h.extra,
            **self.extra,
        }

    def write(self, out, *, figures: bool = True) -> list:
        """Write ``validation.json``, ``fe_results.npz`` and the pictures into ``out``
        (:func:`compas_ccu.fea.output.write_results`); returns the paths."""
        return write_results(out, self.summary(), self.comparison, figures=figures)

    def figures(self, out) -> list:
        """``fe_stress.png``, ``fe_deviation.png``, ``fe_curves.png``
        (:func:`compas_ccu.fea.output.write_figures`); returns the paths."""
        return write_figures(out, self.comparison)


def validate(model, **options) -> Validation:
    """Deploy ``model`` with a nonlinear FE engine and compare with the kinematic model.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    **options
        Fields of :class:`FESettings` (engine, mode, element_size, steps, alpha, material,
        thickness, orthotropic, hinge_stiffness, control, drive, prebend, checks, loads,
        load_cases, area_load, supports, design_code, ...). Without ``thickness`` or
        ``material`` (or with None) the design's ``[plates]`` values are used (a material name
        may be one of the file's ``[materials.NAME]``); without ``loads``, ``supports``,
        ``deflection_limit``, ``hinge_stiffness`` or ``hinge_translational_stiffness`` the
        design's ``[loads]``, ``[supports]`` and ``[hinges]``; and the design's
        ``[design_code]`` gives the design strength of the checks. ``summary()["plates"]``
        says which were used and where they came from.

    Returns
    -------
    Validation

    Raises
    ------
    FEError
        An unknown or invalid option, or the engine is not available.
    ConvergenceError
        A step did not converge even after cutting it; names the step, the angle and the
        residual (the partial history is attached, never returned as a result).
    DeploymentLimitError
        The target angle lies beyond the deployment limit.
    """
    options = dict(options)
    plates = {}
    for key in ("thickness", "material"):
        given = options.get(key) is not None
        if not given:
            options[key] = getattr(model.design.plates, key)
        plates[key + "_from"] = "option" if given else "design [plates]"
    options["material"] = model.design.resolve_material(options["material"])
    design = model.design
    from_design = {
        "loads": (design.loads.to_dict(), "[loads]"),
        "supports": (design.supports.to_dict(), "[supports]"),
        "deflection_limit": (1.0 / design.loads.deflection_limit, "[loads] deflection_limit"),
        "hinge_stiffness": (design.hinges.rotational_stiffness, "[hinges]"),
        "hinge_translational_stiffness": (design.hinges.translational_stiffness, "[hinges]"),
        "hinge_eccentricity": (design.hinges.eccentricity, "[hinges] eccentricity"),
    }
    sources = {}
    for key, (value, section) in from_design.items():
        given = options.get(key) is not None
        if not given:
            options[key] = value
        sources[key] = "option" if given else f"design {section}"
    if not isinstance(options.get("design_code"), DesignFactors):
        options["design_code"] = model.design.design_factors(
            options["material"], **(options.get("design_code") or {})
        )
    settings = FESettings.from_options(options)
    plates.update(thickness=settings.thickness, material=settings.material.name)
    alpha = model.alpha_design if settings.alpha is None else float(settings.alpha)
    model.deploy(alpha)  # the limit and self-intersection checks, with their errors
    mesh = mesh_model(model, element_size=settings.element_size)
    start = time.perf_counter()
    strategy = STRATEGIES[settings.mode]
    if settings.drive == "leading":
        strategy = deploy_by_leading_crease
    history = strategy(model, mesh, settings, alpha=alpha)
    comparison = compare(history, alignment=ALIGNMENT[settings.mode])
    validation = Validation(history, comparison)
    validation.extra["plates"] = plates
    validation.extra["structural_inputs"] = sources
    validation.extra["wall_time_total_s"] = time.perf_counter() - start
    return validation
