"""The engineering record of the report: the design file's hash, the tolerant fabrication
reader, the PDF writer."""

from __future__ import annotations

import datetime
import hashlib
import json
import re

import pytest

pytest.importorskip("matplotlib")

from compas_ccu.errors import OptionError  # noqa: E402
from compas_ccu.key_figures.text import figure_rows, rows_lines, validation_rows  # noqa: E402
from compas_ccu.viz.pdf import write_pdf  # noqa: E402
from compas_ccu.viz.record import design_record, read_fabrication, read_sheets  # noqa: E402
from conftest import EXAMPLES  # noqa: E402


def test_the_hash_is_of_the_bytes_and_changes_with_the_file(tmp_path, cone_model):
    design = tmp_path / "cone.toml"
    design.write_bytes((EXAMPLES / "cone.toml").read_bytes())
    when = datetime.datetime(2026, 1, 2, 3, 4, 5, tzinfo=datetime.timezone.utc)
    first = design_record(cone_model, design, now=when)
    assert first["sha256"] == hashlib.sha256(design.read_bytes()).hexdigest()
    assert first["text"] == design.read_text(encoding="utf-8")
    assert first["date"] == "2026-01-02T03:04:05+00:00"
    design.write_text(design.read_text(encoding="utf-8") + "\n", encoding="utf-8")
    second = design_record(cone_model, design, now=when)
    assert second["sha256"] != first["sha256"]
    assert second["text"].endswith("\n\n")


def test_the_record_without_a_file_still_has_the_materials(cone_model):
    r = design_record(cone_model)
    assert r["file"] is r["sha256"] is r["text"] is None
    c = r["material_constants"]
    assert c["E1"] == 9e9 and c["density"] == 600.0 and c["thickness"] == 0.005
    assert c["design_factors"]["k_mod"] == 0.6 and c["design_factors"]["gamma_M"] == 1.2
    assert dict(r["material"])["density"] == "600 kg/m3"


def test_the_fabrication_reader_tolerates_a_folder_without_a_manifest(tmp_path):
    (tmp_path / "a.dxf").write_text("x")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b.svg").write_text("<svg/>")
    (tmp_path / ".ccu-files.json").write_text("{}")  # the output manifest is not a file to list
    f = read_fabrication(tmp_path)
    assert f["files"] == ["a.dxf", "sub/b.svg"]
    assert f["manifest"] is None and f["bom"] is None and f["sheets"] is None
    assert f["problems"] == ["no fabrication.json in the folder: the files are listed only"]


@pytest.mark.parametrize(
    "text, problem",
    [
        ("{not json", "fabrication.json could not be read"),
        ("[1, 2]", "fabrication.json holds a list, not an object"),
        ('{"bom": {"a": 1}}', "bom is not a list of objects, not shown"),
        ('{"sheets": [1, 2]}', "sheets is not a list of objects, not shown"),
    ],
)
def test_the_fabrication_reader_names_what_it_could_not_read(tmp_path, text, problem):
    (tmp_path / "fabrication.json").write_text(text)
    f = read_fabrication(tmp_path)
    assert f["files"] == ["fabrication.json"]
    assert any(problem in p for p in f["problems"]), f["problems"]
    assert f["bom"] is None and f["sheets"] is None


def test_the_fabrication_reader_reads_the_tables_where_they_are(tmp_path):
    manifest = {
        "design": "cone",
        "design_sha256": "ab" * 32,
        "bom": [{"item": "plywood", "quantity": 2}],
        "nesting": {"sheets": [{"sheet": 1}], "utilisation": 0.5},
    }
    (tmp_path / "fabrication.json").write_text(json.dumps(manifest))
    f = read_fabrication(tmp_path, design="cone", sha256="ab" * 32)
    assert f["bom"] == manifest["bom"] and f["sheets"] == [{"sheet": 1}]
    assert f["utilisation"] == 0.5 and f["problems"] == []
    with pytest.raises(OptionError, match="written from another version of the design file"):
        read_fabrication(tmp_path, design="cone", sha256="cd" * 32)
    with pytest.raises(OptionError, match="holds the fabrication of design 'cone', not of 'x'"):
        read_fabrication(tmp_path, design="x")
    with pytest.raises(OptionError, match="must be a folder .* got '.*nothing'"):
        read_fabrication(tmp_path / "nothing")


