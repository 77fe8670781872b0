"""Run a sweep on Dask: a local cluster by default, any existing cluster by address.

The client submits one task per missing variant (:func:`compas_ccu.explore.evaluate_variant`,
plain data in and out), writes every result to the journal as it arrives and shows progress.
Resuming is by variant id: a run in an output folder that already holds results of the same
sweep (same base design, checks, FE options and compas_ccu version: the *fingerprint*) computes
only the variants that are missing. A variant that fails is a row with its error; a worker that
dies is replaced by Dask, which recomputes the tasks it held (a variant that kills workers
repeatedly is recorded as ``KilledWorker``); nothing the client has received is lost.
"""

from __future__ import annotations

import asyncio
import itertools
import json
import logging
import os
import socket
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import compas_ccu
from compas_ccu import __version__
from compas_ccu.errors import SweepError
from compas_ccu.explore.evaluate import STAGES, evaluate_variant, row_template
from compas_ccu.explore.metrics import metric, metric_names
from compas_ccu.explore.results import Journal, write_table
from compas_ccu.explore.stop import StopRequest
from compas_ccu.explore.summary import summarise
from compas_ccu.outputs import write_json

__all__ = ["run_sweep", "SweepResult", "columns", "local_cluster", "CLUSTER_ERRORS", "WORKER_ENV"]
__all__ += ["runner_label"]
__all__ += ["connect", "dask_client", "check_runner", "read_manifest", "write_manifest"]
__all__ += ["reach_scheduler"]
__all__ += ["cluster_failure", "progress_bar"]

#: How often the client looks for finished variants and for a stop request, seconds.
POLL_SECONDS = 0.05


#: Errors of the cluster rather than of the design: such variants are computed again on resume.
CLUSTER_ERRORS = ("KilledWorker", "CancelledError", "FutureCancelledError", "CommClosedError")
#: Environment of the local cluster's worker processes. Dask's nannies set
#: MALLOC_TRIM_THRESHOLD_=65536, and glibc then maps and unmaps every large NumPy temporary
#: afresh (page faults, system time): the collision check of an 8-plate vault variant took
#: 0.51 s on such a worker. Keeping arrays up to 32 MiB on the heap and trimming above 256 MiB
#: gives 0.12 s (docs/benchmarks.md). Set the same variables on the workers of your own
#: cluster (``distributed.nanny.pre-spawn-environ``).
WORKER_ENV = {"MALLOC_MMAP_THRESHOLD_": str(2**25), "MALLOC_TRIM_THRESHOLD_": str(2**28)}
CONNECT_TIMEOUT = "20s"  # to reach a --scheduler
PROBE_SECONDS = 10.0  # for a --scheduler's host to accept a TCP connection (reach_scheduler)
WORKER_TIMEOUT = 60.0  # s for a first worker to join it
MANIFEST = "sweep.json"
JOURNAL = "journal.jsonl"
TABLE = "results.parquet"


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


def runner_label(scheduler: str, workers: int) -> str:
    """Where a run computed, for a sentence: "in this process", "on 2 local Dask workers",
    "on 4 workers of tcp://...".

    >>> runner_label("in-process", 1), runner_label("local", 2)
    ('in this process', 'on 2 local Dask workers')
    """
    if scheduler == "in-process":
        return "in this process"
    if scheduler == "local":
        return f"on {workers} local Dask workers"
    return f"on {workers} workers of {scheduler}"


def columns(sweep) -> tuple:
    """Column order and declared types of the results table of ``sweep``."""

    metrics = metric_names(collisions=sweep.collisions, fe=sweep.fe is not None)
    head = ["variant", "index", *sweep.parameter_names, "status", "stage", "error_type", "error"]
    tail = ["seconds", *[f"t_{s}" for s in STAGES], "worker", "run"]
    declared = {name: metric(name).dtype for name in metrics}
    declared.update({k: "str" for k in ("variant", "status", "stage", "error_type", "error")})
    declared.update({k: "float" for k in tail[:-2]}, worker="str", run="int", index="int")
    return head + metrics + tail, declared


