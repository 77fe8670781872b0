"""Key figures: one definition, and ``ccu info``, the report, the sweep columns and the catalog
table all show the same numbers."""

from __future__ import annotations

import html
import json
import pickle
import re

import numpy as np
import pytest

from compas_ccu.catalog import COLUMNS, catalog_metrics, catalog_path
from compas_ccu.cli import main
from compas_ccu.design import load_design
from compas_ccu.errors import OptionError
from compas_ccu.explore import evaluate_variant
from compas_ccu.explore.metrics import KEY_FIGURE_COLUMNS, METRICS
from compas_ccu.key_figures import (
    FIGURES,
    GROUPS,
    KeyFigures,
    figures_markdown,
    key_figures,
)
from compas_ccu.key_figures.text import figure_rows
from compas_ccu.model import load_model
from conftest import EXAMPLES

DESIGNS = {
    "vault": EXAMPLES / "vault.toml",
    "fig09a-arc": catalog_path("fig09a-arc"),
}


@pytest.fixture(scope="module", params=sorted(DESIGNS))
def design(request):
    path = DESIGNS[request.param]
    model = load_model(path)
    return request.param, path, model, key_figures(model, path=24)


def _info(path, capsys) -> dict:
    """span, rise, height and the invariant error as ``ccu info`` prints them."""
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    return {
        "span": re.search(r"^span +(\S+) m", out, re.M).group(1),
        "rise": re.search(r"^rise +(\S+) m", out, re.M).group(1),
        "height": re.search(r"^bounding box +\S+ x \S+ x (\S+) m", out, re.M).group(1),
        "invariant": re.search(r"max relative error (\S+),", out).group(1),
    }


def test_info_report_sweep_and_catalog_agree(design, capsys, tmp_path):
    name, path, model, k = design
    # the numbers themselves: the leading crease (2.5 m chord, 1 m rise) of a 1.046 m high vault
    assert k.crease_span == pytest.approx(2.5, abs=1e-12)
    assert k.crease_rise == pytest.approx(1.0, abs=1e-12)
    assert k.height == pytest.approx(1.0456247529798, abs=1e-12)
    assert 1e-16 < k.invariant_max_relative < 1e-15
    # ccu info
    info = _info(path, capsys)
    assert info == {
        "span": f"{k.crease_span:.4f}",
        "rise": f"{k.crease_rise:.4f}",
        "height": f"{k.height:.3f}",
        "invariant": f"{k.invariant_max_relative:.1e}",
    }
    # the sweep's columns (the historical names span, rise, invariant_error)
    row = evaluate_variant(load_design(path).document, path_states=5)
    assert row["status"] == "ok", row["error"]
    assert row["span"] == k.crease_span and row["rise"] == k.crease_rise
    assert row["height"] == k.height and row["invariant_error"] == k.invariant_max_relative
    # the catalog's table
    table = catalog_metrics(model, steps=24, relax=False)
    assert table == k.to_dict()
    if name == "fig09a-arc":
        assert main(["catalog", "--out", str(tmp_path), "--only", name, "--no-figures"]) == 0
        (row,) = json.loads((tmp_path / "catalog.json").read_text())
        for figure in ("crease_span", "crease_rise", "height", "invariant_max_relative"):
            assert row[figure] == k[figure], figure


@pytest.mark.slow  # a whole report per design (~4 s)
def test_the_report_shows_the_same_key_figures(design, tmp_path):
    pytest.importorskip("matplotlib")
    from compas_ccu.viz.report import write_report

    name, path, model, k = design
    report = write_report(model, tmp_path, steps=2, frames=2, formats=("png",))
    for figure in ("crease_span", "crease_rise", "height", "invariant_max_relative"):
        assert report.figures[figure] == k[figure], figure
    page = report.index.read_text(encoding="utf-8")
    # the rows of the design state, worded as ccu info words them (one definition)
    for label, value in figure_rows(k)[:13]:
        assert f"<th>{html.escape(label)}</th><td>{html.escape(value)}</td>" in page, label
    assert f"<td>{k.crease_span:.4f} m (leading crease chord)</td>" in page


