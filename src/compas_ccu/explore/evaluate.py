"""One variant of a sweep: build, deploy and measure a design document, never raising.

:func:`evaluate_variant` is the task a Dask worker runs. It takes plain data (the design
document and the options) and returns one row of plain Python scalars: the metrics of
:data:`compas_ccu.explore.metrics.METRICS`, the time of every stage, and for a variant that
cannot be built or checked the stage, type and message of the error instead of the missing
metrics. The same function runs in-process (``ccu explore --in-process``), so both give
identical numbers.
"""

from __future__ import annotations

import os
import socket
import time

import numpy as np

from compas_ccu.design.document import Design
from compas_ccu.explore import metrics as mx
from compas_ccu.explore.pareto import meets
from compas_ccu.model import CCUModel
from compas_ccu.thickness import ThickModel

__all__ = ["evaluate_variant", "STAGES", "row_template"]

#: Stages of an evaluation, in order; each is timed in the column ``t_<stage>`` (seconds).
STAGES = ("model", "path", "thickness", "collisions", "fe")


def row_template(*, collisions: bool = False, fe: bool = False) -> dict:
    """A row with every column of an evaluation set to None (metrics, status, timings)."""

    row = {"status": None, "stage": None, "error_type": None, "error": None}
    row.update(dict.fromkeys(mx.metric_names(collisions=collisions, fe=fe)))
    row["seconds"] = None
    row.update({f"t_{s}": None for s in STAGES})
    row["worker"] = None
    return row


def evaluate_variant(
    document: dict,
    *,
    path_states: int = 21,
    collisions: bool = False,
    fe: dict | None = None,
    fe_when: dict | None = None,
) -> dict:
    """Build, deploy and measure one design.

    Parameters
    ----------
    document : dict
        A design document (the parsed TOML of a design file).
    path_states : int
        States from the flat stack (alpha = 0) to the design at which the path metrics
        (crease planarity, bending, collisions) are measured.
    collisions : bool
        Run the collision check of the thick plates along the path.
    fe : dict, optional
        FE validation options (:class:`compas_ccu.fea.validation.FESettings` fields); None:
        no FE.
    fe_when : dict, optional
        Constraints (metric -> ``{min, max}`` or a bool, as a sweep's ``[constraints]``) on the
        metrics measured before the FE stage: the FE runs only for a design that meets them
        (:func:`compas_ccu.explore.pareto.meets`); otherwise the FE metrics and ``t_fe`` stay
        empty and the row is "ok". The cheap checks decide whether the FE time is spent.

    Returns
    -------
    dict
        ``status`` ("ok" or "failed"); for failures ``stage`` (where it failed), ``error_type``
        and ``error`` (the message, naming the cause and the value); every metric (None where
        not reached); ``seconds`` and ``t_<stage>`` timings; ``worker`` (host:pid).

    Examples
    --------
    >>> from compas_ccu.design import load_design
    >>> doc = load_design("examples/cone.toml").document
    >>> row = evaluate_variant(doc, path_states=5)
    >>> row["status"], row["plates"], round(row["span"], 6)
    ('ok', 2, 2.619468)
    >>> doc["deployment"]["alpha"] = 89.5  # the cut pattern unfolds at most to 89.06 deg
    >>> bad = evaluate_variant(doc)
    >>> bad["status"], bad["stage"], bad["error_type"]
    ('failed', 'model', 'DeploymentLimitError')
    >>> doc["deployment"]["alpha"] = 40.0  # FE only for designs of at most 1 plate: none here
    >>> gated = evaluate_variant(doc, path_states=5, fe={}, fe_when={"plates": {"max": 1}})
    >>> gated["status"], gated["t_fe"], gated["fe_buckling_factor"]
    ('ok', None, None)
    """

    row = row_template(collisions=collisions, fe=fe is not None)
    row["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    start = time.perf_counter()
    stage = "model"
    try:
        t = time.perf_counter()
        model = CCUModel(Design(document))
        structure = model.deploy()
        row.update(mx.shape_metrics(model, structure))
        row["t_model"] = time.perf_counter() - t

        stage = "path"
        t = time.perf_counter()
        alphas = np.linspace(0.0, model.alpha_design, path_states)
        row.update(mx.path_metrics(model, alphas))
        row["t_path"] = time.perf_counter() - t

        stage = "thickness"
        t = time.perf_counter()

        thick = ThickModel(model)
        row.update(mx.thickness_metrics(thick, alphas))
        row["t_thickness"] = time.perf_counter() - t

        if collisions:
            stage = "collisions"
            t = time.perf_counter()
            row.update(mx.collision_metrics(thick, alphas))
            row["t_collisions"] = time.perf_counter() - t

        if fe is not None and (fe_when is None or meets(row, fe_when)):
            stage = "fe"
            t = time.perf_counter()
            row.update(mx.fe_metrics(model, thick, fe))
            row["t_fe"] = time.perf_counter() - t
        row["status"] = "ok"
    except Exception as exc:  # a bad variant is a result, never the end of the sweep
        row.update(status="failed", stage=stage, error_type=type(exc).__name__, error=str(exc))
    row["seconds"] = time.perf_counter() - start
    return row