def test_the_sheets_reader_refuses_what_is_no_nesting_of_this_design(tmp_path):
    with pytest.raises(OptionError, match=r"'.*' has no sheets.json \(the nesting .* again"):
        read_sheets(tmp_path)
    with pytest.raises(OptionError, match="must be a folder .* got '.*nothing'"):
        read_sheets(tmp_path / "nothing")
    path = tmp_path / "sheets.json"
    for text, message in [
        ("{not json", "sheets.json cannot be read"),
        ('{"format": "ccu.fold"}', "sheets.json is not a 'ccu.sheets' nesting"),
        ('{"format": "ccu.sheets", "sheets": []}', "sheets.json has no parts list"),
    ]:
        path.write_text(text)
        with pytest.raises(OptionError, match=message):
            read_sheets(tmp_path)
        # the report's reader names the problem and goes on (the viewer: its own layout)
        f = read_fabrication(tmp_path)
        assert f["layout"] is None
        assert any(message in p and "its own layout" in p for p in f["problems"])
    doc = {"format": "ccu.sheets", "design": "cone", "design_sha256": "ab" * 32}
    path.write_text(json.dumps({**doc, "sheets": [], "parts": []}))
    assert read_sheets(tmp_path, design="cone", sha256="ab" * 32)["design"] == "cone"
    assert read_fabrication(tmp_path, design="cone")["layout"]["parts"] == []
    for reader in (read_sheets, read_fabrication):
        with pytest.raises(OptionError, match="holds the fabrication of design 'cone', not of 'x'"):
            reader(tmp_path, design="x")
        with pytest.raises(OptionError, match="written from another version of the design file"):
            reader(tmp_path, design="cone", sha256="cd" * 32)


@pytest.mark.slow  # a fabrication or a multi-page PDF (2.5-3.5 s)
def test_the_pdf_has_the_rows_as_text_and_breaks_pages(tmp_path, vault_model):
    pypdf = pytest.importorskip("pypdf")
    from compas_ccu.key_figures import key_figures

    rows = figure_rows(key_figures(vault_model, path=2))
    long = "\n".join(f"line {i} " + "x" * 150 for i in range(150))  # wrapped, 3 pages
    path = write_pdf(
        tmp_path / "r.pdf",
        [("title", "vault", "sub"), ("rows", rows), ("code", long)]
        + [("table", ["a", "b"], [[1, 2]])],
        footer="vault record",
    )
    reader = pypdf.PdfReader(str(path))
    assert len(reader.pages) >= 3
    text = "\n".join(p.extract_text() for p in reader.pages)
    for line in rows_lines(rows)[:13]:
        assert line.split()[-1] in text
    assert "line 149" in text and f"page 1 of {len(reader.pages)}" in text


def test_a_pdf_table_wider_than_the_page_wraps_its_cells_and_loses_no_number(tmp_path):
    """The load-case table has seven columns of up to 60 characters: each cell wraps within its
    column (it was cut to the column width, dropping the end feet's reactions)."""
    pypdf = pytest.importorskip("pypdf")
    columns = [f"column {j} with a long title" for j in range(7)]
    rows = [
        [f"{1000 * i + j} / {j}.25 | end {7000 + i} / 8{j}" for j in range(7)] for i in range(3)
    ]
    path = write_pdf(tmp_path / "t.pdf", [("table", columns, rows)])
    text = " ".join(pypdf.PdfReader(str(path)).pages[0].extract_text().split())
    for row in rows:
        for cell in row:
            for number in cell.replace("/", " ").replace("|", " ").split():
                assert number in text, (number, cell)


def test_the_pdf_refuses_an_unknown_block(tmp_path):
    with pytest.raises(OptionError, match="unknown PDF block 'chart'"):
        write_pdf(tmp_path / "r.pdf", [("chart", 1)])
    assert not (tmp_path / "r.pdf").exists()


def test_validation_rows_mark_a_failed_check():
    record = {
        "engine": "kratos",
        "mode": "linear",
        "alpha": 30.0,
        "deviation": {"max_percent": 0.1, "mean_percent": 0.05},
        "stresses": {"max_bending_MPa": 12.0},
        "checks": {
            "deflection_max_m": 0.01,
            "deflection_limit_m": 0.005,
            "utilisation_max": 0.5,
            "deflection_ok": False,
            "utilisation_ok": True,
        },
        "when": "2026-01-01T00:00:00",
        "out": "/x",
    }
    rows = validation_rows(record)
    assert rows[1] == (
        "FE checks",
        "deflection 10.00 mm (limit 5.00 mm), utilisation 0.500  ** NOT OK **",
    )