def test_the_invariant_figure_is_relative_once():
    """max_invariant_error is already relative to the size: the catalog divided it again."""
    model = load_model(catalog_path("fig09a-arc"))
    s = model.deploy()
    m = s.metrics
    absolute = max(m[k] for k in ("isometry", "quad_planarity", "hinge_gap", "mirror_error"))
    k = key_figures(model, s)
    assert k.invariant_max_relative == pytest.approx(absolute / model.size, rel=1e-12)
    assert k.invariant_max_relative == s.max_invariant_error
    # round-off (a few 1e-16: its last digits differ between CPUs and plane fits)
    assert 1e-17 < k.invariant_max_relative < 1e-14
    assert catalog_metrics(model, steps=2, relax=False)["invariant_max_relative"] == (
        k.invariant_max_relative
    )


def test_crease_rise_and_height_are_two_figures(design):
    _, _, model, k = design
    s = model.deploy()
    assert k.crease_rise == s.metrics["rise"] and k.crease_span == s.metrics["span"]
    assert k.height == float(np.ptp(np.asarray(s.deployed)[..., 2]))
    assert k.height - k.crease_rise > 0.04  # the plates reach above the leading crease


def test_key_figures_are_plain_json_read_only_and_pickle(design):
    _, _, _, k = design
    d = k.to_dict()
    assert list(d) == [f.name for f in FIGURES] == list(k)
    assert json.loads(json.dumps(d)) == d
    kinds = {"float": float, "int": int, "bool": bool, "str": str}
    for f in FIGURES:
        assert d[f.name] is None or type(d[f.name]) is kinds[f.dtype], f.name
    assert k.crease_kinds == "4 anticlastic, 5 synclastic"
    assert k.crease_kind_counts() == {"anticlastic": 4, "synclastic": 5}
    with pytest.raises(AttributeError):
        k.crease_span = 3.0
    assert pickle.loads(pickle.dumps(k)) == k
    assert k.group("path")["path_states"] == 24
    with pytest.raises(OptionError, match=r"no key figure 'rise'; the key figures are: name"):
        KeyFigures(rise=1.0)


def test_options_are_checked(vault_model):
    with pytest.raises(OptionError, match=r"key figures describe the design state"):
        key_figures(vault_model, vault_model.deploy(20.0))
    with pytest.raises(OptionError, match=r"measured along a path"):
        key_figures(vault_model, thickness=True)
    with pytest.raises(OptionError, match=r"steps must be an integer >= 1, got 0"):
        key_figures(vault_model, path=0)


def test_thickness_and_path_figures(vault_model):
    alphas = np.linspace(0.0, 30.0, 21)
    k = key_figures(vault_model, path=alphas, thickness=True)
    assert k.path_states == 21 and k.crease_planarity_exact and k.crease_planarity_path < 1e-13
    assert k.thickness == 0.006 and k.material == "plywood"
    assert k.stack_height == pytest.approx(0.06, abs=1e-15)
    assert k.mass == pytest.approx(k.plate_area * 0.006 * 600.0, rel=1e-13)
    assert 0.0 < k.bending_utilisation_characteristic < 1.0
    # the default basis, EC5 SC1 permanent: k_mod 0.6, gamma_M 1.2 (docs/thickness.md)
    assert (k.bending_basis, k.k_mod, k.gamma_M, k.k_def) == ("EC5 SC1 permanent", 0.6, 1.2, 0.8)
    assert k.bending_utilisation == pytest.approx(
        k.bending_utilisation_characteristic * 1.2 / 0.6, rel=1e-12
    )
    assert k.relaxed_strain is None  # exact designs are not relaxed


def test_every_figure_is_defined_once_and_documented():
    names = [f.name for f in FIGURES]
    assert len(names) == len(set(names))
    assert {f.group for f in FIGURES} == set(GROUPS)
    assert {f.dtype for f in FIGURES} <= {"float", "int", "bool", "str"}
    doc = (EXAMPLES.parent / "docs" / "key-figures.md").read_text(encoding="utf-8")
    table = doc.split("<!-- figures:begin")[1].split("-->", 1)[1].split("<!-- figures:end -->")[0]
    assert table.strip() == figures_markdown().strip()  # regenerate: see the comment in the docs
    readme = (EXAMPLES.parent / "README.md").read_text(encoding="utf-8")
    assert "docs/key-figures.md" in readme


