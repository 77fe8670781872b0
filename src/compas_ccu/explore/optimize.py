"""Run an optimisation study (``ccu optimize``): Optuna proposes designs, Dask evaluates them.

The client asks the study's sampler (:mod:`compas_ccu.explore.sampler`: TPE for one objective,
NSGA-II / -III for several, or random search) for a batch of trials, one per worker thread,
and the shared runner (:mod:`compas_ccu.explore.runner`, the runner of sweeps) evaluates their
designs with :func:`compas_ccu.explore.evaluate_variant` on a local Dask cluster, an existing
one at ``scheduler``, or in this process. The cheap checks come first: with an ``[fe]`` section
the FE runs only for a design that meets the constraints on the kinematic and thickness metrics
(``fe_when``); one that misses them is told to the sampler as infeasible with its violations
(:mod:`compas_ccu.explore.feasibility`).

Every trial's row is appended to ``journal.jsonl`` (fsynced) before it is told to the sampler,
whose history is Optuna's own journal (``optuna.journal``): running the same study into the same
folder continues it; a different study (another fingerprint) is refused. Ctrl-C / SIGTERM stop
between two trials and keep everything finished. The summary, the best designs and the plots
are :mod:`compas_ccu.explore.study_summary`; the study file is :mod:`compas_ccu.explore.study`.

The names this module held before the split are re-exported here.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

from compas_ccu import __version__, limits
from compas_ccu.errors import SweepError
from compas_ccu.explore.cluster import check_runner
from compas_ccu.explore.feasibility import (
    FAILED_VIOLATION,
    STUDY_COLUMNS,
    UNMEASURED_VIOLATION,
    Assessment,
    assess,
    feasible_rows,
)
from compas_ccu.explore.run import columns
from compas_ccu.explore.runner import CLUSTER_ERRORS, JOURNAL, TABLE, Session, in_batches
from compas_ccu.explore.sampler import (
    EI_CANDIDATES,
    POPULATION,
    STORAGE,
    AskTell,
    make_sampler,
    open_storage,
    reconcile,
    sampler_seed,
)
from compas_ccu.explore.study_summary import best_value, convergence, summarise_study

__all__ = ["run_study", "StudyResult", "Assessment", "assess", "make_sampler", "table_columns"]
__all__ += ["summarise_study", "convergence", "feasible_rows", "FAILED_VIOLATION"]
__all__ += ["UNMEASURED_VIOLATION", "STUDY_COLUMNS", "EI_CANDIDATES", "POPULATION"]
__all__ += ["MANIFEST", "JOURNAL", "STORAGE", "TABLE"]

MANIFEST = "study.json"
#: What :func:`~compas_ccu.explore.runner.read_manifest` says differs in another study's folder.
PARTS = (
    "base design, [checks], [fe], parameters, objectives, constraints, sampler, seed or "
    "compas_ccu version"
)


@dataclass
class StudyResult:
    """What a run of a study did.

    Attributes
    ----------
    out : Path
    rows : list of dict
        One row per trial of the study so far (this run's and earlier ones), by trial number.
    budget : int
        Trials the study is to have.
    earlier : int
        Trials of earlier runs (not computed again).
    computed : int
        Trials this run told the sampler.
    evaluations : int
        Of these, the designs evaluated (a design proposed again reuses its row).
    gated : int
        Of these, the designs whose FE a cheap check saved.
    failed : int
        Trials (all runs) whose design could not be built or measured.
    seconds, startup : float
        Wall time of this run's trials and of the cluster start, s.
    workers : int
    scheduler : str
        "in-process", "local", "client" or the scheduler address.
    interrupted : bool
    summary : dict or None
        :func:`summarise_study`.
    """

    out: Path
    rows: list
    budget: int
    earlier: int
    computed: int
    evaluations: int
    gated: int
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
        """Trials per second in this run."""
        return self.computed / self.seconds if self.seconds > 0 else 0.0


def table_columns(study) -> tuple:
    """Column order and declared types of a study's results table: ``trial``, ``variant``,
    the parameters, the status, :data:`STUDY_COLUMNS`, the metrics, the timings, ``run``."""
    names, declared = columns(study)
    names = ["trial"] + [n for n in names if n != "index"]
    at = names.index("error") + 1
    names[at:at] = list(STUDY_COLUMNS)
    declared = {k: v for k, v in declared.items() if k != "index"}
    declared.update(STUDY_COLUMNS, trial="int")
    return names, declared


def _manifest(study, runs: int, budget: int) -> dict:
    return {
        "format": "ccu.study",
        "version": 1,
        "name": study.name,
        "fingerprint": study.fingerprint,
        "compas_ccu": __version__,
        "base": str(study.base_path),
        "sampler": study.sampler_name,
        "seed": study.seed,
        "trials": budget,
        "options": study.options,
        "parameters": study.parameter_names,
        "objectives": study.objectives,
        "constraints": study.constraints,
        "runs": runs,
    }


def run_study(
    study,
    out,
    *,
    trials: int | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    client=None,
    in_process: bool = False,
    progress: bool = True,
    summary: bool = True,
    plots: bool = True,
    dashboard: bool = False,
) -> StudyResult:
    """Run ``study`` until it has ``trials`` trials and write the results into ``out``.

    Parameters
    ----------
    study : compas_ccu.explore.study.Study
    out : path-like
        Output folder: ``study.json`` (manifest), ``journal.jsonl`` (every trial's row as it
        arrives), ``optuna.journal`` (the sampler's history), ``results.parquet``,
        ``summary.json``, ``plots/`` and ``best/``. A folder that holds this study is
        continued.
    trials : int, optional
        Trials the study is to have, this run's and earlier runs' (default ``study.trials``).
    scheduler, workers, client, in_process, dashboard
        Where the designs are evaluated, as :func:`compas_ccu.explore.run_sweep`; on Dask one
        trial per worker thread is in flight.
    progress : bool
        Progress bar on stderr.
    summary, plots : bool
        Write the summary (best designs, least-violating ones) and its plots.

    Returns
    -------
    StudyResult

    Raises
    ------
    SweepError
        The folder holds another study, or the scheduler cannot be reached.
    """
    check_runner(workers, scheduler)
    if in_process and (scheduler is not None or workers is not None):
        raise SweepError("in-process runs without Dask: no scheduler or workers")
    budget = study.trials if trials is None else trials
    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 1:
        raise SweepError(f"--trials must be an integer >= 1, got {budget!r}")
    limits.check("variants", budget, what="trials")
    import optuna

    session = Session(
        out,
        study.fingerprint,
        lambda run: _manifest(study, run, budget),
        name=MANIFEST,
        what="study",
        parts=PARTS,
        key="trial",
    )
    rows = session.rows
    earlier = len(rows)
    state = {"computed": 0, "evaluations": 0, "gated": 0}
    verbosity = optuna.logging.get_verbosity()
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    session.progress(budget, min(earlier, budget), study.name, progress, unit="trial")
    where = {"client": client, "scheduler": scheduler, "workers": workers}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            trials = _trials(study, session, budget, state)
            session.execute(
                lambda evaluator, stop: in_batches(
                    evaluator, trials.next_batch, trials.record, stop, trials.abandon
                ),
                study.options,
                prefix=f"ccu-trial-{study.fingerprint}",
                todo=trials.todo,
                batch=True,
                in_process=in_process,
                dashboard=dashboard,
                **where,
            )
    finally:
        optuna.logging.set_verbosity(verbosity)
        ordered = [rows[k] for k in sorted(rows)]
        names, declared = table_columns(study)
        metadata = {"name": study.name, "fingerprint": study.fingerprint, "kind": "study"}
        session.close(ordered, names, declared, metadata)
    timing = session.timing
    result = StudyResult(
        out=session.out,
        rows=ordered,
        budget=budget,
        earlier=earlier,
        computed=state["computed"],
        evaluations=state["evaluations"],
        gated=state["gated"],
        failed=sum(r.get("status") == "failed" for r in ordered),
        seconds=timing.seconds if state["computed"] else 0.0,
        startup=timing.startup,
        workers=timing.workers,
        scheduler=timing.scheduler,
        interrupted=timing.interrupted,
        files=[*session.files[:2], session.out / STORAGE, session.files[2]],
    )
    if summary:
        result.summary = summarise_study(study, ordered, session.out, run=result, plots=plots)
        result.files += [Path(f) for f in result.summary["files"]]
    return result


class _Trials(AskTell):
    """The study's side of a run: the sampler's ask and tell, and each finished trial's row
    (journalled, then told; counted)."""

    def __init__(self, ostudy, study, session, budget: int, state: dict):
        rows = session.rows
        cache = {
            r["variant"]: r for r in rows.values() if r.get("error_type") not in CLUSTER_ERRORS
        }
        names, _ = table_columns(study)
        super().__init__(ostudy, study, max(0, budget - len(rows)), cache, names)
        self.session, self.state = session, state

    def record(self, task, row: dict) -> None:
        """Journal the trial's row, then tell the sampler."""
        trial, variant = task.item
        reused = task.document is None
        a = assess(row, self.study)
        full = {
            "trial": trial.number,
            "variant": variant.id,
            **variant.params,
            **row,
            "feasible": a.feasible,
            "violation": a.violation,
            "violations": "; ".join(a.details) or None,
            "fe_gated": a.gated,
            "reused": reused,
            "run": self.session.run,
        }
        self.session.record(full)
        self.session.rows[trial.number] = full
        self.tell(trial, row, a)
        if row.get("stage") != "cluster":
            self.cache.setdefault(variant.id, full)
        self.state["computed"] += 1
        self.state["evaluations"] += not reused
        self.state["gated"] += a.gated and not reused
        best = best_value(self.session.rows.values(), self.study)
        if best is not None:
            self.session.bar.set_postfix_str(f"best {best:.4g}", refresh=False)


def _trials(study, session, budget: int, state: dict) -> _Trials:
    """The study's Optuna study opened (or continued) in the session's folder, reconciled
    with the journal and given its sampler, as the run's :class:`_Trials`."""
    ostudy = open_storage(study, session.out)
    reconcile(ostudy, study, session.rows)
    ostudy.sampler = make_sampler(study, sampler_seed(study.seed, len(ostudy.trials)))
    return _Trials(ostudy, study, session, budget, state)
