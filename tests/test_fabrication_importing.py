"""``ccu import``: plate DXFs back to a design that deploys (fabricate -> import -> deploy)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from compas_ccu.catalog import catalog_path
from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.design.document import parse_toml
from compas_ccu.errors import DesignError
from compas_ccu.model import CCUModel, load_model
from compas_ccu.thickness import ThickModel
from conftest import EXAMPLES, circumradius_error

ezdxf = pytest.importorskip("ezdxf")
pytest.importorskip("shapely")
pytest.importorskip("rhino3dm")
pytest.importorskip("trimesh")

from compas_ccu.fabrication import import_thickness  # noqa: E402
from compas_ccu.fabrication.fabricate import fabricate  # noqa: E402
from compas_ccu.fabrication.importing import (  # noqa: E402
    UNDO_TOLERANCE,
    import_design,
    import_structure,
    pair_creases,
    read_plate_drawing,
    read_plate_folder,
    round_trip_error,
    structure_round_trip_error,
    thickness_shifts,
)
from compas_ccu.fabrication.workshop import WorkshopOptions  # noqa: E402

#: The sheets nested by shelves: fast, and the plate files do not depend on the nesting.
SHELF = WorkshopOptions(nesting="shelf")

R, WIDTH, SWEEP, N, ALPHA = 2.0, 0.4, 90.0, 48, 40.0


def sector(msp, *, radius=R, rulings=None, far=None, crease_entity="ARC", layers=None):
    """An annular sector drawn by hand (mm): crease = outer arc, rulings radial."""
    layers = layers or {"CUT": "CUT", "CREASE": "CREASE", "RULING_SCORE": "RULING_SCORE"}
    k = 1000.0
    a0, a1 = 45.0, 45.0 + SWEEP
    inner = radius - WIDTH
    bulge = math.tan(math.radians(SWEEP) / 4.0)

    def at(r, deg):
        return (r * k * math.cos(math.radians(deg)), r * k * math.sin(math.radians(deg)))

    if layers["CUT"]:
        msp.add_lwpolyline(
            [(*at(radius, a0), bulge), (*at(radius, a1), 0.0), (*at(inner, a1), -bulge),
             (*at(inner, a0), 0.0)],
            format="xyb",
            close=True,
            dxfattribs={"layer": layers["CUT"]},
        )  # fmt: skip
    if crease_entity == "ARC":
        msp.add_arc((0, 0), radius * k, a0, a1, dxfattribs={"layer": layers["CREASE"]})
    angles = np.linspace(a0, a1, N + 1)[1:-1] if rulings is None else rulings
    if layers["RULING_SCORE"]:
        for j, deg in enumerate(angles):
            end = at(inner, deg) if far is None else far(j, deg)
            msp.add_line(at(radius, deg), end, dxfattribs={"layer": layers["RULING_SCORE"]})


def hand_drawn(folder, **partner):
    folder.mkdir(exist_ok=True)
    for name, options in (("plate_a.dxf", {}), ("plate_b.dxf", partner)):
        doc = ezdxf.new("R2010")
        doc.units = ezdxf.units.MM
        sector(doc.modelspace(), **options)
        doc.saveas(folder / name)
    return folder


def test_hand_drawn_circular_crease_deploys_to_the_cone(tmp_path):
    """One ARC crease, 47 radial LINE rulings, bulged outlines, no XDATA, no fabrication.json:
    the plates pair by their creases' lengths and the design deploys to the cone, the crease a
    circle of radius r3D = R cos(alpha), and equals examples/cone.toml's structure."""
    folder = hand_drawn(tmp_path / "drawn")
    document, report = import_design(folder, alpha=ALPHA)
    assert report["segments"] == N and report["partner_error"] < 1e-12
    near = np.asarray(document["crease"]["points"])
    assert np.abs(np.linalg.norm(near, axis=1) - R).max() < 1e-12  # vertices on the arc
    structure = CCUModel(Design(document)).deploy(ALPHA)
    deployed = np.asarray(structure.deployed)
    expected = R * math.cos(math.radians(ALPHA))
    assert circumradius_error(deployed[0, : N + 1], expected) < 1e-12
    assert circumradius_error(deployed[0, N + 1 :], (R - WIDTH) * math.cos(math.radians(ALPHA))) < (
        1e-12
    )
    cone = load_model(EXAMPLES / "cone.toml").deploy(ALPHA)
    # the same plates up to a rigid motion: compare the (rigid-invariant) pairwise distances
    a = deployed.reshape(-1, 3)[::7]
    b = np.asarray(cone.deployed).reshape(-1, 3)[::7]
    da = np.linalg.norm(a[:, None] - a[None], axis=2)
    db = np.linalg.norm(b[:, None] - b[None], axis=2)
    assert np.abs(da - db).max() < 1e-12


