"""``ccu report``: the page, its key figures, and every link resolving to a file written."""

from __future__ import annotations

import datetime
import hashlib
import html
import json
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

pytest.importorskip("matplotlib")

from compas_ccu import __version__  # noqa: E402
from compas_ccu.cli import main  # noqa: E402
from compas_ccu.fea.design_values import StiffnessBasis  # noqa: E402
from compas_ccu.key_figures import key_figures  # noqa: E402
from compas_ccu.key_figures.text import (  # noqa: E402
    design_values_text,
    figure_rows,  # noqa: E402
    load_case_lines,
    load_case_table,
)
from compas_ccu.outputs import MANIFEST
from compas_ccu.viz.report import FIGURES, structural_section, write_report  # noqa: E402
from conftest import EXAMPLES  # noqa: E402
from imagecheck import assert_picture, load_rgb  # noqa: E402


class Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.text = [], []

    def handle_starttag(self, tag, attrs):
        for key, value in attrs:
            if key in ("href", "src") and value:
                self.links.append(value)

    def handle_data(self, data):
        self.text.append(data)


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    with pytest.MonkeyPatch.context() as mp:  # no validation of vault.toml from elsewhere
        mp.setenv("CCU_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
        code = main(
            ["report", str(EXAMPLES / "vault.toml"), "--out", str(out)]
            + ["--steps", "6", "--frames", "4"]
        )
    assert code == 0
    page = Links()
    page.feed((out / "index.html").read_text(encoding="utf-8"))
    return out, page


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_every_link_resolves_and_every_file_is_linked(report):
    out, page = report
    assert page.links
    for link in page.links:
        assert "://" not in link, f"external link {link}"
        assert (out / link).is_file(), f"broken link {link}"
    written = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    written -= {"index.html", MANIFEST}
    assert written <= set(page.links), written - set(page.links)
    for name, _ in FIGURES:
        assert f"figures/{name}.png" in written and f"figures/{name}.svg" in written
    assert {"viewer.html", "deployment.gif", "data/structure.json", "data/path.csv"} <= written


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_key_figures_are_on_the_page(report, vault_model):
    out, page = report
    text = " ".join(" ".join(page.text).split())
    s = vault_model.deploy()
    # worded as ccu info words them: one definition (compas_ccu.key_figures.text)
    assert f"span {s.metrics['span']:.4f} m (leading crease chord)" in text
    assert f"rise {s.metrics['rise']:.4f} m" in text
    assert "plates 10" in text
    assert "creases 9 (4 anticlastic, 5 synclastic)" in text
    assert f"deployment limit {vault_model.alpha_limit:.4f} deg (crease segment" in text
    assert "FE validation none yet ('ccu validate' to run one)" in text
    # every key figure with its unit in the complete table
    assert f"isometry_relative {s.metrics['isometry_relative']:.6g}" in text
    assert "crease_span 2.5 m" in text


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_report_pictures_are_real(report):
    out, _ = report
    for name, _ in FIGURES:
        assert_picture(load_rgb(out / "figures" / f"{name}.png"), min_ink=0.02, min_colours=20)


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_report_cli_is_quiet_with_quiet(tmp_path, capsys):
    code = main(
        [
            "report",
            str(EXAMPLES / "cone.toml"),
            "--out",
            str(tmp_path),
            "--steps",
            "2",
            "--frames",
            "2",
            "--quiet",
        ]
    )
    assert code == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""
    assert (tmp_path / "index.html").is_file()


def test_report_refuses_bad_steps(tmp_path, capsys):
    code = main(["report", str(EXAMPLES / "cone.toml"), "--out", str(tmp_path), "--steps", "0"])
    assert code == 2
    assert "--steps must be >= 1, got 0" in capsys.readouterr().err
    assert not (Path(tmp_path) / "index.html").exists()


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_thickness_checks_are_on_the_page(report):
    out, page = report
    text = " ".join(" ".join(page.text).split())
    assert "thickness 6 mm plywood, flat stack 60 mm" in text
    assert "axis-shift hinges 5 intrados-intrados, 4 extrados-extrados" in text
    assert "collisions none from the flat stack to the design; min clearance 6 mm" in text
    # 6 mm plywood: within the design strength (0.922; characteristic 0.461)
    assert "utilisation 0.922 (plate 0 at alpha 30 deg" in text and "EXCEEDED" not in text
    assert (
        "bending basis EC5 SC1 permanent: f_d = k_mod f_k / gamma_M, k_mod 0.6, gamma_M 1.2" in text
    )
    assert "characteristic utilisation 0.461" in text
    assert "creep: k_def 0.8, final stiffness E/(1 + k_def) 5 / 5 GPa (E1 / E2)" in text
    # a passed check is not marked on the page (a failed one is, test_the_failed_check_is_marked)
    html_text = (out / "index.html").read_text(encoding="utf-8")
    assert "<tr><th>bending check</th>" in html_text and "class=bad" not in html_text


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_the_failed_check_is_marked_on_the_page(tmp_path, monkeypatch):
    """The 8 mm vault (examples/overbent.toml) exceeds its design bending strength (1.229)."""
    monkeypatch.setenv("CCU_CACHE_DIR", str(tmp_path / "cache"))
    out = tmp_path / "report"
    argv = ["report", str(EXAMPLES / "overbent.toml"), "--out", str(out), "--steps", "1"]
    assert main(argv + ["--frames", "2"]) == 0
    html_text = (out / "index.html").read_text(encoding="utf-8")
    assert "<tr class=bad><th>bending check</th>" in html_text
    assert "utilisation 1.229" in html_text and "EXCEEDED" in html_text


def _load_case_checks() -> dict:
    """The checks of a validation.json with two load cases (one failed)."""
    actions = [
        dict(name="self-weight", value_N_per_m2=47.1, where="surface", half_span=False, gamma=1.35),
        dict(
            name="wet concrete",
            value_N_per_m2=2040.5,
            where="projected",
            half_span=False,
            gamma=1.5,
        ),
    ]
    case = dict(
        name="wet-concrete",
        actions=actions,
        deflection_max_m=0.0061,
        deflection_ratio=1.22,
        deflection_ok=False,
        utilisation_max=0.8,
        utilisation_ok=True,
        basis={"k_mod": 0.9},
        strength_MPa=22.5,
        buckling_factor=3.2,
        reactions_uls=dict(
            start_vertical_N=1200.4,
            start_horizontal_N=800.0,
            end_vertical_N=1199.6,
            end_horizontal_N=800.0,
            tie_N=0.0,
        ),
        hinges_uls=dict(
            tension_max_N_per_m=12.0, out_of_plane_max_N_per_m=900.0, line_mean_N_per_m=300.0
        ),
    )
    checks = {
        "cases": [case, {**case, "name": "snow", "deflection_ok": True, "buckling_factor": None}],
        "supports": {"type": "springs", "tie": False},
        "deflection_limit_m": 0.005,
        "governing": dict(deflection="wet-concrete", utilisation="snow", buckling="wet-concrete"),
        "stiffness": StiffnessBasis("plywood", 1.2, 0.8, 1.0).to_dict(),
    }
    return checks


def test_structural_section_shows_every_case_and_marks_the_failed_ones():
    checks = _load_case_checks()
    html = structural_section({"checks": checks, "engine": "kratos"}, ["figures/fe_load_cases.png"])
    assert "feet springs" in html and "deflection limit 5.00 mm" in html
    assert "<tr class=bad><th>wet-concrete</th>" in html and "<tr><th>snow</th>" in html
    assert "wet concrete 2040 N/m² (projected, γ 1.5)" in html
    assert "6.10 mm (1.220)" in html and "0.800 (k_mod 0.9, 22.5 MPa)" in html
    assert "1200 / 800 | 1200 / 800" in html and "12 / 900 / 300" in html
    assert "<td class=num>—</td>" in html  # no buckling factor: a dash, not a number
    assert '<img src="figures/fe_load_cases.png"' in html
    assert structural_section({"checks": {"deflection_max_m": 0.001}}) == ""  # an old file


def test_console_and_report_show_the_same_load_case_cells():
    """One definition (key_figures.text.load_case_table): the report does not format its own."""
    checks = _load_case_checks()
    page = structural_section({"checks": checks, "engine": "kratos"})
    console = "\n".join(load_case_lines(checks))
    heading, rows, governing = load_case_table(checks)
    assert len(rows) == 2 and [ok for _, ok in rows] == [False, True]
    for cells, _ in rows:
        for cell in cells[2:]:
            assert f"<td class=num>{html.escape(cell)}</td>" in page
            assert cell in console
    assert f"governing: {governing}" in page and console.endswith(f"governing: {governing}")
    assert heading in console and html.escape(heading) in page
    assert console.count("EXCEEDED") == 1
    # the design values with their clauses, once in each
    note = design_values_text(checks)
    assert note.startswith("design values: k_mod of each case (EN 1995-1-1 Table 3.1, shortest")
    assert "E_d = E_mean / gamma_M (EN 1995-1-1 2.4.1(2)P, eq. (2.15)), gamma_M 1.2" in note
    assert console.count(note) == 1 and page.count(html.escape(note)) == 1


# -- the engineering record, the PDF, the fabrication section ------------------------------


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_the_record_shows_the_design_file_as_read_with_its_hash(report):
    out, page = report
    text = " ".join(page.text)
    design = (EXAMPLES / "vault.toml").read_bytes()
    sha = hashlib.sha256(design).hexdigest()
    assert sha in text
    assert (out / "design" / "vault.toml").read_bytes() == design  # the copy, linked
    assert "design/vault.toml" in page.links
    html_text = (out / "index.html").read_text(encoding="utf-8")
    verbatim = re.search(r"<pre>(.*?)</pre>", html_text, re.S).group(1)
    assert html.unescape(verbatim) == design.decode("utf-8")
    assert f"compas_ccu {__version__}" in text
    date = re.search(r"date \(UTC\)\s*(\S+)", text).group(1)
    when = datetime.datetime.fromisoformat(date)
    assert when.utcoffset() == datetime.timedelta(0)
    assert abs(datetime.datetime.now(datetime.timezone.utc) - when).total_seconds() < 3600
    for row in ("stiffness E1 9 GPa, E2 9 GPa, G12 3.462 GPa, nu12 0.3", "density 600 kg/m3"):
        assert row in " ".join(text.split())
    assert "f1 30 MPa, f2 30 MPa (characteristic f_k)" in text
    assert "design strengths f_d f1 15 MPa, f2 15 MPa" in text  # k_mod 0.6 / gamma_M 1.2


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_the_pdf_is_read_by_an_independent_reader(report, vault_model):
    pypdf = pytest.importorskip("pypdf")
    out, page = report
    assert "report.pdf" in page.links
    reader = pypdf.PdfReader(str(out / "report.pdf"))
    assert 4 <= len(reader.pages) <= 12
    assert reader.pages[0].mediabox.width == pytest.approx(595.44, abs=1)  # A4
    text = "\n".join(p.extract_text() for p in reader.pages)
    sha = hashlib.sha256((EXAMPLES / "vault.toml").read_bytes()).hexdigest()
    assert sha in text
    k = key_figures(vault_model)
    for label, value in figure_rows(k)[:13]:  # the key figures, as ccu info words them
        assert value in text, label
    assert "utilisation 0.922" in text and "EXCEEDED" not in text
    assert 'name = "vault"' in text  # the design file, verbatim
    # one picture per figure
    images = sum(len(p.images) for p in reader.pages)
    assert images >= len(FIGURES)


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_the_pdf_hash_follows_the_design_file(tmp_path):
    pypdf = pytest.importorskip("pypdf")
    original = (EXAMPLES / "cone.toml").read_bytes()
    design = tmp_path / "cone.toml"
    design.write_bytes(original + b"# a comment changes the file, so its hash\n")
    out = tmp_path / "r"
    code = main(["report", str(design), "--out", str(out), "--steps", "1", "--frames", "2"])
    assert code == 0
    text = "\n".join(p.extract_text() for p in pypdf.PdfReader(str(out / "report.pdf")).pages)
    assert hashlib.sha256(design.read_bytes()).hexdigest() in text
    assert hashlib.sha256(original).hexdigest() not in text
    assert "# a comment changes the file, so its hash" in text  # the file as read
    assert (out / "design" / "cone.toml").read_bytes() == design.read_bytes()


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_no_pdf_writes_no_pdf(tmp_path):
    code = main(
        ["report", str(EXAMPLES / "cone.toml"), "--out", str(tmp_path), "--steps", "1"]
        + ["--frames", "2", "--no-pdf", "--quiet"]
    )
    assert code == 0
    assert not (tmp_path / "report.pdf").exists()
    assert "report.pdf" not in (tmp_path / "index.html").read_text(encoding="utf-8")


def _fabrication_folder(folder, **manifest):
    (folder / "plates").mkdir(parents=True)
    (folder / "plates" / "plate_0.dxf").write_text("0\nEOF\n")
    (folder / "hinges.dxf").write_text("0\nEOF\n")
    (folder / "fabrication.json").write_text(json.dumps(manifest), encoding="utf-8")
    return folder


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_the_fabrication_section_links_every_file_and_shows_the_tables(tmp_path):
    fab = _fabrication_folder(
        tmp_path / "fab",
        design="cone",
        plates=2,
        utilisation=0.625,
        bom=[{"item": "plywood 8 mm", "quantity": 2, "area_m2": 1.23456}],
        nesting={"sheets": [{"sheet": 1, "size_mm": [2500, 1250], "plates": [0, 1]}]},
    )
    out = tmp_path / "report"
    code = main(
        ["report", str(EXAMPLES / "cone.toml"), "--out", str(out), "--steps", "1"]
        + ["--frames", "2", "--fabrication", str(fab), "--quiet"]
    )
    assert code == 0
    page = Links()
    page.feed((out / "index.html").read_text(encoding="utf-8"))
    for rel in ("plates/plate_0.dxf", "hinges.dxf", "fabrication.json"):
        assert f"fabrication/{rel}" in page.links
        assert (out / "fabrication" / rel).read_bytes() == (fab / rel).read_bytes()
    text = " ".join(" ".join(page.text).split())
    assert "utilisation 62.5%" in text
    assert "Bill of materials (fabrication.json: bom)" in text
    assert "plywood 8 mm 2 1.235" in text
    assert "Sheets (fabrication.json: sheets)" in text and "2500, 1250 0, 1" in text
    pypdf = pytest.importorskip("pypdf")
    pdf = "\n".join(p.extract_text() for p in pypdf.PdfReader(str(out / "report.pdf")).pages)
    assert "plates/plate_0.dxf" in pdf and "plywood 8 mm" in pdf


def test_a_fabrication_of_another_design_is_refused_before_any_work(tmp_path, capsys):
    fab = _fabrication_folder(tmp_path / "fab", design="vault")
    out = tmp_path / "report"
    code = main(
        ["report", str(EXAMPLES / "cone.toml"), "--out", str(out), "--fabrication", str(fab)]
    )
    assert code == 2
    err = capsys.readouterr().err
    assert "holds the fabrication of design 'vault', not of 'cone'" in err
    assert not (out / "index.html").exists()
    code = main(
        ["report", str(EXAMPLES / "cone.toml"), "--out", str(out), "--fabrication", "nowhere"]
    )
    assert code == 2
    assert "--fabrication must be a folder written by 'ccu fabricate', got 'nowhere'" in (
        capsys.readouterr().err
    )


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_the_last_validation_of_the_file_joins_the_checks_and_the_pdf(tmp_path, monkeypatch):
    pypdf = pytest.importorskip("pypdf")
    from compas_ccu.fea.record import remember

    monkeypatch.setenv("CCU_CACHE_DIR", str(tmp_path / "cache"))
    design = tmp_path / "cone.toml"
    design.write_bytes((EXAMPLES / "cone.toml").read_bytes())
    fe = tmp_path / "fe"
    fe.mkdir()
    checks = {
        **_load_case_checks(),
        "deflection_max_m": 0.0061,
        "utilisation_max": 0.8,
        "deflection_ok": False,
        "utilisation_ok": True,
    }
    summary = {
        "design": "cone",
        "engine": "kratos",
        "mode": "nonlinear",
        "alpha": 30.0,
        "span": 1.0,
        "deviation": {"max_percent": 0.12, "mean_percent": 0.05, "max_m": 0.001},
        "stresses": {"max_bending_MPa": 21.5},
        "checks": checks,
        "converged": True,
    }
    (fe / "validation.json").write_text(json.dumps(summary), encoding="utf-8")
    remember(str(design), summary, fe)
    out = tmp_path / "report"
    code = main(["report", str(design), "--out", str(out), "--steps", "1", "--frames", "2"])
    assert code == 0
    page = Links()
    page.feed((out / "index.html").read_text(encoding="utf-8"))
    text = " ".join(" ".join(page.text).split())
    assert "FE validation kratos nonlinear, alpha 30 deg: deviation max 0.120 %" in text
    assert "FE checks deflection 6.10 mm (limit 5.00 mm), utilisation 0.800" in text
    assert "NOT OK" in text
    assert "Structural checks (FE, load cases)" in text
    pdf = "\n".join(p.extract_text() for p in pypdf.PdfReader(str(out / "report.pdf")).pages)
    assert "Structural checks (FE, load cases)" in pdf
    assert "governing: deflection wet-concrete, utilisation snow" in pdf
    # the file changes: its validation is not the report's any more
    from compas_ccu.cli.pictures import _last_validation

    assert _last_validation(str(design))[0] is not None
    with design.open("a", encoding="utf-8") as f:
        f.write("# changed\n")
    assert _last_validation(str(design)) == (None, [])


@pytest.mark.slow  # a whole report of the vault (5-9 s)
def test_the_viewer_of_the_report_shows_the_sheets_of_the_fabrication(tmp_path, cone_model):
    from compas_ccu.fabrication import fabrication_data
    from compas_ccu.fabrication.hinges import hinge_strips
    from compas_ccu.fabrication.workshop import WorkshopOptions, plan_workshop

    data = fabrication_data(cone_model)
    plan = plan_workshop(data, hinge_strips(data), WorkshopOptions(nesting="shelf"), density=600.0)
    layout = plan.layout()
    fab = _fabrication_folder(tmp_path / "fab", design="cone")
    (fab / "sheets.json").write_text(json.dumps(layout), encoding="utf-8")
    count = f"cut patterns: {len(plan.sheets)} sheets, {len(plan.parts)} parts"
    out = tmp_path / "report"
    report = write_report(cone_model, out, steps=1, frames=2, fabrication=fab, pdf=False)
    assert count in (out / "viewer.html").read_text(encoding="utf-8")
    assert "viewer sheets" not in report.skipped
    # a nesting of other plates: the viewer falls back to its own layout, and says so
    layout["model_plate_ids"] = [7, 8]
    (fab / "sheets.json").write_text(json.dumps(layout), encoding="utf-8")
    report = write_report(cone_model, out, steps=1, frames=2, fabrication=fab, pdf=False)
    assert "the nesting is of 2 plates [7, 8]" in report.skipped["viewer sheets"]
    html = (out / "viewer.html").read_text(encoding="utf-8")
    assert count not in html and '"name":"cut patterns"' in html


def test_an_unexpected_error_in_a_task_is_raised_not_skipped(vault_model, tmp_path, monkeypatch):
    """A refusal (a CCUError) is listed under "Not produced"; any other exception is a bug and
    reaches the caller, never a warning with exit 0."""
    from compas_ccu.viz import report as report_module

    def broken(*args, **kwargs):
        raise ValueError("a bug in a figure")

    monkeypatch.setattr(report_module, "save_figure", broken)
    with pytest.raises(ValueError, match="a bug in a figure"):
        report_module.write_report(vault_model, tmp_path / "r", steps=3, frames=2,
                                   progress=False, pdf=False)  # fmt: skip


@pytest.fixture
def quick_report(monkeypatch):
    """``write_report`` of the report module with no figures and no animation (the tasks that
    matter to a test run in a second)."""
    from compas_ccu.viz import report as report_module

    monkeypatch.setattr(report_module, "FIGURES", ())
    monkeypatch.setattr(report_module, "write_animations", lambda *a, **k: [])
    return report_module


@pytest.mark.parametrize("error", [RuntimeError("a bug"), ValueError("a bug"), KeyError("bug")])
def test_a_figure_function_that_fails_is_raised_not_skipped(
    vault_model, tmp_path, monkeypatch, error
):
    """A figure function with a bug (not a refusal: no CCUError) reaches the caller."""
    from compas_ccu.viz import report as report_module

    def broken(*args, **kwargs):
        raise error

    monkeypatch.setattr(report_module, "plot_views", broken)
    with pytest.raises(type(error), match="bug"):
        report_module.write_report(vault_model, tmp_path / "r", steps=2, frames=2, pdf=False)
    assert not (tmp_path / "r" / "index.html").exists()


def test_a_viewer_that_fails_is_raised_not_skipped(cone_model, tmp_path, monkeypatch, quick_report):
    """A plain ValueError (a bug, not an OptionError refusal) from the viewer is raised, with or
    without the fabrication's sheets to fall back from."""

    def broken(*args, **kwargs):
        raise ValueError("a bug in the viewer")

    monkeypatch.setattr(quick_report, "write_viewer", broken)
    with pytest.raises(ValueError, match="a bug in the viewer"):
        quick_report.write_report(cone_model, tmp_path / "r", steps=1, frames=2, pdf=False)


@pytest.mark.parametrize("error", [OSError("no space left"), RuntimeError("a bug in the PDF")])
def test_a_pdf_that_fails_is_raised_not_skipped(
    cone_model, tmp_path, monkeypatch, quick_report, error
):
    """Only a refusal of the PDF writer is listed under "Not produced"; anything else (a bug,
    the disk) is raised, not turned into a warning with exit 0."""

    def broken(*args, **kwargs):
        raise error

    monkeypatch.setattr(quick_report, "write_pdf", broken)
    with pytest.raises(type(error), match=str(error)):
        quick_report.write_report(cone_model, tmp_path / "r", steps=1, frames=2)


def test_a_refusal_is_listed_as_not_produced(cone_model, tmp_path, monkeypatch, quick_report):
    """A named refusal (a missing optional extra: MissingExtraError, a CCUError) of a figure, the
    viewer or the PDF is a "Not produced" note; the report is written."""
    from compas_ccu.errors import MissingExtraError

    def missing(*args, **kwargs):
        raise MissingExtraError("the viz extra is missing (pip install 'compas_ccu[viz]')")

    monkeypatch.setattr(quick_report, "FIGURES", (("views-kind", "3D views"),))
    for name in ("plot_views", "write_viewer", "write_pdf"):
        monkeypatch.setattr(quick_report, name, missing)
    report = quick_report.write_report(cone_model, tmp_path / "r", steps=1, frames=2)
    assert set(report.skipped) >= {"figure views-kind", "viewer", "report.pdf"}
    assert report.pdf is None and report.index.exists()
    page = report.index.read_text(encoding="utf-8")
    assert "Not produced" in page and "the viz extra is missing" in page
