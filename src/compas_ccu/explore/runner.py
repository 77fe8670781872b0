"""The one runner of sweeps (``ccu explore``) and optimisation studies (``ccu optimize``).

A run works in an output folder (:class:`Session`): the manifest names the sweep or study
(its *fingerprint*; another one's folder is refused) and counts the runs, ``journal.jsonl``
receives every finished evaluation (fsynced) the moment it reaches the client, and the table
``results.parquet`` is written from the rows at the end of every run, also an interrupted one.

The evaluations (:func:`compas_ccu.explore.evaluate_variant`, plain data in and out) run in
this process or on Dask (:func:`open_evaluator`: a local cluster, the cluster at ``scheduler``
or a given client; :mod:`compas_ccu.explore.cluster`), a bounded number at a time. Two ways
to drive them share the evaluator and the stop handling:

- :func:`stream` (a sweep): a window of tasks in flight; each result is recorded as it
  arrives and the next task is submitted. The rows do not depend on each other, so the order
  they finish in decides nothing but the journal's line order.
- :func:`in_batches` (a study): a batch of tasks (one per worker thread) is submitted, and
  recorded in task order once all of it has finished, before the next batch is asked for: what
  a sampler is told never depends on which worker finished first.

Ctrl-C and SIGTERM are a stop request (:class:`~compas_ccu.explore.stop.StopRequest`) honoured
between two recorded results: what finished is journalled, what is in flight is cancelled, and
the journal and the table agree. A second signal stops at once.
"""

from __future__ import annotations

import asyncio
import itertools
import json
import os
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from compas_ccu.errors import SweepError
from compas_ccu.explore.cluster import dask_client
from compas_ccu.explore.evaluate import evaluate_variant, row_template
from compas_ccu.explore.results import Journal, write_table
from compas_ccu.explore.stop import StopRequest
from compas_ccu.outputs import write_json

__all__ = ["Session", "Task", "Timing", "InProcess", "OnDask", "open_evaluator", "stream"]
__all__ += ["in_batches", "read_manifest", "write_manifest", "cluster_failure", "progress_bar"]
__all__ += ["CLUSTER_ERRORS", "POLL_SECONDS", "JOURNAL", "TABLE"]

#: How often the client looks for finished evaluations and for a stop request, seconds.
POLL_SECONDS = 0.05
#: Errors of the cluster rather than of the design: such rows are computed again on resume.
CLUSTER_ERRORS = ("KilledWorker", "CancelledError", "FutureCancelledError", "CommClosedError")
JOURNAL = "journal.jsonl"
TABLE = "results.parquet"


# -- the output folder -------------------------------------------------------------------------
def read_manifest(
    out: Path,
    fingerprint: str,
    *,
    name: str = "sweep.json",
    what: str = "sweep",
    parts: str = "base design, [checks], [fe] or compas_ccu version",
) -> dict:
    """The manifest ``out/name`` of an earlier run ({} if none); SweepError if it belongs to
    another sweep or study (its ``fingerprint`` differs: the message names both)."""
    path = out / name
    if not path.exists():
        return {}
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as exc:
        raise SweepError(f"{path} is not a {what} manifest ({exc}); use another --out") from exc
    if manifest.get("fingerprint") != fingerprint:
        raise SweepError(
            f"{out} holds results of a different {what} ({parts} differ: fingerprint "
            f"{manifest.get('fingerprint')!r}, this {what} {fingerprint!r}); choose another "
            "--out or delete the folder"
        )
    return manifest


def write_manifest(out: Path, manifest: dict, name: str = "sweep.json") -> None:
    """Write ``out/name`` atomically (a reader never sees half a manifest)."""
    tmp = out / (name + ".tmp")
    write_json(tmp, manifest)
    os.replace(tmp, out / name)


def progress_bar(total: int, initial: int, desc: str, show: bool, unit: str = "variant"):
    """A tqdm progress bar on stderr (disabled unless ``show``)."""
    from tqdm import tqdm  # the explore extra

    return tqdm(
        total=total,
        initial=initial,
        desc=desc,
        unit=unit,
        file=sys.stderr,
        mininterval=0.5,
        dynamic_ncols=True,
        disable=not show,
    )


@dataclass
class Timing:
    """Where and how long a run computed.

    Attributes
    ----------
    scheduler : str
        "in-process", "local", "client" or the scheduler address.
    workers : int
        Workers (1 in-process).
    startup : float
        Time to start or connect to the cluster, s.
    seconds : float
        Wall time of the evaluations (first submission to last result; not the cluster's
        shutdown), s.
    interrupted : bool
        Stopped by Ctrl-C / SIGTERM before the work was done.
    """

    scheduler: str = "in-process"
    workers: int = 1
    startup: float = 0.0
    seconds: float = 0.0
    interrupted: bool = False


