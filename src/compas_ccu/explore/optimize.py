"""Run an optimisation study (``ccu optimize``): Optuna proposes designs, Dask evaluates them.

The client asks Optuna's sampler (:func:`make_sampler`: TPE for one objective, NSGA-II / -III
for several, or random search) for a trial, evaluates its design with
:func:`compas_ccu.explore.evaluate_variant` (the task of a sweep: on a local Dask cluster, an
existing one at ``scheduler``, or in this process), keeps up to one trial per worker in flight
and asks for the next as each finishes. The cheap checks come first: with an ``[fe]`` section
the FE runs only for a design that meets the constraints on the kinematic and thickness metrics
(``fe_when``); one that misses them is told to the sampler as infeasible with its violations.

Every trial's row is appended to ``journal.jsonl`` (fsynced) before it is told to the sampler,
whose history is Optuna's own journal (``optuna.journal``, a ``JournalFileBackend``): running
the same study into the same folder continues it; a different study (another fingerprint) is
refused. Ctrl-C / SIGTERM stop between two trials and keep everything finished.

Constraints are told to the sampler as Optuna constraint values (``Trial.set_constraint``, <= 0
feasible): the relative violations of :func:`compas_ccu.explore.pareto.violations`. A design
that cannot be built or measured is infeasible by :data:`FAILED_VIOLATION`; a constraint or an
objective that was not measured (not because a cheap check stopped the FE) by
:data:`UNMEASURED_VIOLATION`. TPE ranks infeasible trials by their total violation
(feasibility-aware TPE) and NSGA-II by constrained domination, so the violations steer the
search towards feasible designs.
"""

from __future__ import annotations

import asyncio
import math
import shutil
import time
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from compas_ccu import __version__, limits
from compas_ccu.errors import SweepError
from compas_ccu.explore.evaluate import evaluate_variant
from compas_ccu.explore.metrics import metric_group
from compas_ccu.explore.pareto import rank_best, violations
from compas_ccu.explore.plots import plot_convergence, plot_design_space, plot_pareto
from compas_ccu.explore.results import Journal, write_table
from compas_ccu.explore.run import (
    CLUSTER_ERRORS,
    POLL_SECONDS,
    check_runner,
    cluster_failure,
    columns,
    dask_client,
    progress_bar,
    read_manifest,
    write_manifest,
)
from compas_ccu.explore.stop import StopRequest
from compas_ccu.explore.summary import counts, stage_seconds, write_best
from compas_ccu.outputs import write_json
from compas_ccu.viz.export import save_figure

__all__ = ["run_study", "StudyResult", "Assessment", "assess", "make_sampler", "table_columns"]
__all__ += ["summarise_study", "convergence", "feasible_rows", "FAILED_VIOLATION"]
__all__ += ["UNMEASURED_VIOLATION"]

MANIFEST = "study.json"
JOURNAL = "journal.jsonl"
STORAGE = "optuna.journal"
TABLE = "results.parquet"
#: Violation of a design that could not be built or measured (its row's error says why).
FAILED_VIOLATION = 1000.0
#: Violation of a constraint or objective that the evaluation did not measure.
UNMEASURED_VIOLATION = 1.0
#: Default NSGA-II / -III population (Optuna's is 50: too many for studies of ~100 trials).
POPULATION = 20
#: TPE: candidates drawn from the good designs' density per proposal, the best by expected
#: improvement is proposed (Optuna's default 24). A design costs 0.1 s to minutes, a candidate
#: microseconds: on examples/optimize/vault-sheets.toml, 128 reached the 1875-design grid's
#: best in 25-96 trials (3 seeds), 24 in 109-317 (docs/optimize.md).
EI_CANDIDATES = 128
#: The columns a study adds to those of a sweep, with their types.
STUDY_COLUMNS = {
    "feasible": "bool",
    "violation": "float",
    "violations": "str",
    "fe_gated": "bool",
    "reused": "bool",
}


# -- feasibility -----------------------------------------------------------------------------
@dataclass(frozen=True)
class Assessment:
    """How a trial's row stands against the study's constraints and objectives.

    Attributes
    ----------
    feasible : bool
        Evaluated, every constraint measured and met, every objective measured.
    violation : float
        Sum of the positive violations (0 for a feasible design): the order of the
        least-violating designs.
    details : tuple of str
        One text per missed constraint (``"bending_utilisation 1.12 > max 1"``), missing
        measurement or error.
    constraints : dict
        Name -> value told to the sampler (<= 0 met); the same keys for every trial.
    gated : bool
        A cheap constraint failed, so the FE stage did not run.
    values : tuple of float
        The objective values told to the sampler (+-inf where not measured).
    """

    feasible: bool
    violation: float
    details: tuple
    constraints: dict
    gated: bool
    values: tuple


