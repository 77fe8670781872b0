"""Layout ``patterns``: a whole structure as the cut patterns of its plates (``ccu import``)."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from compas_ccu.catalog import catalog_path
from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.design.document import parse_toml
from compas_ccu.design.writer import design_toml
from compas_ccu.errors import DesignError
from compas_ccu.geometry import rigid_align
from compas_ccu.model import CCUModel, load_model, patterns_design
from conftest import EXAMPLES

#: The vault with 8 segments: every error path on a 10-plate structure, fast.
SMALL = {
    "crease": {"profile": "arc", "span": 2.5, "rise": 1.0, "segments": 8},
    "rulings": {"type": "orthogonal"},
    "deployment": {"alpha": 30.0},
    "layout": {"type": "parallel", "plates": 10, "spacing": 0.12},
}


@pytest.fixture(scope="module")
def small():
    """The small vault and its patterns document (metres)."""
    design = Design(copy.deepcopy(SMALL))
    return CCUModel(design), patterns_design(design).document


def deployed_error(model, other) -> float:
    """Largest vertex distance of two models' deployed structures (plates matched by id),
    after a best rigid alignment, relative to the structure's size."""
    a = np.asarray(model.deploy().deployed).reshape(-1, 3)
    b = np.asarray(other.deploy().deployed).reshape(-1, 3)
    assert model.plate_ids == other.plate_ids
    return float(np.linalg.norm(rigid_align(b, a) - a, axis=1).max()) / model.size


@pytest.mark.parametrize(
    "path",
    [
        EXAMPLES / "vault.toml",
        EXAMPLES / "cone.toml",
        catalog_path("fig11a-constant-apex"),
        catalog_path("fig12b-dome"),
    ],
    ids=["vault", "cone", "fig11a", "fig12b"],
)
def test_patterns_design_deploys_to_the_design(path):
    """Every plate by its flat pattern (the stack at 0) deploys to the design's structure:
    measured 1.4e-15 (vault), 6.9e-16 (cone), 1.2e-15 (fig11a), 6.1e-15 (fig12b)."""
    design = load_design(path)
    patterns = patterns_design(design)
    assert patterns.layout.type == "patterns" and patterns.crease.state == "flat"
    assert len(patterns.layout.patterns) == CCUModel(design).plates.count - 1
    assert deployed_error(CCUModel(design), CCUModel(patterns)) < 1e-9


def test_patterns_design_refuses_quadrants():
    with pytest.raises(DesignError, match=r"layout.quadrants: the curved-crease-folding"):
        patterns_design(load_design(EXAMPLES / "quadrants.toml"))


def test_units_convert_the_pattern_rows(small):
    model, document = small
    mm = Design.from_metric(document, units="mm")
    assert mm.document["layout"]["patterns"][0]["near"][0][0] == pytest.approx(
        1e3 * document["layout"]["patterns"][0]["near"][0][0], rel=1e-14
    )
    table = mm.layout.patterns[3]
    assert np.allclose(table["far"], document["layout"]["patterns"][3]["far"], rtol=1e-13)
    assert deployed_error(model, CCUModel(mm)) < 1e-9


def broken(document, i, **changes):
    doc = copy.deepcopy(document)
    doc["layout"]["patterns"][i].update(changes)
    return doc


def test_pattern_keys_are_checked_one_by_one(small):
    _, document = small
    cases = [
        (broken(document, 2, parent=-1), r"layout.patterns\[2\].parent: must be an integer >= 0"),
        (
            broken(document, 2, boundary="side"),
            r"layout.patterns\[2\].boundary: must be 'near' or 'far', got 'side'",
        ),
        (
            broken(document, 2, near=[[0.0, 0.0]], far=[[0.0, 1.0]]),
            r"layout.patterns\[2\].near: needs at least 2 points \(one per crease vertex\), got 1",
        ),
        (
            broken(document, 2, far=document["layout"]["patterns"][2]["far"][:-1]),
            r"layout.patterns\[2\].far: 8 ruling ends for 9 crease points",
        ),
        (
            broken(document, 4, near=[[0.0, math.inf]] * 9),
            r"layout.patterns\[4\].near: must be a list of \[x, y\] pairs of finite numbers",
        ),
        (broken(document, 1, width=1.0), r"layout.patterns\[1\].width: unknown key"),
    ]
    no_near = copy.deepcopy(document)
    del no_near["layout"]["patterns"][5]["near"]
    cases.append((no_near, r"layout.patterns\[5\].near: missing required key"))
    for doc, message in cases:
        with pytest.raises(DesignError, match=message):
            Design(doc)


