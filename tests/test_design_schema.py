from __future__ import annotations

from pathlib import Path

import pytest

from compas_ccu.design import Design, load_design
from compas_ccu.design.schema import SCHEMA, schema_markdown
from compas_ccu.errors import DesignError
from compas_ccu.model import CCUModel, load_model
from conftest import EXAMPLES, make_design

BASE = {
    "crease": {"profile": "arc", "span": 2.0, "rise": 0.6},
    "rulings": {"type": "orthogonal"},
    "deployment": {"alpha": 30.0},
    "layout": {"width": 0.3},
}


def with_change(section, key, value):
    doc = {k: dict(v) for k, v in BASE.items()}
    doc.setdefault(section, {})[key] = value
    return doc


@pytest.mark.parametrize(
    "section,key,value,message",
    [
        ("crease", "spam", 1, r"crease\.spam: unknown key; allowed in \[crease\]: profile"),
        ("crease", "span", "2", r"crease\.span: must be a finite number, got '2'"),
        ("crease", "span", True, r"crease\.span: must be a finite number, got True"),
        ("crease", "span", -1.0, r"crease\.span: must be > 0 and <= 1e6, got -1\.0"),
        ("crease", "span", 1e308, r"crease\.span: must be > 0 and <= 1e6, got 1e\+308"),
        ("crease", "span", 10**400, r"crease\.span: must be a finite number, got 1000000000"),
        ("crease", "profile", "parabola", r"crease\.profile: must be one of 'arc', 'catenary'"),
        ("crease", "segments", 1, r"crease\.segments: must be 2 \.\.\. 2e6, got 1"),
        ("crease", "segments", 2.5, r"crease\.segments: must be an integer, got 2\.5"),
        ("crease", "reference", 1.5, r"crease\.reference: must be 0 \.\.\. 1, got 1\.5"),
        ("deployment", "alpha", 90.0, r"deployment\.alpha: must be 0 < alpha < 90, got 90\.0"),
        ("rulings", "type", "tangent", r"rulings\.type: must be one of 'orthogonal'"),
        ("rulings", "gamma", [[0.0, 80.0], [0.5, 90.0]], r"rulings\.gamma: must have increas"),
        ("rulings", "gamma", 190.0, r"rulings\.gamma: ruling angles must be in \(0, 180\)"),
        ("layout", "quadrants", "yes", r"layout\.quadrants: must be true or false"),
        ("plane", "origin", [0, 0], r"plane\.origin: must be a list of 3 numbers"),
    ],
)
def test_bad_values_name_the_key_the_value_and_what_is_allowed(section, key, value, message):
    with pytest.raises(DesignError, match=message):
        Design(with_change(section, key, value))


def test_unknown_section_and_missing_keys():
    with pytest.raises(DesignError, match=r"\[extras\]: unknown section; allowed: design"):
        Design({**BASE, "extras": {}})
    doc = {k: v for k, v in BASE.items() if k != "rulings"}
    with pytest.raises(DesignError, match=r"\[rulings\]: missing required section"):
        Design(doc)
    with pytest.raises(DesignError, match=r"deployment\.alpha: missing required key"):
        Design({**BASE, "deployment": {}})


def test_build_time_errors_name_the_key():
    with pytest.raises(DesignError, match=r"layout\.width: required for layout type 'single'"):
        CCUModel(Design({**BASE, "layout": {}}))
    with pytest.raises(DesignError, match=r"rulings\.direction: required for type"):
        CCUModel(make_design(rulings={"type": "cylindrical"}))
    with pytest.raises(DesignError, match=r"layout\.spacing: needs one value per plate \(3\)"):
        CCUModel(make_design(layout={"type": "parallel", "plates": 3, "spacing": [0.1, 0.1]}))
    with pytest.raises(DesignError, match=r"crease\.state: layout 'parallel' needs"):
        CCUModel(
            make_design(
                crease={"state": "flat"}, layout={"type": "parallel", "plates": 2, "spacing": 0.1}
            )
        )
    with pytest.raises(DesignError, match=r"layout\.leading: must be a plane with a plate"):
        CCUModel(
            make_design(layout={"type": "parallel", "plates": 2, "spacing": 0.1, "leading": 2})
        )
    with pytest.raises(DesignError, match=r"plane\.yaxis: must not be parallel"):
        CCUModel(make_design(plane={"xaxis": [1.0, 0.0, 0.0], "yaxis": [2.0, 0.0, 0.0]}))


def test_files_errors(tmp_path: Path):
    with pytest.raises(DesignError, match="cannot read design file"):
        load_design(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[crease\nprofile = 'arc'", encoding="utf-8")
    with pytest.raises(DesignError, match="bad.toml: not valid TOML"):
        load_design(bad)


@pytest.mark.parametrize("name", ["vault", "cone", "quadrants"])
def test_examples_load_and_build(name):
    model = load_model(EXAMPLES / f"{name}.toml")
    assert model.design.name == name
    assert model.deploy().max_invariant_error < 1e-12


def test_docs_list_every_key_and_are_up_to_date():
    doc = (Path(__file__).resolve().parents[1] / "docs" / "design-files.md").read_text(
        encoding="utf-8"
    )
    assert doc.strip() == schema_markdown().strip(), (
        "regenerate: python -m compas_ccu.design.schema > docs/design-files.md"
    )
    for section, keys in SCHEMA.items():
        assert f"## [{section}]" in doc
        for name in keys:
            if not name.startswith("_"):
                assert f"| `{name}` |" in doc