def _missed(name: str, value, rule) -> str:
    """``"bending_utilisation 1.12 > max 1"``: 4 significant digits, more when they would
    show the value equal to its bound (1.00004 > max 1)."""
    if isinstance(rule, bool):
        return f"{name} is {value} (required {rule})"
    side, bound = (">", rule["max"]) if "max" in rule and value > rule["max"] else ("<", None)
    if bound is None:
        bound = rule["min"]
    digits = next((d for d in (4, 6, 9) if f"{value:.{d}g}" != f"{bound:.{d}g}"), 12)
    kind = "max" if side == ">" else "min"
    return f"{name} {value:.{digits}g} {side} {kind} {bound:.4g}"


def _measured(value) -> bool:
    return value is not None and not (isinstance(value, float) and not math.isfinite(value))


def assess(row: dict, study) -> Assessment:
    """Feasibility, violations and the sampler's values of one evaluated trial.

    Examples
    --------
    >>> from compas_ccu.explore.study import Study
    >>> study = Study({"study": {"base": "vault.toml"},
    ...                "parameters": {"crease.rise": {"min": 0.6, "max": 1.4}},
    ...                "objectives": {"mass": "min"}}, base_dir="examples")
    >>> a = assess({"status": "ok", "mass": 30.0, "bending_utilisation": 1.25}, study)
    >>> a.feasible, a.violation, a.details, a.values
    (False, 0.25, ('bending_utilisation 1.25 > max 1',), (30.0,))
    >>> assess({"status": "ok", "mass": 30.0, "bending_utilisation": 1.00004}, study).details
    ('bending_utilisation 1.00004 > max 1',)
    """
    senses = list(study.objectives.values())
    names = list(study.constraints)
    if row.get("status") != "ok":
        stage = row.get("stage")
        text = f"failed at stage {stage}: {row.get('error_type')}: {row.get('error')}"
        constraints = dict.fromkeys(names, 0.0)
        constraints.update(dict.fromkeys((f"objective {k}" for k in study.objectives), 0.0))
        constraints["evaluation"] = FAILED_VIOLATION
        worst = tuple(math.inf if s == "min" else -math.inf for s in senses)
        return Assessment(False, FAILED_VIOLATION, (text,), constraints, False, worst)

    gated = study.fe is not None and row.get("t_fe") is None
    details, constraints = [], {}
    for name, v in violations(row, study.constraints).items():
        if v is None and gated and metric_group(name) == "fe":
            constraints[name] = 0.0  # not measured because a cheap check failed: counted there
        elif v is None:
            constraints[name] = UNMEASURED_VIOLATION
            details.append(f"{name} not measured")
        else:
            constraints[name] = v
            if v > 0:
                details.append(_missed(name, row[name], study.constraints[name]))
    values = []
    for name, sense in study.objectives.items():
        value = row.get(name)
        if _measured(value):
            values.append(float(value))
            continue
        values.append(math.inf if sense == "min" else -math.inf)
        if not gated:
            constraints[f"objective {name}"] = UNMEASURED_VIOLATION
            details.append(f"objective {name} not measured")
    if gated:
        details.append("no FE: a cheap check failed")
    constraints["evaluation"] = 0.0
    for name in study.objectives:  # the same keys for every trial
        constraints.setdefault(f"objective {name}", 0.0)
    total = float(sum(v for v in constraints.values() if v > 0))
    ok = total == 0.0 and not gated
    return Assessment(ok, total, tuple(details), constraints, gated, tuple(values))


