"""The design report: one folder with ``index.html``, the viewer, the figures and the data.

``write_report`` runs every picture of the toolkit on one design and writes a page that shows
them with the key figures of the design (:mod:`compas_ccu.key_figures`) and links to every file
written.
"""

from __future__ import annotations

import html
import re
import shutil
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from compas_ccu import __version__
from compas_ccu.errors import CCUError, OptionError
from compas_ccu.io import write_compas_json, write_obj, write_path_table, write_structure_json
from compas_ccu.key_figures import FIGURES as KEY_FIGURES
from compas_ccu.key_figures import KeyFigures, key_figures
from compas_ccu.key_figures.text import (
    LOAD_CASE_COLUMNS,
    design_values_text,
    figure_rows,
    load_case_table,
    row_failed,
    thickness_rows,
    validation_rows,
    value_text,
)
from compas_ccu.thickness import ThickModel
from compas_ccu.viz.animation import mp4_available, write_animations
from compas_ccu.viz.colors import KIND_COLORS
from compas_ccu.viz.export import save_figure
from compas_ccu.viz.patterns import plot_cut_patterns
from compas_ccu.viz.pdf import write_pdf
from compas_ccu.viz.planarity import plot_planarity
from compas_ccu.viz.quadrants import plot_quadrants
from compas_ccu.viz.record import cell_text, design_record, read_fabrication, table_columns
from compas_ccu.viz.sequence import plot_deployment_sequence
from compas_ccu.viz.viewer import write_viewer
from compas_ccu.viz.views import plot_views

__all__ = ["write_report", "Report", "structural_section"]

FIGURES = (
    ("views-kind", "3D views, creases coloured by kind"),
    ("views-curvature", "3D views, plates coloured by their bending curvature |κ|"),
    ("views-alpha", "3D views, creases coloured by the reflection angle α"),
    ("cut-patterns", "Cut patterns of all plates: creases by kind, rulings as score lines"),
    ("sequence", "Deployment sequence from the flat-folded stack (paper Fig. 1)"),
    ("quadrants", "The four quadrants of the leading crease (paper Fig. 2)"),
    ("planarity", "Planarity of every crease along the deployment path (paper Fig. 6d)"),
)


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
    structure = model.deploy()
    alphas = np.linspace(0.0, model.alpha_design, int(steps) + 1)
    path_structures = model.path(alphas)
    figures_of_design = key_figures(model, structure, path=alphas)
    report.figures = figures_of_design.to_dict()
    try:
        report.figures["thickness"] = ThickModel(model).summary(path_states=int(steps) + 1)
    except CCUError as exc:
        report.skipped["thickness"] = str(exc)
    figures: dict = {}

    def inputs():
        if design_file is None:
            return
        dst = out / "design" / Path(design_file).name
        dst.parent.mkdir(exist_ok=True)
        shutil.copyfile(design_file, dst)
        report.files.append(dst)
        record["copy"] = dst

    def fabrication_files():
        if fab is None:
            return
        copied = []
        for rel in fab["files"]:
            dst = out / "fabrication" / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(fab["folder"] / rel, dst)
            copied.append(dst)
        fab["copies"] = copied
        report.files += copied

    def data():
        data_dir = out / "data"
        data_dir.mkdir(exist_ok=True)
        report.files += [
            write_structure_json(structure, data_dir / "structure.json"),
            write_obj(structure, data_dir / "structure.obj"),
            write_compas_json(structure, data_dir / "structure.compas.json"),
            write_path_table(path_structures, data_dir / "path.csv"),
        ]

    def figure(name):
        def run():
            fig = _make_figure(name, model, structure)
            paths = save_figure(fig, out / "figures" / name, formats=formats)
            figures[name] = paths
            report.files += paths

        return run

    def animation():
        paths = [out / "deployment.gif"]
        if mp4_available():
            paths.append(out / "deployment.mp4")
        else:
            report.skipped["deployment.mp4"] = (
                "no MP4 encoder: install the video extra (imageio-ffmpeg)"
            )
        report.files += write_animations(model, paths, frames=frames)  # one rendering

    def viewer():
        layout = None if fab is None else fab.get("layout")
        try:  # the fabrication's sheets as the cut patterns, when the folder has them
            page = write_viewer(model, out / "viewer.html", steps=steps, sheets=layout)
        except OptionError as exc:
            if layout is None:
                raise
            report.skipped["viewer sheets"] = f"{exc}; the viewer shows its own layout"
            page = write_viewer(model, out / "viewer.html", steps=steps)
        report.files.append(page)

    tasks = [("design file", inputs), ("fabrication files", fabrication_files)]
    tasks += [("data files", data)]
    tasks += [(f"figure {name}", figure(name)) for name, _ in FIGURES]
    tasks += [("animation", animation), ("viewer", viewer)]
    from tqdm.auto import tqdm

    bar = tqdm(tasks, desc="report", disable=not progress, file=sys.stderr, leave=False)
    for label, task in bar:
        bar.set_postfix_str(label)
        try:
            task()
        except CCUError as exc:  # a refusal, named; anything else is a bug and is raised
            report.skipped[label] = str(exc)
    bar.close()
    structural = ""
    shown = []
    if validation is not None:
        for src in validation_figures:
            src = Path(src)
            if src.exists():
                dst = out / "figures" / src.name
                dst.parent.mkdir(exist_ok=True)
                shutil.copyfile(src, dst)
                report.files.append(dst)
                shown.append(dst)
        structural = structural_section(validation, [_rel(p, out) for p in shown])
    checks = _check_rows(figures_of_design, report.figures.get("thickness"), validation_record)
    if pdf:
        try:
            report.pdf = write_pdf(
                out / "report.pdf",
                _pdf_blocks(figures_of_design, report, checks, figures, validation, shown),
                footer=_footer(figures_of_design, record),
            )
            report.files.append(report.pdf)
        except (CCUError, OSError) as exc:  # a refusal, or the disk
            report.skipped["report.pdf"] = str(exc)
    elapsed = time.perf_counter() - started
    page = _page(figures_of_design, structure, report, figures, elapsed, structural, checks)
    report.index.write_text(page, encoding="utf-8")
    report.files.append(report.index)
    return report


