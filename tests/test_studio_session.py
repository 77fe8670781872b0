"""The studio without a browser: controls from the schema, the editing session (errors, undo,
save, recovery), the file guards, the checks panel and the view arrays."""

from __future__ import annotations

import json
import os
import shutil
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

import strategies
from compas_ccu.catalog import catalog_path
from compas_ccu.cli import main
from compas_ccu.design.document import parse_toml
from compas_ccu.design.schema import SCHEMA
from compas_ccu.errors import DesignError, LimitError, OptionError
from compas_ccu.key_figures import key_figures
from compas_ccu.limits import LIMITS
from compas_ccu.model import load_model
from compas_ccu.studio import StudioSession
from compas_ccu.studio.checks import design_checks, first_collision
from compas_ccu.studio.controls import UNSET, applies, design_controls, format_value, parse_value
from compas_ccu.studio.export import export
from compas_ccu.studio.files import StudioFiles
from compas_ccu.studio.session import document_text
from compas_ccu.studio.view import COLORINGS, cut_patterns_svg, legend_html, view_state
from compas_ccu.thickness import ThickModel
from conftest import EXAMPLES, property_examples

pytest.importorskip("tomlkit")


@pytest.fixture
def folders(tmp_path):
    design = tmp_path / "designs"
    design.mkdir()
    shutil.copy(EXAMPLES / "vault.toml", design / "vault.toml")
    shutil.copy(EXAMPLES / "cone.toml", design / "cone.toml")
    return design, tmp_path / "out"


@pytest.fixture
def session(folders):
    design, out = folders
    return StudioSession.start(design / "vault.toml", out=out)


# -- controls ---------------------------------------------------------------------------------
def test_every_schema_key_is_a_control_with_its_unit():
    controls = {c.key: c for c in design_controls()}
    keys = {f"{s}.{k}" for s, keys in SCHEMA.items() for k in keys if not k.startswith("_")}
    assert set(controls) == keys
    for c in controls.values():
        if c.kind in ("float", "int", "float_or_list", "gamma", "point2", "points2", "point3"):
            assert c.unit, f"{c.key} has no unit"
    assert controls["crease.span"].label == "span [m]"
    assert controls["deployment.alpha"].label == "alpha [deg]"
    assert controls["layout.plates"].label == "plates"
    assert controls["crease.profile"].widget == "dropdown"
    assert controls["layout.quadrants"].widget == "checkbox"
    assert "Allowed: > 0 and <= 1e6." in controls["crease.rise"].hint


def test_controls_follow_the_section_type():
    controls = {c.key: c for c in design_controls()}
    arc = {"crease": {"profile": "arc"}, "layout": {"type": "parallel"}}
    assert applies(controls["crease.rise"], arc)
    assert not applies(controls["crease.points"], arc)
    assert not applies(controls["crease.point_loads"], arc)
    assert applies(controls["layout.spacing"], arc)
    assert not applies(controls["layout.axis"], arc)
    assert not applies(controls["layout.width"], arc)
    radial = {"crease": {"profile": "spline"}, "layout": {"type": "radial"}}
    assert applies(controls["crease.points"], radial)
    assert applies(controls["layout.axis"], radial)
    assert not applies(controls["layout.spacing"], radial)
    # a key the document sets is shown even where it does not apply (so it can be removed)
    assert applies(controls["layout.axis"], {"layout": {"type": "parallel", "axis": 1.0}})


def test_values_round_trip_through_the_text_of_a_field():
    controls = {c.key: c for c in design_controls()}
    for key, value in (
        ("crease.span", 2.5),
        ("crease.segments", 64),
        ("crease.points", [[0.0, 0.0], [1.0, 0.5], [2.0, 0.0]]),
        ("layout.spacing", [0.1, 0.12, 0.14]),
        ("rulings.gamma", [[0.0, 80.0], [1.0, 100.0]]),
        ("plane.origin", [0.0, 1.5, -2.0]),
        ("design.name", 'my "vault"'),
    ):
        c = controls[key]
        assert parse_value(c, format_value(c, value)) == value
    assert parse_value(controls["crease.rise"], "  ") is UNSET
    assert parse_value(controls["crease.rise"], "1,5") == "1,5"  # refused by the schema


# -- editing ----------------------------------------------------------------------------------
def test_an_invalid_value_names_the_key_as_the_cli_does_and_keeps_the_last_model(
    session, folders, tmp_path, capsys
):
    model = session.model
    problem = session.edit("crease", "rise", -1.0)
    assert problem.key == "crease.rise"
    assert problem.message == "crease.rise: must be > 0 and <= 1e6, got -1.0"
    assert session.model is model  # the last valid model stays
    # the ccu command prints the same message for the same file
    bad = tmp_path / "bad.toml"
    bad.write_text(session.fields_text())
    capsys.readouterr()
    assert main(["info", str(bad)]) == 2  # (in this process: test_cli_process runs ccu's own)
    assert problem.message in capsys.readouterr().err
    problem = session.edit("crease", "rise", "abc")
    assert problem.message == "crease.rise: must be a finite number, got 'abc'"
    assert session.edit("crease", "rise", 0.8) is None
    assert session.model is not model
    assert session.model.design.crease.rise == 0.8