# -- the sampler -------------------------------------------------------------------------------
def make_sampler(study, seed: int):
    """The Optuna sampler of ``study`` (:attr:`~compas_ccu.explore.study.Study.sampler_name`):
    ``tpe`` (multivariate, :data:`EI_CANDIDATES` candidates per proposal, constant liar for
    parallel trials, ``startup`` random trials first), ``nsga2`` / ``nsga3`` (population
    ``study.population``, default :data:`POPULATION`) or ``random``."""
    import optuna

    name = study.sampler_name
    population = study.population or POPULATION
    if name == "tpe":
        return optuna.samplers.TPESampler(
            seed=seed,
            n_startup_trials=study.startup,
            n_ei_candidates=EI_CANDIDATES,
            multivariate=True,
            constant_liar=True,
        )
    if name == "nsga2":
        return optuna.samplers.NSGAIISampler(seed=seed, population_size=population)
    if name == "nsga3":
        return optuna.samplers.NSGAIIISampler(seed=seed, population_size=population)
    return optuna.samplers.RandomSampler(seed=seed)


def _sampler_seed(seed: int, told: int) -> int:
    """The sampler's seed after ``told`` trials: a resumed study does not replay the random
    proposals of its first run."""
    if told == 0:
        return seed
    return int(np.random.SeedSequence([seed, told]).generate_state(1)[0])


def _open_storage(study, out: Path):
    """The study's Optuna study in ``out/optuna.journal`` (created or continued)."""
    import optuna
    from optuna.storages import JournalStorage
    from optuna.storages.journal import JournalFileBackend

    storage = JournalStorage(JournalFileBackend(str(out / STORAGE)))
    directions = ["minimize" if s == "min" else "maximize" for s in study.objectives.values()]
    return optuna.create_study(
        storage=storage,
        sampler=optuna.samplers.RandomSampler(seed=study.seed),  # replaced once counted
        study_name=f"ccu-{study.fingerprint}",
        directions=directions,
        load_if_exists=True,
    )


def _reconcile(ostudy, study, rows: dict) -> None:
    """Bring the sampler's history in line with the journal after an interruption: trials
    left running are failed; a trial whose row was journalled but not told is added (with
    the user attribute ``trial``: the journal's number)."""
    import optuna
    from optuna.trial import TrialState

    complete = set()
    for t in ostudy.get_trials(deepcopy=False):
        if t.state == TrialState.RUNNING:
            ostudy.tell(t.number, state=TrialState.FAIL)
        elif t.state == TrialState.COMPLETE:
            complete.add(t.user_attrs.get("trial", t.number))
    distributions = study.distributions()
    for number, row in rows.items():
        if number in complete or row.get("stage") == "cluster":
            continue
        a = assess(row, study)
        params = {}
        for p in study.parameters:  # a range's value rounded to 12 digits stays in its range
            d, value = distributions[p.name], row[p.name]
            params[p.name] = value if not p.is_range else min(max(value, d.low), d.high)
        ostudy.add_trial(
            optuna.trial.create_trial(
                params=params,
                distributions=distributions,
                values=list(a.values),
                constraints=a.constraints,
                user_attrs={"trial": number},
            )
        )


# -- the run -----------------------------------------------------------------------------------
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


class _InProcess:
    """Evaluate each design when it is submitted, in this process."""

    window = 1

    def __init__(self, options: dict):
        self.options = options
        self.done = []

    def submit(self, key, document) -> None:
        self.done.append((key, evaluate_variant(document, **self.options)))

    def collect(self) -> list:
        done, self.done = self.done, []
        return done

    def cancel(self, key) -> None:  # nothing runs between two calls
        pass


class _OnDask:
    """Evaluate designs on a Dask cluster; :meth:`collect` returns those that finished."""

    def __init__(self, client, options: dict, fingerprint: str, window: int):
        from distributed import as_completed

        self.client, self.options, self.fingerprint = client, options, fingerprint
        self.window = window
        self.futures = {}
        self.flow = as_completed()

    def submit(self, key, document) -> None:
        future = self.client.submit(
            evaluate_variant,
            document,
            key=f"ccu-trial-{self.fingerprint}-{key}",
            pure=False,
            **self.options,
        )
        self.futures[future] = key
        self.flow.add(future)

    def collect(self) -> list:
        batch = self.flow.next_batch(block=False)
        if not batch:
            time.sleep(POLL_SECONDS)
            return []
        out = []
        for future in batch:
            key = self.futures.pop(future)
            try:  # evaluate_variant never raises: an error here is the cluster's
                row = future.result()
            except (Exception, asyncio.CancelledError) as exc:  # CancelledError: Base
                row = cluster_failure(exc, self.options)
            future.release()
            out.append((key, row))
        return out

    def cancel(self, key) -> None:
        for future, k in list(self.futures.items()):
            if k == key:
                future.cancel()
                del self.futures[future]