@pytest.mark.slow  # ~1.3 s; the quick loop's cone round trip: test_design_patterns.py
def test_round_trip_cone_fabricate_import_deploy(tmp_path):
    model = load_model(EXAMPLES / "cone.toml")
    fabricate(model, tmp_path / "fab", workshop=SHELF)
    result = round_trip_error(model, tmp_path / "fab")
    assert result.max_relative < 1e-9
    assert result.plate_ids == [0, 1] and result.crease_id == 0


@pytest.mark.slow
def test_round_trip_vault_every_crease_pair(tmp_path):
    """The vault's orthogonal rulings need no offset-crease correction: every one of its nine
    crease pairs comes back to rounding (measured 1.1e-15 ... 1.6e-15 relative)."""
    model = load_model(EXAMPLES / "vault.toml")
    fabricate(model, tmp_path / "fab", workshop=SHELF)
    errors = [round_trip_error(model, tmp_path / "fab", crease=c).max_relative for c in range(9)]
    assert max(errors) < 1e-9
    with pytest.raises(DesignError, match="9 creases .*one crease pair: choose one"):
        import_design(tmp_path / "fab")
    # the whole vault, all ten plates joined into one mechanism (measured 1.4e-15)
    whole = structure_round_trip_error(model, tmp_path / "fab", crease=4)
    assert whole.plates == 10 and whole.max_relative < 1e-9
    assert whole.report["attached"][:2] == ["plate_5.dxf", "plate_4.dxf"]  # upper plate leads


def leading_crease(model, folder):
    """The crease id (XDATA) of the model's leading crease in a fabricated folder."""
    lead = next(c for c in model.mechanism.creases if c.fixed)
    ids = {model.plates.output_id(lead.plate_a), model.plates.output_id(lead.plate_b)}
    pairs = pair_creases(read_plate_folder(folder))
    return next(p.crease_a.crease_id for p in pairs if {p.a.plate_id, p.b.plate_id} == ids)