def test_rules_between_keys(small):
    _, document = small
    doc = copy.deepcopy(document)
    doc["crease"]["state"] = "deployed"
    with pytest.raises(DesignError, match=r"rulings.points: explicit rulings describe a cut"):
        Design(doc)
    doc = copy.deepcopy(document)
    doc["rulings"] = {"type": "orthogonal"}
    with pytest.raises(DesignError, match=r"layout.type: layout 'patterns' lists cut patterns"):
        Design(doc)
    doc = copy.deepcopy(document)
    del doc["layout"]["patterns"]
    with pytest.raises(DesignError, match=r"layout.patterns: required for layout type 'patterns'"):
        Design(doc)


def test_how_the_patterns_fit_together_is_checked_when_built(small):
    _, document = small
    tables = document["layout"]["patterns"]
    partner = next(i for i, t in enumerate(tables) if (t["parent"], t["boundary"]) == (0, "near"))
    later = len(tables) - 1
    wider = [list(p) for p in tables[later]["near"]]
    wider[3] = [wider[3][0] + 1e-3, wider[3][1]]
    angled = copy.deepcopy(document)
    far = np.asarray(tables[later]["far"])
    near = np.asarray(tables[later]["near"])
    turn = math.radians(1.0)
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    far[4] = near[4] + (far[4] - near[4]) @ rot.T  # same length, another angle
    angled["layout"]["patterns"][later]["far"] = far.tolist()
    no_partner = copy.deepcopy(document)  # the leading plate and the plate after it
    del no_partner["layout"]["leading"]
    no_partner["layout"]["patterns"] = [{k: v for k, v in tables[0].items() if k != "id"}]
    no_ids = copy.deepcopy(document)
    del no_ids["layout"]["patterns"][3]["id"]
    twice = broken(document, 3, id=document["layout"]["leading"])
    cases = [
        (
            broken(document, 2, parent=9),
            r"layout.patterns\[2\].parent: must be an earlier plate, 0 \(the leading plate\) "
            r"\.\.\. 2 \(pattern 1\), got 9",
        ),
        (
            broken(document, later, parent=0, boundary="near"),
            rf"layout.patterns\[{later}\].boundary: the near boundary of plate 0 already joins "
            rf"plate {partner + 1} \(pattern {partner}\)",
        ),
        (
            broken(document, later, near=tables[later]["near"][:-1], far=tables[later]["far"][:-1]),
            rf"layout.patterns\[{later}\].near: 8 points, the leading crease has 9 vertices",
        ),
        (
            broken(document, later, near=wider),
            rf"layout.patterns\[{later}\].near: its segment 3 is 0.4292\d+ m, the parent's \(plate "
            r"8, far boundary\) 0.4302\d+ m "
            r"\(difference 0.000989 m > 1e-06 of the crease's length\)",
        ),
        (
            angled,
            rf"layout.patterns\[{later}\]: plate {later + 1} is not the mirror image of its "
            r"parent's rulings across their crease: in quad 3 its far edge is 0.3645\d+ m, as the "
            r"mechanism attaches it 0.3604\d+ m \(difference 0.00415 m > 1e-06 of the plate's "
            r"size\)",
        ),
        (no_partner, r"layout.patterns: no pattern is the leading plate's partner"),
        (no_ids, r"layout.patterns\[3\].id: missing: give every pattern an id, or none"),
        (twice, r"layout.patterns\[3\].id: 5 is the id of layout.leading too"),
        (broken(document, 3, id=10), r"layout.patterns\[3\].id: must be 0 \.\.\. 9"),
    ]
    for doc, message in cases:
        with pytest.raises(DesignError, match=message):
            CCUModel(Design(doc))


