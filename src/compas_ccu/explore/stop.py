"""Stopping a sweep cleanly: Ctrl-C and SIGTERM as a request honoured between two variants."""

from __future__ import annotations

import signal
import threading

__all__ = ["StopRequest"]


class StopRequest:
    """Ctrl-C (SIGINT) and SIGTERM as a request to stop between two variants.

    Inside ``with stop:`` (in the main thread) the two signals set :attr:`requested` instead of
    raising wherever the program happens to be, so a result is never half recorded: the journal
    and the table always agree. A second signal stops at once (KeyboardInterrupt).
    """

    def __init__(self):
        self._event = threading.Event()
        self._previous = {}

    @property
    def requested(self) -> bool:
        return self._event.is_set()

    def _handle(self, signum, frame):
        if self._event.is_set():
            raise KeyboardInterrupt
        self._event.set()

    def __enter__(self) -> StopRequest:
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._handle)
        return self

    def __exit__(self, *exc) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
        self._previous.clear()
