"""The design report: one folder with ``index.html``, the viewer, the figures and the data.

``write_report`` runs every picture of the toolkit on one design and writes a page that shows
them with the key figures of the design (:mod:`compas_ccu.key_figures`) and links to every file
written.
"""

from __future__ import annotations

import html
import shutil
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from compas_ccu import __version__
from compas_ccu.errors import CCUError, OptionError
from compas_ccu.io import write_compas_json, write_obj, write_path_table, write_structure_json
from compas_ccu.key_figures import KeyFigures, key_figures
from compas_ccu.thickness import ThickModel
from compas_ccu.thickness.bending import bending_verdict
from compas_ccu.thickness.model import collision_text
from compas_ccu.viz.animation import mp4_available, write_animation
from compas_ccu.viz.colors import KIND_COLORS
from compas_ccu.viz.export import save_figure
from compas_ccu.viz.patterns import plot_cut_patterns
from compas_ccu.viz.planarity import plot_planarity
from compas_ccu.viz.quadrants import plot_quadrants
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
    files : list of Path
        Every file written (the page included).
    skipped : dict
        Picture name to the reason it could not be made (e.g. no MP4 encoder).
    figures : dict
        Key figures of the design shown on the page
        (:meth:`compas_ccu.key_figures.KeyFigures.to_dict`, the path figures over the ``steps``
        intervals of the path) and under ``thickness`` the thick-plate summary
        (:meth:`compas_ccu.thickness.ThickModel.summary`).
    """

    index: Path
    files: list = field(default_factory=list)
    skipped: dict = field(default_factory=dict)
    figures: dict = field(default_factory=dict)


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
        Frames of the animation.
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

    Returns
    -------
    Report

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> import tempfile
    >>> r = write_report(load_model("examples/cone.toml"), tempfile.mkdtemp(),
    ...                  steps=4, frames=3)
    >>> r.index.name, r.figures["plates"]
    ('index.html', 2)
    """
    if int(steps) != steps or steps < 1:
        raise OptionError(f"steps must be an integer >= 1, got {steps!r}")
    formats = tuple(dict.fromkeys(("png", *formats)))
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    report = Report(index=out / "index.html")
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

    def animation(fmt):
        def run():
            if fmt == "mp4" and not mp4_available():
                report.skipped["deployment.mp4"] = (
                    "no MP4 encoder: install the video extra (imageio-ffmpeg)"
                )
                return
            report.files.append(write_animation(model, out / f"deployment.{fmt}", frames=frames))

        return run

    def viewer():
        report.files.append(write_viewer(model, out / "viewer.html", steps=steps))

    tasks = [("data files", data)]
    tasks += [(f"figure {name}", figure(name)) for name, _ in FIGURES]
    tasks += [("animation gif", animation("gif")), ("animation mp4", animation("mp4"))]
    tasks += [("viewer", viewer)]
    from tqdm.auto import tqdm

    bar = tqdm(tasks, desc="report", disable=not progress, file=sys.stderr, leave=False)
    for label, task in bar:
        bar.set_postfix_str(label)
        try:
            task()
        except (CCUError, ValueError) as exc:
            report.skipped[label] = str(exc)
    bar.close()
    structural = ""
    if validation is not None:
        shown = []
        for src in validation_figures:
            src = Path(src)
            if src.exists():
                dst = out / "figures" / src.name
                dst.parent.mkdir(exist_ok=True)
                shutil.copyfile(src, dst)
                report.files.append(dst)
                shown.append(dst)
        structural = structural_section(validation, [_rel(p, out) for p in shown])
    elapsed = time.perf_counter() - started
    page = _page(figures_of_design, structure, report, figures, elapsed, structural)
    report.index.write_text(page, encoding="utf-8")
    report.files.append(report.index)
    return report


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
tr.bad th, tr.bad td { color: #b00020; }
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


def _fmt(x, digits=4) -> str:
    return f"{x:.{digits}g}"


def _rel(path: Path, root: Path) -> str:
    return path.relative_to(root).as_posix()


def _page(
    k: KeyFigures, structure, report: Report, figures: dict, elapsed: float, structural: str = ""
) -> str:
    e = html.escape
    root = report.index.parent
    kinds = ", ".join(
        f'<span class="kind" style="background:{KIND_COLORS.get(c, "#888")}"></span>{v} {e(c)}'
        for c, v in k.crease_kind_counts().items()
    )
    bbox = " × ".join(f"{v:.3f}" for v in (k.plan_x, k.plan_y, k.height))
    rows = [
        ("Span (leading crease chord)", f"{k.crease_span:.4f} m"),
        ("Rise", f"{k.crease_rise:.4f} m"),
        ("Bounding box (x × y × z)", f"{bbox} m"),
        ("Plates", str(k.plates)),
        ("Creases", f"{k.creases} ({kinds})" if k.creases else "0"),
        ("Segments per crease", str(k.segments)),
        ("Design α (reference vertex)", f"{k.alpha_design:g}°"),
        ("α along the creases", f"{k.alpha_min:.3f}° … {k.alpha_max:.3f}°"),
        ("Deployment limit", f"{k.alpha_limit:.4f}°"),
        ("First self-overlap of a crease", f"{k.overlap_alpha:.4f}°"),
        ("Flat-folded stack footprint", f"{k.stack_x:.3f} × {k.stack_y:.3f} m"),
    ]
    inv = [
        ("Isometry (quad sides and diagonals)", k.isometry_relative),
        ("Quad planarity", k.quad_planarity_relative),
        ("Hinge coincidence", k.hinge_gap_relative),
        ("Mirror symmetry", k.mirror_error_relative),
        ("Crease planarity, largest along the path", k.crease_planarity_path_relative),
    ]
    key_rows = "\n".join(f"<tr><th>{e(a)}</th><td class=num>{b}</td></tr>" for a, b in rows)
    inv_rows = "\n".join(f"<tr><th>{e(a)}</th><td class=num>{b:.1e}</td></tr>" for a, b in inv)
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
    thick = _thickness_section(report.figures.get("thickness"))
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"> <meta name="viewport" content="width=device-width,
initial-scale=1"> <title>{e(k.name)}: compas_ccu report</title><style>{_CSS}</style></head> <body>
<h1>{e(k.name)}</h1>{description} <p class="sub">compas_ccu {e(__version__)} · curved-crease
unfolding report · written in {elapsed:.1f} s</p> <h2 id="viewer">Interactive viewer</h2>{viewer}
<h2 id="key-figures">Key figures</h2><table>{key_rows}</table> <h3>Invariant errors (relative to the
structure size {k.size:.3f} m; exact below 1e-9)</h3>
<table>{inv_rows}</table> <h3>Creases at the design state</h3>
<table><tr><th>crease</th><th>plates</th><th>kind</th><th>α range</th><th>mean Σβ</th>
<th>planarity</th></tr>{crease_rows}</table> {thick} {structural} {anim} <h2
id="figures">Figures</h2>{"".join(figs)} {
        "<h2>Not produced</h2><ul>" + skipped + "</ul>" if skipped else ""
    } <h2 id="files">Files</h2><table>{file_rows}</table> </body></html>
"""


def _thickness_section(t) -> str:
    """The page's "Thickness and bending" section from ``ThickModel.summary()``."""
    if not t:
        return ""
    e = html.escape
    b, c = t["bending"], t["collisions"]
    collide = e(collision_text(c, degree="°"))
    if c["first"] is not None:
        collide = f'<b class="skip">{collide}</b>'
    worst = b["worst"]
    verdict = bending_verdict(b["exceeded"], b["basis"])
    verdict = f'<b class="skip">{e(verdict)}</b>' if b["exceeded"] else e(verdict)
    pairs = t["pairing"]
    basis = b["basis"]
    design = basis["code"] != "characteristic"
    basis_line = (
        f"{basis['basis']}: f_d = k_mod · f_k / γ_M with k_mod = {basis['k_mod']:g}, "
        f"γ_M = {basis['gamma_M']:g} ({basis['source']})"
        if design
        else "characteristic strengths f_k (k_mod = γ_M = 1)"
    )
    rows = [
        ("Plates", f"{t['thickness'] * 1e3:.4g} mm {e(t['material'])}, grain {t['grain']:g}°"),
        ("Flat-folded stack height (Σt)", f"{t['stack_height'] * 1e3:.4g} mm"),
        ("Stack order, bottom to top", ", ".join(f"P{i}" for i in t["stack_order"])),
        (
            "Axis-shift hinges (Fig. 8c)",
            f"{pairs.count('intrados')} intrados–intrados, "
            f"{pairs.count('extrados')} extrados–extrados",
        ),
        (
            "Offset-crease correction at the design state",
            f"{max(t['correction_design'], default=0.0) * 1e3:.3g} mm",
        ),
        ("Hinge gap along the path", f"{t['hinge_gap_max_path'] * 1e3:.3g} mm"),
        ("Collisions, flat stack → design", collide),
        ("Largest plate curvature", f"{b['max_curvature']:.4g} 1/m"),
        (
            "Bending utilisation κ / (f_d / (E t/2))"
            if design
            else "Bending utilisation κ / (f_k / (E t/2))",
            f"{b['max_utilisation']:.3f} (plate {worst['plate']} at α {worst['alpha']:.3g}°): "
            f"{verdict}",
        ),
        ("Basis of the bending check", e(basis_line)),
    ]
    if design:
        rows.append(
            (
                "Characteristic utilisation κ / (f_k / (E t/2))",
                f"{b['max_utilisation_characteristic']:.3f}",
            )
        )
    if b.get("final_modulus") is not None and basis.get("k_def") is not None:
        rows.append(
            (
                "Creep (k_def), final stiffness E / (1 + k_def)",
                f"k_def {basis['k_def']:g}: "
                + " / ".join(f"{v / 1e9:.3g}" for v in b["final_modulus"])
                + " GPa (E1 / E2)",
            )
        )
    body = "\n".join(f"<tr><th>{e(a)}</th><td>{v}</td></tr>" for a, v in rows)
    return (
        '<h2 id="thickness">Thickness and bending (paper §5.3)</h2>'
        f"<table>{body}</table>"
        "<p>Per plate utilisation: "
        + ", ".join(
            f"P{i}: {u:.2f}"
            for i, u in zip(range(len(b["utilisation_per_plate"])), b["utilisation_per_plate"])
        )
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
    sup = c.get("supports", {})
    feet = sup.get("type", "pinned") + (" with a tie" if sup.get("tie") else "")
    rows = []
    for k in c["cases"]:
        r, hg = k["reactions_uls"], k["hinges_uls"]
        actions = ", ".join(
            f"{a['name']} {a['value_N_per_m2']:.0f} N/m² ({a['where']}"
            + (", half span" if a["half_span"] else "")
            + f", γ {a['gamma']:g})"
            for a in k["actions"]
        )
        b = k["buckling_factor"]
        ok = k["deflection_ok"] and k["utilisation_ok"]
        rows.append(
            f"<tr{'' if ok else ' class=bad'}><th>{e(k['name'])}</th><td>{e(actions)}</td>"
            f"<td class=num>{k['deflection_max_m'] * 1e3:.2f} mm ({k['deflection_ratio']:.2f})</td>"
            f"<td class=num>{k['utilisation_max']:.2f} (k_mod {k['basis']['k_mod']:g}, "
            f"{k['strength_MPa']:.3g} MPa)</td>"
            f"<td class=num>{'—' if b is None else format(b, '.3g')}</td>"
            f"<td class=num>{r['start_vertical_N']:.0f} / {r['start_horizontal_N']:.0f} | "
            f"{r['end_vertical_N']:.0f} / {r['end_horizontal_N']:.0f}"
            + (f"; tie {r['tie_N']:.0f}" if r.get("tie_N") else "")
            + f"</td><td class=num>{hg.get('tension_max_N_per_m', 0):.0f} / "
            f"{hg.get('out_of_plane_max_N_per_m', 0):.0f} / {hg.get('line_mean_N_per_m', 0):.0f}"
            "</td></tr>"
        )
    figs = "".join(
        f'<figure><a href="{e(p)}"><img src="{e(p)}" alt="deflection of every load case">'
        "</a><figcaption>Deflection under the characteristic loads of every case (one colour "
        "scale; displacements magnified as printed)</figcaption></figure>"
        for p in pictures
    )
    g = c["governing"]
    return (
        '<h2 id="structural">Structural checks (FE, load cases)</h2>'
        f"<p>{e(validation.get('engine', ''))} · {e(validation.get('mode', ''))} · feet "
        f"{e(feet)} · deflection limit {c['deflection_limit_m'] * 1e3:.2f} mm · ULS stresses "
        "with the active-bending prestress over k_mod f_k / γ_M, the k_mod of each case's "
        f"load duration · governing: deflection {e(str(g['deflection']))}, utilisation "
        f"{e(str(g['utilisation']))}, buckling {e(str(g.get('buckling')))}</p>"
        "<table><tr><th>case</th><th>actions (characteristic)</th><th>deflection "
        "(/limit)</th><th>utilisation</th><th>buckling factor</th><th>reactions V / H, N "
        "(start | end)</th><th>hinge N/m: tension / shear / mean</th></tr>"
        + "".join(rows)
        + "</table>"
        + figs
    )
