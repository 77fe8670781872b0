"""``ccu report``: the page, its key figures, and every link resolving to a file written."""

from __future__ import annotations

from html.parser import HTMLParser
from pathlib import Path

import pytest

pytest.importorskip("matplotlib")

from compas_ccu.cli import main  # noqa: E402
from compas_ccu.outputs import MANIFEST
from compas_ccu.viz.report import FIGURES, structural_section  # noqa: E402
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


def test_structural_section_shows_every_case_and_marks_the_failed_ones():
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
    }
    html = structural_section({"checks": checks, "engine": "kratos"}, ["figures/fe_load_cases.png"])
    assert "feet springs" in html and "deflection limit 5.00 mm" in html
    assert "<tr class=bad><th>wet-concrete</th>" in html and "<tr><th>snow</th>" in html
    assert "wet concrete 2040 N/m² (projected, γ 1.5)" in html
    assert "6.10 mm (1.22)" in html and "0.80 (k_mod 0.9, 22.5 MPa)" in html
    assert "1200 / 800 | 1200 / 800" in html and "12 / 900 / 300" in html
    assert "<td class=num>—</td>" in html  # no buckling factor: a dash, not a number
    assert '<img src="figures/fe_load_cases.png"' in html
    assert structural_section({"checks": {"deflection_max_m": 0.001}}) == ""  # an old file
