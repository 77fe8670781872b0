"""Export from the studio: the files the ``ccu`` commands write, into the output folder only.

:class:`ExportProcess` runs an export in a separate process (``spawn``): the nesting (spyrrow)
and the report's pictures (matplotlib) hold the GIL for seconds, which in the studio's process
would stall its event loop and so every page and the α slider.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import multiprocessing
import os
import tempfile
import threading
from pathlib import Path

from compas_ccu.design import Design
from compas_ccu.fabrication.fabricate import fabricate
from compas_ccu.io import write_compas_json, write_obj, write_structure_json
from compas_ccu.limits import LIMITS, raised
from compas_ccu.model import CCUModel
from compas_ccu.outputs import staged_folder
from compas_ccu.viz.report import write_report

__all__ = [
    "EXPORTS",
    "export",
    "export_job",
    "export_warnings",
    "ExportProcess",
    "BackgroundProcess",
]

#: What the studio exports, each into its own subfolder of ``OUT/<design name>/``.
EXPORTS = ("structure", "fabrication", "report")


def export(model, out, *, alpha: float, what=EXPORTS, design_text: str | None = None) -> dict:
    """Write ``what`` of ``model`` into ``out/<design name>/``.

    * ``structure``: structure.json, structure.obj, structure.compas.json at ``alpha`` (as
      ``ccu deploy --alpha``), plus ``design.toml`` (the design as edited);
    * ``fabrication``: the workshop files at the design state (as ``ccu fabricate``);
    * ``report``: the report (as ``ccu report``), with the design as edited (its text and
      hash) and the fabrication folder when that is exported too.

    Each folder is written as one transaction (:func:`compas_ccu.outputs.staged_folder`): a
    failure leaves the previous export as it was.

    Returns
    -------
    dict
        Export name -> the folder written.
    """
    unknown = [w for w in what if w not in EXPORTS]
    if unknown:
        raise ValueError(f"unknown export {unknown[0]!r}; known: {', '.join(EXPORTS)}")
    root = Path(out) / model.design.name
    written = {}
    if "structure" in what:
        structure = model.deploy(alpha)
        with staged_folder(root / "structure") as stage:
            write_structure_json(structure, stage / "structure.json")
            write_obj(structure, stage / "structure.obj")
            write_compas_json(structure, stage / "structure.compas.json")
            if design_text is not None:
                (stage / "design.toml").write_text(design_text, "utf-8")
        written["structure"] = root / "structure"
    if "fabrication" in what:
        with staged_folder(root / "fabrication") as stage:
            sha = None if design_text is None else hashlib.sha256(design_text.encode()).hexdigest()
            fabricate(model, stage, design_sha256=sha)
        written["fabrication"] = root / "fabrication"
    if "report" in what:
        with staged_folder(root / "report") as stage, tempfile.TemporaryDirectory() as tmp:
            design_file = None  # the design as edited: the report's record and its hash
            if design_text is not None:  # its bytes as hashed for the fabrication above
                design_file = Path(tmp) / f"{model.design.name}.toml"
                design_file.write_bytes(design_text.encode("utf-8"))
            write_report(
                model, stage, design_file=design_file, fabrication=written.get("fabrication")
            )
        written["report"] = root / "report"
    return written


def export_warnings(written: dict) -> list:
    """The warnings of an export (the export process's own warnings do not reach the studio):
    those its fabrication recorded (``fabrication.json`` ``workshop.warnings``: a nester
    missing, the parts nested by shelves).

    Parameters
    ----------
    written : dict
        :func:`export`'s export name -> folder.

    Returns
    -------
    list of str
    """
    folder = written.get("fabrication")
    if folder is None:
        return []
    try:
        manifest = json.loads((Path(folder) / "fabrication.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    notes = (manifest.get("workshop") or {}).get("warnings") or []
    return [str(n) for n in notes]


def export_job(document: dict, *, name: str, base, out, alpha: float, what, design_text,
               limits: dict) -> tuple:  # fmt: skip
    """Build the model of design ``document`` (curve files read from ``base``) under ``limits``
    and :func:`export` it; what :class:`ExportProcess` runs in its process.

    Returns
    -------
    tuple
        ``(pid, written)``: the id of the process that exported, and :func:`export`'s dict.
    """
    with raised(**limits):
        model = CCUModel(Design(document, name=name, base=base))
        written = export(model, out, alpha=alpha, what=what, design_text=design_text)
    return os.getpid(), written


#: How much lower than the studio the export process runs (``os.nice``): the studio's page and
#: slider come first, the export takes the rest of the machine.
NICE = 19


def background() -> None:
    """Run this process (the export process) at a lower priority than the studio."""
    if hasattr(os, "nice"):
        try:
            os.nice(NICE)
        except OSError:  # not allowed here: the export runs at the studio's priority
            pass


class BackgroundProcess:
    """One process for a studio's slow jobs, started at the first job (``spawn``: a fresh
    interpreter, whatever threads the studio runs, at :data:`NICE`) and reused; a process that
    died is started again; :meth:`stop` ends it. The jobs hold the GIL for seconds (the nesting,
    the report's pictures, a design fit), which in the studio's process would stall the page."""

    def __init__(self):
        self._pool = None
        self._lock = threading.Lock()

    def run(self, job, *args, **kwargs):
        """``job(*args, **kwargs)`` in the process (``job`` a module-level function).

        Returns
        -------
        concurrent.futures.Future
            Of the job's result (or its exception).
        """
        from concurrent.futures import ProcessPoolExecutor
        from concurrent.futures.process import BrokenProcessPool

        with self._lock:
            for _ in range(2):  # a process that died (killed, out of memory) is started again
                if self._pool is None:
                    context = multiprocessing.get_context("spawn")
                    self._pool = ProcessPoolExecutor(
                        max_workers=1, mp_context=context, initializer=background
                    )
                try:
                    return self._pool.submit(job, *args, **kwargs)
                except BrokenProcessPool:
                    self._pool.shutdown(wait=False)
                    self._pool = None
            raise RuntimeError("the background process cannot be started")

    def stop(self) -> None:
        """Let the process end after the job under way, if any (queued ones are cancelled)."""
        with self._lock:
            pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)


class ExportProcess(BackgroundProcess):
    """The export process of a studio (:class:`BackgroundProcess`)."""

    def submit(self, model, out, *, alpha: float, what, design_text: str | None):
        """Export ``model`` (rebuilt in the export process from its design) into ``out``.

        Returns
        -------
        concurrent.futures.Future
            Of :func:`export_job`'s ``(pid, written)``.
        """
        design = model.design
        job = dict(
            name=design.name, base=design.base, out=str(out), alpha=alpha, what=tuple(what),
            design_text=design_text, limits=dataclasses.asdict(LIMITS),
        )  # fmt: skip
        return self.run(export_job, design.document, **job)