def test_a_design_that_cannot_be_built_is_a_problem_without_a_key(session):
    problem = session.edit("rulings", "type", "conical")
    assert problem.key == "rulings.apex" and problem.message.startswith("rulings.apex: required")
    problem = session.edit("rulings", "apex", [0.0, 1.0])  # on the crease's chord
    assert problem.key is None and problem.kind == "GeometryError"
    assert "cone apex [0.0, -1.0] is not on one side of the crease" in problem.message
    assert session.model.design.rulings.type == "orthogonal"  # the last valid model


def test_plates_ten_to_six_rebuilds(session):
    assert session.model.plates.count == 10
    gen = session.generation
    assert session.edit("layout", "plates", 6) is None
    assert session.model.plates.count == 6 and session.generation == gen + 1


def test_undo_redo(session):
    session.edit("crease", "rise", 0.8)
    session._last_edit = (None, 0.0)  # a separate step
    session.edit("layout", "plates", 6)
    assert session.undo()
    assert session.model.plates.count == 10 and session.model.design.crease.rise == 0.8
    assert session.undo()
    assert session.model.design.crease.rise == 1.0
    assert not session.undo()
    assert session.redo() and session.model.design.crease.rise == 0.8
    assert session.redo() and session.model.plates.count == 6
    assert not session.redo()


def test_typing_one_number_is_one_undo_step(session):
    rise = next(c for c in design_controls() if c.key == "crease.rise")
    for text in ("0", "0.", "0.7", "0.75"):
        session.edit("crease", "rise", parse_value(rise, text))
    assert session.model.design.crease.rise == 0.75
    assert session.undo()
    assert session.model.design.crease.rise == 1.0


def test_removing_a_key_with_an_empty_field(session):
    session.edit("plates", "grain", 45.0)
    assert session.value("plates", "grain") == 45.0
    session.edit("plates", "grain", UNSET)
    assert session.value("plates", "grain") is UNSET
    assert session.model.design.plates.grain == 0.0  # the default


# -- saving -----------------------------------------------------------------------------------
def test_save_keeps_comments_and_ccu_info_reads_the_new_values(session, folders, capsys):
    design, _ = folders
    session.edit("crease", "rise", 0.9)
    session.edit("layout", "plates", 6)
    path = session.save()
    assert path == design / "vault.toml" and session.saved
    text = path.read_text()
    assert "# m, chord of the leading (ridge) crease" in text  # the comments are kept
    assert parse_toml(text)["crease"]["rise"] == 0.9
    capsys.readouterr()
    assert main(["info", str(path)]) == 0
    said = capsys.readouterr()
    assert said.err == ""
    figures = key_figures(load_model(path))
    assert figures.plates == 6 and abs(figures.crease_rise - 0.9) < 1e-12
    assert f"crease rise       {figures.crease_rise:.4f}" in said.out or "0.9" in said.out


def test_save_as_writes_inside_the_design_folder_only(session, folders, tmp_path):
    design, _ = folders
    path = session.save_as("variants/low.toml")
    assert path == design / "variants" / "low.toml" and session.name == "variants/low.toml"
    outside = tmp_path / "outside.toml"
    for name in ("../outside.toml", str(outside), "/etc/passwd.toml", "~/x.toml", "a\\..\\b.toml"):
        with pytest.raises(OptionError):
            session.save_as(name)
    assert not outside.exists()
    with pytest.raises(OptionError, match="must end with .toml"):
        session.save_as("vault.txt")


def test_symbolic_links_out_of_the_folder_are_refused(folders, tmp_path):
    design, out = folders
    secret = tmp_path / "secret"
    secret.mkdir()
    (secret / "x.toml").write_text((EXAMPLES / "cone.toml").read_text())
    os.symlink(secret, design / "link")
    os.symlink(secret / "x.toml", design / "x.toml")
    files = StudioFiles(design, out)
    for name in ("link/x.toml", "x.toml"):
        with pytest.raises(OptionError, match="outside"):
            files.inside(name)
    assert "x.toml" not in files.designs()
    session = StudioSession.start(design / "vault.toml", out=out)
    with pytest.raises(OptionError):
        session.open_file("x.toml")
    with pytest.raises(OptionError):
        session.save_as("link/x.toml")


def test_open_catalog_upload_and_bad_uploads(session):
    session.open_catalog("fig12b-dome")
    assert session.model.plates.count > 2 and session.name == "fig12b-dome.toml"
    assert not session.saved
    with pytest.raises(OptionError, match="unknown catalog design"):
        session.open_catalog("nope")
    session.open_upload("mine.toml", (EXAMPLES / "cone.toml").read_bytes())
    assert session.name == "mine.toml" and session.model.plates.count == 2
    with pytest.raises(OptionError, match="not a text file"):
        session.open_upload("x.toml", b"\x89PNG\r\n\x1a\n\x00\x00")
    with pytest.raises(LimitError, match="at most 1,000,000 bytes .the limit upload_bytes"):
        session.open_upload("x.toml", b"#" * (LIMITS.upload_bytes + 1))
    with pytest.raises(OptionError, match="not valid TOML"):
        session.open_upload("x.toml", b"[crease\nspan = ")
    with pytest.raises(OptionError, match=".toml"):
        session.open_upload("x.png", b"a = 1")
    assert session.name == "mine.toml"  # a refused upload changes nothing


