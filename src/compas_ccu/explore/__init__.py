"""Design-space exploration: sweeps of design variants on Dask (``ccu explore``).

A sweep file names a base design and the parameters to vary (:mod:`.sweep`, with the parts it
shares with study files in :mod:`.parsing`); every variant is built, deployed and measured
(:mod:`.evaluate`, :mod:`.metrics`) on a Dask cluster (:mod:`.run`); the results go to a Parquet
table (:mod:`.results`) and a summary with the Pareto front and the best variants
(:mod:`.pareto`, :mod:`.summary`, :mod:`.plots`). See docs/explore.md.

An optimisation study (``ccu optimize``, docs/optimize.md) searches the parameters of a base
design with Optuna under constraints: the study file (:mod:`.study`), the feasibility of a
design (:mod:`.feasibility`), Optuna's ask and tell (:mod:`.sampler`), the run
(:mod:`.optimize`) and its outputs (:mod:`.study_summary`).

Sweeps and studies run on one runner (:mod:`.runner`: the output folder's manifest and journal,
in-process or Dask evaluation, streams and batches, Ctrl-C) and one cluster connection
(:mod:`.cluster`: a local cluster or ``--scheduler``). Dask, pyarrow and Optuna are imported
only when a sweep or a study runs (the ``explore`` extra).
"""

from __future__ import annotations

from compas_ccu.explore.evaluate import evaluate_variant
from compas_ccu.explore.metrics import METRICS, metric_names
from compas_ccu.explore.optimize import StudyResult, run_study
from compas_ccu.explore.pareto import pareto_mask
from compas_ccu.explore.run import SweepResult, run_sweep
from compas_ccu.explore.study import Study, load_study
from compas_ccu.explore.sweep import Sweep, Variant, load_sweep

__all__ = [
    "Sweep",
    "Variant",
    "load_sweep",
    "run_sweep",
    "SweepResult",
    "evaluate_variant",
    "METRICS",
    "metric_names",
    "pareto_mask",
    "Study",
    "load_study",
    "run_study",
    "StudyResult",
]
