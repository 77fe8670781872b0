"""The picture commands: ccu figures | animate | view | sheet, their outputs and their errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from PIL import Image  # noqa: E402

from compas_ccu.cli import main  # noqa: E402
from compas_ccu.outputs import MANIFEST
from conftest import EXAMPLES  # noqa: E402
from imagecheck import assert_picture, load_rgb  # noqa: E402

CONE = str(EXAMPLES / "cone.toml")
VAULT = str(EXAMPLES / "vault.toml")


@pytest.mark.slow  # every figure in every format (~4.5 s)
def test_figures_writes_every_figure_in_every_format(tmp_path, capsys):
    assert main(["figures", CONE, "--out", str(tmp_path), "--format", "png,svg"]) == 0
    names = sorted(p.name for p in tmp_path.iterdir() if p.name != MANIFEST)
    stems = ["views-kind", "views-curvature", "views-alpha", "cut-patterns", "sequence"]
    stems += ["quadrants", "planarity"]
    assert names == sorted(f"{s}.{f}" for s in stems for f in ("png", "svg"))
    for stem in stems:
        assert_picture(load_rgb(tmp_path / f"{stem}.png"), min_ink=0.02, min_colours=20)
    assert capsys.readouterr().out.count("wrote ") == len(names)


def test_figures_colour_by_values_from_a_file(tmp_path, cone_model):
    s = cone_model.deploy()
    values = np.asarray(s.deployed)[..., 2]
    np.save(tmp_path / "v.npy", values)
    (tmp_path / "v.json").write_text(json.dumps(values.tolist()))
    for name in ("v.npy", "v.json"):
        out = tmp_path / name.replace(".", "-")
        args = ["figures", CONE, "--out", str(out), "--only", "views", "--format", "png"]
        args += ["--dpi", "40"]  # what is tested is the values file read, not the drawing
        assert main(args + ["--values", str(tmp_path / name), "--label", "z (m)"]) == 0
        assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "views-values.png"]


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--format", "jpeg"], "--format must be a comma list of png, svg, pdf, got 'jpeg'"),
        (["--only", "views,stress"], "--only must be a comma list of views"),
        (["--color-by", "stress"], "--color-by must be kind, curvature or alpha, got 'stress'"),
        (["--values", "missing.npy"], "cannot read --values 'missing.npy'"),
        (["--alpha", "95"], "beyond the deployment limit"),
        (["--view", "top-left"], "unknown view 'top-left'"),
        (["--view", "30,120"], "view elevation must be within -90 to 90 degrees, got '30,120'"),
        (["--size", "12by7"], "--size must be WIDTHxHEIGHT in inches, e.g. 12x7, got '12by7'"),
        (["--size", "0x7"], "--size must be positive inches up to 200, got '0x7'"),
        (["--dpi", "5"], "--dpi must be >= 10, got 5"),
        (["--dpi", "5000"], "--dpi must be <= 2400, got 5000"),
    ],
)
def test_figures_errors_name_the_cause(tmp_path, capsys, extra, message):
    assert main(["figures", CONE, "--out", str(tmp_path)] + extra) == 2
    err = capsys.readouterr().err
    assert err.startswith("ccu: error: ") and message in err


def test_figures_refuse_values_of_the_wrong_shape(tmp_path, capsys):
    np.save(tmp_path / "bad.npy", np.zeros((2, 5)))
    args = ["figures", CONE, "--out", str(tmp_path), "--only", "views"]
    assert main(args + ["--values", str(tmp_path / "bad.npy")]) == 2
    assert "per-vertex values must have shape (2, 98)" in capsys.readouterr().err


def test_figures_dpi_size_and_view_options(tmp_path):
    # --dpi and --size set the pixel size of the PNG (today: always 150 dpi, each figure's size)
    out = tmp_path / "a"
    args = ["figures", VAULT, "--out", str(out), "--only", "views", "--color-by", "kind"]
    assert main(args + ["--dpi", "40", "--size", "6x4", "--format", "png"]) == 0
    assert Image.open(out / "views-kind.png").size == (240, 160)
    out = tmp_path / "b"
    args[3] = str(out)
    assert main(args + ["--dpi", "80", "--view", "iso", "--format", "png,svg"]) == 0
    w, h = Image.open(out / "views-kind.png").size
    assert (w, h) == (12 * 80, 7 * 80)
    # one camera (the iso view), its title on the one panel; SVG text stays text
    svg = (out / "views-kind.svg").read_text(encoding="utf-8")
    assert svg.count("<text") >= 3 and ">iso<" in svg.replace("\n", "")
    assert "span 2.50 m · rise 1.00 m · plate length 2.72 m" in svg
    out = tmp_path / "c"
    args[3] = str(out)
    assert main(args + ["--dpi", "40", "--view=-90,0", "--format", "png"]) == 0
    assert_picture(load_rgb(out / "views-kind.png"), min_ink=0.05, min_colours=20)


def test_animate_writes_the_gif_with_the_frame_count(tmp_path, capsys):
    args = ["animate", CONE, "--out", str(tmp_path), "--frames", "5", "--format", "gif"]
    assert main(args + ["--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""  # no progress bar with --quiet
    assert Image.open(tmp_path / "deployment.gif").n_frames == 5


def test_animate_shows_progress_unless_quiet(tmp_path, capsys):
    assert main(["animate", CONE, "--out", str(tmp_path), "--frames", "3", "--format", "gif"]) == 0
    captured = capsys.readouterr()
    assert "animation frames" in captured.err
    assert "wrote" in captured.out


def test_view_writes_one_offline_page(tmp_path, capsys):
    assert main(["view", CONE, "--out", str(tmp_path), "--steps", "3"]) == 0
    page = (tmp_path / "viewer.html").read_text(encoding="utf-8")
    assert "works offline" in capsys.readouterr().out
    assert '<script src="http' not in page and '<link href="http' not in page


def test_view_opens_on_the_chosen_camera(tmp_path, capsys):
    assert main(["view", CONE, "--out", str(tmp_path), "--steps", "2", "--view", "top"]) == 0
    html = (tmp_path / "viewer.html").read_text(encoding="utf-8")
    assert '"projection":{"type":"orthographic"}' in html.replace(" ", "")
    assert main(["view", CONE, "--out", str(tmp_path / "x"), "--view", "nowhere"]) == 2
    assert "unknown view 'nowhere'" in capsys.readouterr().err


def test_sheet_of_several_designs(tmp_path):
    args = ["sheet", CONE, VAULT, str(EXAMPLES / "quadrants.toml"), "--out", str(tmp_path)]
    assert main(args + ["--format", "png", "--quiet"]) == 0
    assert_picture(load_rgb(tmp_path / "contact-sheet.png"), min_ink=0.05)


def test_picture_commands_have_help(capsys):
    for command in ("figures", "animate", "view", "sheet", "report"):
        with pytest.raises(SystemExit) as exc:
            main([command, "--help"])
        assert exc.value.code == 0
        assert "--out" in capsys.readouterr().out