@pytest.fixture(scope="module")
def inclined3(tmp_path_factory):
    """fig11a's inclined layout with 3 plates and 16 segments, fabricated with 8 mm plates:
    its cut patterns carry the thickness correction (7.7e-5 m on crease 0)."""
    document = parse_toml(catalog_path("fig11a-constant-apex").read_text(encoding="utf-8"))
    document["crease"]["segments"] = 16
    document["layout"].update(plates=3, spacing_start=[0.08, 0.08, 0.16])
    model = CCUModel(Design(document))
    folder = tmp_path_factory.mktemp("inclined3") / "fab"
    manifest = fabricate(model, folder, hinge_width=0.03, allow_collisions=True)
    assert manifest["thickness"] == 0.008 and max(manifest["correction_design"]) > 7e-5
    return model, folder


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_thickness_shifts_are_the_thick_models(inclined3):
    """The forward correction the import undoes is ThickModel's, vertex by vertex."""
    model, _ = inclined3
    thick = ThickModel(model)
    near, far = thickness_shifts(model.mechanism, thick.thickness, model.alpha_design)
    index = model.plates
    assert np.abs(near - thick.shifts[:, index.near_rows]).max() < 1e-15
    assert np.abs(far - thick.shifts[:, index.far_rows]).max() < 1e-15
    assert np.abs(far).max() > 7e-5


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_round_trip_undoes_the_thickness_correction(inclined3):
    """8 mm plates: the correction undone, the structure and the leading pair come back to
    rounding (measured 2.5e-16); taken as drawn, they are off by the correction (2.6e-5)."""
    model, folder = inclined3
    crease = leading_crease(model, folder)
    whole = structure_round_trip_error(model, folder, crease=crease)
    assert whole.plates == 3 and whole.max_relative < 1e-9
    undone = whole.report["thickness_correction"]
    assert undone["thickness"] == 0.008 and undone["iterations"] <= 3
    assert 7e-5 < undone["largest"] < 8e-5 and undone["change"] <= UNDO_TOLERANCE
    pair = round_trip_error(model, folder, crease=crease)
    assert pair.max_relative < 1e-9
    assert pair.report["thickness_correction"]["iterations"] == undone["iterations"]
    drawn = structure_round_trip_error(model, folder, crease=crease, as_drawn=True)
    assert drawn.report["thickness_correction"] is None
    assert drawn.max_relative > 1e-5


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_undoing_that_does_not_converge_is_refused(inclined3, monkeypatch):
    model, folder = inclined3
    crease = leading_crease(model, folder)
    monkeypatch.setattr(import_thickness, "UNDO_ITERATIONS", 1)
    with pytest.raises(
        DesignError,
        match=rf"{re.escape(str(folder))}: undoing the thickness correction of the cut patterns "
        r"\(0.008 m plates, fabrication.json\) did not converge in 1 iterations \(the shifts "
        r"still change by [\d.e-]+ m > [\d.e-]+ m\); import the patterns as drawn",
    ):
        import_structure(folder, crease=crease)
    with pytest.raises(DesignError, match="did not converge in 1 iterations"):
        import_design(folder, crease=crease)
    structure = import_structure(folder, crease=crease, as_drawn=True)  # no undoing: no error
    assert structure.report["thickness_correction"] is None


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_cli_import_undoes_or_takes_the_patterns_as_drawn(inclined3, tmp_path, capsys):
    """``ccu import`` undoes the correction: the leading plate's ruling ends move out by the
    correction of its far crease (7.45e-5 m), its crease (the leading one) does not move.
    ``--as-drawn`` takes the drawn patterns: the whole structure is written; of the leading
    pair alone (``--leading-pair-only``) the partner (its far edge free, not corrected) is no
    longer the leading plate's mirror image: refused, nothing written."""
    model, folder = inclined3
    crease = str(leading_crease(model, folder))
    undone, drawn = tmp_path / "undone.toml", tmp_path / "drawn.toml"
    assert main(["import", str(folder), "--crease", crease, "--out", str(undone)]) == 0
    out = capsys.readouterr().out
    assert "the thickness correction of 8 mm plates undone (up to 0.0745 mm, 2 iterations)" in out
    assert "# the thickness correction of 8 mm plates undone" in undone.read_text(encoding="utf-8")
    design = load_design(undone)
    assert design.layout.type == "patterns" and len(design.layout.patterns) == 2
    as_drawn = import_structure(folder, crease=crease, as_drawn=True).design
    moved = np.linalg.norm(np.subtract(design.rulings.points, as_drawn.rulings.points), axis=1)
    assert 7.4e-5 < moved.max() < 7.5e-5
    assert np.abs(np.subtract(design.crease.points, as_drawn.crease.points)).max() < 1e-12
    argv = ["import", str(folder), "--crease", crease, "--out", str(drawn), "--as-drawn"]
    assert main(argv) == 0 and load_design(drawn).layout.type == "patterns"
    capsys.readouterr()
    argv += ["--leading-pair-only", "--force"]
    assert main(argv) == 2
    assert re.search(
        r"plate_\d.dxf RULING_SCORE #\w+ \(end ruling\): the ruling at crease vertex \d+ is "
        r"0.157603132 m long, its partner in plate_\d.dxf 0.157528644 m",
        capsys.readouterr().err,
    )


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_bad_thickness_in_fabrication_json_is_refused(tmp_path):
    folder = hand_drawn(tmp_path / "drawn")
    (folder / "fabrication.json").write_text('{"alpha": 40.0, "thickness": -0.008}')
    with pytest.raises(
        DesignError,
        match=r"drawn: fabrication.json's thickness must be a length > 0 m, got -0.008",
    ):
        import_design(folder)
    document, report = import_design(folder, as_drawn=True)
    assert report["thickness_correction"] is None and document["deployment"]["alpha"] == 40.0