def test_validation_rows_give_the_design_values_with_their_clauses():
    from compas_ccu.fea.design_values import StiffnessBasis

    stiffness = StiffnessBasis("plywood", 1.2, 0.8, 1.0).to_dict()
    record = {
        "engine": "kratos",
        "mode": "displacement",
        "alpha": 30.0,
        "deviation": {"max_percent": 0.1, "mean_percent": 0.05},
        "stresses": {"max_bending_MPa": 12.0},
        "checks": {
            "deflection_max_m": 0.00065,
            "deflection_final_max_m": 0.00117,
            "deflection_limit_m": 0.005,
            "utilisation_max": 0.81,
            "deflection_ok": True,
            "utilisation_ok": True,
            "buckling_factor": 8.78 / 2.16,
            "buckling_factor_mean": 8.78,
            "stiffness": stiffness,
        },
        "when": "2026-01-01T00:00:00",
        "out": "/x",
    }
    rows = validation_rows(record)
    assert rows[1] == (
        "FE checks",
        "deflection 0.65 mm (limit 5.00 mm), final 1.17 mm, utilisation 0.810, buckling factor "
        "4.06 (E_mean 8.78)",
    )
    assert ("", f"stiffness basis: {stiffness['text']}") in rows
    assert "k_def 0.8 (EN 1995-1-1 Table 3.2), psi2 1" in stiffness["text"]


def test_a_manifest_without_tables_is_said_so_on_the_page(tmp_path):
    from compas_ccu.viz.report_page import fabrication_section

    (tmp_path / "fabrication.json").write_text('{"design": "cone", "plates": 2}')
    page = fabrication_section(read_fabrication(tmp_path, design="cone"), tmp_path)
    assert "design cone · 2 plates" in page
    assert "lists no sheets and no bill of materials" in page
    assert fabrication_section(None, tmp_path) == ""


@pytest.mark.slow  # a fabrication or a multi-page PDF (2.5-3.5 s)
def test_the_fabrication_reader_reads_what_ccu_fabricate_writes(tmp_path, overbent_model):
    """A real folder: the workshop's sheets, the BOM's rows and totals, the failed checks (the
    8 mm vault on 2.5 x 1.25 m sheets: every plate spliced)."""
    vault_model = overbent_model
    from compas_ccu.fabrication.fabricate import fabricate
    from compas_ccu.fabrication.workshop import WorkshopOptions
    from compas_ccu.viz.report_page import fabrication_section

    options = WorkshopOptions(nesting="shelf", splice_thickness=0.003)
    manifest = fabricate(vault_model, tmp_path / "fab", workshop=options)
    f = read_fabrication(tmp_path / "fab", design=vault_model.design.name)
    assert f["problems"] == []
    work = manifest["workshop"]
    assert f["utilisation"] == work["utilisation"] and len(f["sheets"]) == work["sheet_count"]
    assert [s["thickness_mm"] for s in f["sheets"]].count(3.0) == 1  # the splice plates' sheet
    assert f["sheets"][-1]["parts"] == 20 and f["sheets"][0]["size_mm"] == "2500 x 1250"
    assert len(f["bom"]) == 20 + 20 + 9  # plate parts, splice plates, hinge strips
    rows = dict(f["workshop_rows"])
    assert f"{manifest['bom']['mass_kg']:.1f} kg" in rows["bill of materials"]
    assert "160 fasteners" in rows["bill of materials"]
    assert rows["splice plates"].startswith(
        "stack 86 mm with them (plates 80 mm); highest pile 6 mm (cuts staggered; 60 mm at the "
        "same rulings); 0.756 kg; clear of the neighbouring plates from alpha "
    )
    assert rows["cost estimate"].startswith(f"{manifest['bom']['cost_total']:.0f} EUR (sheets ")
    assert rows["sheets"].startswith(
        f"{work['sheet_count']} of 2500 x 1250 mm (15 of 8 mm, 1 of 3 mm)"
    )
    # the worst splice: the plates bend uniformly, all ten cuts tie to round-off
    worst = re.match(
        r"\*\* utilisation 2\.151 \(characteristic 1\.075\) at P(\d) ruling (\d+)",
        rows["splice bending"],
    )
    assert work["splits"][worst[1]] == [int(worst[2])]
    assert f["failed_checks"] == manifest["failed_checks"] and len(f["failed_checks"]) == 2
    assert "splice plates: bending utilisation 2.151 > 1" in f["failed_checks"][1]
    page = fabrication_section(f, tmp_path)
    assert '<p class="bad">check failed: splice plates: bending utilisation 2.151' in page
    assert "<th>splice bending</th>" in page and "Sheets (fabrication.json: sheets)" in page
