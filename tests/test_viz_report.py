"""``ccu report``: the page, its key figures, and every link resolving to a file written."""

from __future__ import annotations

from html.parser import HTMLParser
from pathlib import Path

import pytest

pytest.importorskip("matplotlib")

from compas_ccu.cli import main  # noqa: E402
from compas_ccu.outputs import MANIFEST
from compas_ccu.viz.report import FIGURES  # noqa: E402
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
    code = main(
        ["report", str(EXAMPLES / "vault.toml"), "--out", str(out), "--steps", "6", "--frames", "4"]
    )
    assert code == 0
    page = Links()
    page.feed((out / "index.html").read_text(encoding="utf-8"))
    return out, page


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


def test_key_figures_are_on_the_page(report, vault_model):
    out, page = report
    text = " ".join(" ".join(page.text).split())
    s = vault_model.deploy()
    assert f"Span (leading crease chord) {s.metrics['span']:.4f} m" in text
    assert f"Rise {s.metrics['rise']:.4f} m" in text
    assert "Plates 10" in text
    assert "Creases 9 ( 4 anticlastic, 5 synclastic)" in text
    assert f"Deployment limit {vault_model.alpha_limit:.4f}°" in text
    assert "α along the creases 30.000° … 30.000°" in text
    assert f"Isometry (quad sides and diagonals) {s.metrics['isometry_relative']:.1e}" in text


def test_report_pictures_are_real(report):
    out, _ = report
    for name, _ in FIGURES:
        assert_picture(load_rgb(out / "figures" / f"{name}.png"), min_ink=0.02, min_colours=20)


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
    assert "steps must be an integer >= 1, got 0" in capsys.readouterr().err
    assert not (Path(tmp_path) / "index.html").exists()


def test_thickness_section_is_on_the_page(report):
    _, page = report
    text = " ".join(" ".join(page.text).split())
    assert "Thickness and bending (paper §5.3)" in text
    assert "Flat-folded stack height (Σt) 80 mm" in text
    assert "Axis-shift hinges (Fig. 8c) 5 intrados–intrados, 4 extrados–extrados" in text
    assert "Collisions, flat stack → design none; min clearance 8 mm" in text
    # 8 mm plywood: within the characteristic strength (0.559), not the design strength (1.118)
    assert "EXCEEDED" in text
    assert (
        "Basis of the bending check EC5 SC1 permanent: f_d = k_mod · f_k / γ_M with k_mod = 0.6, "
        "γ_M = 1.2" in text
    )
    assert "Characteristic utilisation κ / (f_k / (E t/2)) 0.559" in text
    assert "k_def 0.8: 5 / 5 GPa (E1 / E2)" in text
