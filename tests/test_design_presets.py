"""ccu new --preset: commented templates that load, deploy and pass ccu info."""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import pytest

from compas_ccu.cli import main
from compas_ccu.design import load_design
from compas_ccu.design.presets import PRESET_DIR, PRESETS, preset_text, write_preset
from compas_ccu.errors import OptionError, UnitsWarning
from compas_ccu.model import CCUModel

ROOT = Path(__file__).resolve().parents[1]


def test_every_preset_has_its_file_and_ships_as_package_data():
    assert sorted(p.stem for p in PRESET_DIR.glob("*.toml")) == sorted(PRESETS)
    assert '"data/presets/*.toml"' in (ROOT / "pyproject.toml").read_text()


def _slow(presets, slow):
    """The presets as parameters, those in ``slow`` marked slow (1.5-3 s each)."""
    return [pytest.param(p, marks=pytest.mark.slow) if p in slow else p for p in presets]


@pytest.mark.parametrize("preset", _slow(PRESETS, {"dome", "funnel"}))
def test_a_preset_loads_deploys_and_its_info_runs(preset, tmp_path, capsys):
    path = tmp_path / f"my-{preset}.toml"
    assert main(["new", "--preset", preset, str(path)]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"wrote {path} (preset {preset}: ")
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitsWarning)
        design = load_design(path)
    assert design.name == f"my-{preset}" and design.units == "m"
    structure = CCUModel(design).deploy()
    assert structure.alpha == design.alpha
    assert structure.max_invariant_error < 1e-12
    assert main(["info", "--json", str(path)]) == 0
    data = json.loads(capsys.readouterr().out)
    k = data["key_figures"]
    assert k["name"] == f"my-{preset}" and k["plates"] == len(structure.plate_ids)
    thickness = data["thickness"]
    if thickness is not None:  # the quadrants' CCF creases have no thickness model
        assert not thickness["collisions"]["first"], "plates interpenetrate"
        assert thickness["bending"]["max_utilisation"] < 1.0
    assert main(["info", str(path)]) == 0
    assert f"design            my-{preset}" in capsys.readouterr().out


@pytest.mark.parametrize(
    "preset", _slow([p for p in PRESETS if p != "quadrants"], {"cone", "dome", "funnel", "vault"})
)
def test_a_preset_passes_ccu_fabricate(preset, tmp_path, capsys):
    """Every check of the workshop passes: the bending of the plates and of the splices (the
    cone and the vault on 3050 x 1525 mm sheets, whole; the dome split with 1 mm splice plates
    (0.58 x 1.5 = 0.87; with 1.5 mm 1.02), the funnel with 1.5 mm (0.88)."""
    pytest.importorskip("ezdxf")
    path = tmp_path / f"{preset}.toml"
    assert main(["new", "--preset", preset, "--quiet", str(path)]) == 0
    out = tmp_path / "fab"
    assert main(["fabricate", str(path), "--out", str(out), "--nesting", "shelf", "--quiet"]) == 0
    manifest = json.loads((out / "fabrication.json").read_text(encoding="utf-8"))
    assert manifest["failed_checks"] == []
    splices = manifest["workshop"]["splice_bending"]
    if preset in ("dome", "funnel"):
        factor = {"dome": 1.5, "funnel": 1.75}[preset]
        assert splices["cuts"] and splices["factor"] == pytest.approx(factor)
        assert 0.5 < splices["max_utilisation"] < 1.0
    else:
        assert splices["cuts"] == []  # nothing split


@pytest.mark.parametrize("preset", list(PRESETS))
def test_every_key_of_a_preset_is_explained(preset):
    text = preset_text(preset)
    assert "docs/design-files.md" in text
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if re.match(r"^[a-z_]+ = ", line):
            assert "#" in line or lines[i - 1].startswith("#"), line
    assert 'units = "m"' in text


def test_an_existing_file_is_not_overwritten_without_force(tmp_path, capsys):
    path = tmp_path / "hall.toml"
    path.write_text("# mine\n")
    assert main(["new", "--preset", "dome", str(path)]) == 2
    assert capsys.readouterr().err == (
        f"ccu: error: {str(path)!r} exists: not overwritten (--force overwrites it)\n"
    )
    assert path.read_text() == "# mine\n"
    assert main(["new", "--preset", "dome", "--force", "--quiet", str(path)]) == 0
    assert capsys.readouterr().out == ""
    assert load_design(path).layout.type == "radial"


def test_the_name_is_the_file_name_and_the_comments_stay_aligned(tmp_path):
    design = write_preset("funnel", tmp_path / 'a "quoted" name.toml')
    assert design.name == 'a "quoted" name'
    line = next(
        x for x in (tmp_path / 'a "quoted" name.toml').read_text().splitlines() if "name =" in x
    )
    assert line == 'name = "a \\"quoted\\" name"    # used in file names and reports'
    assert line.index("#") == 30  # the column of the template's comments
    short = preset_text("vault", name="v")
    assert 'name = "v"                    # used in file names and reports' in short


@pytest.mark.parametrize(
    "preset, path, message",
    [
        (
            "igloo",
            "x.toml",
            r"--preset must be one of vault, dome, funnel, cone, quadrants, got 'igloo'",
        ),
        ("vault", "x.txt", r"the new design file must end in \.toml, got '.*x\.txt'"),
    ],
)
def test_bad_presets_and_paths_are_named(preset, path, message, tmp_path):
    with pytest.raises(OptionError, match=message):
        write_preset(preset, tmp_path / path)
    assert not (tmp_path / path).exists()
