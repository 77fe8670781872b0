"""The design report: one folder with ``index.html``, the viewer, the figures and the data.

``write_report`` runs every picture of the toolkit on one design and writes a page that shows
them with the key figures of the design (:mod:`compas_ccu.key_figures`) and links to every file
written. Each file group is one task (design file, fabrication files, data, every figure, the
animation, the viewer); a task that is refused (a :class:`compas_ccu.errors.CCUError`, e.g. a
missing optional extra) is listed under "Not produced", any other exception is raised. The page
is :mod:`compas_ccu.viz.report_page`, the PDF's blocks :mod:`compas_ccu.viz.report_blocks`.
"""

from __future__ import annotations

import shutil
import sys
import time
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import numpy as np

from compas_ccu.errors import CCUError, OptionError
from compas_ccu.io import write_compas_json, write_obj, write_path_table, write_structure_json
from compas_ccu.key_figures import KeyFigures, key_figures
from compas_ccu.thickness import ThickModel
from compas_ccu.viz.animation import mp4_available, write_animations
from compas_ccu.viz.export import save_figure
from compas_ccu.viz.patterns import plot_cut_patterns
from compas_ccu.viz.pdf import write_pdf
from compas_ccu.viz.planarity import plot_planarity
from compas_ccu.viz.quadrants import plot_quadrants
from compas_ccu.viz.record import design_record, read_fabrication
from compas_ccu.viz.report_blocks import pdf_blocks, pdf_footer
from compas_ccu.viz.report_content import FIGURES, check_rows
from compas_ccu.viz.report_page import page_html, relative_path, structural_section
from compas_ccu.viz.sequence import plot_deployment_sequence
from compas_ccu.viz.viewer import write_viewer
from compas_ccu.viz.views import plot_views

__all__ = ["write_report", "Report", "structural_section", "FIGURES"]


@dataclass
class Report:
    """What :func:`write_report` wrote.

    Attributes
    ----------
    index : Path
        The report page.
    pdf : Path or None
        The PDF version of the report (``report.pdf``), if written.
    files : list of Path
        Every file written (the page included).
    skipped : dict
        Picture name to the reason it could not be made (e.g. no MP4 encoder).
    figures : dict
        Key figures of the design shown on the page
        (:meth:`compas_ccu.key_figures.KeyFigures.to_dict`, the path figures over the ``steps``
        intervals of the path) and under ``thickness`` the thick-plate summary
        (:meth:`compas_ccu.thickness.ThickModel.summary`).
    record : dict
        The engineering record (:func:`compas_ccu.viz.record.design_record`: design file,
        SHA-256, version, date, units, material constants).
    fabrication : dict or None
        The fabrication folder as read (:func:`compas_ccu.viz.record.read_fabrication`).
    """

    index: Path
    pdf: Path | None = None
    files: list = field(default_factory=list)
    skipped: dict = field(default_factory=dict)
    figures: dict = field(default_factory=dict)
    record: dict = field(default_factory=dict)
    fabrication: dict | None = None