def _check_rows(k: KeyFigures, thickness, validation_record) -> list:
    """The key figures and checks, as ``ccu info`` words them (one definition)."""
    rows = figure_rows(k)
    if thickness:
        rows += thickness_rows(thickness)
    rows += validation_rows(validation_record)
    return rows


def _footer(k: KeyFigures, record: dict) -> str:
    sha = f" · sha256 {record['sha256'][:12]}" if record.get("sha256") else ""
    return f"{k.name} · compas_ccu {record['version']} · {record['date']}{sha}"


def _record_rows(record: dict) -> list:
    rows = [
        ("design file", record["file"] or "not given (the model was built in Python)"),
    ]
    if record["sha256"]:
        rows.append(("sha256", record["sha256"]))
    rows += [
        ("compas_ccu", f"{record['version']} (Python {record['python']})"),
        ("date (UTC)", record["date"]),
    ]
    rows.append(("units", "; ".join(f"{k} {v}" for k, v in record["units"].items())))
    return rows


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


# -- the page --------------------------------------------------------------------------------

_CSS = """
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; color: #222;
       margin: 0 auto; max-width: 1180px; padding: 1.2em 1.5em 3em; }
h1 { margin-bottom: 0.1em; } h2 { margin-top: 1.8em; border-bottom: 1px solid #ddd; }
tr.bad th, tr.bad td, p.bad { color: #b00020; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 0.85em; }
table.rows th { white-space: nowrap; }
.sub { color: #666; margin-top: 0; }
table { border-collapse: collapse; margin: 0.6em 0; }
td, th { padding: 0.25em 0.9em 0.25em 0; text-align: left; vertical-align: top; }
th { color: #555; font-weight: 600; } td.num { font-variant-numeric: tabular-nums; }
iframe { width: 100%; height: 720px; border: 1px solid #ddd; border-radius: 6px; }
figure { margin: 1.2em 0; } figure img { max-width: 100%; border: 1px solid #eee; }
figcaption { color: #444; font-size: 0.93em; }
.kind { display: inline-block; width: 0.9em; height: 0.9em; border-radius: 2px;
        vertical-align: -0.1em; margin-right: 0.3em; }
.skip { color: #a33; } code { font-size: 0.92em; }
"""


def _rel(path: Path, root: Path) -> str:
    return path.relative_to(root).as_posix()


def _html_text(text: str) -> str:
    """A row's text as HTML: a failed check (``** ... **``) in bold red."""
    return re.sub(r"\*\* (.+?) \*\*", r'<b class="skip">\1</b>', html.escape(text))


def _rows_table(rows, *, cls: str = "rows") -> str:
    body = "\n".join(
        f"<tr{' class=bad' if row_failed(text) else ''}><th>{html.escape(label)}</th>"
        f"<td>{_html_text(text)}</td></tr>"
        for label, text in rows
    )
    return f'<table class="{cls}">{body}</table>'