def test_the_recovery_copy_restores_an_unsaved_edit(folders):
    design, out = folders
    session = StudioSession.start(design / "vault.toml", out=out)
    session.edit("crease", "rise", 0.85)
    del session  # the server is killed: nothing saved
    again = StudioSession.start(design / "vault.toml", out=out)
    assert again.model.design.crease.rise == 0.85 and not again.saved
    assert "restored unsaved edits" in again.notice
    again.save()
    third = StudioSession.start(design / "vault.toml", out=out)
    assert third.saved and third.notice == ""
    assert third.model.design.crease.rise == 0.85


def test_a_value_toml_cannot_hold_is_named(session):
    with pytest.raises(DesignError, match=r"deployment.alpha: a NoneType cannot be written"):
        document_text({"deployment": {"alpha": None}})
    session.replace({**session.document, "deployment": {"alpha": None}})
    assert session.problem.key == "deployment.alpha"
    assert session.notice == ""  # an invalid design never reaches the recovery copy


def test_document_text_without_a_source():
    document = {"crease": {"profile": "arc", "points": [[0.0, 1.0], [2.0, 3.0]]}}
    text = document_text(document)
    assert parse_toml(text) == document
    assert "[[0.0, 1.0], [2.0, 3.0]]" in text  # compact point lists


# -- checks and view ----------------------------------------------------------------------------
def test_checks_of_the_vault(vault_model):
    checks = design_checks(vault_model)
    rows = {r.name: r for r in checks.rows}
    figures = checks.figures
    # 6 mm plywood: characteristic utilisation 0.46, design (EC5 SC1 permanent) 0.92: it
    # passes, within BENDING_WARN of the limit
    assert rows["bending"].status == "warn" and "EC5 SC1 permanent" in rows["bending"].reason
    assert "t = 6 mm" in rows["bending"].reason
    assert rows["bending"].value == f"{figures.bending_utilisation:.3f}"
    assert rows["collision"].status == "ok" and checks.collision is None
    assert rows["crease planarity"].status == "ok"
    assert rows["invariants"].status == "ok"
    assert rows["global curvature"].value == "monoclastic"
    assert rows["span"].value == f"{figures.crease_span:.4g} m"
    assert max(checks.plate_utilisation.values()) == pytest.approx(figures.bending_utilisation)
    assert sorted(checks.plate_utilisation) == sorted(vault_model.plate_ids)


def test_checks_fail_with_their_reason():
    model = load_model(EXAMPLES / "vault.toml")
    document = model.design.document
    document["plates"]["thickness"] = 0.03  # 30 mm plywood cannot bend this far
    from compas_ccu.design import Design
    from compas_ccu.model import CCUModel

    thick = CCUModel(Design(document, name="thick"))
    rows = {r.name: r for r in design_checks(thick).rows}
    assert rows["bending"].status == "fail"
    reason = rows["bending"].reason
    assert "EXCEEDED: above the design bending strength (EC5 SC1 permanent)" in reason


def test_first_collision_is_refined_between_scanned_states():
    model = load_model(catalog_path("fig12a-asymmetric"))
    thick = ThickModel(model)
    upto = min(model.overlap_alpha, model.alpha_limit)
    hit = first_collision(thick, upto)
    assert hit is not None and 55.0 < hit["alpha"] < upto
    before = hit["alpha"] - upto / 24 / 64 * 1.01
    assert thick.collisions([before]).first is None
    assert thick.collisions([hit["alpha"]]).first is not None
    rows = {r.name: r for r in design_checks(model).rows}
    assert rows["collision"].status == "warn"  # beyond the design alpha of 30 deg
    assert f"{hit['alpha']:.4g}" in rows["collision"].reason
    assert thick.collisions([before]).first is None
    assert thick.collisions([hit["alpha"]]).first is not None


@pytest.mark.parametrize("coloring", COLORINGS)
def test_view_arrays_and_legends(vault_model, coloring):
    thick = ThickModel(vault_model)
    view = view_state(vault_model, 40.0, coloring=coloring, thick=thick, solids=True)
    s = vault_model.deploy(40.0)
    assert np.array_equal(view.vertices, s.deployed)
    assert view.span == s.metrics["span"] and view.rise == s.metrics["rise"]
    p, n = len(vault_model.plate_ids), vault_model.segments
    assert view.triangles.shape == (p, 2 * n, 3)
    assert view.creases.shape == (p - 1, n, 2, 3)
    assert view.crease_colors.shape == (p - 1, n, 3)
    # crease segments lie on the plates' crease vertices
    assert np.array_equal(view.creases[:, :-1, 1], view.creases[:, 1:, 0])
    assert len(view.solids) == p
    text = legend_html(view.legend)
    if coloring == "reflection angle":
        # orthogonal rulings: alpha is constant along every crease of the vault
        alphas = np.concatenate([c["alpha"] for c in s.creases])
        assert np.nanmax(alphas) - np.nanmin(alphas) < 1e-9
        assert f"constant {np.nanmean(alphas):.4f}°" in text
    if coloring == "bending utilisation":
        u = thick.bending([40.0]).per_plate[0]
        for pid, value in zip(vault_model.plate_ids, u):
            assert f"plate {pid}: {value:.3f}" in text
    if coloring == "crease planarity":
        assert "every crease planar" in text