@contextmanager
def _runner(study, todo: int, *, in_process, client, scheduler, workers, dashboard):
    """``(runner, label, worker count)``: in this process, or on Dask with one trial per
    worker thread in flight."""
    if in_process or not todo:
        yield _InProcess(study.options), "in-process", 1
        return
    cluster = dask_client(
        client, scheduler=scheduler, workers=workers, todo=todo, dashboard=dashboard
    )
    with cluster as (use, label, count):
        workers = use.scheduler_info().get("workers", {}).values()
        threads = sum(w.get("nthreads", 1) for w in workers)
        yield _OnDask(use, study.options, study.fingerprint, max(1, threads, count)), label, count


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

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    manifest = read_manifest(
        out,
        study.fingerprint,
        name=MANIFEST,
        what="study",
        parts="base design, [checks], [fe], parameters, objectives, constraints, sampler, seed "
        "or compas_ccu version",
    )
    run = int(manifest.get("runs", 0)) + 1
    write_manifest(out, _manifest(study, run, budget), MANIFEST)
    journal = Journal(out / JOURNAL, key="trial")
    rows = journal.read()
    earlier = len(rows)
    names, declared = table_columns(study)
    distributions = study.distributions()
    cache = {r["variant"]: r for r in rows.values() if r.get("error_type") not in CLUSTER_ERRORS}
    state = {"computed": 0, "evaluations": 0, "gated": 0}
    verbosity = optuna.logging.get_verbosity()
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    bar = progress_bar(budget, min(earlier, budget), study.name, progress, unit="trial")

    def finish(trial, variant, row, reused):
        """Journal the trial's row, then tell the sampler."""
        a = assess(row, study)
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
            "run": run,
        }
        journal.append(full)
        rows[trial.number] = full
        if row.get("stage") == "cluster":
            ostudy.tell(trial, state=optuna.trial.TrialState.FAIL)
        else:
            for key, value in a.constraints.items():
                trial.set_constraint(key, value)
            ostudy.tell(trial, list(a.values))
            cache.setdefault(variant.id, full)
        state["computed"] += 1
        state["evaluations"] += not reused
        state["gated"] += a.gated and not reused
        bar.update(1)
        best = _best_value(rows.values(), study)
        if best is not None:
            bar.set_postfix_str(f"best {best:.4g}", refresh=False)

    interrupted = False
    label, count, startup, end = "in-process", 1, 0.0, None
    stop = StopRequest()
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            ostudy = _open_storage(study, out)
            _reconcile(ostudy, study, rows)
            ostudy.sampler = make_sampler(study, _sampler_seed(study.seed, len(ostudy.trials)))
            todo = max(0, budget - len(rows))
            where = {"client": client, "scheduler": scheduler, "workers": workers}
            evaluations = _runner(study, todo, in_process=in_process, dashboard=dashboard, **where)
            with evaluations as (runner, label, count):
                startup = time.perf_counter() - t0 if label != "in-process" else 0.0
                t0 = time.perf_counter()
                with stop:
                    _trials(ostudy, study, runner, todo, distributions, cache, names, finish, stop)
                end = time.perf_counter()
    except KeyboardInterrupt:  # a second Ctrl-C, or one while the cluster starts
        interrupted = True
    finally:
        interrupted = interrupted or stop.requested
        seconds = (end or time.perf_counter()) - t0
        bar.close()
        optuna.logging.set_verbosity(verbosity)
        ordered = [rows[k] for k in sorted(rows)]
        table = write_table(
            ordered,
            names,
            out / TABLE,
            declared=declared,
            metadata={"name": study.name, "fingerprint": study.fingerprint, "kind": "study"},
        )
    result = StudyResult(
        out=out,
        rows=ordered,
        budget=budget,
        earlier=earlier,
        computed=state["computed"],
        evaluations=state["evaluations"],
        gated=state["gated"],
        failed=sum(r.get("status") == "failed" for r in ordered),
        seconds=seconds if state["computed"] else 0.0,
        startup=startup,
        workers=count,
        scheduler=label,
        interrupted=interrupted,
        files=[out / MANIFEST, out / JOURNAL, out / STORAGE, table],
    )
    if summary:
        result.summary = summarise_study(study, ordered, out, run=result, plots=plots)
        result.files += [Path(f) for f in result.summary["files"]]
    return result