@pytest.mark.slow
def test_round_trip_fig11a_at_8_mm_undoes_the_thickness_correction(tmp_path):
    """fig11a's inclined planes need the offset-crease correction (up to 3.0e-4 m), which the
    cut patterns carry; undone, the whole structure comes back to 1.6e-15 relative (measured;
    2.4e-4 as drawn). Its plates alternate in width, so of the crease pairs only the leading
    one is a mirror pair a design file can hold (measured 1.4e-15)."""
    model = load_model(catalog_path("fig11a-constant-apex"))
    fabricate(model, tmp_path / "fab", hinge_width=0.03, allow_collisions=True)
    whole = structure_round_trip_error(model, tmp_path / "fab", crease=4)
    assert whole.plates == 10 and whole.max_relative < 1e-9
    assert whole.report["thickness_correction"]["largest"] > 2.9e-4
    assert round_trip_error(model, tmp_path / "fab", crease=4).max_relative < 1e-9
    with pytest.raises(DesignError, match=r"RULING_SCORE #\w+ \(end ruling\): the ruling at"):
        import_design(tmp_path / "fab", crease=0)
    structure = import_structure(tmp_path / "fab", crease=4)
    assert len(structure.plate_ids) == 10 and structure.design.alpha == 30.0


@pytest.mark.slow
def test_round_trip_fig12b_at_8_mm_undoes_the_thickness_correction(tmp_path):
    """fig12b's radial layout: the correction (up to 2.1e-4 m) undone, the whole dome and its
    leading pair come back to rounding (measured 8.0e-15 and 2.1e-15; 1.9e-4 and 6.5e-5 as
    drawn). Another pair of the leading crease's parity (the same reflection angle) too
    (7.2e-15): its correction is undone on the tree of a crease of that parity, found by
    trying."""
    model = load_model(catalog_path("fig12b-dome"))
    fabricate(model, tmp_path / "fab", hinge_width=0.03, allow_collisions=True)
    crease = leading_crease(model, tmp_path / "fab")
    whole = structure_round_trip_error(model, tmp_path / "fab", crease=crease)
    assert whole.plates == 12 and whole.max_relative < 1e-9
    assert round_trip_error(model, tmp_path / "fab", crease=crease).max_relative < 1e-9
    pairs = pair_creases(read_plate_folder(tmp_path / "fab"))
    plates = {p.crease_a.crease_id: {p.a.plate_id, p.b.plate_id} for p in pairs}
    near = {c for c, ids in plates.items() if ids & plates[crease]} - {crease}
    second = {c for c, ids in plates.items() if any(ids & plates[n] for n in near)}
    other = round_trip_error(model, tmp_path / "fab", crease=min(second - near - {crease}))
    assert other.max_relative < 1e-9
    # undone on a tree whose leading crease has the design's reflection angle: the leading
    # crease's or another of its parity (fig12b's creases 1, 3, 5, 7, 9), whichever converges
    # first
    leading = other.report["thickness_correction"]["leading"]
    assert int(leading.split()[1]) % 2 == crease % 2, (leading, crease)