def test_plate_ids_default_to_the_mechanism_order(small):
    model, document = small
    doc = copy.deepcopy(document)
    del doc["layout"]["leading"]
    for table in doc["layout"]["patterns"]:
        del table["id"]
    plain = CCUModel(Design(doc))
    assert plain.geometry.plate_ids == list(range(10))
    assert (
        model.geometry.plate_ids == CCUModel(Design(document)).geometry.plate_ids != list(range(10))
    )


# -- ccu import: fabricate -> import (the TOML) -> load -> deploy ------------------------------

ezdxf = pytest.importorskip("ezdxf")
pytest.importorskip("shapely")
pytest.importorskip("rhino3dm")
pytest.importorskip("trimesh")

from compas_ccu.fabrication.fabricate import fabricate  # noqa: E402
from compas_ccu.fabrication.importing import import_structure, structure_error  # noqa: E402
from compas_ccu.fabrication.workshop import WorkshopOptions  # noqa: E402

#: The sheets nested by shelves: fast, and the plate files do not depend on the nesting.
SHELF = WorkshopOptions(nesting="shelf")


def header_of(text: str) -> str:
    lines = []
    for line in text.splitlines():
        if not line.startswith("# "):
            break
        lines.append(line[2:])
    return "\n".join(lines)


@pytest.mark.parametrize(
    ("path", "plates", "options"),
    [
        # 3-4 s each (fabricate and import 10-12 plates): the cone is the quick loop's
        pytest.param(EXAMPLES / "vault.toml", 10, {}, marks=pytest.mark.slow),
        (EXAMPLES / "cone.toml", 2, {}),
        pytest.param(
            catalog_path("fig11a-constant-apex"),
            10,
            {"hinge_width": 0.03, "allow_collisions": True},
            marks=pytest.mark.slow,
        ),
        pytest.param(
            catalog_path("fig12b-dome"),
            12,
            {"hinge_width": 0.03, "allow_collisions": True},
            marks=pytest.mark.slow,
        ),
    ],
    ids=["vault", "cone", "fig11a", "fig12b"],
)
def test_ccu_import_writes_the_whole_structure(tmp_path, capsys, path, plates, options):
    """The design file alone reproduces the whole structure: measured 1.6e-15 (vault),
    8.7e-16 (cone), 1.6e-15 (fig11a, its thickness correction undone), 8.0e-15 (fig12b)
    relative; the leading crease is fabrication.json's leading_crease, no --crease needed."""
    model = load_model(path)
    folder = tmp_path / "fab"
    manifest = fabricate(model, folder, workshop=SHELF, **options)
    out = tmp_path / "imported.toml"
    assert main(["import", str(folder), "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert f"{plates} plates joined from crease {manifest['leading_crease']}" in said
    loaded = load_model(out)  # its checks pass (isometry, crossing rulings, overlap)
    assert loaded.design.layout.type == "patterns" and loaded.plates.count == plates
    error = structure_error(model, folder, loaded.mechanism, loaded.geometry.plate_ids)
    assert error.plates == plates and error.max_relative < 1e-9
    imported = import_structure(folder)  # the API's mechanism is the file's
    assert imported.plate_ids == loaded.geometry.plate_ids  # the files' (workshop) ids
    alpha = math.radians(model.alpha_design)
    assert np.abs(
        imported.mechanism.deploy(alpha).far - loaded.mechanism.deploy(alpha).far
    ).max() < (1e-12)
    old, new = model.deploy(), loaded.deploy()
    assert new.alpha == old.alpha == model.alpha_design
    for key in ("span", "rise"):
        assert new.metrics[key] == pytest.approx(old.metrics[key], rel=1e-9, abs=0.0)
    assert new.max_invariant_error < 1e-9 * model.size
    text = out.read_text(encoding="utf-8")
    assert design_toml(parse_toml(text), header=header_of(text)) == text  # re-writes identically
    assert text.count("[[layout.patterns]]") == plates - 1


def _dome(tmp_path_factory, plates: int):
    """The dome preset with ``plates`` plates (radial) fabricated: its model and folder."""
    from compas_ccu.design.presets import preset_text

    root = tmp_path_factory.mktemp(f"dome{plates}")
    path = root / f"dome{plates}.toml"
    text = preset_text("dome").replace("plates = 12 ", f"plates = {plates} ")
    path.write_text(text, encoding="utf-8")
    model = load_model(path)
    fabricate(model, root / "fab", workshop=SHELF, allow_collisions=True)
    return model, root / "fab"


@pytest.fixture(scope="module")
def dome22(tmp_path_factory):
    """The dome preset with 22 plates (radial, 15 deg apart) fabricated: its folder."""
    return _dome(tmp_path_factory, 22)


@pytest.fixture(scope="module", params=[6, pytest.param(22, marks=pytest.mark.slow)])
def dome_plates(tmp_path_factory, request):
    """A 6-plate dome (the quick loop) and the 22-plate one (the full suite), fabricated."""
    if request.param == 22:
        return request.getfixturevalue("dome22")
    return _dome(tmp_path_factory, request.param)


@pytest.mark.slow  # 22 plates: about 10 s; the undoing's fast test: the 6-plate dome below
def test_ccu_import_of_the_22_plate_dome(dome22, tmp_path, capsys):
    """Many plates, radial: the undoing of the 4 mm correction stops at the rounding floor
    (planar steps change by 3e-12 to 6e-12 m; it needed a tolerance relative to the plates'
    size) after 13 iterations; 8.3e-13 relative through the TOML."""
    model, folder = dome22
    out = tmp_path / "dome22.toml"
    assert main(["import", str(folder), "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "22 plates joined from crease 10" in said
    assert "the thickness correction of 4 mm plates undone" in said
    loaded = load_model(out)
    error = structure_error(model, folder, loaded.mechanism, loaded.geometry.plate_ids)
    assert error.plates == 22 and error.max_relative < 1e-9


def test_an_undoing_that_does_not_converge_is_refused_with_the_way_out(dome_plates, monkeypatch):
    """No tolerance can be met: the leading crease fails, every other crease diverges (until
    a pattern degenerates, a GeometryError that escaped before); the error says what to do."""
    import compas_ccu.fabrication.import_thickness as importing

    monkeypatch.setattr(importing, "UNDO_RELATIVE", 0.0)
    monkeypatch.setattr(importing, "UNDO_TOLERANCE", 0.0)
    _, folder = dome_plates
    with pytest.raises(DesignError) as info:
        import_structure(folder)
    text = str(info.value)
    assert "did not converge in 20 iterations" in text
    assert "ccu import --as-drawn" in text and "tried every crease of the folder" in text


@pytest.mark.slow  # a fabrication and an import (~1 s); the cone's round trip is quick
def test_ccu_import_leading_pair_only_keeps_the_single_crease_design(tmp_path, capsys):
    model = load_model(EXAMPLES / "cone.toml")
    fabricate(model, tmp_path / "fab", workshop=SHELF)
    out = tmp_path / "pair.toml"
    argv = ["import", str(tmp_path / "fab"), "--out", str(out), "--leading-pair-only"]
    assert main(argv) == 0
    design = load_design(out)
    assert design.layout.type == "single" and design.layout.patterns is None
    assert "# Imported by `ccu import --leading-pair-only`" in out.read_text(encoding="utf-8")
    assert deployed_error(model, CCUModel(design)) < 1e-9
