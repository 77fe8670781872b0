"""Where the evaluations of a sweep or a study run: a local Dask cluster, or an existing one.

:func:`connect` starts a local cluster (single-threaded worker processes with
:data:`WORKER_ENV`) or connects to a running scheduler (its workers checked for this compas_ccu
version); :func:`check_runner` and :func:`reach_scheduler` refuse bad options and an
unreachable scheduler before a run writes anything. The run itself (submitting, journaling,
stopping) is :mod:`compas_ccu.explore.runner`.
"""

from __future__ import annotations

import asyncio
import logging
import os
import socket
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager

import compas_ccu
from compas_ccu import __version__
from compas_ccu.errors import SweepError

__all__ = ["connect", "dask_client", "check_runner", "reach_scheduler", "local_cluster"]
__all__ += ["runner_label", "WORKER_ENV", "CONNECT_TIMEOUT", "PROBE_SECONDS", "WORKER_TIMEOUT"]

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