class Session:
    """One run of a sweep or a study in its output folder.

    Opening it checks the folder's manifest against ``fingerprint`` (SweepError: another sweep
    or study), writes the manifest of this run (``manifest(run)``, run = earlier runs + 1) and
    reads the journal (:attr:`rows`, keyed by ``key``).

    Parameters
    ----------
    out : path-like
    fingerprint : str
    manifest : callable
        ``manifest(run) -> dict``, written as ``out/name``.
    name, what, parts : str
        The manifest's file name, and what :func:`read_manifest` calls the folder's owner.
    key : str
        The journal's key column: ``"variant"`` or ``"trial"``.
    """

    def __init__(self, out, fingerprint: str, manifest, *, name, what, parts, key="variant"):
        self.out = Path(out)
        self.out.mkdir(parents=True, exist_ok=True)
        earlier = read_manifest(self.out, fingerprint, name=name, what=what, parts=parts)
        self.run = int(earlier.get("runs", 0)) + 1
        write_manifest(self.out, manifest(self.run), name)
        self.journal = Journal(self.out / JOURNAL, key=key)
        self.rows = self.journal.read()
        self.files = [self.out / name, self.out / JOURNAL]
        self.timing = Timing()
        self.bar = None

    def progress(self, total: int, initial: int, desc: str, show: bool, unit: str) -> None:
        """Start the progress bar (:func:`progress_bar`)."""
        self.bar = progress_bar(total, initial, desc, show, unit=unit)

    def record(self, row: dict) -> None:
        """Journal one finished row (on disk before this returns) and count it."""
        self.journal.append(row)
        if self.bar is not None:
            self.bar.update(1)

    def execute(self, drive, options: dict, *, prefix: str, todo: int, batch=False, **where):
        """Open the evaluator (:func:`open_evaluator`) and call ``drive(evaluator, stop)``
        with Ctrl-C / SIGTERM turned into the stop request ``stop``; fills :attr:`timing`.
        A second signal (or one while the cluster starts) ends the run at once."""
        timing, stop = self.timing, StopRequest()
        t0, end = time.perf_counter(), None
        try:
            with open_evaluator(options, prefix=prefix, todo=todo, batch=batch, **where) as (
                evaluator,
                timing.scheduler,
                timing.workers,
            ):
                if timing.scheduler != "in-process":
                    timing.startup = time.perf_counter() - t0
                t0 = time.perf_counter()
                with stop:
                    drive(evaluator, stop)
                end = time.perf_counter()  # the cluster's shutdown is not the run's time
        except KeyboardInterrupt:
            timing.interrupted = True
        finally:
            timing.interrupted = timing.interrupted or stop.requested
            timing.seconds = (end or time.perf_counter()) - t0
        return timing

    def close(self, rows: list, names: list, declared: dict, metadata: dict) -> Path:
        """Close the progress bar and write the table ``results.parquet`` of ``rows``."""
        if self.bar is not None:
            self.bar.close()
        table = write_table(rows, names, self.out / TABLE, declared=declared, metadata=metadata)
        self.files.append(table)
        return table


# -- evaluating ----------------------------------------------------------------------------
@dataclass
class Task:
    """One evaluation to make (or, without ``document``, a row already known).

    Attributes
    ----------
    key : str or int
        Unique in the run: a variant id, a trial number.
    document : dict or None
        The design document to evaluate; None: nothing to evaluate, ``row`` is the result.
    item : object
        What the caller needs to record the result (the variant, the trial).
    row : dict or None
        The known result of a task without ``document``.
    """

    key: object
    document: dict | None
    item: object = None
    row: dict | None = None


def cluster_failure(exc: BaseException, options: dict) -> dict:
    """The row of a task that failed on the cluster, not in the design (stage ``cluster``)."""

    row = row_template(collisions=options["collisions"], fe=options["fe"] is not None)
    name = type(exc).__name__
    hint = " (the variant killed its worker repeatedly)" if name == "KilledWorker" else ""
    row.update(status="failed", stage="cluster", error_type=name, error=f"{exc}{hint}")
    return row


class InProcess:
    """Evaluate in this process, one design at a time, when the result is collected (a stop
    requested after a result is recorded evaluates nothing more)."""

    window = 1

    def __init__(self, options: dict):
        self.options = options
        self.queued = []

    def submit(self, key, document) -> None:
        self.queued.append((key, document))

    def collect(self) -> list:
        """``[(key, row)]``: the first queued design, evaluated."""
        if not self.queued:
            return []
        key, document = self.queued.pop(0)
        return [(key, evaluate_variant(document, **self.options))]

    def cancel(self, key) -> None:
        self.queued = [(k, d) for k, d in self.queued if k != key]


