"""The report's page: the HTML of ``index.html``.

:func:`page_html` renders what :func:`compas_ccu.viz.report.write_report` wrote (the record,
the key figures and checks, the structural and fabrication sections, the viewer, the
animation, the figures, the design file and the files) as one HTML page. Rows of text come from
:mod:`compas_ccu.key_figures.text` and :mod:`compas_ccu.viz.report_content`, so the terminal,
the page and the PDF say the same; the PDF's blocks are :mod:`compas_ccu.viz.report_blocks`
(:func:`pdf_blocks`, :func:`pdf_footer`, importable from here too).
"""

from __future__ import annotations

import html
import re
from pathlib import Path

import numpy as np

from compas_ccu import __version__
from compas_ccu.key_figures import FIGURES as KEY_FIGURES
from compas_ccu.key_figures import KeyFigures
from compas_ccu.key_figures.text import (
    LOAD_CASE_COLUMNS,
    design_values_text,
    load_case_table,
    row_failed,
    value_text,
)
from compas_ccu.viz.colors import KIND_COLORS
from compas_ccu.viz.report_blocks import pdf_blocks, pdf_footer
from compas_ccu.viz.report_content import FIGURES, check_rows, fabrication_tables, record_rows

__all__ = [
    "FIGURES",
    "page_html",
    "pdf_blocks",
    "pdf_footer",
    "check_rows",
    "structural_section",
    "fabrication_section",
    "relative_path",
]

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


def relative_path(path: Path, root: Path) -> str:
    """``path`` relative to the report folder ``root``, as a link (POSIX separators)."""
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
        _rows_table(record_rows(record)),
    ]
    if copy is not None:
        parts.append(
            f'<p>The design file as read: <a href="{relative_path(copy, root)}">'
            f"{e(relative_path(copy, root))}</a>"
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


def fabrication_section(fab: dict | None, root: Path) -> str:
    """The page's "Fabrication" section: the folder's facts, problems, failed checks, workshop
    rows, sheets and bill of materials, and links to its files copied under ``root``.

    Parameters
    ----------
    fab : dict or None
        :func:`compas_ccu.viz.record.read_fabrication` (with ``copies``); None: no section.
    root : Path
        The report folder.
    """
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
    for title, columns, rows in fabrication_tables(fab):
        head = "".join(f"<th>{e(c)}</th>" for c in columns)
        body = "".join(
            "<tr>" + "".join(f"<td class=num>{e(c)}</td>" for c in r) + "</tr>" for r in rows
        )
        lines.append(f"<h3>{e(title)}</h3><table><tr>{head}</tr>{body}</table>")

    files = "\n".join(
        f'<tr><td><a href="{relative_path(p, root)}">{e(relative_path(p, root))}</a></td>'
        f"<td class=num>{_size(p)}</td></tr>"
        for p in fab.get("copies", [])
    )
    return (
        '<h2 id="fabrication">Fabrication</h2>'
        f'<p class="sub">From {e(str(fab["folder"]))} ({len(fab["files"])} files, copied into '
        "fabrication/)</p>" + "".join(lines) + f"<h3>Fabrication files</h3><table>{files}</table>"
    )


def page_html(
    k: KeyFigures,
    structure,
    report,
    figures: dict,
    elapsed: float,
    structural: str = "",
    checks=(),
) -> str:
    """The report page, ``index.html``.

    Parameters
    ----------
    k : KeyFigures
        The design's key figures.
    structure : compas_ccu.structure.Structure
        The design state (its creases in a table).
    report : compas_ccu.viz.report.Report
        What was written (files, what was not produced, the record, the fabrication).
    figures : dict
        Figure name (:data:`FIGURES`) to the paths written.
    elapsed : float
        Seconds the report took.
    structural : str
        :func:`structural_section`.
    checks : list of (str, str)
        :func:`check_rows`.
    """
    e = html.escape
    root = report.index.parent
    skipped = "".join(
        f"<li class=skip>{e(k)}: {e(v)}</li>" for k, v in sorted(report.skipped.items())
    )
    files = sorted(set(report.files) | {report.index})
    file_rows = "\n".join(
        f'<tr><td><a href="{relative_path(p, root)}">{e(relative_path(p, root))}</a></td>'
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
<th>planarity</th></tr>{_crease_rows(structure)}</table> {structural}
{fabrication_section(report.fabrication, root)}
<h2 id="viewer">Interactive viewer</h2>{_viewer_html(root)} {_animation_html(root)} <h2
id="figures">Figures</h2>{_figures_html(figures, root)} {_inputs_section(r)} {
        "<h2>Not produced</h2><ul>" + skipped + "</ul>" if skipped else ""
    } <h2 id="files">Files</h2><table>{file_rows}</table> </body></html>
"""


def _crease_rows(structure) -> str:
    """The rows of the creases table: plates, kind, α range, mean Σβ, planarity."""
    e = html.escape
    return "\n".join(
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


def _figures_html(figures: dict, root: Path) -> str:
    """Every figure written: its PNG, caption and links to every format."""
    e = html.escape
    figs = []
    for name, caption in FIGURES:
        if name not in figures:
            continue
        paths = figures[name]
        png = next(p for p in paths if p.suffix == ".png")
        links = " · ".join(
            f'<a href="{relative_path(p, root)}">{p.suffix[1:].upper()}</a>' for p in paths
        )
        figs.append(
            f'<figure id="{name}"><a href="{relative_path(png, root)}">'
            f'<img src="{relative_path(png, root)}" '
            f'alt="{e(caption)}"></a><figcaption>{e(caption)} ({links})'
            "</figcaption></figure>"
        )
    return "".join(figs)


def _animation_html(root: Path) -> str:
    """The animation section, if the GIF was written (with a link to the MP4, if any)."""
    if not (root / "deployment.gif").exists():
        return ""
    mp4 = root / "deployment.mp4"
    extra = ' · <a href="deployment.mp4">MP4</a>' if mp4.exists() else ""
    return (
        '<h2 id="animation">Deployment animation</h2><figure><img src="deployment.gif" '
        'alt="deployment animation"><figcaption>From the flat-folded stack to the design '
        f'state (<a href="deployment.gif">GIF</a>{extra})</figcaption></figure>'
    )


def _viewer_html(root: Path) -> str:
    """The viewer in a frame with a link to its page, or a note that it was not written."""
    if (root / "viewer.html").exists():
        return (
            '<iframe src="viewer.html" title="interactive viewer"></iframe>'
            '<p><a href="viewer.html">Open the viewer on its own page</a> (works offline).</p>'
        )
    return '<p class="skip">The viewer could not be written (see below).</p>'


def _per_plate(t) -> str:
    if not t:
        return ""
    u = t["bending"]["utilisation_per_plate"]
    return (
        "<p>Bending utilisation per plate: "
        + ", ".join(f"P{i}: {v:.3f}" for i, v in enumerate(u))
        + "</p>"
    )


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
