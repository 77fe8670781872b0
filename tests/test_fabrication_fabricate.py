"""``ccu fabricate``: every file from one command, read back against the thick model."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from conftest import EXAMPLES

pytest.importorskip("ezdxf")
pytest.importorskip("rhino3dm")
pytest.importorskip("trimesh")

from compas_ccu.cli import main  # noqa: E402
from compas_ccu.cli.text import thickness_lines  # noqa: E402
from compas_ccu.fabrication.dxf import read_plate_dxf  # noqa: E402
from compas_ccu.fabrication.fabricate import fabricate  # noqa: E402
from compas_ccu.fabrication.fold import read_fold  # noqa: E402
from compas_ccu.fabrication.rhino import read_3dm_summary  # noqa: E402
from compas_ccu.fabrication.workshop import WorkshopOptions  # noqa: E402
from compas_ccu.thickness import ThickModel  # noqa: E402
from compas_ccu.thickness.model import collision_text  # noqa: E402

VAULT = str(EXAMPLES / "vault.toml")
OVERBENT = str(EXAMPLES / "overbent.toml")


#: the nesting of the sheets: shelf packing in the quick loop; spyrrow's true-shape search (the
#: default, about a minute for the vault) in the full suite only (its own fast tests:
#: test_fabrication_packing, test_nesting_keeps_parts_on_the_sheets_and_apart)
NESTINGS = ["shelf", pytest.param("spyrrow", marks=pytest.mark.slow)]


@pytest.fixture(scope="module", params=NESTINGS)
def fabricated(tmp_path_factory, request):
    """The vault as shipped: 6 mm plates cut whole from 1525 x 3050 mm sheets, every check
    passes (exit 0 without --allow-exceeded)."""
    out = tmp_path_factory.mktemp("fab")
    nesting = [] if request.param == "spyrrow" else ["--nesting", request.param]
    assert main(["fabricate", VAULT, "--out", str(out), "--quiet", *nesting]) == 0
    return out, json.loads((out / "fabrication.json").read_text())


@pytest.fixture(scope="module")
def fabricated_overbent(tmp_path_factory):
    """The same vault in 8 mm on 2.5 x 1.25 m sheets: every plate spliced, two checks fail
    (the files are written, exit 3)."""
    out = tmp_path_factory.mktemp("fab8")
    assert main(["fabricate", OVERBENT, "--out", str(out), "--quiet", "--nesting", "shelf"]) == 3
    return out, json.loads((out / "fabrication.json").read_text())


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_manifest_lists_every_file(fabricated):
    out, manifest = fabricated
    assert manifest["format"] == "ccu.fabrication"
    for name in manifest["files"]:
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    suffixes = {name.rsplit(".", 1)[-1] for name in manifest["files"]}
    assert suffixes == {"dxf", "csv", "3dm", "obj", "glb", "fold", "svg", "pdf", "json"}
    assert sum(name.startswith("sheets/") for name in manifest["files"]) == len(
        manifest["workshop"]["sheets"]
    )
    assert sum(name.startswith("plates/") for name in manifest["files"]) == 10


def _every_item_assembled_and_clear(m: dict, thickness: float) -> None:
    """One list of steps handles every BOM item; the plates of ``thickness`` clear each other
    by one thickness in the flat stack; the design utilisation is the characteristic one x
    gamma_M / k_mod (EC5 SC1 permanent: 1.2 / 0.6)."""
    handled = {name for step in m["assembly"] for name in step["parts"]}
    assert handled == {row["item"] for row in m["bom"]["rows"]}
    assert m["thickness"] == thickness and m["material"] == "plywood"
    assert m["collisions"]["interpenetration"] is False
    assert m["collisions"]["min_clearance"] == pytest.approx(thickness, abs=1e-12)
    assert m["bending"]["max_utilisation"] == pytest.approx(
        m["bending"]["max_utilisation_characteristic"] * 1.2 / 0.6, rel=1e-12
    )


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_manifest_numbers_of_the_vault_as_shipped(fabricated, vault_model):
    _, m = fabricated
    # ten 6 mm plates cut whole: no splice plates, nothing in the stack but the plates
    assert m["stack_height_plates"] == pytest.approx(0.060, abs=1e-12)
    assert m["stack_height"] == pytest.approx(0.060, abs=1e-12)
    s = m["splices"]
    assert (s["count"], s["mass"], s["max_pile"], s["records"]) == (0, 0.0, 0.0, [])
    assert all(cuts == [] for cuts in s["cuts"].values())
    assert m["failed_checks"] == [] and m["bom"]["splices"] == 0
    _every_item_assembled_and_clear(m, 0.006)
    # 6 mm plywood: characteristic 0.46, design (EC5 SC1 permanent) 0.92: it passes
    assert 0.4 < m["bending"]["max_utilisation_characteristic"] < 0.5
    assert m["bending"]["max_utilisation"] == pytest.approx(0.9217, abs=5e-4)
    assert m["bending"]["exceeded"] is False
    assert m["stack_order"] == ThickModel(vault_model).stack_order


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_manifest_numbers_of_the_8mm_vault(fabricated_overbent, overbent_model):
    _, m = fabricated_overbent
    # ten 8 mm plates and, over one point at most, one cut's two 8 mm splice plates
    assert m["stack_height_plates"] == pytest.approx(0.080, abs=1e-12)
    assert m["stack_height"] == pytest.approx(0.096, abs=1e-12)
    s = m["splices"]
    assert (s["stack_height"], s["max_pile"], s["max_pile_unstaggered"]) == pytest.approx(
        (0.096, 0.016, 0.160), abs=1e-12
    )
    assert s["count"] == 20 and s["mass"] == pytest.approx(20 * 0.15 * 0.14 * 0.008 * 600.0)
    assert s["cuts"] == {str(k): v for k, v in m["workshop"]["splits"].items()}
    assert s["collisions"]["interpenetration"] is False and "failed_checks" in m
    assert not any("splice plates lie inside" in f for f in m["failed_checks"])
    assert len(m["assembly"]) == 49
    _every_item_assembled_and_clear(m, 0.008)
    # 8 mm plywood in the vault: characteristic 0.61, design (EC5 SC1 permanent) 1.23
    assert 0.4 < m["bending"]["max_utilisation_characteristic"] < 0.7
    assert m["bending"]["exceeded"] is True
    basis = m["bending"]["basis"]
    assert (basis["code"], basis["service_class"], basis["load_duration"]) == (
        "EC5",
        1,
        "permanent",
    )
    assert (basis["k_mod"], basis["gamma_M"], basis["k_def"]) == (0.6, 1.2, 0.8)
    assert basis["basis"] == "EC5 SC1 permanent" and basis["strength_factor"] == 0.5
    assert max(m["correction_design"]) < 1e-12
    assert m["stack_order"] == ThickModel(overbent_model).stack_order
    assert [f.split(":")[0].split(" utilisation")[0] for f in m["failed_checks"]] == [
        "bending",
        "splice plates",
    ]


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_printed_check_states_the_basis(fabricated, fabricated_overbent):
    """``ccu fabricate`` prints thickness_lines(manifest): the basis and the factors."""
    text = "\n".join(thickness_lines(fabricated[1]))
    assert "EXCEEDED" not in text and "utilisation 0.922 (plate 0 at alpha 30 deg" in text
    assert "flat stack 60 mm (no splice plates)" in text
    _, m = fabricated_overbent
    text = "\n".join(thickness_lines(m))
    assert "EXCEEDED" in text
    assert "limit f_d(1-nu^2)/(E t/2)" in text
    assert (
        "bending basis     EC5 SC1 permanent: f_d = k_mod f_k / gamma_M, k_mod 0.6, gamma_M 1.2"
        in text
    )
    assert "characteristic utilisation 0.614" in text
    assert "flat stack 96 mm with the splice plates (80 mm plates)" in text
    assert "creep: k_def 0.8, final stiffness E/(1 + k_def) 5 / 5 GPa (E1 / E2)" in text


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_plate_dxf_matches_cut_pattern(fabricated, vault_model):
    out, _ = fabricated
    flat = vault_model.flat()
    n = vault_model.segments
    order = np.r_[np.arange(n + 1), np.arange(2 * n + 1, n, -1)]
    for i, pid in enumerate(vault_model.plate_ids):
        plate = read_plate_dxf(out / "plates" / f"plate_{pid}.dxf")
        assert np.abs(plate["outline"] - flat[i, order, :2]).max() < 1e-5  # 0.01 mm
        assert len(plate["rulings"]) == n - 1
        assert any(f"{pid}" in text for text in plate["labels"])


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_3dm_layers_and_solids(fabricated, vault_model):
    out, _ = fabricated
    summary = read_3dm_summary(out / "vault.3dm")
    assert summary["units"] == "Meters"
    layers = summary["layers"]
    for name in ("plates", "creases", "rulings", "solids", "cut patterns"):
        assert name in layers
    assert layers["solids"]["count"] == 10
    assert layers["creases"]["count"] == len(vault_model.mechanism.creases)


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_fold_file_has_the_structure(fabricated, vault_model):
    out, _ = fabricated
    fold = read_fold(out / "vault.fold")
    assert fold["file_spec"] == 1.2
    n = vault_model.segments
    assert len(fold["faces_vertices"]) == 10 * n
    assignments = set(fold["edges_assignment"])
    assert {"B", "M", "V"} <= assignments
    # the rulings of the deployed vault are bent (about 1.3 deg), so they are folds too
    rulings = [a for a, k in zip(fold["edges_assignment"], fold["edges_ccu:kind"]) if k == "ruling"]
    assert rulings and set(rulings) <= {"M", "V"}


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_stack_obj_is_sum_of_thicknesses(fabricated, vault_model):
    import trimesh

    out, _ = fabricated
    scene = trimesh.load(out / "stack.obj", force="scene")
    points = np.concatenate([g.vertices for g in scene.geometry.values()])
    heights = (points - vault_model.origin) @ vault_model.axes[2]
    assert np.ptp(heights) == pytest.approx(0.060, abs=1e-9)  # ten 6 mm plates


@pytest.mark.parametrize(
    "option, message",
    [
        (["--thickness", "0"], "--thickness must be > 0, got 0.0"),
        (["--thickness", "0.3"], "--thickness must be <= 0.1, got 0.3"),
        (["--thickness", "nan"], "--thickness must be a finite number, got nan"),
        (["--material", "balsa"], "unknown material 'balsa'"),
        (["--hinge-width", "-0.01"], "--hinge-width must be > 0, got -0.01"),
    ],
)
def test_bad_values_refused(tmp_path, capsys, option, message):
    assert main(["fabricate", VAULT, "--out", str(tmp_path / "x"), *option]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x" / "fabrication.json").exists()


# ------------------------------------------------ the Python API: checks first, strict JSON


def _strict_json(text: str):
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"hinge_width": 1e6}, "too large for the curvature"),
        ({"hinge_width": -0.01}, "hinge width must be a finite number > 0"),
        ({"thickness": 0.0}, "thickness must be a finite length > 0"),
        ({"material": "balsa"}, "unknown material 'balsa'"),
    ],
)
def test_nothing_is_written_before_every_check_passed(vault_model, tmp_path, options, message):
    out = tmp_path / "fab"
    with pytest.raises(ValueError, match=re.escape(message)):
        fabricate(vault_model, out, **options)
    assert not out.exists()  # not even the folder


@pytest.mark.parametrize("nesting", NESTINGS)
def test_two_plates_write_strict_json_without_a_clearance(cone_model, tmp_path, nesting):
    """The cone's two plates share their one crease: no plate pair to measure a clearance on."""
    workshop = WorkshopOptions.from_section(cone_model.design.fabrication, nesting=nesting)
    manifest = fabricate(cone_model, tmp_path, workshop=workshop)
    text = (tmp_path / "fabrication.json").read_text()
    assert "Infinity" not in text and "NaN" not in text
    data = _strict_json(text)
    assert data == json.loads(json.dumps(manifest))
    c = data["collisions"]
    assert c["min_clearance"] is None and c["closest"] is None
    assert c["clearance_pairs"] == 0 and c["interpenetration"] is False
    words = collision_text(c)
    assert words == "none; no plate pair to check (every pair of plates shares a crease)"
    assert "inf" not in words
    for name in data["files"]:
        if name.endswith((".json", ".fold")):
            _strict_json((tmp_path / name).read_text())