def _all_figures_table(k: KeyFigures) -> str:
    e = html.escape
    body = "\n".join(
        f"<tr><td><code>{e(f.name)}</code></td><td class=num>{e(value_text(f.name, k[f.name]))}"
        f"</td><td>{e(f.group)}</td><td>{e(f.doc)}</td></tr>"
        for f in KEY_FIGURES
    )
    return (
        "<details><summary>Every key figure (docs/key-figures.md)</summary><table>"
        "<tr><th>figure</th><th>value</th><th>group</th><th>meaning</th></tr>"
        f"{body}</table></details>"
    )


def _record_section(record: dict, root: Path) -> str:
    """The page's "Engineering record": file, hash, version, date, units, materials."""
    e = html.escape
    copy = record.get("copy")
    parts = [
        '<h2 id="record">Engineering record</h2>',
        _rows_table(_record_rows(record)),
    ]
    if copy is not None:
        parts.append(
            f'<p>The design file as read: <a href="{_rel(copy, root)}">{e(_rel(copy, root))}</a>'
            " (verbatim at the end of the page, under Design inputs).</p>"
        )
    if record["material"]:
        parts.append('<h3 id="materials">Material constants</h3>' + _rows_table(record["material"]))
    elif record["material_error"]:
        parts.append(f'<p class="skip">Material not modelled: {e(record["material_error"])}</p>')
    return "".join(parts)


def _inputs_section(record: dict) -> str:
    """The page's "Design inputs": the design file verbatim with its hash."""
    if record["text"] is None:
        return ""
    e = html.escape
    return (
        f'<h2 id="design-inputs">Design inputs: {e(record["file"])} as read</h2>'
        f'<p class="sub">sha256 <code>{e(record["sha256"])}</code></p>'
        f"<pre>{e(record['text'])}</pre>"
    )


def _fabrication_tables(fab: dict) -> list:
    """(title, columns, rows of cell strings) of the fabrication folder's tables."""
    out = []
    for key, title in (("sheets", "Sheets"), ("bom", "Bill of materials")):
        rows = fab.get(key)
        if rows:
            columns = table_columns(rows)
            out.append(
                (
                    f"{title} (fabrication.json: {key})",
                    columns,
                    [[cell_text(r.get(c)) for c in columns] for r in rows],
                )
            )
    return out


def _fabrication_section(fab: dict | None, root: Path) -> str:
    if fab is None:
        return ""
    e = html.escape
    m = fab["manifest"] or {}
    lines = []
    if m:
        facts = [f"design {m.get('design')}"] if m.get("design") else []
        if m.get("plates") is not None:
            facts.append(f"{m['plates']} plates")
        if fab["sheets"]:
            facts.append(f"{len(fab['sheets'])} sheets")
        if fab["utilisation"] is not None:
            facts.append(f"utilisation {fab['utilisation']:.1%}")
        if isinstance(m.get("units"), dict):
            facts.append("units " + ", ".join(f"{k} {v}" for k, v in m["units"].items()))
        lines.append(f"<p>{e(' · '.join(facts))}</p>")
    lines += [f'<p class="skip">{e(p)}</p>' for p in fab["problems"]]
    lines += [f'<p class="bad">check failed: {e(c)}</p>' for c in fab.get("failed_checks", [])]
    if fab.get("workshop_rows"):
        lines.append(f"<h3>Workshop</h3>{_rows_table(fab['workshop_rows'])}")
    if m and not fab["bom"] and not fab["sheets"]:
        lines.append(
            '<p class="sub">fabrication.json lists no sheets and no bill of materials (its keys '
            "<code>sheets</code>, <code>bom</code>).</p>"
        )
    for title, columns, rows in _fabrication_tables(fab):
        head = "".join(f"<th>{e(c)}</th>" for c in columns)
        body = "".join(
            "<tr>" + "".join(f"<td class=num>{e(c)}</td>" for c in r) + "</tr>" for r in rows
        )
        lines.append(f"<h3>{e(title)}</h3><table><tr>{head}</tr>{body}</table>")

    files = "\n".join(
        f'<tr><td><a href="{_rel(p, root)}">{e(_rel(p, root))}</a></td>'
        f"<td class=num>{_size(p)}</td></tr>"
        for p in fab.get("copies", [])
    )
    return (
        '<h2 id="fabrication">Fabrication</h2>'
        f'<p class="sub">From {e(str(fab["folder"]))} ({len(fab["files"])} files, copied into '
        "fabrication/)</p>" + "".join(lines) + f"<h3>Fabrication files</h3><table>{files}</table>"
    )


