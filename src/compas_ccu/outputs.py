"""Output folders as transactions: a folder holds exactly one complete run's files.

A command writes into a staging folder beside the output folder (``.NAME.ccu-staging-PID``);
only when everything is written are the files moved into the output folder, the files that the
previous run listed in its manifest (``.ccu-files.json``) and this run did not write are removed,
and the new manifest is written. A run that fails leaves the output folder as it was (the previous
complete run's files) and removes its staging folder. Files in the output folder that no run of
compas_ccu wrote are never touched. Ctrl-C and SIGTERM (which ``ccu`` turns into a
:class:`KeyboardInterrupt`) are a failure like any other: the staging folder is removed; one that
arrives while the files are moved in or the staging folder is removed waits until that is done,
so a folder is never left half moved.

>>> import tempfile, pathlib
>>> out = pathlib.Path(tempfile.mkdtemp()) / "run"
>>> with staged_folder(out) as stage:
...     _ = (stage / "a.txt").write_text("one")
>>> sorted(p.name for p in out.iterdir())
['.ccu-files.json', 'a.txt']
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import threading
import uuid
from contextlib import contextmanager
from pathlib import Path

from compas_ccu.errors import GeometryError, OptionError

__all__ = ["MANIFEST", "check_output_folder", "staged_folder", "manifest_files", "signals_held"]
__all__ += ["json_text", "write_json", "first_non_finite", "NAMESPACE", "name_id"]

#: The namespace of :func:`name_id` (name-based UUIDs of ``compas_ccu``).
NAMESPACE = uuid.uuid5(uuid.NAMESPACE_DNS, "compas-ccu.org")


def name_id(*parts) -> uuid.UUID:
    """A fixed id of the object named by ``parts`` (a name-based UUID, version 5): written files
    carry ids that are the same every time, never random ones.

    >>> name_id("vault", "plate 0") == name_id("vault", "plate 0") != name_id("dome", "plate 0")
    True
    """
    return uuid.uuid5(NAMESPACE, "/".join(str(p) for p in parts))


#: The manifest of the files of the last complete run, inside the output folder.
MANIFEST = ".ccu-files.json"


def first_non_finite(data, where: str = "") -> str | None:
    """The key path (``"plates[3].deployed[5][2]"``) of the first NaN or infinity in ``data``."""
    if isinstance(data, float):
        return None if math.isfinite(data) else (where or "the value")
    if isinstance(data, dict):
        items = ((f"{where}.{k}" if where else str(k), v) for k, v in data.items())
    elif isinstance(data, (list, tuple)):
        items = ((f"{where}[{i}]", v) for i, v in enumerate(data))
    else:
        return None
    for path, value in items:
        found = first_non_finite(value, path)
        if found is not None:
            return found
    return None


def json_text(data, *, what: str = "the JSON file", **options) -> str:
    """Strict JSON text of ``data``: JSON has no NaN or infinity, so they are refused.

    Raises
    ------
    GeometryError
        ``data`` holds a non-finite number; the message names where.
    """
    try:
        return json.dumps(data, allow_nan=False, **options)
    except ValueError:
        where = first_non_finite(data)
        raise GeometryError(
            f"{what} would hold a non-finite number at {where}: nothing is written (a result "
            "that is not finite is not a result)"
        ) from None


def write_json(path, data, *, indent=1, **options) -> Path:
    """Write ``data`` as strict JSON (:func:`json_text`) to ``path``; returns the path."""
    path = Path(path)
    path.write_text(json_text(data, what=path.name, indent=indent, **options) + "\n", "utf-8")
    return path


def check_output_folder(path, *, option: str = "--out") -> Path:
    """The output folder ``path``, checked before any work.

    Raises
    ------
    OptionError
        The path is empty, names an existing file, lies under a file, or its nearest existing
        folder is not writable.
    """
    text = str(path)
    if not text.strip():
        raise OptionError(f"{option} must name a folder, got an empty path")
    out = Path(text).expanduser()
    if out.exists() and not out.is_dir():
        raise OptionError(f"{option} {text!r} is a file, not a folder")
    existing = out
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise OptionError(f"{option} {text!r} lies under {str(existing)!r}, which is a file")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OptionError(f"{option} {text!r}: cannot write into {str(existing)!r}")
    return out


def manifest_files(out: Path) -> list:
    """The files (relative paths) that the last complete run listed in ``out``'s manifest."""
    try:
        data = json.loads((Path(out) / MANIFEST).read_text(encoding="utf-8"))
        return [str(f) for f in data["files"]]
    except (OSError, ValueError, KeyError, TypeError):
        return []


def _relative_files(folder: Path) -> list:
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())


def _inside(folder: Path, relative: str) -> Path | None:
    """``folder / relative`` if it stays inside ``folder`` (a manifest is not trusted)."""
    path = (folder / relative).resolve()
    root = folder.resolve()
    return path if root in path.parents else None


def _commit(stage: Path, out: Path) -> list:
    written = _relative_files(stage)
    previous = manifest_files(out)
    out.mkdir(parents=True, exist_ok=True)
    for rel in written:
        target = out / rel
        if target.is_dir():
            shutil.rmtree(target)
        target.parent.mkdir(parents=True, exist_ok=True)
        os.replace(stage / rel, target)
    for rel in sorted(set(previous) - set(written)):
        stale = _inside(out, rel)
        if stale is not None and stale.is_file():
            stale.unlink()
            for parent in stale.parents:  # folders the stale files leave empty
                if parent == out.resolve() or any(parent.iterdir()):
                    break
                parent.rmdir()
    text = json.dumps({"format": "ccu.files", "version": 1, "files": written}, indent=1)
    partial = out / (MANIFEST + ".partial")
    partial.write_text(text + "\n", encoding="utf-8")
    os.replace(partial, out / MANIFEST)
    return written


@contextmanager
def signals_held():
    """Hold Ctrl-C (SIGINT) and SIGTERM until the block ends, then deliver the first one.

    In the main thread only (elsewhere, and for a signal whose handler Python did not set or
    that is ignored, as under ``nohup`` or ``cmd &``, the block runs as it is).
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held = []
    previous = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        handler = signal.getsignal(sig)
        if handler is not None and handler != signal.SIG_IGN:
            previous[sig] = signal.signal(sig, lambda signum, frame: held.append(signum))
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        if held:
            signal.raise_signal(held[0])


@contextmanager
def staged_folder(out, *, option: str = "--out"):
    """Write into a staging folder; move its files into ``out`` when the block succeeds.

    Parameters
    ----------
    out : path
        The output folder (created if needed).

    Yields
    ------
    pathlib.Path
        The staging folder to write into.
    """
    out = check_output_folder(out, option=option)
    # stage in the nearest existing folder: nothing is created before the run succeeds
    existing = out.parent
    while not existing.exists():
        existing = existing.parent
    stage = existing / f".{out.name or 'out'}.ccu-staging-{os.getpid()}"
    if stage.exists():
        shutil.rmtree(stage)
    stage.mkdir()
    try:
        yield stage
        with signals_held():
            _commit(stage, out)
    finally:
        with signals_held():
            shutil.rmtree(stage, ignore_errors=True)
