"""Process-level habits of the ``ccu`` command: closed pipes, Ctrl-C and SIGTERM.

* **A reader that leaves** (``ccu info --json | head -1``, a closed pipe): the first write that
  meets the broken pipe points the stream's file descriptor at the null device
  (:func:`os.dup2`), and the command goes on to the end with nothing more printed on that
  stream: the files it writes are complete, its exit status is its own (0 on success), and
  there is no "Broken pipe" message. 0 rather than 141 (a shell's status of a process killed by
  SIGPIPE): the command did its work, only its reader stopped listening.
* **Ctrl-C** (SIGINT) and **SIGTERM** stop the command where it is, with one line on stderr
  (``ccu: interrupted``, ``ccu: terminated``) and the exit status 130 (128 + SIGINT) or 143
  (128 + SIGTERM); no traceback. SIGTERM raises :class:`Terminated` (a
  :class:`KeyboardInterrupt`), so everything that cleans up after Ctrl-C cleans up after SIGTERM
  too: the staging folder of an output folder is removed and the previous complete run's files
  stay as they were (:mod:`compas_ccu.outputs`).
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from contextlib import contextmanager

__all__ = ["Terminated", "ReaderGuard", "process_habits", "stop_report"]


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the program is, like Ctrl-C's :class:`KeyboardInterrupt`."""


def _terminate(signum, frame):
    raise Terminated(signum)


class ReaderGuard:
    """A text stream whose reader may leave: a broken pipe makes it a sink of the null device.

    Every attribute but :meth:`write`, :meth:`writelines` and :meth:`flush` is the stream's.
    """

    def __init__(self, stream):
        self.stream = stream
        #: The reader left: nothing more is written.
        self.left = False

    def __getattr__(self, name):
        return getattr(self.stream, name)

    def _leave(self) -> None:
        self.left = True
        try:
            fd = self.stream.fileno()
        except (AttributeError, OSError, ValueError):  # an in-memory stream: nothing to point
            return
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, fd)  # what the stream still buffers now goes to the null device
        finally:
            os.close(null)

    def write(self, text):
        if not self.left:
            try:
                return self.stream.write(text)
            except BrokenPipeError:
                self._leave()
        return len(text)

    def writelines(self, lines) -> None:
        for line in lines:
            self.write(line)

    def flush(self) -> None:
        if not self.left:
            try:
                self.stream.flush()
            except BrokenPipeError:
                self._leave()


@contextmanager
def process_habits():
    """Guard ``sys.stdout`` / ``sys.stderr`` against a reader that leaves and turn SIGTERM into
    :class:`Terminated` for the block; both are restored after it (streams flushed first).
    """
    streams = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = (s if s is None else ReaderGuard(s) for s in streams)
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _terminate) if main else None
    try:
        yield
    finally:
        for guard in (sys.stdout, sys.stderr):
            if isinstance(guard, ReaderGuard):
                guard.flush()
        sys.stdout, sys.stderr = streams
        if main:  # None: a handler not set from Python, which cannot be put back
            signal.signal(signal.SIGTERM, signal.SIG_DFL if previous is None else previous)


def stop_report(exc: KeyboardInterrupt) -> tuple:
    """``(line, exit status)`` of a command stopped by Ctrl-C or SIGTERM."""
    if isinstance(exc, Terminated):
        return "ccu: terminated", 128 + int(signal.SIGTERM)
    return "ccu: interrupted", 128 + int(signal.SIGINT)