def _trials(ostudy, study, runner, todo, distributions, cache, names, finish, stop) -> None:
    """Ask for trials in batches of ``runner.window`` and evaluate them, until ``todo`` trials
    are told or a stop is requested; trials still in flight then are failed.

    A batch is told to the sampler only when all of it has finished, in trial order: the
    sampler sees the same history whatever order the workers finish in, so the same study,
    seed and window (the worker threads) give the same trials on any machine and load.
    """
    import optuna

    asked, in_flight = 0, {}
    try:
        while asked < todo and not stop.requested:
            batch = []
            while len(batch) < runner.window and asked < todo:
                trial = ostudy.ask(distributions)
                asked += 1
                variant = study.variant(study.settings_of(trial.params), trial.number)
                batch.append((trial, variant))
                if variant.id not in cache:
                    runner.submit(trial.number, study.document_for(variant))
                    in_flight[trial.number] = (trial, variant)
            done = {}
            while True:  # what has finished is kept, a stop or not
                done.update(runner.collect())
                if len(done) >= len(in_flight) or stop.requested:
                    break
            for trial, variant in batch:  # in trial order
                if trial.number in done:
                    del in_flight[trial.number]
                    finish(trial, variant, done[trial.number], False)
                elif variant.id in cache:  # proposed again: the same numbers, no evaluation
                    finish(trial, variant, _evaluation(cache[variant.id], names, study), True)
    finally:
        for number, (trial, _) in in_flight.items():  # never finished: forgotten
            runner.cancel(number)
            ostudy.tell(trial, state=optuna.trial.TrialState.FAIL)


def _evaluation(row: dict, names: list, study) -> dict:
    """The evaluation columns of a journalled row (to reuse for the same design)."""
    skip = {"trial", "variant", "run", *STUDY_COLUMNS, *study.parameter_names}
    return {k: row.get(k) for k in names if k not in skip}


# -- the summary -------------------------------------------------------------------------------
def _best_value(rows, study):
    """The best feasible value of the first objective so far (None: none feasible)."""
    name, sense = next(iter(study.objectives.items()))
    values = [r[name] for r in rows if r.get("feasible")]
    if not values:
        return None
    return min(values) if sense == "min" else max(values)


def _distinct(rows: list) -> list:
    """Indices of the first row of every design (a design proposed again is not ranked twice)."""
    seen, out = set(), []
    for i, r in enumerate(rows):
        if r["variant"] not in seen:
            seen.add(r["variant"])
            out.append(i)
    return out


def _best(study, rows: list) -> tuple:
    """(front mask, [(row index, score)]): one objective: the feasible designs by value;
    several: the Pareto front of the feasible designs, closest to the ideal point first."""
    idx = _distinct(rows)
    sub = [rows[i] for i in idx]
    good = np.array([bool(r.get("feasible")) for r in sub], dtype=bool)
    front = np.zeros(len(rows), dtype=bool)
    if len(study.objectives) == 1:
        name, sense = next(iter(study.objectives.items()))
        ranked = sorted(
            (j for j in range(len(sub)) if good[j]),
            key=lambda j: sub[j][name] if sense == "min" else -sub[j][name],
        )
        if ranked:
            front[[idx[j] for j in ranked if sub[j][name] == sub[ranked[0]][name]]] = True
        return front, [(idx[j], float(sub[j][name])) for j in ranked[: study.best]]
    # feasibility as the assessment decided it (constraints, objectives measured)
    sub_front, best = rank_best(sub, study.objectives, {"feasible": True}, study.best)
    front[[idx[j] for j in np.flatnonzero(sub_front)]] = True
    return front, [(idx[j], d) for j, d in best]


def convergence(rows: list, study) -> list:
    """The best feasible value of the first objective after every trial (None before the
    first feasible one), in trial order."""
    out, best = [], None
    name, sense = next(iter(study.objectives.items()))
    for r in rows:
        if r.get("feasible"):
            v = r[name]
            if best is None or (v < best if sense == "min" else v > best):
                best = v
        out.append(best)
    return out


def _trial_entry(study, row: dict) -> dict:
    return {
        "trial": row["trial"],
        "variant": row["variant"],
        "parameters": {k: row.get(k) for k in study.parameter_names},
        "objectives": {k: row.get(k) for k in study.objectives},
        "constraints": {k: row.get(k) for k in study.constraints},
    }


