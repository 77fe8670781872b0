"""Span scaling studies: similar designs whose numbers follow the exact scaling laws."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.errors import OptionError
from compas_ccu.explore.scale import law_thickness, scale_study, scaled_document
from compas_ccu.model import CCUModel
from conftest import EXAMPLES


@pytest.fixture(scope="module")
def vault():
    return load_design(EXAMPLES / "vault.toml").document


@pytest.mark.parametrize(
    "law, bending_power, mass_power, energy_power",
    [
        # ~1 s each: the quick loop checks one law
        pytest.param("constant", -1.0, 2.0, 0.0, marks=pytest.mark.slow),
        ("proportional", 0.0, 3.0, 3.0),
        pytest.param("cuberoot", -1.0 / 3.0, 8.0 / 3.0, 2.0, marks=pytest.mark.slow),
    ],
)
def test_similar_designs_follow_the_scaling_laws(
    vault, law, bending_power, mass_power, energy_power
):
    # curvature ~ 1/s, bending stress ~ t kappa: utilisation ~ t / s; mass ~ s^2 t;
    # bending energy ~ t^3 kappa^2 area ~ t^3; the force between the feet ~ energy / s
    rows = scale_study(vault, 2.5, to_span=6.0, steps=3, law=law, collisions=False)
    base = rows[0]
    assert [r["status"] for r in rows] == ["ok"] * 4
    for r in rows:
        s = r["scale"]
        assert r["span"] == pytest.approx(2.5 * s, rel=1e-12)
        assert r["rise"] == pytest.approx(base["rise"] * s, rel=1e-12)
        assert r["plate_length"] == pytest.approx(base["plate_length"] * s, rel=1e-9)
        assert r["bending_utilisation"] == pytest.approx(
            base["bending_utilisation"] * s**bending_power, rel=1e-9
        )
        assert r["mass"] == pytest.approx(base["mass"] * s**mass_power, rel=1e-12)
        assert r["stack_height"] == pytest.approx(10 * r["thickness"], rel=1e-12)
        assert r["deployment_energy"] == pytest.approx(
            base["deployment_energy"] * s**energy_power, rel=1e-9
        )
        assert r["actuation_force"] == pytest.approx(
            base["actuation_force"] * s ** (energy_power - 1.0), rel=1e-9
        )
    # 6 mm plates: the 8 mm vault's 291.1 J and 1337.2 N times (6/8)^3
    assert base["deployment_energy"] == pytest.approx(122.81, abs=0.05)
    assert base["actuation_force"] == pytest.approx(564.13, abs=0.05)
    assert [r["span_target"] for r in rows] == pytest.approx([2.5, 3.666666, 4.833333, 6.0])


def test_the_sheet_check_and_the_given_law(vault):
    rows = scale_study(vault, 2.5, to_span=3.0, steps=1, law="given",
                       thicknesses=[0.008, 0.012], sheet=(3.0, 1.25), collisions=False)  # fmt: skip
    assert [r["thickness"] for r in rows] == [0.008, 0.012]
    assert [r["fits_sheet"] for r in rows] == [True, False]  # 2.72 x 0.99 fits; 3.27 m does not


def test_every_length_of_the_schema_is_scaled_and_nothing_else():
    doc = {
        "crease": {"profile": "funicular", "span": 2.0, "rise": 0.5, "segments": 40,
                   "point_loads": [[0.2, 3.0]], "distributed_loads": [[-1.0, 1.0, 1.0, 2.0]],
                   "reference": 0.5},
        "rulings": {"type": "conical", "apex": [0.0, -2.0]},
        "deployment": {"alpha": 30.0},
        "layout": {"type": "inclined", "plates": 4, "spacing": [0.1, 0.2, 0.1, 0.2],
                   "spacing_start": 0.05},
        "target": {"apex": [[0.0, 0.5], [1.0, 0.6]]},
        "plates": {"thickness": 0.008, "hinge_width": 0.05, "grain": 30.0},
        "plane": {"origin": [1.0, 2.0, 3.0], "xaxis": [1.0, 0.0, 0.0]},
        "fabrication": {"sheets": [[3.05, 1.525]], "kerf": 0.003},
    }  # fmt: skip
    out = scaled_document(doc, 2.0)
    assert out["fabrication"] == doc["fabrication"]  # the workshop's stock and tools
    assert out["crease"] == {**doc["crease"], "span": 4.0, "rise": 1.0,
                             "point_loads": [[0.4, 3.0]],
                             "distributed_loads": [[-2.0, 2.0, 1.0, 2.0]]}  # fmt: skip
    assert out["rulings"]["apex"] == [0.0, -4.0]
    assert out["layout"]["spacing"] == [0.2, 0.4, 0.2, 0.4] and out["layout"]["plates"] == 4
    assert out["layout"]["spacing_start"] == 0.1
    assert out["target"]["apex"] == [[0.0, 1.0], [2.0, 1.2]]
    assert out["plates"] == doc["plates"]  # thickness by its law, hinge width and grain kept
    assert out["plane"] == {"origin": [2.0, 4.0, 6.0], "xaxis": [1.0, 0.0, 0.0]}
    assert out["deployment"] == doc["deployment"]
    assert doc["crease"]["span"] == 2.0  # the input is not changed


def test_refusals(vault):
    with pytest.raises(OptionError, match="needs 4 thicknesses"):
        scale_study(vault, 2.5, to_span=6.0, steps=3, law="given", thicknesses=[0.01])
    with pytest.raises(OptionError, match="unknown thickness law 'square'"):
        scale_study(vault, 2.5, to_span=6.0, law="square")
    with pytest.raises(OptionError, match="scale factor must be > 0"):
        scaled_document(vault, 0.0)
    with pytest.raises(OptionError, match="steps must be >= 1"):
        scale_study(vault, 2.5, to_span=6.0, steps=0)
    assert law_thickness("proportional", 0.01, 1.5) == pytest.approx(0.015)


@pytest.mark.slow  # an imported structure or the scale plots (1.8-4 s)
def test_ccu_scale_writes_the_table_and_the_plots(tmp_path, capsys):
    out = tmp_path / "scale"
    code = main(["scale", str(EXAMPLES / "vault.toml"), "--to", "4", "--steps", "2",
                 "--thickness-law", "cuberoot", "--out", str(out)])  # fmt: skip
    assert code == 0
    with open(out / "scale.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [float(r["span"]) for r in rows] == pytest.approx([2.5, 3.25, 4.0])
    assert all(r["status"] == "ok" and r["collision_free"] == "True" for r in rows)
    t = np.array([float(r["thickness"]) for r in rows])
    assert t == pytest.approx(0.006 * (np.array([2.5, 3.25, 4.0]) / 2.5) ** (2 / 3))
    assert (out / "scale.png").stat().st_size > 10_000 and (out / "scale.svg").is_file()
    text = capsys.readouterr().out
    assert "larger than the sheet" in text and "wrote" in text
    assert "without --fe, self-weight and buckling are not in this table" in text
    with pytest.raises(SystemExit) as exit_:  # the sheet as ccu fabricate takes it: two numbers
        main(["scale", str(EXAMPLES / "vault.toml"), "--to", "4", "--sheet", "2.4x1.2",
              "--out", str(tmp_path / "x")])  # fmt: skip
    assert exit_.value.code == 2 and "--sheet" in capsys.readouterr().err
    assert main(["scale", str(EXAMPLES / "vault.toml"), "--to", "4", "--area-load", "900",
                 "--out", str(tmp_path / "y")]) == 2  # fmt: skip
    assert "--area-load and --load-case choose the load of the FE checks: give --fe" in (
        capsys.readouterr().err
    )


def _numbers(value):
    """The numbers of a nested value, in order (the pattern rows' coordinates)."""
    if isinstance(value, list):
        return [x for v in value for x in _numbers(v)]
    return [value]


@pytest.fixture(scope="module")
def imported(tmp_path_factory):
    """The vault through ``ccu fabricate`` and ``ccu import``: a ``[[layout.patterns]]``
    design, its document (metres) and its deployed span and rise."""
    pytest.importorskip("ezdxf")
    pytest.importorskip("rhino3dm")
    pytest.importorskip("trimesh")
    root = tmp_path_factory.mktemp("imported")
    fab, path = root / "fab", root / "imported.toml"
    assert main(["fabricate", str(EXAMPLES / "vault.toml"), "--out", str(fab),
                 "--nesting", "shelf", "--allow-exceeded", "--quiet"]) == 0  # fmt: skip
    assert main(["import", str(fab), "--out", str(path), "--quiet"]) == 0
    design = load_design(path)
    assert design.layout.type == "patterns" and len(design.layout.patterns) == 9
    return path, design.metric_document(), CCUModel(design).deploy().metrics


@pytest.mark.slow  # an imported structure or the scale plots (1.8-4 s)
def test_an_imported_patterns_design_scales_with_its_patterns(imported, tmp_path):
    """``ccu scale`` walks the loader's length keys: the cut patterns of an imported design
    scale with the crease (they stayed at scale 1 and the design was refused)."""
    path, document, metrics = imported
    factor = 1.37
    out = scaled_document(document, factor)
    crease, layout = document["crease"], document["layout"]
    assert out["crease"]["points"] == [[factor * x, factor * y] for x, y in crease["points"]]
    assert len(out["layout"]["patterns"]) == len(layout["patterns"]) == 9
    for new, old in zip(out["layout"]["patterns"], layout["patterns"]):
        for row in ("near", "far"):
            assert _numbers(new[row]) == [factor * v for v in _numbers(old[row])]
            assert len(new[row]) == len(old[row]) and len(new[row][0]) == 2
        assert {k: v for k, v in new.items() if k not in ("near", "far")} == {
            k: v for k, v in old.items() if k not in ("near", "far")
        }  # parent, boundary, id kept
    assert out["plates"] == document["plates"] and out["deployment"] == document["deployment"]
    model = CCUModel(Design(out))  # its checks pass: every pattern fits its parent
    scaled = model.deploy().metrics
    for key in ("span", "rise"):
        assert scaled[key] == pytest.approx(factor * metrics[key], rel=1e-12, abs=0.0)
    assert document["layout"]["patterns"][0]["near"] == layout["patterns"][0]["near"]

    code = main(["scale", str(path), "--to", str(1.25 * metrics["span"]), "--steps", "1",
                 "--out", str(tmp_path / "scale"), "--quiet"])  # fmt: skip
    assert code == 0
    with open(tmp_path / "scale" / "scale.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["status"] for r in rows] == ["ok", "ok"], [r["error"] for r in rows]
    assert float(rows[1]["span"]) == pytest.approx(1.25 * metrics["span"], rel=1e-12)