def read_manifest(
    out: Path,
    fingerprint: str,
    *,
    name: str = MANIFEST,
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


def write_manifest(out: Path, manifest: dict, name: str = MANIFEST) -> None:
    """Write ``out/name`` atomically (a reader never sees half a manifest)."""
    tmp = out / (name + ".tmp")
    write_json(tmp, manifest)
    os.replace(tmp, out / name)


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


def cluster_failure(exc: BaseException, options: dict) -> dict:
    """The row of a task that failed on the cluster, not in the design (stage ``cluster``)."""

    row = row_template(collisions=options["collisions"], fe=options["fe"] is not None)
    name = type(exc).__name__
    hint = " (the variant killed its worker repeatedly)" if name == "KilledWorker" else ""
    row.update(status="failed", stage="cluster", error_type=name, error=f"{exc}{hint}")
    return row


def _worker_version():  # runs on every worker of a remote cluster

    return compas_ccu.__version__


def connect(scheduler: str | None, workers: int | None, todo: int, dashboard: bool = False):
    """(client, cluster or None, label, worker count): a client of the scheduler at
    ``scheduler`` (its workers checked for this compas_ccu version), or of a new local cluster
    of ``workers`` processes (default: one per core, at most ``todo``)."""
    try:
        from distributed import Client
    except ImportError as exc:  # pragma: no cover - the explore extra is missing
        raise SweepError(
            "ccu explore needs Dask: pip install 'compas_ccu[explore]' (dask[distributed], pyarrow)"
        ) from exc
    if scheduler is not None:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT)
        except Exception as exc:  # a refused connection, a server that is not Dask's  # noqa: BLE001
            raise SweepError(
                f"cannot connect to the Dask scheduler at {scheduler!r}: {_cause(exc)}"
            ) from exc
        try:
            client.wait_for_workers(1, timeout=60)
        except TimeoutError as exc:
            client.close()
            raise SweepError(
                f"no Dask worker joined the scheduler at {scheduler!r} in 60 s"
            ) from exc

        versions = client.run(_worker_version)
        wrong = {w: v for w, v in versions.items() if v != __version__}
        if wrong:
            client.close()
            raise SweepError(
                f"workers run another compas_ccu version than this client ({__version__}): "
                f"{wrong}; install the same version on every worker"
            )
        return client, None, scheduler, len(versions)
    n = workers or max(1, min(os.cpu_count() or 1, todo))
    cluster = local_cluster(n, dashboard=dashboard)
    return Client(cluster), cluster, "local", n


@contextmanager
def dask_client(client=None, *, scheduler=None, workers=None, todo: int = 1, dashboard=False):
    """``(client, label, worker count)`` of the cluster to run on: ``client``'s (label
    "client"), the one at ``scheduler``, or a new local one (:func:`connect`); a client and a
    cluster it started are closed on exit."""
    own = cluster = None
    try:
        if client is not None:
            yield client, "client", len(client.scheduler_info().get("workers", {}))
        else:
            own, cluster, label, count = connect(scheduler, workers, todo, dashboard)
            yield own, label, count
    finally:
        if own is not None:
            own.close()
        if cluster is not None:
            cluster.close()


def check_runner(workers, scheduler) -> None:
    """Refuse a worker count below 1, ``workers`` with ``scheduler``, and a scheduler that
    cannot be reached (:func:`reach_scheduler`), before anything runs or is written."""
    if workers is not None and (isinstance(workers, bool) or workers < 1):
        raise SweepError(f"--workers must be >= 1, got {workers}")
    if scheduler is not None and workers is not None:
        raise SweepError(
            "--workers sizes the local cluster; with --scheduler the cluster's own workers "
            f"are used (got --workers {workers} and --scheduler {scheduler})"
        )
    if scheduler is not None:
        reach_scheduler(scheduler)