class OnDask:
    """Evaluate designs on a Dask cluster; :meth:`collect` returns those that finished.

    Parameters
    ----------
    client : distributed.Client
    options : dict
        Keyword arguments of :func:`compas_ccu.explore.evaluate_variant`.
    prefix : str
        The tasks' keys are ``<prefix>-<key>``.
    window : int
        Tasks in flight at a time.
    """

    def __init__(self, client, options: dict, prefix: str, window: int):
        from distributed import as_completed

        self.client, self.options, self.prefix, self.window = client, options, prefix, window
        self.futures = {}
        self.flow = as_completed()

    def submit(self, key, document) -> None:
        future = self.client.submit(
            evaluate_variant, document, key=f"{self.prefix}-{key}", pure=False, **self.options
        )
        self.futures[future] = key
        self.flow.add(future)

    def collect(self) -> list:
        """``[(key, row)]`` of the tasks that finished since the last call (waits
        :data:`POLL_SECONDS` if none did)."""
        batch = self.flow.next_batch(block=False)
        if not batch:  # wait a little, listening for a stop request
            time.sleep(POLL_SECONDS)
            return []
        out = []
        for future in batch:
            key = self.futures.pop(future)
            # evaluate_variant turns every error of the design into a row, so result() raises
            # only for the cluster. It waits if the result was lost with a killed worker after
            # it finished (Dask computes it again), instead of reading the status at the wrong
            # moment.
            try:
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


def dask_window(client, count: int, *, batch: bool, window: int | None = None) -> int:
    """Tasks in flight on ``client``'s cluster: a batch has one per worker thread; a stream
    ``window`` (default: 8 per worker, at least 64), so the client and the scheduler hold a
    bounded number of tasks however large the sweep."""
    info = client.scheduler_info().get("workers", {})
    if batch:
        return max(1, sum(w.get("nthreads", 1) for w in info.values()), count)
    return window or max(64, 8 * (len(info) or 1))


@contextmanager
def open_evaluator(
    options: dict,
    *,
    prefix: str,
    todo: int,
    batch: bool = False,
    window: int | None = None,
    in_process: bool = False,
    client=None,
    scheduler: str | None = None,
    workers: int | None = None,
    dashboard: bool = False,
):
    """``(evaluator, label, worker count)``: :class:`InProcess` (``in_process``, or nothing to
    do), or :class:`OnDask` on ``client``, the cluster at ``scheduler`` or a new local one of
    ``workers`` processes (:func:`compas_ccu.explore.cluster.dask_client`), closed on exit."""
    if in_process or not todo:
        yield InProcess(options), "in-process", 1
        return
    cluster = dask_client(
        client, scheduler=scheduler, workers=workers, todo=todo, dashboard=dashboard
    )
    with cluster as (use, label, count):
        size = dask_window(use, count, batch=batch, window=window)
        yield OnDask(use, options, prefix, size), label, count


def stream(evaluator, tasks, record, stop) -> None:
    """Keep ``evaluator.window`` of ``tasks`` in flight; ``record(task, row)`` each result as
    it arrives and submit the next task, until all are recorded or a stop is requested (the
    tasks in flight are then cancelled)."""
    queue = iter(tasks)
    pending = {}

    def submit(task) -> None:
        pending[task.key] = task
        evaluator.submit(task.key, task.document)

    for task in itertools.islice(queue, evaluator.window):
        submit(task)
    try:
        while pending and not stop.requested:
            for key, row in evaluator.collect():
                record(pending.pop(key), row)
                nxt = next(queue, None)
                if nxt is not None:
                    submit(nxt)
    finally:
        for key in pending:  # interrupted: forget the rest on the cluster
            evaluator.cancel(key)


def in_batches(evaluator, next_batch, record, stop, abandon=None) -> None:
    """Evaluate ``next_batch(evaluator.window)`` (a list of :class:`Task`; empty: done) and
    ``record(task, row)`` the whole batch in task order once all of it has finished, then ask
    for the next; tasks without a document are recorded with their known row.

    On a stop request the finished tasks of the batch are recorded (in order) and the others
    are cancelled and given to ``abandon(task)``.
    """
    pending = {}
    try:
        while not stop.requested:
            batch = next_batch(evaluator.window)
            if not batch:
                break
            for task in batch:
                if task.document is not None:
                    evaluator.submit(task.key, task.document)
                    pending[task.key] = task
            done = {}
            while True:  # what has finished is kept, a stop or not
                done.update(evaluator.collect())
                if len(done) >= len(pending) or stop.requested:
                    break
            for task in batch:  # in task order
                if task.key in done:
                    del pending[task.key]
                    record(task, done[task.key])
                elif task.document is None:
                    record(task, task.row)
    finally:
        for key, task in pending.items():  # never finished: forgotten
            evaluator.cancel(key)
            if abandon is not None:
                abandon(task)
