"""Importing Kratos Multiphysics for the :mod:`.kratos` engine: its C++ banners silenced, its
log reduced to warnings and its OpenMP threads set to :data:`THREADS`, once per process; and
:func:`available`, whether it imports and its version."""

from __future__ import annotations

import contextlib
import os

__all__ = ["THREADS", "kratos_modules", "available"]

_KM = None
#: Kratos' OpenMP threads unless ``OMP_NUM_THREADS`` is set: one. The time of a solve is the
#: single-threaded sparse LU; a second thread only assembles, and on a shared machine its
#: waiting threads spin: the cone's validation took 21 s of CPU with two threads on two busy
#: cores, 3.4 s with one (docs/benchmarks.md), with the same numbers.
THREADS = 1


@contextlib.contextmanager
def _quiet():
    """Silence the C++ banners Kratos prints to stdout on import."""
    try:
        fd = os.dup(1)
    except OSError:  # no real stdout (e.g. a notebook): nothing to silence
        yield
        return
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            yield
    finally:
        os.dup2(fd, 1)
        os.close(fd)


def kratos_modules() -> tuple:
    """``(KratosMultiphysics, StructuralMechanicsApplication, LinearSolversApplication)``,
    imported on the first call.

    Raises
    ------
    ImportError
        Kratos is not installed.
    """
    global _KM
    if _KM is None:
        with _quiet():
            import KratosMultiphysics as KM
            import KratosMultiphysics.LinearSolversApplication as LSA
            import KratosMultiphysics.StructuralMechanicsApplication as SMA

            KM.Logger.GetDefaultOutput().SetSeverity(KM.Logger.Severity.WARNING)
            if not os.environ.get("OMP_NUM_THREADS"):
                KM.ParallelUtilities.SetNumThreads(THREADS)
        _KM = (KM, SMA, LSA)
    return _KM


def available() -> tuple:
    """``(True, version)`` if Kratos imports, else ``(False, reason)``."""
    try:
        KM, _, _ = kratos_modules()
    except Exception as exc:  # ImportError or a broken wheel
        return False, f"KratosMultiphysics does not import: {exc}"
    try:
        from importlib.metadata import version

        return True, version("KratosMultiphysics")
    except Exception:
        return True, "0 (version unknown)"