def test_a_constant_angle_is_named_constant_not_spread_over_a_scale(cone_model):
    view = view_state(cone_model, 30.0, coloring="reflection angle")
    text = legend_html(view.legend)
    assert "constant 30.0000°" in text and "gradient" not in text


def test_a_varying_angle_is_drawn_on_a_scale_of_the_drawn_values():
    model = load_model(catalog_path("fig11c-alternating"))
    view = view_state(model, 35.0, coloring="reflection angle")
    alphas = np.concatenate([c["alpha"] for c in model.deploy(35.0).creases])
    lo, hi = np.nanmin(alphas), np.nanmax(alphas)
    assert hi - lo > 1.0
    text = legend_html(view.legend)
    assert "linear-gradient" in text
    # the scale spans the segment values drawn (means of two vertices): within the vertex range
    _, slo, shi, _ = view.legend["scale"]
    assert lo <= slo < shi <= hi and shi - slo > 0.9 * (hi - lo)


def test_cut_patterns_svg_flags_plates_larger_than_a_sheet(vault_model):
    svg, too_large = cut_patterns_svg(vault_model)
    assert svg.startswith("<svg") and svg.count("<polygon") == 10
    assert too_large == sorted(vault_model.plate_ids) or set(too_large) == set(
        vault_model.plate_ids
    )  # every vault plate is 2723 x 994 mm
    _, none = cut_patterns_svg(vault_model, sheet=(3.0, 1.5))
    assert none == []


@pytest.mark.slow  # an export process (1-3 s)
def test_export_writes_into_the_output_folder_only(session, folders):
    pytest.importorskip("ezdxf")
    design, out = folders
    before = sorted(p.name for p in design.iterdir())
    # shelf packing: spyrrow's true-shape search of the vault's sheets takes a minute (it has
    # tests of its own); the export writes what ccu fabricate writes either way
    assert session.edit("fabrication", "nesting", "shelf") is None
    text = session.text()
    written = export(session.model, out, alpha=35.0, what=("structure", "fabrication"),
                     design_text=text)  # fmt: skip
    assert written == {"structure": out / "vault" / "structure",
                       "fabrication": out / "vault" / "fabrication"}  # fmt: skip
    data = json.loads((out / "vault" / "structure" / "structure.json").read_text())
    assert data["alpha"] == 35.0
    assert (out / "vault" / "structure" / "design.toml").read_text() == text
    assert (out / "vault" / "fabrication" / "fabrication.json").is_file()
    assert sorted(p.name for p in design.iterdir()) == before
    with pytest.raises(ValueError, match="unknown export 'pictures'"):
        export(session.model, out, alpha=35.0, what=("pictures",))


