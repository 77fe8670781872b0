"""The sampler of a study (``ccu optimize``): Optuna's ask and tell.

:func:`make_sampler` is the study's sampler (TPE for one objective, NSGA-II / -III for several,
or random search); its history is Optuna's own journal (``optuna.journal``, a
``JournalFileBackend``: :func:`open_storage`), brought in line with the study's journal after
an interruption by :func:`reconcile`. :class:`AskTell` asks for the trials of a batch (the
shared runner, :func:`compas_ccu.explore.runner.in_batches`, evaluates them) and tells the
sampler each trial's objective values and constraint values (:func:`compas_ccu.explore.
feasibility.assess`). TPE ranks infeasible trials by their total violation (feasibility-aware
TPE) and NSGA-II by constrained domination, so the violations steer the search towards feasible
designs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from compas_ccu.explore.feasibility import STUDY_COLUMNS, assess
from compas_ccu.explore.runner import Task

__all__ = ["make_sampler", "sampler_seed", "open_storage", "reconcile", "AskTell"]
__all__ += ["evaluation", "POPULATION", "EI_CANDIDATES", "STORAGE"]

STORAGE = "optuna.journal"
#: Default NSGA-II / -III population (Optuna's is 50: too many for studies of ~100 trials).
POPULATION = 20
#: TPE: candidates drawn from the good designs' density per proposal, the best by expected
#: improvement is proposed (Optuna's default 24). A design costs 0.1 s to minutes, a candidate
#: microseconds: on examples/optimize/vault-sheets.toml, 128 reached the 1875-design grid's
#: best in 25-96 trials (3 seeds), 24 in 109-317 (docs/optimize.md).
EI_CANDIDATES = 128


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


def sampler_seed(seed: int, told: int) -> int:
    """The sampler's seed after ``told`` trials: a resumed study does not replay the random
    proposals of its first run."""
    if told == 0:
        return seed
    return int(np.random.SeedSequence([seed, told]).generate_state(1)[0])


def open_storage(study, out: Path):
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


def reconcile(ostudy, study, rows: dict) -> None:
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


class AskTell:
    """Ask the sampler for trials and tell it their rows.

    Parameters
    ----------
    ostudy : optuna.Study
        The study's Optuna study (:func:`open_storage`).
    study : compas_ccu.explore.study.Study
    todo : int
        Trials to ask for in this run.
    cache : dict
        Variant id -> journalled row of the designs evaluated so far: a design proposed
        again is not evaluated again (its :class:`~compas_ccu.explore.runner.Task` has no
        document and the row's evaluation columns).
    names : list of str
        The results table's columns.
    """

    def __init__(self, ostudy, study, todo: int, cache: dict, names: list):
        self.ostudy, self.study, self.todo = ostudy, study, todo
        self.cache, self.names = cache, names
        self.asked = 0
        self.distributions = study.distributions()

    def next_batch(self, size: int) -> list:
        """Up to ``size`` new trials (fewer at the end of the run) as runner tasks, with
        ``(trial, variant)`` as their item."""
        batch = []
        while len(batch) < size and self.asked < self.todo:
            trial = self.ostudy.ask(self.distributions)
            self.asked += 1
            variant = self.study.variant(self.study.settings_of(trial.params), trial.number)
            if variant.id in self.cache:  # proposed again: the same numbers, no evaluation
                row = evaluation(self.cache[variant.id], self.names, self.study)
                batch.append(Task(trial.number, None, (trial, variant), row))
            else:
                document = self.study.document_for(variant)
                batch.append(Task(trial.number, document, (trial, variant)))
        return batch

    def tell(self, trial, row: dict, assessment) -> None:
        """Tell the sampler a finished trial: its objective and constraint values, or a
        failure of the cluster (the trial failed)."""
        import optuna

        if row.get("stage") == "cluster":
            self.ostudy.tell(trial, state=optuna.trial.TrialState.FAIL)
            return
        for key, value in assessment.constraints.items():
            trial.set_constraint(key, value)
        self.ostudy.tell(trial, list(assessment.values))

    def abandon(self, task) -> None:
        """A trial that never finished (the run was stopped): failed in the history."""
        import optuna

        self.ostudy.tell(task.item[0], state=optuna.trial.TrialState.FAIL)


def evaluation(row: dict, names: list, study) -> dict:
    """The evaluation columns of a journalled row (to reuse for the same design)."""
    skip = {"trial", "variant", "run", *STUDY_COLUMNS, *study.parameter_names}
    return {k: row.get(k) for k in names if k not in skip}