def write_report(
    model,
    out,
    *,
    steps: int = 24,
    frames: int = 48,
    formats=("png", "svg"),
    progress: bool = False,
    validation: dict | None = None,
    validation_figures=(),
    validation_record: dict | None = None,
    design_file=None,
    fabrication=None,
    pdf: bool = True,
) -> Report:
    """Write the report of a design into the folder ``out``.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    out : str or Path
        Output folder (created).
    steps : int
        Intervals of the deployment path (viewer slider, path table, planarity).
    frames : int
        Frames of the animation (rendered once for the GIF and the MP4).
    formats : sequence of str
        Figure formats (PNG is always written: the page shows it).
    progress : bool
        Show a progress bar on stderr.
    validation : dict, optional
        A ``validation.json`` of this design (``ccu validate``): the page gets a "Structural
        checks" section with its load cases.
    validation_figures : sequence of path
        Pictures of that validation to copy into ``out/figures`` and show there (e.g.
        ``fe_load_cases.png``).
    validation_record : dict, optional
        The record of that validation (:func:`compas_ccu.fea.record.last_validation`): its
        headline joins the key figures and checks, worded as by ``ccu info``.
    design_file : str or Path, optional
        The design TOML the model was loaded from: copied into ``out/design/`` and shown
        verbatim with its SHA-256 (the engineering record).
    fabrication : str or Path, optional
        A folder written by ``ccu fabricate`` for this design: copied into
        ``out/fabrication/``; the page links every file and shows its sheets and bill of
        materials (:func:`compas_ccu.viz.record.read_fabrication`), and the viewer's cut
        patterns are its sheets (its ``sheets.json``; without one, the viewer's own layout).
    pdf : bool
        Also write ``report.pdf``: the record, the key figures and checks, the FE and
        fabrication sections, the design file and every figure.

    Returns
    -------
    Report

    Raises
    ------
    compas_ccu.errors.OptionError
        Bad ``steps``; ``fabrication`` is no folder or the fabrication of another design.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> import tempfile
    >>> r = write_report(load_model("examples/cone.toml"), tempfile.mkdtemp(),
    ...                  steps=4, frames=3, design_file="examples/cone.toml", pdf=False)
    >>> r.index.name, r.figures["plates"], len(r.record["sha256"])
    ('index.html', 2, 64)
    """
    if int(steps) != steps or steps < 1:
        raise OptionError(f"steps must be an integer >= 1, got {steps!r}")
    formats = tuple(dict.fromkeys(("png", *formats)))
    out = Path(out)
    record = design_record(model, design_file)
    fab = None
    if fabrication is not None:  # read (and refused) before any work
        fab = read_fabrication(fabrication, design=model.design.name, sha256=record["sha256"])
    out.mkdir(parents=True, exist_ok=True)
    report = Report(index=out / "index.html", record=record, fabrication=fab)
    started = time.perf_counter()
    job = _start(model, out, report, steps, frames, formats, design_file)
    _run(_tasks(job), progress, report)
    structural, shown = "", []
    if validation is not None:
        shown = _copy_validation_figures(out, report, validation_figures)
        structural = structural_section(validation, [relative_path(p, out) for p in shown])
    checks = check_rows(job.key_figures, report.figures.get("thickness"), validation_record)
    if pdf:
        _write_pdf(job, checks, validation, shown)
    elapsed = time.perf_counter() - started
    page = page_html(
        job.key_figures, job.structure, report, job.figures, elapsed, structural, checks
    )
    report.index.write_text(page, encoding="utf-8")
    report.files.append(report.index)
    return report


@dataclass
class _Job:
    """What the tasks of one report share: the model, its states, the folder, the results."""

    model: object
    out: Path
    report: Report
    steps: int  # as given (the viewer checks it again)
    frames: int
    formats: tuple
    design_file: object
    structure: object
    path_structures: list
    key_figures: KeyFigures
    figures: dict = field(default_factory=dict)  # name: the paths of a figure written


def _start(model, out, report, steps, frames, formats, design_file) -> _Job:
    """Deploy the model, compute its path and key figures, and its thick-plate summary (a
    refusal there is noted under "Not produced")."""
    structure = model.deploy()
    alphas = np.linspace(0.0, model.alpha_design, int(steps) + 1)
    path_structures = model.path(alphas)
    figures_of_design = key_figures(model, structure, path=alphas)
    report.figures = figures_of_design.to_dict()
    try:
        report.figures["thickness"] = ThickModel(model).summary(path_states=int(steps) + 1)
    except CCUError as exc:
        report.skipped["thickness"] = str(exc)
    return _Job(
        model=model,
        out=out,
        report=report,
        steps=steps,
        frames=frames,
        formats=formats,
        design_file=design_file,
        structure=structure,
        path_structures=path_structures,
        key_figures=figures_of_design,
    )


def _tasks(job: _Job) -> list:
    """(label, task) of every file group of the report, in the order they are written."""
    tasks = [
        ("design file", lambda: _copy_design_file(job)),
        ("fabrication files", lambda: _copy_fabrication(job)),
        ("data files", lambda: _write_data(job)),
    ]
    tasks += [(f"figure {name}", partial(_write_figure, job, name)) for name, _ in FIGURES]
    tasks += [("animation", lambda: _write_animation(job)), ("viewer", lambda: _write_viewer(job))]
    return tasks


def _run(tasks: list, progress: bool, report: Report) -> None:
    """Run the tasks (with a progress bar); a refusal is noted under "Not produced".

    Only a :class:`compas_ccu.errors.CCUError` (a refusal, named: e.g. a missing optional extra,
    :class:`compas_ccu.errors.MissingExtraError`) becomes a note; any other exception is a bug
    and reaches the caller.
    """
    from tqdm.auto import tqdm

    bar = tqdm(tasks, desc="report", disable=not progress, file=sys.stderr, leave=False)
    for label, task in bar:
        bar.set_postfix_str(label)
        try:
            task()
        except CCUError as exc:  # a refusal, named; anything else is a bug and is raised
            report.skipped[label] = str(exc)
    bar.close()