def _page(
    k: KeyFigures,
    structure,
    report: Report,
    figures: dict,
    elapsed: float,
    structural: str = "",
    checks=(),
) -> str:
    e = html.escape
    root = report.index.parent
    crease_rows = "\n".join(
        "<tr><td>c{id}</td><td>P{a} – P{b}</td><td>"
        '<span class="kind" style="background:{col}"></span>{kind}</td>'
        "<td class=num>{amin:.3f}° … {amax:.3f}°</td><td class=num>{sb:.3f}°</td>"
        "<td class=num>{pl:.1e} m</td></tr>".format(
            id=c["id"],
            a=c["plates"][0],
            b=c["plates"][1],
            col=KIND_COLORS.get(c["kind"], "#888"),
            kind=e(c["kind"]),
            amin=min(c["alpha"]),
            amax=max(c["alpha"]),
            sb=float(np.mean(c["sum_beta"])) if c["sum_beta"] else float("nan"),
            pl=c["planarity"],
        )
        for c in structure.creases
    )
    figs = []
    for name, caption in FIGURES:
        if name not in figures:
            continue
        paths = figures[name]
        png = next(p for p in paths if p.suffix == ".png")
        links = " · ".join(f'<a href="{_rel(p, root)}">{p.suffix[1:].upper()}</a>' for p in paths)
        figs.append(
            f'<figure id="{name}"><a href="{_rel(png, root)}"><img src="{_rel(png, root)}" '
            f'alt="{e(caption)}"></a><figcaption>{e(caption)} ({links})'
            "</figcaption></figure>"
        )
    anim = ""
    gif = root / "deployment.gif"
    if gif.exists():
        mp4 = root / "deployment.mp4"
        extra = ' · <a href="deployment.mp4">MP4</a>' if mp4.exists() else ""
        anim = (
            '<h2 id="animation">Deployment animation</h2><figure><img src="deployment.gif" '
            'alt="deployment animation"><figcaption>From the flat-folded stack to the design '
            f'state (<a href="deployment.gif">GIF</a>{extra})</figcaption></figure>'
        )
    viewer = (
        '<iframe src="viewer.html" title="interactive viewer"></iframe>'
        '<p><a href="viewer.html">Open the viewer on its own page</a> (works offline).</p>'
        if (root / "viewer.html").exists()
        else '<p class="skip">The viewer could not be written (see below).</p>'
    )
    skipped = "".join(
        f"<li class=skip>{e(k)}: {e(v)}</li>" for k, v in sorted(report.skipped.items())
    )
    files = sorted(set(report.files) | {report.index})
    file_rows = "\n".join(
        f'<tr><td><a href="{_rel(p, root)}">{e(_rel(p, root))}</a></td>'
        f"<td class=num>{_size(p)}</td></tr>"
        for p in files
        if p != report.index
    )
    description = f'<p class="sub">{e(k.description)}</p>' if k.description else ""
    pdf = ' · <a href="report.pdf">PDF version</a>' if report.pdf is not None else ""
    r = report.record
    sha = f" · design sha256 <code>{e(r['sha256'][:12])}</code>" if r.get("sha256") else ""
    per_plate = _per_plate(report.figures.get("thickness"))
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"> <meta name="viewport" content="width=device-width,
initial-scale=1"> <title>{e(k.name)}: compas_ccu report</title><style>{_CSS}</style></head> <body>
<h1>{e(k.name)}</h1>{description} <p class="sub">compas_ccu {e(__version__)} · curved-crease
unfolding report · {e(r.get("date", ""))}{sha} · written in {elapsed:.1f} s{pdf}</p>
{_record_section(r, root)}
<h2 id="key-figures">Key figures and checks</h2><p class="sub">As <code>ccu info</code> prints
them; lengths in metres, angles in degrees.</p>{_rows_table(checks)}{per_plate}
{_all_figures_table(k)} <h3>Creases at the design state</h3>
<table><tr><th>crease</th><th>plates</th><th>kind</th><th>α range</th><th>mean Σβ</th>
<th>planarity</th></tr>{crease_rows}</table> {structural}
{_fabrication_section(report.fabrication, root)}
<h2 id="viewer">Interactive viewer</h2>{viewer} {anim} <h2
id="figures">Figures</h2>{"".join(figs)} {_inputs_section(r)} {
        "<h2>Not produced</h2><ul>" + skipped + "</ul>" if skipped else ""
    } <h2 id="files">Files</h2><table>{file_rows}</table> </body></html>
