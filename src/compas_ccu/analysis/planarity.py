"""Crease planarity along the whole deployment path (paper §5.1, Fig. 6d; docs/geometry.md §2).

At the design state every crease is planar by construction. During deployment a subsequent
crease stays planar exactly for parallel planes (any ruling field) and for planes inclined about
the actuation rotation axis with cylindrical rulings; otherwise it leaves its plane, the mirror
construction has no exact solution and the kinematic model reflects across the best-fit plane.
:func:`planarity_along_path` measures the deviation of every crease at every state and, on
request, relaxes the worst state by least squares to show what the rigid-ruling model costs.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.outputs import write_json
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["PlanarityReport", "planarity_along_path"]


@dataclass
class PlanarityReport:
    """Crease planarity of a design along its deployment path.

    Attributes
    ----------
    alphas : (k,) float
        Reference reflection angles, degrees.
    deviation : (k, c) float
        Largest distance of each crease's vertices from its best-fit plane, m.
    creases : list of dict
        Per crease: ``id``, ``plates``, ``kind``, ``max`` (m), ``max_relative``,
        ``alpha_at_max`` (degrees), ``exact`` (max_relative <= 1e-9).
    size : float
        Structure size (bounding-box diagonal at the design state), m.
    relaxation : dict or None
        Residuals of the least-squares relaxation at the worst state, if requested.
    """

    alphas: np.ndarray
    deviation: np.ndarray
    creases: list
    size: float
    relaxation: dict | None = None

    @property
    def max(self) -> float:
        return float(self.deviation.max()) if self.deviation.size else 0.0

    @property
    def exact(self) -> bool:
        return self.max <= EXACT_RELATIVE * self.size

    def summary(self) -> dict:
        """Plain JSON-able values."""
        worst = int(np.argmax(self.deviation.max(axis=1))) if self.deviation.size else 0
        return {
            "planarity_max": self.max,
            "planarity_max_relative": self.max / self.size,
            "planarity_alpha_at_max": float(self.alphas[worst]),
            "planarity_exact": self.exact,
            "alphas": [float(a) for a in self.alphas],
            "creases": self.creases,
            "relaxation": self.relaxation,
        }

    def rows(self) -> list:
        """Table rows ``(alpha, crease, deviation)`` for every state and crease."""
        return [
            (float(a), ci, float(d))
            for a, row in zip(self.alphas, self.deviation)
            for ci, d in enumerate(row)
        ]

    def write(self, out) -> list:
        """Write ``planarity.csv`` (every state and crease: ``alpha_deg, crease, deviation_m``)
        and ``planarity.json`` (:meth:`summary`) into the folder ``out`` (created).

        Returns the two paths.
        """
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        with open(out / "planarity.csv", "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(["alpha_deg", "crease", "deviation_m"])
            writer.writerows(self.rows())
        write_json(out / "planarity.json", self.summary())
        return [out / "planarity.csv", out / "planarity.json"]


def path_alphas(model, steps: int) -> np.ndarray:
    """``steps`` reference angles (degrees) of the path above the flat stack: ``k alpha / steps``
    for ``k = 1 .. steps`` up to the design angle ``alpha``."""
    if isinstance(steps, bool) or int(steps) != steps or steps < 1:
        raise OptionError(f"steps must be an integer >= 1, got {steps!r}")
    top = model.alpha_design
    return np.linspace(top / steps, top, int(steps))


def planarity_along_path(model, alphas=None, *, steps: int = 32, relax: bool = False):
    """Measure every crease's distance from its plane along the deployment path.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    alphas : (k,) float, optional
        Reference angles, degrees; default: ``steps`` angles from just above 0 to the design
        angle (:func:`path_alphas`).
    steps : int
    relax : bool
        Also relax the state with the largest deviation (:meth:`CCUModel.relax`) and report
        its residuals.

    Returns
    -------
    PlanarityReport

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/vault.toml")
    >>> report = planarity_along_path(model, steps=8)
    >>> report.exact, len(report.creases)
    (True, 9)
    """
    if alphas is None:
        alphas = path_alphas(model, steps)
    alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
    deviation = model.crease_planarity(alphas)
    kinds = model.crease_kinds()
    size = model.size
    creases = []
    for ci in range(len(model.mechanism.creases)):
        column = deviation[:, ci]
        worst = int(np.argmax(column))
        creases.append(
            {
                "id": ci,
                "plates": list(model.plates.crease_ids(ci)),
                "kind": kinds[ci][0],
                "max": float(column[worst]),
                "max_relative": float(column[worst]) / size,
                "alpha_at_max": float(alphas[worst]),
                "exact": bool(column[worst] <= EXACT_RELATIVE * size),
            }
        )
    report = PlanarityReport(alphas, deviation, creases, size)
    if relax and deviation.size:
        worst = int(np.argmax(deviation.max(axis=1)))
        structure, result = model.relax(float(alphas[worst]))
        report.relaxation = {
            "alpha": float(alphas[worst]),
            "kinematic_isometry": float(
                model.invariants(
                    model.mechanism.deploy(np.radians(alphas[worst : worst + 1]))
                ).isometry[0]
            ),
            "relaxed_isometry": structure.metrics["isometry"],
            "relaxed_crease_planarity": structure.metrics["crease_planarity_max"],
            **result.summary(),
        }
    return report
