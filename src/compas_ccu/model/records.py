"""Placed states as :class:`~compas_ccu.structure.Structure` objects: the crease records and the
metrics of the ``ccu.structure`` contract (docs/structure-json.md).

A redeploy (an interactive slider, a path) often reads only the plate vertices, so the records
are lazy: :class:`StateRecords` holds the placed states of one call and computes, on the first
read of any of its structures' ``creases`` or ``metrics``, the invariants of every state at once
(:meth:`CCUModel.invariants`) and the crease relations of every crease of every state in a few
vectorised calls (:meth:`CCUModel.all_relations`, in chunks of states). Every value is the same as
that of a crease, a state, computed alone.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.geometry import edge_fold_angles
from compas_ccu.kinematics.invariants import INVARIANT_KEYS, InvariantErrors
from compas_ccu.strips.rulings import vertex_reflection_angles
from compas_ccu.structure import Structure
from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = ["StateRecords", "state_structure", "path_structures", "leading_span"]

#: Crease vertices per batch of the crease relations: bounds the temporaries (~20 arrays of
#: this many 3-vectors) of a long path while amortising NumPy's per-call overhead.
RELATION_CHUNK = 65_536


def _bounding_box(deployed: np.ndarray) -> list:
    # np.ptp(points, axis=0) of the (N, 3) points, by rows x, y, z: a reduction along a short
    # inner axis is ~15 times slower than along a long one, and max / min are exact either way
    xyz = np.ascontiguousarray(deployed.reshape(-1, 3).T)
    return (np.maximum.reduce(xyz, axis=1) - np.minimum.reduce(xyz, axis=1)).tolist()


def leading_span(states, k: int) -> float:
    """The ``span`` of the metrics of state ``k`` of placed mechanism ``states``: the distance
    in plan (local x-y) between the ends of the leading crease, m.

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> round(leading_span(model.mechanism.deploy(np.radians([40.0])), 0), 6)
    2.619468
    """
    lead_near = states.near[k, 0]
    return float(np.linalg.norm(lead_near[-1, :2] - lead_near[0, :2]))


class StateRecords:
    """The crease records and metrics of ``k`` placed states, computed on first use.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    states : compas_ccu.kinematics.mechanism.MechanismStates
    invariants : dict, optional
        :meth:`CCUModel.invariants` of ``states`` (computed on first use if not given).

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> records = StateRecords(model, model.mechanism.deploy(np.radians([20.0, 40.0])))
    >>> records.fold_angles(0, 0).shape, records.fold_angles(1, 0).round(4)[:2].tolist()
    ((48,), [80.0129, 80.0129])
    >>> round(records.metrics(1)["span"], 6), bool(records.metrics(1)["isometry"] < 1e-12)
    (2.619468, True)
    """

    def __init__(self, model, states, invariants: dict | None = None):
        self.model = model
        self.states = states
        self._invariants = invariants
        self._alpha = None  # (k, c, n + 1) reflection angles at the crease vertices, degrees
        self._sum_beta = None  # (k, c, n - 1) sector-angle sums at the inner vertices, degrees

    @property
    def invariants(self) -> InvariantErrors:
        if self._invariants is None:
            self._invariants = self.model.invariants(self.states)
        return self._invariants

    def _relations(self) -> None:
        """The two per-vertex fields of the records, for every crease of every state."""
        if self._alpha is not None:
            return
        model, states = self.model, self.states
        k = states.near.shape[0]
        c = len(model.mechanism.creases)
        m = model.segments + 1
        alpha = np.empty((k, c, m))
        sum_beta = np.empty((k, c, max(m - 2, 0)))
        step = max(1, RELATION_CHUNK // max(c * m, 1))
        for lo in range(0, k if c else 0, step):
            rel = model.all_relations(states, slice(lo, lo + step))
            alpha[lo : lo + step] = np.degrees(rel.alpha)
            sum_beta[lo : lo + step] = np.degrees(rel.sum_beta[..., 1:-1])
        self._alpha, self._sum_beta = alpha, sum_beta

    def fold_angles(self, k: int, crease: int) -> np.ndarray:
        """(n,) the angle between the two plates across every edge of ``crease`` in state
        ``k``, degrees (:func:`compas_ccu.geometry.edge_fold_angles`): the fold a builder
        sets, twice the reflection angle of the edge."""
        plates, states = self.model.plates, self.states
        row, side_a = plates.crease_boundary(crease, states.near[k], states.far[k])
        b = plates.crease_plates[crease][1]
        return edge_fold_angles(row, side_a, states.far[k, b])

    def creases(self, k: int) -> list:
        """The crease records of state ``k`` (docs/structure-json.md)."""
        model, states = self.model, self.states
        self._relations()
        kinds = model.crease_kinds()
        planarity = self.invariants.crease_planarity
        creases = []
        for ci in range(len(model.mechanism.creases)):
            rows_a, rows_b = model.plates.crease_rows(ci)
            kind, vertex_kinds, _ = kinds[ci]
            fold = self.fold_angles(k, ci)
            origin = model.frame.to_world(states.plane_origins[k, ci])
            normal = model.frame.vector_to_world(states.plane_normals[k, ci])
            record = {
                "id": ci,
                "plates": list(model.plates.crease_ids(ci)),
                "vertices": [rows_a.tolist(), rows_b.tolist()],
                "kind": kind,
                "plane": {"origin": origin.tolist(), "normal": normal.tolist()},
                "planarity": float(planarity[k, ci]),
                "alpha": self._alpha[k, ci].tolist(),
                "fold_angles": fold.tolist(),
                "fold_alpha": (0.5 * fold).tolist(),
                "sum_beta": self._sum_beta[k, ci].tolist(),
            }
            if kind == "mixed":
                record["vertex_kinds"] = vertex_kinds
            creases.append(record)
        return creases

    def metrics(self, k: int, bounding_box: list | None = None) -> dict:
        """The metrics of state ``k`` (``bounding_box``: of its world vertices, if at hand)."""
        model, states = self.model, self.states
        invariants = self.invariants
        if bounding_box is None:
            bounding_box = _bounding_box(model.state_vertices(states, k))
        lead_near, lead_far = states.near[k, 0], states.far[k, 0]
        chord = lead_near[-1, :2] - lead_near[0, :2]
        span = leading_span(states, k)
        normal2d = np.array([-chord[1], chord[0]]) / max(span, DIVISION_FLOOR)
        rise = float(np.abs((lead_near[:, :2] - lead_near[0, :2]) @ normal2d).max())
        rulings = lead_far - lead_near
        metrics = {
            "alpha_limit": model.alpha_limit,
            "reference_vertex": model.reference,
            "segments": model.segments,
            "span": span,
            "rise": rise,
            "bounding_box": bounding_box,
            "size": model.size,
            "alpha_leading": np.degrees(
                vertex_reflection_angles(
                    lead_near[:, :2], rulings / np.linalg.norm(rulings, axis=1)[:, None]
                )
            ).tolist(),
        }
        for key in INVARIANT_KEYS:
            metrics[key] = float(getattr(invariants, key)[k])
            metrics[key + "_relative"] = metrics[key] / model.size
        cp = invariants.crease_planarity[k]
        metrics["crease_planarity_max"] = float(cp.max()) if cp.size else 0.0
        metrics["crease_planarity_max_relative"] = metrics["crease_planarity_max"] / model.size
        return metrics

    def structure(self, k: int, alpha: float) -> Structure:
        """The :class:`Structure` of state ``k`` at reference angle ``alpha`` (degrees), its
        crease records and metrics computed when first read."""
        model = self.model
        deployed = model.state_vertices(self.states, k)
        box = _bounding_box(deployed)  # now: the caller may move the vertices before reading
        return Structure(
            alpha,
            model.faces,
            model.flat(),
            deployed,
            lambda: self.creases(k),
            lambda: self.metrics(k, box),
            model.plate_ids,
            name=model.design.name,
        )


def state_structure(
    model, states, k: int, alpha: float, invariants: dict | None = None
) -> Structure:
    """The :class:`Structure` of state ``k`` of placed mechanism ``states``.

    Parameters
    ----------
    states : compas_ccu.kinematics.mechanism.MechanismStates
    k : int
    alpha : float
        The state's reference reflection angle, degrees.
    invariants : dict, optional
        :meth:`invariants` of ``states`` (computed when first needed if not given).

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> structure = state_structure(model, model.mechanism.deploy(np.radians([20.0])), 0, 20.0)
    >>> structure
    Structure(alpha=20 deg, plates=2, creases=1)
    >>> structure.deployed.shape, round(structure.metrics["span"], 6)
    ((2, 98, 3), 2.788401)
    """
    return StateRecords(model, states, invariants).structure(k, alpha)


def path_structures(model, states, alphas, invariants: dict | None = None) -> list:
    """The :class:`Structure` of every state of ``states`` at reference angles ``alphas``
    (degrees), sharing one :class:`StateRecords`: reading any structure's records computes
    those of all states in one go.

    Examples
    --------
    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> states = model.mechanism.deploy(np.radians([20.0, 40.0]))
    >>> [(s.alpha, round(s.metrics["span"], 6)) for s in path_structures(model, states, [20, 40])]
    [(20.0, 2.788401), (40.0, 2.619468)]
    """
    records = StateRecords(model, states, invariants)
    return [records.structure(k, float(a)) for k, a in enumerate(alphas)]
