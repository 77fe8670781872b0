"""Run a sweep (``ccu explore``) on the shared runner (:mod:`compas_ccu.explore.runner`).

One task per missing variant (:func:`compas_ccu.explore.evaluate_variant`, plain data in and
out) goes to a local Dask cluster, an existing one at ``scheduler`` or this process; every
result is journalled as it arrives, a window of variants stays in flight. Resuming is by variant
id: a run in an output folder that already holds results of the same sweep (same base design,
checks, FE options and compas_ccu version: the *fingerprint*) computes only the variants that
are missing. A variant that fails is a row with its error; a worker that dies is replaced by
Dask, which recomputes the tasks it held (a variant that kills workers repeatedly is recorded
as ``KilledWorker``); nothing the client has received is lost.

The names of the runner and of the cluster connection that this module held before are
re-exported here (``from compas_ccu.explore.run import local_cluster`` keeps working).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from compas_ccu.explore.cluster import (
    CONNECT_TIMEOUT,
    PROBE_SECONDS,
    WORKER_ENV,
    WORKER_TIMEOUT,
    check_runner,
    connect,
    dask_client,
    local_cluster,
    reach_scheduler,
    runner_label,
)
from compas_ccu.explore.evaluate import STAGES
from compas_ccu.explore.metrics import metric, metric_names
from compas_ccu.explore.runner import (
    CLUSTER_ERRORS,
    JOURNAL,
    POLL_SECONDS,
    TABLE,
    Session,
    Task,
    cluster_failure,
    progress_bar,
    read_manifest,
    stream,
    write_manifest,
)
from compas_ccu.explore.summary import summarise

__all__ = ["run_sweep", "SweepResult", "columns", "local_cluster", "CLUSTER_ERRORS", "WORKER_ENV"]
__all__ += ["runner_label"]
__all__ += ["connect", "dask_client", "check_runner", "read_manifest", "write_manifest"]
__all__ += ["reach_scheduler"]
__all__ += ["cluster_failure", "progress_bar"]
__all__ += ["CONNECT_TIMEOUT", "PROBE_SECONDS", "WORKER_TIMEOUT", "POLL_SECONDS"]
__all__ += ["JOURNAL", "TABLE", "MANIFEST"]

MANIFEST = "sweep.json"


@dataclass
class SweepResult:
    """What a run did.

    Attributes
    ----------
    out : Path
        Output folder.
    rows : list of dict
        One row per variant of the sweep that has a result, in sweep order.
    total : int
        Variants in the sweep.
    reused : int
        Variants finished by earlier runs (not computed again).
    computed : int
        Variants computed by this run.
    failed : int
        Rows with status "failed".
    seconds : float
        Wall time of this run's computation (first submission to last result).
    startup : float
        Time to start or connect to the cluster, s.
    workers : int
        Workers (1 in-process).
    scheduler : str
        "in-process", "local" or the scheduler address.
    interrupted : bool
        The run was stopped (Ctrl-C, SIGTERM) before all variants were computed.
    summary : dict or None
        :func:`compas_ccu.explore.summary.summarise` of a complete sweep.
    """

    out: Path
    rows: list
    total: int
    reused: int
    computed: int
    failed: int
    seconds: float
    startup: float
    workers: int
    scheduler: str
    interrupted: bool = False
    summary: dict | None = None
    files: list = field(default_factory=list)

    @property
    def throughput(self) -> float:
        """Variants computed per second in this run."""
        return self.computed / self.seconds if self.seconds > 0 else 0.0

    @property
    def complete(self) -> bool:
        return len(self.rows) == self.total


def columns(sweep) -> tuple:
    """Column order and declared types of the results table of ``sweep``."""

    metrics = metric_names(collisions=sweep.collisions, fe=sweep.fe is not None)
    head = ["variant", "index", *sweep.parameter_names, "status", "stage", "error_type", "error"]
    tail = ["seconds", *[f"t_{s}" for s in STAGES], "worker", "run"]
    declared = {name: metric(name).dtype for name in metrics}
    declared.update({k: "str" for k in ("variant", "status", "stage", "error_type", "error")})
    declared.update({k: "float" for k in tail[:-2]}, worker="str", run="int", index="int")
    return head + metrics + tail, declared


def _sweep_manifest(sweep, runs: int) -> dict:
    return {
        "format": "ccu.sweep",
        "version": 1,
        "name": sweep.name,
        "fingerprint": sweep.fingerprint,
        "base": str(sweep.base_path),
        "sampling": sweep.sampling,
        "seed": sweep.seed,
        "options": sweep.options,
        "parameters": sweep.parameter_names,
        "objectives": sweep.objectives,
        "constraints": sweep.constraints,
        "runs": runs,
        "variants": [{"variant": v.id, "index": v.index, **v.params} for v in sweep.variants],
    }


def run_sweep(
    sweep,
    out,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    client=None,
    in_process: bool = False,
    progress: bool = True,
    summary: bool = True,
    plots: bool = True,
    dashboard: bool = False,
    window: int | None = None,
) -> SweepResult:
    """Compute every missing variant of ``sweep`` and write the results into ``out``.

    Parameters
    ----------
    sweep : compas_ccu.explore.Sweep
    out : path-like
        Output folder: ``sweep.json`` (manifest), ``journal.jsonl`` (every result as it
        arrives), ``results.parquet`` (the table), and for a complete sweep the summary
        (``summary.json``, ``plots/``, ``best/``).
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``); its workers need the same
        compas_ccu version. Default: start a local cluster.
    workers : int, optional
        Worker processes of the local cluster (default: one per core, at most one per
        variant).
    client : distributed.Client, optional
        Use this client (and its cluster) instead.
    in_process : bool
        Evaluate in this process, one variant after the other, without Dask.
    progress : bool
        Show a progress bar on stderr.
    summary, plots : bool
        Write the summary (and its plots) when the sweep is complete.
    dashboard : bool
        Serve the local cluster's Dask dashboard on port 8787.
    window : int, optional
        Variants in flight on the cluster at a time (default: 8 per worker, at least 64).

    Returns
    -------
    SweepResult

    Raises
    ------
    SweepError
        The folder belongs to another sweep, the scheduler cannot be reached, or its workers
        run another compas_ccu version.
    """
    check_runner(workers, scheduler)  # before anything is written
    session = Session(
        out,
        sweep.fingerprint,
        lambda run: _sweep_manifest(sweep, run),
        name=MANIFEST,
        what="sweep",
        parts="base design, [checks], [fe] or compas_ccu version",
    )
    work = _Variants(sweep, session)
    session.progress(len(sweep.variants), len(work.kept), sweep.name, progress, unit="variant")
    where = {"client": client, "scheduler": scheduler, "workers": workers}
    try:
        timing = session.execute(
            work.drive,
            sweep.options,
            prefix=f"ccu-variant-{sweep.fingerprint}",
            todo=len(work.todo),
            window=window,
            in_process=in_process,
            dashboard=dashboard,
            **where,
        )
    finally:
        rows = [work.kept[v.id] for v in sweep.variants if v.id in work.kept]
        names, declared = columns(sweep)
        metadata = {"name": sweep.name, "fingerprint": sweep.fingerprint}
        session.close(rows, names, declared, metadata)
    result = SweepResult(
        out=session.out,
        rows=rows,
        total=len(sweep.variants),
        reused=len(sweep.variants) - len(work.todo),
        computed=work.computed,
        failed=work.failed,
        seconds=timing.seconds if work.todo else 0.0,
        startup=timing.startup,
        workers=timing.workers,
        scheduler=timing.scheduler,
        interrupted=timing.interrupted,
        files=list(session.files),
    )
    if summary and result.complete and not timing.interrupted:
        result.summary = summarise(sweep, rows, session.out, run=result, plots=plots)
        result.files += [Path(f) for f in result.summary["files"]]
    return result


class _Variants:
    """The sweep's side of a run: the variants to compute (those without a kept row: a
    cluster failure is computed again) and each result's row, journalled and counted."""

    def __init__(self, sweep, session):
        self.sweep, self.session = sweep, session
        current = {v.id for v in sweep.variants}
        self.kept = {
            vid: row
            for vid, row in session.rows.items()
            if vid in current and row.get("error_type") not in CLUSTER_ERRORS
        }
        self.todo = [v for v in sweep.variants if v.id not in self.kept]
        self.computed = 0
        self.failed = sum(r.get("status") == "failed" for r in self.kept.values())

    def drive(self, evaluator, stop) -> None:
        """Stream the missing variants through ``evaluator`` (the shared runner)."""
        tasks = (Task(v.id, self.sweep.document_for(v), v) for v in self.todo)
        stream(evaluator, tasks, self.record, stop)

    def record(self, task, row: dict) -> None:
        variant = task.item
        full = {"variant": variant.id, "index": variant.index, **variant.params, **row}
        full["run"] = self.session.run
        self.session.record(full)
        self.kept[variant.id] = full
        self.computed += 1
        self.failed += row["status"] == "failed"
        self.session.bar.set_postfix(failed=self.failed, refresh=False)
