"""The one runner of sweeps and studies (explore/runner.py): both go through it, both resume
from their journal after an interruption after k evaluations, and its two ways of driving an
evaluator (a stream, batches in task order) do not depend on the order results arrive in."""

from __future__ import annotations

import signal
from contextlib import contextmanager

import pytest

from compas_ccu.explore import load_sweep, run_sweep, runner
from compas_ccu.explore.optimize import run_study
from compas_ccu.explore.results import Journal
from compas_ccu.explore.study import load_study
from conftest import EXAMPLES

pytest.importorskip("pyarrow")
pytest.importorskip("tqdm")

# columns that depend on where and when a row was computed, not on its numbers
PLACE = ("seconds", "t_model", "t_path", "t_thickness", "t_collisions", "t_fe", "worker", "run")

SWEEP = """
[sweep]
name = "small"
base = "base.toml"

[parameters]
"crease.rise" = [0.8, 1.0, 1.2]
"plates.thickness" = [0.006, 0.008]

[checks]
path_states = 5
"""

STUDY = """
[study]
name = "small"
base = "base.toml"
trials = 6
seed = 2
startup = 3

[parameters]
"plates.thickness" = {min = 0.004, max = 0.012}
"crease.rise" = {min = 0.6, max = 1.4}

[checks]
path_states = 5

[objectives]
mass = "min"
"""


@pytest.fixture()
def files(tmp_path):
    text = (EXAMPLES / "vault.toml").read_text()
    text = text.replace("spacing = 0.12", "spacing = 0.05")
    text = text.replace("segments = 64", "segments = 16")
    (tmp_path / "base.toml").write_text(text.replace("plates = 10", "plates = 4"))
    (tmp_path / "sweep.toml").write_text(SWEEP)
    (tmp_path / "study.toml").write_text(STUDY)
    return load_sweep(tmp_path / "sweep.toml"), load_study(tmp_path / "study.toml")


def numbers(rows: list) -> list:
    return [{k: v for k, v in r.items() if k not in PLACE} for r in rows]


def interrupting(monkeypatch, after: int, seen: list):
    """Wrap the runner's evaluator: note what opened it, and send Ctrl-C (SIGINT) while the
    ``after``-th design is evaluated (``after`` 0: never)."""
    opened = runner.open_evaluator

    @contextmanager
    def evaluator(options, **kwargs):
        with opened(options, **kwargs) as (inner, label, count):
            seen.append(kwargs["prefix"].split("-")[1])
            collect = inner.collect

            def counted():
                done = collect()
                seen.append(len(done))
                if after and sum(x for x in seen if isinstance(x, int)) == after:
                    signal.raise_signal(signal.SIGINT)  # the stop request of Ctrl-C
                return done

            inner.collect = counted
            yield inner, label, count

    monkeypatch.setattr(runner, "open_evaluator", evaluator)


@pytest.mark.slow  # a sweep and a study, each resumed (~5 s)
def test_a_sweep_and_a_study_resume_after_k_evaluations_as_if_never_interrupted(
    files, tmp_path, monkeypatch
):
    sweep, study = files
    whole_sweep = run_sweep(sweep, tmp_path / "sweep", in_process=True, progress=False)
    whole_study = run_study(study, tmp_path / "study", in_process=True, progress=False)
    k = 3
    seen = []
    interrupting(monkeypatch, k, seen)
    cut = run_sweep(sweep, tmp_path / "sweep-cut", in_process=True, progress=False)
    assert seen[0] == "variant"  # the sweep went through the runner
    assert cut.interrupted and cut.computed == k and cut.summary is None
    assert len(Journal(tmp_path / "sweep-cut" / "journal.jsonl").read()) == k
    seen.clear()
    cut = run_study(study, tmp_path / "study-cut", in_process=True, progress=False)
    assert seen[0] == "trial"  # and so did the study
    assert cut.interrupted and cut.computed == k
    assert len(Journal(tmp_path / "study-cut" / "journal.jsonl", key="trial").read()) == k
    # the first k trials are the uninterrupted study's (same seed, same sampler history)
    assert numbers(cut.rows) == numbers(whole_study.rows[:k])
    monkeypatch.undo()

    again = run_sweep(sweep, tmp_path / "sweep-cut", in_process=True, progress=False)
    assert (again.reused, again.computed, again.interrupted) == (k, 6 - k, False)
    assert numbers(again.rows) == numbers(whole_sweep.rows)  # the same table
    assert again.summary["pareto"] == whole_sweep.summary["pareto"]
    again = run_study(study, tmp_path / "study-cut", in_process=True, progress=False)
    assert (again.earlier, again.computed, again.interrupted) == (k, 6 - k, False)
    assert [r["trial"] for r in again.rows] == list(range(6))
    assert [r["run"] for r in again.rows] == [1] * k + [2] * (6 - k)  # none computed twice
    assert numbers(again.rows[:k]) == numbers(whole_study.rows[:k])


class Reversed:
    """A fake evaluator with 3 tasks in flight that returns the last submitted first."""

    window = 3

    def __init__(self):
        self.queued, self.cancelled = [], []

    def submit(self, key, document):
        self.queued.append((key, {"status": "ok", "value": document["x"]}))

    def collect(self):
        return [self.queued.pop()] if self.queued else []

    def cancel(self, key):
        self.cancelled.append(key)


class Never:
    requested = False


def test_a_stream_records_every_result_as_it_arrives():
    tasks = [runner.Task(i, {"x": i * i}, item=i) for i in range(7)]
    got = []
    runner.stream(Reversed(), tasks, lambda task, row: got.append((task.item, row["value"])), Never)
    assert sorted(got) == [(i, i * i) for i in range(7)]
    assert got[:3] == [(2, 4), (3, 9), (4, 16)]  # arrival order: the window refills


def test_batches_are_recorded_in_task_order_and_a_stop_abandons_the_rest():
    asked = iter(range(7))

    def next_batch(size):
        batch = []
        for i in asked:
            known = i == 4  # a task whose row is known: recorded without evaluation
            batch.append(runner.Task(i, None if known else {"x": i}, i, {"value": -1}))
            if len(batch) == size:
                break
        return batch

    got = []
    runner.in_batches(Reversed(), next_batch, lambda t, r: got.append((t.key, r["value"])), Never)
    assert got == [(0, 0), (1, 1), (2, 2), (3, 3), (4, -1), (5, 5), (6, 6)]

    class Stop:
        requested = False

    class Slow(Reversed):
        def collect(self):
            Stop.requested = True  # Ctrl-C after the first result of the first batch
            return super().collect()

    evaluator, got, abandoned = Slow(), [], []
    asked = iter(range(7))
    runner.in_batches(evaluator, next_batch, lambda t, r: got.append(t.key), Stop, abandoned.append)
    assert got == [2] and [t.key for t in abandoned] == [0, 1] == evaluator.cancelled