def test_missing_layer_is_refused_naming_the_file(tmp_path):
    folder = tmp_path / "drawn"
    folder.mkdir()
    doc = ezdxf.new("R2010")
    sector(doc.modelspace(), layers={"CUT": "CUT", "CREASE": "CREASE", "RULING_SCORE": None})
    doc.saveas(folder / "plate_a.dxf")
    with pytest.raises(DesignError, match="plate_a.dxf: no entity on layer RULING_SCORE"):
        read_plate_drawing(folder / "plate_a.dxf")


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_crossing_rulings_are_refused_naming_both_entities(tmp_path):
    inner = R - WIDTH

    def crossed(j, deg):  # rulings 10 and 11 swap their far ends
        other = {10: 1, 11: -1}.get(j, 0)
        d = math.radians(deg + other * SWEEP / N)
        return (inner * 1000 * math.cos(d), inner * 1000 * math.sin(d))

    folder = hand_drawn(tmp_path / "drawn", far=crossed)
    with pytest.raises(
        DesignError, match=r"plate_b.dxf RULING_SCORE #\w+ and #\w+: the rulings cross"
    ):
        import_design(folder, alpha=ALPHA)


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_partner_creases_of_different_length_are_refused(tmp_path):
    folder = hand_drawn(tmp_path / "drawn", radius=2.1)
    with pytest.raises(
        DesignError,
        match=r"partner creases of different length: plate_a.dxf CREASE #\w+ is 3.14159265 m "
        r"long, plate_b.dxf CREASE #\w+ 3.29867229 m",
    ):
        import_design(folder, alpha=ALPHA)


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_partner_that_is_not_the_mirror_image_is_refused(tmp_path):
    inner = R - WIDTH - 0.05

    def longer(j, deg):
        d = math.radians(deg)
        r = inner if j == 20 else R - WIDTH
        return (r * 1000 * math.cos(d), r * 1000 * math.sin(d))

    folder = hand_drawn(tmp_path / "drawn", far=longer)
    with pytest.raises(
        DesignError, match=r"plate_b.dxf RULING_SCORE #\w+: the ruling at crease vertex 21 is"
    ):
        import_design(folder, alpha=ALPHA)


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_no_angle_without_fabrication_json(tmp_path):
    with pytest.raises(DesignError, match=r"give the design reflection angle \(--alpha DEG\)"):
        import_design(hand_drawn(tmp_path / "drawn"))


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_cli_import_writes_a_design_that_loads(tmp_path, capsys):
    folder = hand_drawn(tmp_path / "drawn")
    out = tmp_path / "cone-imported.toml"
    assert main(["import", str(folder), "--out", str(out), "--alpha", "40", "--quiet"]) == 0
    design = load_design(out)
    assert design.crease.state == "flat" and design.rulings.type == "explicit"
    assert len(design.crease.points) == N + 1 and design.alpha == ALPHA
    assert main(["import", str(folder), "--out", str(out), "--alpha", "40"]) == 2
    assert "exists; give --force" in capsys.readouterr().err


@pytest.mark.slow  # a fabrication, or an import of a thick structure (1-1.5 s)
def test_open_outline_ruling_off_the_crease_and_crease_off_the_outline(tmp_path):
    folder = tmp_path / "drawn"
    folder.mkdir()
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    msp = doc.modelspace()
    sector(msp, layers={"CUT": None, "CREASE": "CREASE", "RULING_SCORE": "RULING_SCORE"})
    msp.add_lwpolyline([(0, 0), (100, 0), (100, 100)], dxfattribs={"layer": "CUT"})
    doc.saveas(folder / "plate_a.dxf")
    with pytest.raises(DesignError, match=r"plate_a.dxf CUT #\w+: the outline is not closed"):
        read_plate_drawing(folder / "plate_a.dxf")

    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    sector(doc.modelspace())
    stray = doc.modelspace().add_line((0, 0), (10, 10), dxfattribs={"layer": "RULING_SCORE"})
    doc.saveas(folder / "plate_a.dxf")
    doc.saveas(folder / "plate_b.dxf")
    with pytest.raises(
        DesignError,
        match=rf"plate_a.dxf RULING_SCORE #{stray.dxf.handle}: the ruling does not start on the "
        r"crease #\w+ \(its ends are 1.\d+ m from it\)",
    ):
        import_design(folder, alpha=ALPHA)

    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    sector(doc.modelspace(), crease_entity=None)
    doc.modelspace().add_arc((0, 0), 2000.0, 44.0, 136.0, dxfattribs={"layer": "CREASE"})
    doc.saveas(folder / "plate_a.dxf")
    doc.saveas(folder / "plate_b.dxf")
    with pytest.raises(DesignError, match=r"plate_a.dxf CREASE #\w+: its end point .* is not a "):
        import_design(folder, alpha=ALPHA)