def test_sweep_and_catalog_columns_are_key_figures():
    by_name = {f.name: f for f in FIGURES}
    for group, columns in KEY_FIGURE_COLUMNS.items():
        for column, name in columns.items():
            metric = next(m for m in METRICS if m.name == column)
            f = by_name[name]
            assert (metric.group, metric.figure, metric.dtype, metric.unit) == (
                group,
                name,
                f.dtype,
                f.unit,
            )
    assert set(COLUMNS) - {"name", "figure", "expected"} <= set(by_name)


def test_a_dome_reports_the_plan_diameter_and_height_of_the_whole_structure(tmp_path):
    """A radial layout's size rows are the whole structure's (the leading crease's chord and
    rise say little of a dome); the plan diameter is the largest plan distance between two
    deployed vertices, computed here pair by pair."""
    from compas_ccu.design.presets import write_preset

    write_preset("dome", tmp_path / "dome.toml")
    model = load_model(tmp_path / "dome.toml")
    k = key_figures(model)
    xy = np.asarray(model.deploy().deployed, dtype=float).reshape(-1, 3)[:, :2]
    brute = max(float(np.linalg.norm(xy - q, axis=1).max()) for q in xy)
    assert k.plan_diameter == pytest.approx(brute, rel=1e-12)
    assert k.plan_diameter > 1.5 * k.crease_span  # the dome, not its leading crease
    # a half dome: its diameter lies across the bounding box (y), twice the foot's 1.9 m
    assert k.plan_diameter == pytest.approx(k.plan_y, rel=1e-12)
    assert k.plan_diameter == pytest.approx(2 * 1.9, rel=1e-12)
    points = np.asarray(model.deploy().deployed, dtype=float).reshape(-1, 3)
    assert k.height == pytest.approx(float(np.ptp(points[:, 2])), rel=1e-12)
    rows = dict(figure_rows(k))
    assert rows["plan diameter"] == f"{k.plan_diameter:.4f} m (the whole structure in plan)"
    assert rows["height"] == f"{k.height:.4f} m (the whole structure)"
    assert "span" not in rows and rows["leading crease"].startswith("chord ")
    vault = key_figures(load_model(EXAMPLES / "vault.toml"))
    assert dict(figure_rows(vault))["span"] == "2.5000 m (leading crease chord)"
    assert vault.plan_diameter == pytest.approx(float(np.hypot(vault.plan_x, vault.plan_y)),
                                                rel=0.05)  # fmt: skip


def test_a_curvature_peak_at_a_funicular_kink_is_explained():
    """Fig. 9d: the crease's one kink (a point load) is on crease vertex 31 and the plates'
    curvature peaks on that ruling, 5.18 1/m against 0.07-1.00 1/m elsewhere; the bending
    rows say so. The vault's peak is at no kink (it has none)."""
    from compas_ccu.catalog import catalog_path
    from compas_ccu.key_figures.text import thickness_rows
    from compas_ccu.strips.curvature import plate_curvature
    from compas_ccu.thickness import ThickModel

    model = load_model(catalog_path("fig09d-funicular"))
    n = model.segments
    assert model.geometry.kinks == (31,)
    kappa = np.abs(plate_curvature(np.asarray(model.deploy().deployed)[None]))[0]
    assert kappa[:, [31, n + 32]].max() == pytest.approx(5.1756, abs=1e-4)
    smooth = np.delete(kappa[:, : n + 1], 31, axis=1)
    assert (smooth.min(), smooth.max()) == pytest.approx((0.0714, 0.9952), abs=1e-4)
    summary = ThickModel(model).summary(path_states=5)
    worst = summary["bending"]["worst"]
    assert worst["ruling"] == 31 and worst["at_kink"]
    rows = thickness_rows(summary)
    note = [text for label, text in rows if "at a kink of the crease" in text]
    assert len(note) == 1 and note[0].startswith("the peak is on ruling 31")
    vault = ThickModel(load_model(EXAMPLES / "vault.toml")).summary(path_states=3)
    assert not vault["bending"]["worst"]["at_kink"]
    assert not any("kink" in text for _, text in thickness_rows(vault))
