"""A worker thread that always runs the latest job: slider steps that arrive faster than they
are drawn are skipped, never queued."""

from __future__ import annotations

import logging
import threading

__all__ = ["LatestWorker", "LoopProbe"]

log = logging.getLogger(__name__)


class LatestWorker:
    """Run ``job(*args)`` in a thread with the arguments of the latest :meth:`submit`.

    A submit while the job runs replaces any waiting arguments, so the thread never falls
    behind. An exception of the job goes to ``on_error`` (default: the log) and the thread
    carries on.
    """

    def __init__(self, job, *, name: str, on_error=None):
        self._job = job
        self._on_error = on_error
        self._cond = threading.Condition()
        self._pending = None
        self._busy = False
        self._stop = False
        self._thread = threading.Thread(target=self._loop, name=name, daemon=True)
        self._thread.start()

    def submit(self, *args) -> None:
        with self._cond:
            self._pending = args
            self._cond.notify()

    @property
    def idle(self) -> bool:
        """Nothing waiting and nothing running."""
        with self._cond:
            return self._pending is None and not self._busy

    def wait_idle(self, timeout: float | None = None) -> bool:
        """Block until :attr:`idle` (or ``timeout`` seconds); True if idle."""
        with self._cond:
            return self._cond.wait_for(
                lambda: self._pending is None and not self._busy, timeout=timeout
            )

    def stop(self) -> None:
        with self._cond:
            self._stop = True
            self._cond.notify_all()
        self._thread.join(timeout=5.0)

    def _loop(self) -> None:
        while True:
            with self._cond:
                self._cond.wait_for(lambda: self._pending is not None or self._stop)
                if self._stop:
                    return
                args, self._pending = self._pending, None
                self._busy = True
            try:
                self._job(*args)
            except Exception as exc:  # a failing job never stops the studio
                if self._on_error is not None:
                    self._on_error(exc)
                else:
                    log.exception("studio worker %s", self._thread.name)
            finally:
                with self._cond:
                    self._busy = False
                    self._cond.notify_all()


class LoopProbe:
    """The largest gap of an asyncio event loop: a heartbeat that sleeps ``interval`` seconds
    on the loop and records how much later than asked it woke (the studio's page and slider
    are served by viser's loop; a gap is the time nothing reached any tab).

    Examples
    --------
    ::

        probe = LoopProbe(studio.server.get_event_loop()).start()
        ...                      # an export
        gap = probe.stop()       # seconds
    """

    def __init__(self, loop, interval: float = 0.005):
        self.loop = loop
        self.interval = interval
        self.largest = 0.0
        self.beats = 0
        self.gaps = []  # every gap, s
        self._running = False
        self._future = None

    async def _beat(self) -> None:
        import asyncio
        import time

        while self._running:
            t0 = time.perf_counter()
            await asyncio.sleep(self.interval)
            gap = time.perf_counter() - t0 - self.interval
            self.largest = max(self.largest, gap)
            self.gaps.append(gap)
            self.beats += 1

    def start(self) -> LoopProbe:
        import asyncio

        self._running = True
        self._future = asyncio.run_coroutine_threadsafe(self._beat(), self.loop)
        return self

    def stop(self) -> float:
        """Stop the heartbeat; the largest gap seen, seconds."""
        self._running = False
        if self._future is not None:
            self._future.result(timeout=10.0)
        return self.largest