def _copy_design_file(job: _Job) -> None:
    """The design file into ``design/`` (the record links the copy)."""
    if job.design_file is None:
        return
    dst = job.out / "design" / Path(job.design_file).name
    dst.parent.mkdir(exist_ok=True)
    shutil.copyfile(job.design_file, dst)
    job.report.files.append(dst)
    job.report.record["copy"] = dst


def _copy_fabrication(job: _Job) -> None:
    """Every file of the fabrication folder into ``fabrication/``."""
    fab = job.report.fabrication
    if fab is None:
        return
    copied = []
    for rel in fab["files"]:
        dst = job.out / "fabrication" / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(fab["folder"] / rel, dst)
        copied.append(dst)
    fab["copies"] = copied
    job.report.files += copied


def _write_data(job: _Job) -> None:
    """``data/``: the deployed structure (JSON, OBJ, COMPAS JSON) and the path table."""
    data_dir = job.out / "data"
    data_dir.mkdir(exist_ok=True)
    job.report.files += [
        write_structure_json(job.structure, data_dir / "structure.json"),
        write_obj(job.structure, data_dir / "structure.obj"),
        write_compas_json(job.structure, data_dir / "structure.compas.json"),
        write_path_table(job.path_structures, data_dir / "path.csv"),
    ]


def _write_figure(job: _Job, name: str) -> None:
    """One figure of :data:`FIGURES` into ``figures/``, in every format."""
    fig = _make_figure(name, job.model, job.structure)
    paths = save_figure(fig, job.out / "figures" / name, formats=job.formats)
    job.figures[name] = paths
    job.report.files += paths


def _write_animation(job: _Job) -> None:
    """``deployment.gif`` and, with an encoder, ``deployment.mp4`` (one rendering)."""
    paths = [job.out / "deployment.gif"]
    if mp4_available():
        paths.append(job.out / "deployment.mp4")
    else:
        job.report.skipped["deployment.mp4"] = (
            "no MP4 encoder: install the video extra (imageio-ffmpeg)"
        )
    job.report.files += write_animations(job.model, paths, frames=job.frames)


def _write_viewer(job: _Job) -> None:
    """``viewer.html``: its cut patterns are the fabrication's sheets when the folder has them
    (a nesting it refuses: the viewer's own layout, and a note)."""
    fab = job.report.fabrication
    layout = None if fab is None else fab.get("layout")
    path = job.out / "viewer.html"
    try:
        page = write_viewer(job.model, path, steps=job.steps, sheets=layout)
    except OptionError as exc:
        if layout is None:
            raise
        job.report.skipped["viewer sheets"] = f"{exc}; the viewer shows its own layout"
        page = write_viewer(job.model, path, steps=job.steps)
    job.report.files.append(page)


def _copy_validation_figures(out: Path, report: Report, pictures) -> list:
    """The validation's pictures that exist, copied into ``figures/``."""
    shown = []
    for src in pictures:
        src = Path(src)
        if src.exists():
            dst = out / "figures" / src.name
            dst.parent.mkdir(exist_ok=True)
            shutil.copyfile(src, dst)
            report.files.append(dst)
            shown.append(dst)
    return shown


def _write_pdf(job: _Job, checks: list, validation, shown: list) -> None:
    """``report.pdf``; a refusal (a :class:`compas_ccu.errors.CCUError`) is noted under "Not
    produced", anything else is raised."""
    report = job.report
    blocks = pdf_blocks(job.key_figures, report, checks, job.figures, validation, shown)
    try:
        report.pdf = write_pdf(
            job.out / "report.pdf", blocks, footer=pdf_footer(job.key_figures, report.record)
        )
    except CCUError as exc:  # a refusal, named; anything else is a bug and is raised
        report.skipped["report.pdf"] = str(exc)
        return
    report.files.append(report.pdf)


def _make_figure(name, model, structure):
    if name.startswith("views-"):
        return plot_views(structure, color_by=name.split("-", 1)[1])
    if name == "cut-patterns":
        return plot_cut_patterns(structure)
    if name == "sequence":
        return plot_deployment_sequence(model)
    if name == "quadrants":
        return plot_quadrants(model.design)
    if name == "planarity":
        return plot_planarity(model)
    raise OptionError(f"unknown figure {name!r}")