"""


def _per_plate(t) -> str:
    if not t:
        return ""
    u = t["bending"]["utilisation_per_plate"]
    return (
        "<p>Bending utilisation per plate: "
        + ", ".join(f"P{i}: {v:.3f}" for i, v in enumerate(u))
        + "</p>"
    )


def _pdf_blocks(k: KeyFigures, report: Report, checks, figures, validation, shown) -> list:
    """The report as blocks of :func:`compas_ccu.viz.pdf.write_pdf`."""
    r = report.record
    blocks = [
        (
            "title",
            k.name,
            (k.description + " · " if k.description else "")
            + f"compas_ccu {r['version']} · curved-crease unfolding report · {r['date']}",
        ),
        ("heading", "Engineering record"),
        ("rows", _record_rows(r)),
        ("heading", "Key figures and checks"),
        ("rows", checks),
    ]
    if r["material"]:
        blocks += [("heading", "Material constants"), ("rows", r["material"])]
    c = (validation or {}).get("checks")
    if c and "cases" in c:
        blocks += [
            ("heading", "Structural checks (FE, load cases)"),
            ("paragraph", f"{validation.get('engine', '')} {validation.get('mode', '')}"),
        ]
        heading, table, governing = load_case_table(c)
        blocks += [
            ("paragraph", heading),
            (
                "table",
                list(LOAD_CASE_COLUMNS),
                [cells if ok else [f"** {cells[0]} **", *cells[1:]] for cells, ok in table],
            ),
            *([("paragraph", design_values_text(c))] if design_values_text(c) else []),
            ("paragraph", f"governing: {governing}"),
        ]
        blocks += [
            ("image", p, "Deflection under the characteristic loads of every case") for p in shown
        ]
    fab = report.fabrication
    if fab is not None:
        blocks += [("heading", "Fabrication"), ("paragraph", f"From {fab['folder']}")]
        blocks += [("paragraph", p) for p in fab["problems"]]
        if fab.get("failed_checks"):
            blocks.append(("rows", [("check failed", f"** {c} **") for c in fab["failed_checks"]]))
        if fab.get("workshop_rows"):
            blocks.append(("rows", fab["workshop_rows"]))
        if fab["utilisation"] is not None:
            blocks.append(("paragraph", f"Sheet utilisation {fab['utilisation']:.1%}"))
        for title, columns, rows in _fabrication_tables(fab):
            blocks += [("paragraph", title), ("table", columns, rows)]

        blocks += [
            ("paragraph", "Files (in fabrication/ beside this report):"),
            ("lines", fab["files"]),
        ]
    for name, caption in FIGURES:
        if name in figures:
            png = next(p for p in figures[name] if p.suffix == ".png")
            blocks.append(("image", png, caption))
    if r["text"] is not None:
        blocks += [
            ("heading", f"Design inputs: {r['file']}"),
            ("paragraph", f"sha256 {r['sha256']}"),
            ("code", r["text"]),
        ]
    if report.skipped:
        blocks += [
            ("heading", "Not produced"),
            ("lines", [f"{a}: {b}" for a, b in sorted(report.skipped.items())]),
        ]
    return blocks


def _size(path: Path) -> str:
    n = path.stat().st_size
    for unit in ("B", "kB", "MB", "GB"):
        if n < 1000 or unit == "GB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1000.0
    return f"{n} B"


def structural_section(validation: dict, pictures=()) -> str:
    """The page's "Structural checks" section from a ``validation.json`` (its load cases).

    Examples
    --------
    >>> structural_section({"checks": None})
    ''
    """
    c = validation.get("checks")
    if not c or "cases" not in c:  # no checks, or a validation.json from before load cases
        return ""
    e = html.escape
    heading, table, governing = load_case_table(c)
    rows = []
    for cells, ok in table:
        tds = "".join(f"<td class=num>{e(v)}</td>" for v in cells[2:])
        rows.append(
            f"<tr{'' if ok else ' class=bad'}><th>{e(cells[0])}</th><td>{e(cells[1])}</td>{tds}"
            "</tr>"
        )
    figs = "".join(
        f'<figure><a href="{e(p)}"><img src="{e(p)}" alt="deflection of every load case">'
        "</a><figcaption>Deflection under the characteristic loads of every case (one colour "
        "scale; displacements magnified as printed)</figcaption></figure>"
        for p in pictures
    )
    return (
        '<h2 id="structural">Structural checks (FE, load cases)</h2>'
        f"<p>{e(validation.get('engine', ''))} · {e(validation.get('mode', ''))} · "
        f"{e(heading)} · governing: {e(governing)}</p>"
        + (f"<p>{e(design_values_text(c))}</p>" if design_values_text(c) else "")
        + "<table><tr>"
        + "".join(f"<th>{e(t)}</th>" for t in LOAD_CASE_COLUMNS)
        + "</tr>"
        + "".join(rows)
        + "</table>"
        + figs
    )