# -- property tests over the whole schema -------------------------------------------------------
def _same(a, b) -> bool:
    """Equal values of equal types, NaN equal to NaN (a design may hold nan or inf)."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return isinstance(b, list) and len(a) == len(b) and all(map(_same, a, b))
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return True
    return type(a) is type(b) and a == b


@settings(
    max_examples=property_examples(60), deadline=None, suppress_health_check=list(HealthCheck)
)
@given(document=strategies.designs())
def test_any_design_is_a_model_or_a_problem_and_saves_as_it_reads(tmp_path_factory, document):
    folder = tmp_path_factory.mktemp("studio")
    (folder / "vault.toml").write_text((EXAMPLES / "vault.toml").read_text())
    session = StudioSession.start(folder / "vault.toml", out=folder / "out")
    vault = session.model
    problem = session.replace(document)
    assert (problem is None) == (session.problem is None)
    if problem is None:
        assert session.model.design.document == document
    else:
        assert problem.kind != "bug", problem.message
        assert session.model is vault  # the last valid model stays
    # the fields' text reads back as the document (over the vault file's comments), or a value
    # TOML cannot hold is named; Save writes the last valid design
    try:
        text = session.fields_text()
    except DesignError as exc:
        assert "cannot be written to a TOML file" in str(exc) and exc.key
        assert problem is not None
        return
    assert _same(parse_toml(session.text()), session.model_document if problem is None
                 else parse_toml((folder / "vault.toml").read_text()))  # fmt: skip
    assert _same(parse_toml(text), document)
    # and every control shows a value that edits back to the same document value
    for control in design_controls():
        value = session.value(control.section, control.name)
        if value is not UNSET and control.widget == "text":
            assert _same(parse_value(control, format_value(control, value)), value), control.key


def test_crowded_slider_marks_keep_the_more_telling_label():
    from types import SimpleNamespace

    from compas_ccu.studio.app import slider_marks

    model = SimpleNamespace(
        alpha_design=30.0, overlap_alpha=79.2, alpha_limit=82.0, collision_free_alpha=79.2
    )
    marks = slider_marks(model, {"alpha": 77.0}, 81.99)
    assert [m[0] for m in marks] == [0.0, 30.0, 77.0, 79.2, 81.99]  # every tick stays
    assert [m[1] for m in marks] == ["0", "design", "collision", "", ""]
    assert slider_marks(model, None, 81.99)[-2:] == [(79.2, "overlap"), (81.99, "")]
    # two plates crossing before any crease overlaps: its own mark, more telling than overlap
    model.collision_free_alpha = 75.9
    marks = slider_marks(model, None, 81.99)
    assert (75.9, "crossing") in marks and 79.2 in [m[0] for m in marks]


@pytest.mark.slow
def test_the_exported_report_records_the_design_as_edited(session, folders):
    """The studio's report export is an engineering record of the design as edited: its text
    and hash, and the fabrication folder exported with it."""
    import hashlib

    pytest.importorskip("ezdxf")
    _, out = folders
    session.edit("crease", "rise", 0.9)
    text = session.text()
    written = export(session.model, out, alpha=30.0, what=("fabrication", "report"),
                     design_text=text)  # fmt: skip
    report = written["report"]
    assert (report / "design" / "vault.toml").read_text("utf-8") == text
    page = (report / "index.html").read_text("utf-8")
    assert hashlib.sha256(text.encode("utf-8")).hexdigest() in page
    assert (report / "fabrication" / "fabrication.json").is_file()
    # the fabrication carries the same hash, so the report's viewer shows its sheets
    sha = hashlib.sha256(text.encode("utf-8")).hexdigest()
    manifest = json.loads((written["fabrication"] / "fabrication.json").read_text("utf-8"))
    assert manifest["design_sha256"] == sha
    sheets = manifest["workshop"]["sheet_count"]
    parts = manifest["bom"]["plates"] + manifest["bom"]["splices"]
    assert parts == 10  # the vault's 1525 x 3050 mm stock sheets take every plate whole
    page = (report / "viewer.html").read_text("utf-8")
    assert f"cut patterns: {sheets} sheets, {parts} parts" in page


# -- nothing lost (issue 27) --------------------------------------------------------------------
def _recovery_text(session) -> str:
    return (session.files.recovery_of(session.path) / "recovery.toml").read_text("utf-8")


def test_two_folders_with_the_same_file_name_never_exchange_edits(tmp_path):
    out = tmp_path / "out"
    for name in ("a", "b"):
        (tmp_path / name).mkdir()
        shutil.copy(EXAMPLES / "vault.toml", tmp_path / name / "vault.toml")
    a = StudioSession.start(tmp_path / "a" / "vault.toml", out=out)
    a.edit("crease", "rise", 0.85)
    b = StudioSession.start(tmp_path / "b" / "vault.toml", out=out)
    assert b.model.design.crease.rise == 1.0 and b.saved and b.notice == ""
    b.edit("layout", "plates", 6)
    again = StudioSession.start(tmp_path / "a" / "vault.toml", out=out)
    assert again.model.design.crease.rise == 0.85 and again.model.plates.count == 10
    assert "restored unsaved edits" in again.notice
    b2 = StudioSession.start(tmp_path / "b" / "vault.toml", out=out)
    assert b2.model.design.crease.rise == 1.0 and b2.model.plates.count == 6
    assert len(list((out / ".ccu-studio").iterdir())) == 2  # one recovery copy per file


def test_a_recovery_copy_older_than_the_file_is_offered_not_restored(folders):
    design, out = folders
    session = StudioSession.start(design / "vault.toml", out=out)
    session.edit("crease", "rise", 0.85)
    del session  # killed; then the file is changed by someone else
    text = (design / "vault.toml").read_text().replace("rise = 1.0", "rise = 0.7")
    (design / "vault.toml").write_text(text)
    again = StudioSession.start(design / "vault.toml", out=out)
    assert again.model.design.crease.rise == 0.7 and again.saved  # the file, not the copy
    assert again.recovery is not None and "rise = 0.85" in again.recovery.text
    assert again.notice.startswith("a recovery copy of vault.toml from ")
    assert "is older than the file (it changed since)" in again.notice
    # a restart before choosing offers it again
    third = StudioSession.start(design / "vault.toml", out=out)
    assert third.recovery is not None and third.model.design.crease.rise == 0.7
    third.restore_recovery()
    assert third.model.design.crease.rise == 0.85 and not third.saved
    assert third.recovery is None and third.notice.startswith("restored the recovery copy")
    assert third.undo() and third.model.design.crease.rise == 0.7  # back to the file
    with pytest.raises(OptionError, match="no recovery copy of vault.toml is waiting"):
        third.restore_recovery()


def test_keeping_the_file_deletes_the_offered_copy(folders):
    design, out = folders
    StudioSession.start(design / "vault.toml", out=out).edit("crease", "rise", 0.85)
    (design / "vault.toml").write_text((design / "vault.toml").read_text() + "\n# changed\n")
    session = StudioSession.start(design / "vault.toml", out=out)
    assert session.recovery is not None
    session.discard_recovery()
    assert session.recovery is None and session.model.design.crease.rise == 1.0
    assert "the recovery copy from" in session.notice and "is deleted" in session.notice
    again = StudioSession.start(design / "vault.toml", out=out)
    assert again.recovery is None and again.notice == ""
    with pytest.raises(OptionError, match="no recovery copy"):
        again.discard_recovery()


def test_save_as_can_never_target_the_studios_own_folder(tmp_path):
    session = StudioSession.start(out=tmp_path)  # design folder == output folder
    assert session.files.design_folder == session.files.out
    for name in (".ccu-studio/x.toml", ".ccu-studio/sub/y.toml", "a/.ccu-studio/z.toml"):
        with pytest.raises(OptionError, match=r"\.ccu-studio/ is the studio's own folder"):
            session.save_as(name)
    session.edit("crease", "rise", 0.5)
    recovery = session.files.recovery_of(session.path)
    os.symlink(recovery, tmp_path / "link")
    with pytest.raises(OptionError, match="the studio's own folder"):
        session.save_as("link/recovery.toml")  # a link into it is refused too
    assert "rise = 0.5" in (recovery / "recovery.toml").read_text()


def test_a_save_keeps_the_permission_bits(session, folders):
    design, _ = folders
    path = design / "vault.toml"
    os.chmod(path, 0o640)
    session.edit("crease", "rise", 0.9)
    session.save()
    assert oct(os.stat(path).st_mode & 0o777) == oct(0o640)
    umask = os.umask(0o022)
    try:
        new = session.save_as("new.toml")
    finally:
        os.umask(umask)
    assert oct(os.stat(new).st_mode & 0o777) == oct(0o644)  # a new file: the umask's


def test_a_failed_save_leaves_the_old_file(session, folders, monkeypatch):
    design, _ = folders
    before = (design / "vault.toml").read_bytes()
    session.edit("crease", "rise", 0.9)

    def refuse(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr("compas_ccu.studio.files.os.replace", refuse)
    with pytest.raises(OSError, match="No space left"):
        session.save()
    assert (design / "vault.toml").read_bytes() == before
    assert sorted(p.name for p in design.iterdir()) == ["cone.toml", "vault.toml"]  # no temp
    assert not session.saved and "rise = 0.9" in _recovery_text(session)


def test_an_invalid_value_never_reaches_the_history_or_the_recovery_copy(session):
    session.edit("crease", "rise", 0.8)
    recovered = _recovery_text(session)
    session._last_edit = (None, 0.0)
    problem = session.edit("crease", "rise", -1.0)
    assert problem.message == "crease.rise: must be > 0 and <= 1e6, got -1.0"
    assert session.value("crease", "rise") == -1.0  # the field keeps what was typed
    assert session.pending == ["crease.rise"]
    assert session.valid_document["crease"]["rise"] == 0.8
    assert parse_toml(session.text())["crease"]["rise"] == 0.8  # what Save writes
    assert _recovery_text(session) == recovered
    session.edit("crease", "rise", "abc")
    assert _recovery_text(session) == recovered
    assert session.edit("crease", "rise", 0.7) is None and session.pending == []
    assert parse_toml(_recovery_text(session))["crease"]["rise"] == 0.7
    assert session.undo() and session.model.design.crease.rise == 0.8
    assert session.undo() and session.model.design.crease.rise == 1.0
    assert not session.undo()
    assert session.redo() and session.redo() and not session.redo()
    assert session.model.design.crease.rise == 0.7
    # an undo with a pending field drops it first: back to the valid design
    session.edit("layout", "plates", 0)
    assert session.pending == ["layout.plates"] and session.can_undo
    assert session.undo() and session.pending == [] and session.problem is None
    assert session.value("layout", "plates") == 10 and session.model.design.crease.rise == 0.7


def test_two_edits_that_build_only_together_are_one_step(session):
    problem = session.edit("crease", "profile", "polyline")
    assert problem.key == "[crease]" and "unknown key 'span'" in problem.message
    for key in ("span", "rise", "segments", "state"):
        session.edit("crease", key, UNSET)
    assert session.edit("crease", "points", PARABOLA) is None
    assert session.model.design.crease.profile == "polyline"
    assert session.undo() and session.model.design.crease.profile == "arc"


#: A smooth polyline crease (a parabola over 9 points), as TOML and as a CSV curve file.
_X = np.linspace(-1.25, 1.25, 9)
PARABOLA = np.column_stack([_X, 0.4 * (1 - (_X / 1.25) ** 2)]).tolist()
PARABOLA_CSV = "".join(f"{x!r} {y!r}\n" for x, y in PARABOLA)


def _curve_design(points: str) -> str:
    return (
        f'[crease]\nprofile = "polyline"\npoints = {points}\n[rulings]\ntype = "orthogonal"\n'
        "[deployment]\nalpha = 30.0\n[layout]\nplates = 2\nwidth = 0.3\n"
    )


def test_curve_files_outside_the_design_folder_are_refused(tmp_path):
    folder, other = tmp_path / "designs", tmp_path / "curves"
    folder.mkdir()
    other.mkdir()
    for where in (folder, other):
        (where / "c.csv").write_text(PARABOLA_CSV)
    (folder / "inside.toml").write_text(_curve_design('"c.csv"'))
    assert StudioSession.start(folder / "inside.toml", out=tmp_path / "o").problem is None
    for points in ('"../curves/c.csv"', f'"{other / "c.csv"}"', f'{{ file = "{other}/c.csv" }}'):
        (folder / "outside.toml").write_text(_curve_design(points))
        session = StudioSession.start(folder / "outside.toml", out=tmp_path / "o")
        problem = session.problem
        assert problem.key == "crease.points" and problem.kind == "DesignError"
        assert f"({other / 'c.csv'}) is outside the design folder {folder}" in problem.message
        assert "ccu studio --allow-dir DIR" in problem.message and "\n" not in problem.message
    allowed = StudioSession.start(folder / "outside.toml", out=tmp_path / "o", allowed=[other])
    assert allowed.problem is None and allowed.model.plates.count == 2
    # an upload naming a file elsewhere is refused the same way
    session = StudioSession.start(folder / "inside.toml", out=tmp_path / "o")
    session.open_upload("up.toml", _curve_design('"/etc/hostname"').encode())
    assert session.problem.key == "crease.points" and "is outside the design folder" in (
        session.problem.message
    )


@pytest.mark.parametrize(
    "content, error, message",
    [
        (b"a = " + b"[" * 100_000 + b"]" * 100_000, OptionError,
         "'x.toml' nests arrays or tables 100000 deep; a design file nests at most 32 deep"),
        (b"a = " + b"[" * 33 + b"]" * 33, OptionError, "nests arrays or tables 33 deep"),
        (b"\x7fELF\x02\x01\x01\x00" + bytes(range(256)), OptionError,
         "'x.toml' is not a text file (byte 136 is not UTF-8)"),
        (b"a = 1\x00", OptionError, "'x.toml' is not a text file (it holds NUL bytes)"),
        (b"#" * 1_000_001, LimitError, "'x.toml' is 1,000,001 bytes; a design file may have "
         "at most 1,000,000 bytes (the limit upload_bytes; raise it with --limit "
         "upload_bytes=1000001)"),
        (b"[crease\nspan = ", OptionError, "x.toml: not valid TOML: "),
        (b"[crease]\nrise = 1\nrise = 2\n", OptionError, "x.toml: not valid TOML: "),
    ],
)  # fmt: skip
def test_a_bad_upload_is_refused_with_one_line(session, content, error, message):
    before = session.text()
    with pytest.raises(error) as info:
        session.open_upload("x.toml", content)
    assert message in str(info.value) and "\n" not in str(info.value)
    assert session.name == "vault.toml" and session.text() == before


def test_a_design_file_nested_32_deep_is_a_problem_not_a_bug(session):
    content = b'[crease]\nprofile = "polyline"\npoints = ' + b"[" * 32 + b"]" * 32
    session.open_upload("deep.toml", content)
    assert session.problem.kind == "DesignError" and session.problem.key == "crease.points"


def test_a_field_text_too_large_or_too_deep_is_refused_with_one_line():
    from compas_ccu.studio.controls import check_field_text

    points = next(c for c in design_controls() if c.key == "crease.points")
    check_field_text(points, "[[0.0, 0.0], [1.0, 0.5]]")
    with pytest.raises(OptionError, match="crease.points: the value nests arrays 50000 deep"):
        check_field_text(points, "[" * 50_000 + "]" * 50_000)
    with pytest.raises(OptionError, match=r"crease.points: the value is 1,000,001 bytes; a"):
        check_field_text(points, "1" * 1_000_001)
    assert parse_value(points, "[" * 50_000 + "]" * 50_000).startswith("[[[")  # no exception


def test_a_long_point_list_edits_and_saves_as_it_reads(tmp_path):
    """10,000 points go around tomlkit (the time is measured in bench_studio_live.py)."""
    (tmp_path / "poly.toml").write_text("# my polyline\n" + _curve_design(f"{PARABOLA}  # m"))
    session = StudioSession.start(tmp_path / "poly.toml", out=tmp_path / "o")
    control = next(c for c in design_controls() if c.key == "crease.points")
    x = np.linspace(-1.25, 1.25, 10_000)
    points = np.column_stack([x, 0.8 * (1 - (x / 1.25) ** 2)]).tolist()
    value = parse_value(control, format_value(control, points))
    assert value == points  # the JSON fast path reads the same floats as TOML
    assert parse_toml(f"v = {format_value(control, points)}")["v"] == points
    assert session.edit("crease", "points", value) is None
    text = session.text()
    assert text.startswith("# my polyline\n") and parse_toml(text)["crease"]["points"] == points
    session.save()
    assert session.edit("layout", "plates", 3) is None  # the saved long array stays as written
    again = session.text()
    assert again.count("\n") == text.count("\n") and parse_toml(again)["layout"]["plates"] == 3
    assert parse_toml(again)["crease"]["points"] == points
    assert "[[-1.25, 0.0], [-1.2497499749974998, " in again


def test_document_text_keeps_a_long_array_with_comments_and_special_numbers():
    source = "[crease]\n# the points\npoints = [\n" + "".join(
        f"  [{i}.0, {i}.5],\n" for i in range(40)) + "]  # end\nrise = 1.0\n"  # fmt: skip
    document = parse_toml(source)
    assert document_text(document, source) == source  # unchanged: kept as written
    document["crease"]["rise"] = 2.0
    assert document_text(document, source) == source.replace("rise = 1.0", "rise = 2.0")
    document["crease"]["points"] = [[float("nan"), float("inf")]] + [[-float("inf"), 1]] * 60
    text = document_text(document, source)
    assert _same(parse_toml(text), document) and "[[nan, inf], [-inf, 1], " in text


@pytest.mark.slow  # an export process (1-3 s)
def test_the_export_runs_in_another_process(session, folders):
    from compas_ccu.studio.export import ExportProcess

    _, out = folders
    exporter = ExportProcess()
    try:
        pid, written = exporter.submit(session.model, out, alpha=35.0, what=("structure",),
                                       design_text=session.text()).result(timeout=300)  # fmt: skip
        assert pid != os.getpid()
        assert written == {"structure": out / "vault" / "structure"}
        assert json.loads((out / "vault" / "structure" / "structure.json").read_text())[
            "alpha"] == 35.0  # fmt: skip
        (out / "blocked").write_text("a file where the folder goes")
        future = exporter.submit(session.model, out / "blocked", alpha=35.0,
                                 what=("structure",), design_text=None)  # fmt: skip
        with pytest.raises(OptionError, match="blocked', which is a file"):
            future.result(timeout=300)  # the error of the export process reaches the studio
    finally:
        exporter.stop()


def test_the_loop_probe_sees_a_blocked_event_loop():
    import asyncio
    import threading
    import time

    from compas_ccu.studio.workers import LoopProbe

    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()
    try:
        probe = LoopProbe(loop).start()
        time.sleep(0.1)
        loop.call_soon_threadsafe(time.sleep, 0.3)  # a callback that holds the loop
        time.sleep(0.5)
        gap = probe.stop()
        assert gap > 0.25 and probe.beats >= 1  # the 0.3 s it was held (more on a busy machine)
    finally:
        loop.call_soon_threadsafe(loop.stop)
        thread.join(5)


def test_opening_a_file_from_the_menu_restores_its_own_recovery_copy(session, folders):
    design, out = folders
    session.edit("crease", "rise", 0.85)
    session.open_file("cone.toml")
    assert session.name == "cone.toml" and session.saved and session.notice == ""
    session.open_file("vault.toml")
    assert session.model.design.crease.rise == 0.85 and not session.saved
    assert session.notice.startswith("restored unsaved edits of vault.toml")


def test_a_curve_file_reached_through_a_link_out_of_the_folder_is_refused(tmp_path):
    folder, other = tmp_path / "designs", tmp_path / "elsewhere"
    folder.mkdir()
    other.mkdir()
    (other / "c.csv").write_text(PARABOLA_CSV)
    os.symlink(other / "c.csv", folder / "c.csv")
    (folder / "d.toml").write_text(_curve_design('"c.csv"'))
    problem = StudioSession.start(folder / "d.toml", out=tmp_path / "o").problem
    assert problem.key == "crease.points"
    assert f"'c.csv' ({other / 'c.csv'}) is outside the design folder" in problem.message


@pytest.mark.slow  # an export process (1-3 s)
def test_a_killed_export_process_is_said_and_started_again(session, folders):
    import signal

    from compas_ccu.studio.export import ExportProcess

    _, out = folders
    exporter = ExportProcess()
    try:
        pid, _ = exporter.submit(session.model, out, alpha=30.0, what=("structure",),
                                 design_text=None).result(timeout=300)  # fmt: skip
        os.kill(pid, signal.SIGKILL)  # the export process dies (out of memory, killed)
        time.sleep(1.0)
        future = exporter.submit(session.model, out, alpha=30.0, what=("structure",),
                                 design_text=None)  # fmt: skip
        try:
            again, _ = future.result(timeout=300)
        except Exception as exc:  # the pool noticed the death only now: it is broken once
            assert type(exc).__name__ == "BrokenProcessPool"
            again, _ = exporter.submit(session.model, out, alpha=30.0, what=("structure",),
                                       design_text=None).result(timeout=300)  # fmt: skip
        assert again not in (pid, os.getpid())
    finally:
        exporter.stop()