def summarise_study(study, rows: list, out, *, run=None, plots: bool = True) -> dict:
    """Write ``summary.json``, the best designs' files and the plots of a study.

    Parameters
    ----------
    study : compas_ccu.explore.study.Study
    rows : list of dict
        The results table's rows, by trial.
    out : path-like
    run : StudyResult, optional
        Adds the run's counts and timing.
    plots : bool
        Write ``plots/convergence.png``, ``plots/design_space.png`` and, for several
        objectives, ``plots/pareto.png`` (needs matplotlib).

    Returns
    -------
    dict
        What ``summary.json`` holds, plus ``files``. With no feasible design, ``best`` is
        empty and ``least_violating`` lists the designs closest to feasible (smallest total
        violation) with what they miss.
    """
    out = Path(out)
    ok = [r for r in rows if r.get("status") == "ok"]
    failed = [r for r in rows if r.get("status") != "ok"]
    good = np.array([bool(r.get("feasible")) for r in rows], dtype=bool)
    front, best = _best(study, rows)
    if (out / "best").is_dir():  # the picks of an earlier summary
        shutil.rmtree(out / "best")
    picks = [(rank + 1, study.variant_of_row(rows[i])) for rank, (i, _) in enumerate(best)]
    files = write_best(
        study,
        picks,
        out,
        origin=lambda rank, v: f"trial {v.index} of study {study.name!r} (rank {rank})",
    )
    history = convergence(rows, study)
    reached = None
    if history and history[-1] is not None:
        reached = next(k + 1 for k, v in enumerate(history) if v == history[-1])
    least = []
    if not good.any():
        order = sorted(_distinct(rows), key=lambda i: (rows[i]["violation"], rows[i]["trial"]))
        least = [
            {**_trial_entry(study, rows[i]), "violation": rows[i]["violation"],
             "violations": rows[i]["violations"]}
            for i in order[:5]
        ]  # fmt: skip
    summary = {
        "format": "ccu.study-summary",
        "version": 1,
        "name": study.name,
        "sampler": study.sampler_name,
        "seed": study.seed,
        "trials": len(rows),
        "evaluations": sum(not r.get("reused") for r in rows),
        "ok": len(ok),
        "failed": len(failed),
        "errors": counts(r.get("error_type") for r in failed),
        "fe_gated": sum(bool(r.get("fe_gated")) for r in rows),
        "feasible": int(good.sum()),
        "objectives": study.objectives,
        "constraints": study.constraints,
        "best": [
            {
                "rank": rank + 1,
                **_trial_entry(study, rows[i]),
                "score": score,
                "folder": str(out / "best" / f"{rank + 1}-{rows[i]['variant']}"),
            }
            for rank, (i, score) in enumerate(best)
        ],
        "pareto": [rows[i]["trial"] for i in np.flatnonzero(front)],
        "best_reached_at_trial": reached,
        "convergence": history,
        "least_violating": least,
        "stage_seconds": stage_seconds(ok),
    }
    if run is not None:
        summary["run"] = {
            "computed": run.computed,
            "evaluations": run.evaluations,
            "fe_gated": run.gated,
            "earlier": run.earlier,
            "seconds": run.seconds,
            "startup_seconds": run.startup,
            "throughput_per_s": run.throughput,
            "workers": run.workers,
            "scheduler": run.scheduler,
            "interrupted": run.interrupted,
        }
    if plots and rows:
        folder = out / "plots"
        folder.mkdir(exist_ok=True)
        fig = plot_convergence(rows, study.objectives, good, title=study.name)
        files += save_figure(fig, folder / "convergence", formats=("png",))
        fig = plot_design_space(rows, study.parameter_names, sweep=study)
        files += save_figure(fig, folder / "design_space", formats=("png",))
        if len(study.objectives) > 1:
            fig = plot_pareto(rows, study.objectives, front, best, good, title=study.name)
            files += save_figure(fig, folder / "pareto", formats=("png",))
    path = out / "summary.json"
    summary["files"] = [str(f) for f in files] + [str(path)]
    write_json(path, summary, default=float)
    return summary


def feasible_rows(rows: list, study) -> np.ndarray:
    """(n,) bool: the study's feasibility (:func:`assess`) of results rows, e.g. of a sweep's
    table on the same problem."""
    return np.array([assess(r, study).feasible for r in rows], dtype=bool)
