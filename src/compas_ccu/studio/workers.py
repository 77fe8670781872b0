"""A worker thread that always runs the latest job: slider steps that arrive faster than they
are drawn are skipped, never queued."""

from __future__ import annotations

import logging
import threading

__all__ = ["LatestWorker"]

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