def _cause(exc: BaseException) -> str:
    """One line on why a connection failed."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0][:200]}" if text else type(exc).__name__


def reach_scheduler(scheduler: str, timeout: float = PROBE_SECONDS) -> None:
    """SweepError unless ``scheduler`` is a Dask scheduler that answers, checked before a run
    writes anything: the address is parsed, the host of a ``tcp://`` or ``tls://`` address
    must accept a TCP connection within ``timeout`` seconds (Dask would retry a refused
    connection until its own timeout), and Dask's handshake must succeed within
    :data:`CONNECT_TIMEOUT` (the run then connects again)."""
    from dask.utils import parse_timedelta
    from distributed.comm import connect as open_comm
    from distributed.comm import parse_address, parse_host_port
    from distributed.comm.registry import get_backend

    where = f"cannot connect to the Dask scheduler at {scheduler!r}"
    try:
        scheme, location = parse_address(scheduler)
        get_backend(scheme)
        host, port = parse_host_port(location) if scheme in ("tcp", "tls") else (None, None)
    except (ValueError, TypeError) as exc:
        raise SweepError(
            f"--scheduler {scheduler!r} is not a Dask scheduler address: {exc}"
        ) from None
    if host is not None:
        try:
            socket.create_connection((host, port), timeout=timeout).close()
        except socket.timeout:
            raise SweepError(f"{where}: no answer in {timeout:g} s") from None
        except OSError as exc:  # refused, unreachable, an unknown host
            raise SweepError(f"{where}: {exc.strerror or exc}") from None

    seconds = parse_timedelta(CONNECT_TIMEOUT)

    async def handshake():  # bounded: a server that accepts and stays silent would hang Dask
        comm = await asyncio.wait_for(open_comm(scheduler, timeout=seconds), seconds + 1.0)
        await comm.close()

    # in a thread of its own: asyncio.run needs a thread without a running event loop
    with ThreadPoolExecutor(1) as pool:
        try:
            pool.submit(asyncio.run, handshake()).result()
        except asyncio.TimeoutError:
            raise SweepError(
                f"{where}: it does not answer as a Dask scheduler (no handshake in {seconds:g} s)"
            ) from None
        except Exception as exc:  # anything but a Dask scheduler's answer  # noqa: BLE001
            raise SweepError(
                f"{where}: it does not answer as a Dask scheduler ({_cause(exc)})"
            ) from None


def local_cluster(workers: int, *, dashboard: bool = False):
    """A ``distributed.LocalCluster`` of ``workers`` single-threaded processes with
    :data:`WORKER_ENV` (set before the worker processes start, also when a nanny restarts one).
    """
    import dask
    from distributed import LocalCluster

    environ = {f"distributed.nanny.pre-spawn-environ.{k}": v for k, v in WORKER_ENV.items()}
    with dask.config.set(environ):
        return LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":8787" if dashboard else None,
            silence_logs=logging.ERROR,
        )


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
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    manifest = read_manifest(out, sweep.fingerprint)
    run = int(manifest.get("runs", 0)) + 1
    write_manifest(out, _sweep_manifest(sweep, run))
    journal = Journal(out / JOURNAL)
    done = journal.read()
    current = {v.id for v in sweep.variants}
    kept = {
        vid: row
        for vid, row in done.items()
        if vid in current and row.get("error_type") not in CLUSTER_ERRORS
    }
    todo = [v for v in sweep.variants if v.id not in kept]
    options = sweep.options
    names, declared = columns(sweep)
    state = {"computed": 0, "failed": sum(r.get("status") == "failed" for r in kept.values())}

    bar = progress_bar(len(sweep.variants), len(kept), sweep.name, progress)

    def record(variant, row):
        full = {"variant": variant.id, "index": variant.index, **variant.params, **row, "run": run}
        journal.append(full)
        kept[variant.id] = full
        state["computed"] += 1
        state["failed"] += row["status"] == "failed"
        bar.update(1)
        bar.set_postfix(failed=state["failed"], refresh=False)

    interrupted = False
    label, count, startup, end = "in-process", 1, 0.0, None
    t0 = time.perf_counter()
    stop = StopRequest()
    try:
        if not todo:
            pass
        elif in_process:
            t0 = time.perf_counter()
            with stop:
                for v in todo:
                    if stop.requested:
                        break
                    record(v, evaluate_variant(sweep.document_for(v), **options))
        else:
            cluster = dask_client(
                client, scheduler=scheduler, workers=workers, todo=len(todo), dashboard=dashboard
            )
            with cluster as (use, label, count):
                startup = time.perf_counter() - t0
                t0 = time.perf_counter()
                with stop:
                    _run_on_dask(use, sweep, todo, options, record, window=window or 0, stop=stop)
                end = time.perf_counter()  # the cluster's shutdown is not the sweep's time
    except KeyboardInterrupt:  # a second Ctrl-C, or one while the cluster starts
        interrupted = True
    finally:
        interrupted = interrupted or stop.requested
        seconds = (end or time.perf_counter()) - t0
        bar.close()
        rows = [kept[v.id] for v in sweep.variants if v.id in kept]
        table = write_table(
            rows,
            names,
            out / TABLE,
            declared=declared,
            metadata={"name": sweep.name, "fingerprint": sweep.fingerprint},
        )
    result = SweepResult(
        out=out,
        rows=rows,
        total=len(sweep.variants),
        reused=len(sweep.variants) - len(todo),
        computed=state["computed"],
        failed=state["failed"],
        seconds=seconds if todo else 0.0,
        startup=startup,
        workers=count,
        scheduler=label,
        interrupted=interrupted,
        files=[out / MANIFEST, out / JOURNAL, table],
    )
    if summary and result.complete and not interrupted:
        result.summary = summarise(sweep, rows, out, run=result, plots=plots)
        result.files += [Path(f) for f in result.summary["files"]]
    return result


def _run_on_dask(
    client, sweep, todo: list, options: dict, record, *, window: int = 0, stop=None
) -> None:
    """Keep up to ``window`` variants in flight (default: 8 per worker, at least 64), record
    each result as it completes and submit the next, so the client and the scheduler hold a
    bounded number of tasks however large the sweep."""
    from distributed import as_completed

    stop = StopRequest() if stop is None else stop
    workers = len(client.scheduler_info().get("workers", {})) or 1
    window = window or max(64, 8 * workers)
    queue = iter(todo)
    pending = {}

    def submit(v):
        future = client.submit(
            evaluate_variant,
            sweep.document_for(v),
            key=f"ccu-variant-{sweep.fingerprint}-{v.id}",
            **options,
        )
        pending[future] = v
        return future

    first = [submit(v) for v in itertools.islice(queue, window)]
    flow = as_completed(first)
    try:
        while pending and not stop.requested:
            batch = flow.next_batch(block=False)
            if not batch:  # wait a little, listening for a stop request
                time.sleep(POLL_SECONDS)
                continue
            for future in batch:
                v = pending.pop(future)
                # evaluate_variant turns every error of the design into a row, so result()
                # raises only for the cluster. It waits if the result was lost with a killed
                # worker after it finished (Dask computes it again), instead of reading the
                # status at the wrong moment.
                try:
                    row = future.result()
                except (Exception, asyncio.CancelledError) as exc:  # CancelledError: Base
                    row = cluster_failure(exc, options)
                future.release()
                record(v, row)
                nxt = next(queue, None)
                if nxt is not None:
                    flow.add(submit(nxt))
    finally:
        for future in pending:  # interrupted: forget the rest on the cluster
            future.cancel()


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