def test_collision_text_with_pairs_but_no_clearance():
    summary = {"first": None, "min_clearance": None, "clearance_pairs": 3, "closest": None}
    assert collision_text(summary) == (
        "none; no plate lies over another one it shares no crease with"
    )
    summary.update(min_clearance=0.008, closest={"plates": [0, 2], "alpha": 0.0})
    assert collision_text(summary) == "none; min clearance 8 mm (plates 0/2 at alpha 0 deg)"


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
@pytest.mark.parametrize("which", ["vault", "overbent"])
def test_sheets_json_records_the_nesting_of_the_sheet_dxfs(which, fabricated, fabricated_overbent):
    """sheets.json: every part placed on its sheet exactly as the sheet DXF's true outline and
    XDATA have it, and the design file's hash (the viewer's guard against another design)."""
    import hashlib

    import ezdxf

    out, manifest = fabricated if which == "vault" else fabricated_overbent
    doc = json.loads((out / "sheets.json").read_text(encoding="utf-8"))
    sha = hashlib.sha256((EXAMPLES / f"{which}.toml").read_bytes()).hexdigest()
    assert manifest["design_sha256"] == doc["design_sha256"] == sha
    assert doc["format"] == "ccu.sheets" and doc["design"] == which and doc["units"] == "m"
    assert "sheets.json" in manifest["files"]
    assert [s["parts"] for s in doc["sheets"]] == [
        s["parts"] for s in manifest["workshop"]["sheets"]
    ]
    parts = {"vault": 10, "overbent": 40}[which]  # plates whole, or in two with two splices
    assert len(doc["parts"]) == manifest["bom"]["plates"] + manifest["bom"]["splices"] == parts
    assert doc["model_plate_ids"] == manifest["model_ids"]["plates"]
    by_sheet = {}
    for part in doc["parts"]:
        by_sheet.setdefault(part["sheet"], []).append(part)
    for k, parts in by_sheet.items():
        msp = ezdxf.readfile(out / f"sheets/sheet_{k + 1}.dxf").modelspace()
        true = msp.query("LWPOLYLINE[layer=='PART_OUTLINE']")
        outlines = [np.asarray(e.get_points("xy")) for e in true]
        paths = msp.query("LWPOLYLINE[layer=='OUTER_CUT']")
        xdata = [e.get_xdata("COMPAS_CCU") for e in paths]
        assert len(outlines) == len(parts)
        for part, outline, tags in zip(parts, outlines, xdata):
            # the DXF in mm, sheets.json in m: the same placement (doubles, to rounding)
            assert np.abs(np.asarray(part["outline"]) * 1000.0 - outline).max() < 1e-9
            assert tags[1].value == part["name"] and tags[2].value == part["rotation"]
            shift = np.multiply(part["translation"], 1000.0)
            assert np.allclose([t.value for t in tags[3:5]], shift, rtol=0, atol=1e-9)
    # a plate part carries its creases by kind; the splices their place is engraved on it
    if which == "vault":
        p0 = next(p for p in doc["parts"] if p["name"] == "P0")
        assert [c["kind"] for c in p0["creases"]] == ["synclastic"]  # c0, the bottom crease
        assert p0["marks"] == [] and p0["label"][0] == "P0"
    else:
        p0 = next(p for p in doc["parts"] if p["name"] == "P0.1")
        assert [c["kind"] for c in p0["creases"]] == ["synclastic"]
        assert len(p0["marks"]) == 1 and p0["label"][0] == "P0.1 of 2"


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_view_shows_the_sheets_of_a_fabrication_folder(fabricated, tmp_path, capsys):
    out, manifest = fabricated
    view = tmp_path / "view"
    assert main(["view", VAULT, "--out", str(view), "--steps", "1", "--fabrication", str(out)]) == 0
    count = manifest["workshop"]["sheet_count"]
    said = capsys.readouterr().out
    assert f"the cut patterns are the {count} sheets of {out} (10 parts)" in said
    html = (view / "viewer.html").read_text(encoding="utf-8")
    assert f"cut patterns: {count} sheets, 10 parts" in html
    # refused: a folder without sheets.json, another design, another version of the file
    capsys.readouterr()
    assert main(["view", VAULT, "--out", str(view), "--fabrication", str(tmp_path)]) == 2
    assert f"--fabrication {str(tmp_path)!r} has no sheets.json" in capsys.readouterr().err
    cone = str(EXAMPLES / "cone.toml")
    assert main(["view", cone, "--out", str(view), "--fabrication", str(out)]) == 2
    assert "holds the fabrication of design 'vault', not of 'cone'" in capsys.readouterr().err
    edited = tmp_path / "vault.toml"
    edited.write_text((EXAMPLES / "vault.toml").read_text(encoding="utf-8") + "\n# edited\n")
    assert main(["view", str(edited), "--out", str(view), "--fabrication", str(out)]) == 2
    assert "was written from another version of the design file" in capsys.readouterr().err


@pytest.mark.slow  # a whole fabrication of the vault (2-7 s)
def test_fabricating_again_into_a_folder_removes_only_its_own_stale_files(tmp_path):
    """A 22-plate dome then a 12-plate one into the same folder: plate_12 .. plate_21.dxf
    (and the extra sheets) were left, and ``ccu import`` read them as part of the structure."""
    from compas_ccu.design.presets import preset_text
    from compas_ccu.model import load_model

    shelf = WorkshopOptions(nesting="shelf")
    out = tmp_path / "fab"
    (tmp_path / "d22.toml").write_text(
        preset_text("dome").replace("plates = 12 ", "plates = 22 "), encoding="utf-8"
    )
    first = fabricate(load_model(tmp_path / "d22.toml"), out, workshop=shelf, allow_collisions=True)
    (out / "notes.txt").write_text("mine")  # the user's file stays
    (out / "plates" / "plate_99.dxf").write_text("0\nEOF\n")  # not listed: stays
    second = fabricate(
        load_model(EXAMPLES / "vault.toml"), out, workshop=shelf, allow_collisions=True
    )
    written = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert written == set(second["files"]) | {"notes.txt", "plates/plate_99.dxf"}
    assert len(first["files"]) > len(second["files"])
    assert not (out / "plates" / "plate_21.dxf").exists()
