from __future__ import annotations

from pathlib import Path

import compas
import pytest

from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.design.keys_fabrication import FABRICATION_SECTIONS
from compas_ccu.design.keys_shape import SHAPE_SECTIONS
from compas_ccu.design.keys_structure import STRUCTURE_SECTIONS
from compas_ccu.design.schema import SCHEMA, schema_markdown
from compas_ccu.errors import DesignError
from compas_ccu.fea.settings import FESettings
from compas_ccu.key_figures import key_figures
from compas_ccu.model import CCUModel, load_model
from compas_ccu.thickness import ThickModel
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


def test_the_schema_holds_every_section_table_once():
    """SCHEMA puts the sections of the keys_* modules in order: none is left out or doubled."""
    tables = [SHAPE_SECTIONS, STRUCTURE_SECTIONS, FABRICATION_SECTIONS]
    assert sum(len(t) for t in tables) == len(SCHEMA)
    assert {s: k for t in tables for s, k in t.items()} == SCHEMA


# -- [materials.NAME] and [design_code] --------------------------------------------------------
def _with(**sections):
    doc = {k: dict(v) for k, v in BASE.items()}
    doc.update(sections)
    return doc


MYPLY = {"base": "birch-plywood", "E1": 12.0e9, "f2": 30.0e6, "description": "supplier X"}


def test_file_material_round_trip(tmp_path):
    text = (
        (EXAMPLES / "vault.toml").read_text().replace('material = "plywood"', 'material = "myply"')
    )
    text += (
        '\n[materials.myply]\nbase = "birch-plywood"\nE1 = 12e9\nf2 = 30e6\n'
        "\n[materials.resin]\nE = 3e9\nnu12 = 0.35\ndensity = 1200.0\nf = 60e6\n"
    )
    path = tmp_path / "myply.toml"
    path.write_text(text)
    design = load_design(path)
    m = design.material
    assert m.name == "myply" and m.kind == "plywood"
    assert (m.E1, m.E2, m.G12, m.f1, m.f2) == (12.0e9, 6.0e9, 0.6e9, 45.0e6, 30.0e6)
    resin = design.materials["resin"]
    assert resin.E1 == resin.E2 == 3e9 and resin.G12 == 3e9 / 2.7 and resin.f1 == resin.f2 == 60e6
    assert resin.kind == "other" and resin.is_isotropic
    assert sorted(design.materials) == ["myply", "resin"]
    assert design.resolve_material("resin") is resin
    assert design.resolve_material("gfrp").name == "gfrp"
    # every value is kept through the typed sections and COMPAS JSON
    assert design.sections.to_values() == design.values
    again = compas.json_loads(compas.json_dumps(design))
    assert again.material == m and again.values == design.values
    # every consumer uses it: the thick model, the key figures, ccu info
    model = CCUModel(design)
    thick = ThickModel(model)
    assert thick.material == m and thick.summary(path_states=3)["material"] == "myply"
    assert ThickModel(model, material="resin", design_code={"k_mod": 0.6, "gamma_M": 1.3})
    assert key_figures(model, path=3, thickness=True).material == "myply"
    assert main(["info", str(path)]) == 0


def test_file_material_in_fe_settings():
    design = Design(_with(plates={"material": "myply"}, materials={"myply": MYPLY}))
    settings = FESettings(material=design.material, design_code=design.design_factors())
    assert settings.material.name == "myply" and settings.design_code.gamma_M == 1.2


@pytest.mark.parametrize(
    "materials, message",
    [
        ({"myply": 3.0}, r"materials\.myply: must be a table \[materials\.NAME\] of values"),
        ({"my ply": MYPLY}, r"\[materials\.my ply\]: a name is letters, digits"),
        (
            {"plywood": {"base": "plywood", "E": 8e9}},
            r"\[materials\.plywood\]: shadows the library material 'plywood'; give it another "
            r'name and base = "plywood"',
        ),
        (
            {"myply": {**MYPLY, "colour": "red"}},
            r"materials\.myply\.colour: unknown key; allowed in \[materials\.NAME\]: base, kind",
        ),
        (
            {"myply": {"base": "plywood", "E1": -1.0}},
            r"materials\.myply\.E1: must be > 0 and <= 1e\+?13 Pa, got -1\.0",
        ),
        (
            {"myply": {"base": "plywood", "E2": 0}},
            r"materials\.myply\.E2: must be > 0 and <= 1e\+?13 Pa, got 0\.0",
        ),
        ({"myply": {"base": "plywood", "G12": "3e9"}}, r"materials\.myply\.G12: must be a finite"),
        (
            {"myply": {"base": "plywood", "f": float("inf")}},
            r"materials\.myply\.f: must be a finite",
        ),
        (
            {"myply": {"base": "plywood", "f1": -2.0}},
            r"materials\.myply\.f1: must be > 0 and <= 1e\+?13 Pa, got -2\.0",
        ),
        ({"myply": {"base": "plywood", "density": 0.0}}, r"materials\.myply\.density: must be > 0"),
        ({"myply": {"base": "plywood", "nu12": 0.5}}, r"materials\.myply\.nu12: must be -1 < nu12"),
        (
            {"myply": {"base": "birch-plywood", "E1": 1e6, "nu12": 0.3}},
            r"materials\.myply\.nu12: nu12 = 0\.3 gives no positive definite stiffness",
        ),
        ({"myply": {"base": "oak"}}, r"materials\.myply\.base: must be one of 'plywood'"),
        ({"myply": {"base": "plywood", "kind": "wood"}}, r"materials\.myply\.kind: must be one of"),
        (
            {"myply": {"base": "plywood", "E": 8e9, "E1": 9e9}},
            r"materials\.myply\.E1: give E \(isotropic\) or E1 and E2, not both",
        ),
        (
            {"myply": {"base": "plywood", "f": 8e6, "f2": 9e6}},
            r"materials\.myply\.f2: give f \(isotropic\) or f1 and f2, not both",
        ),
        (
            {"myply": {"E1": 9e9, "E2": 5e9, "nu12": 0.1, "density": 500.0, "f": 20e6}},
            r"materials\.myply: missing G12: give every value",
        ),
        ({"myply": {}}, r"materials\.myply: missing E1, E2, G12, nu12, density, f1, f2"),
    ],
)
def test_file_material_errors_name_the_key(materials, message):
    with pytest.raises(DesignError, match=message):
        Design(_with(materials=materials))


def test_materials_section_must_hold_tables():
    with pytest.raises(DesignError, match=r"\[materials\]: must be a table"):
        Design(_with(materials=3))


@pytest.mark.parametrize(
    "values, message",
    [
        ({"code": "EC9"}, r"design_code\.code: must be one of 'EC5', 'characteristic'"),
        ({"service_class": 4}, r"design_code\.service_class: must be 1, 2 or 3, got 4"),
        ({"service_class": 1.0}, r"design_code\.service_class: must be an integer"),
        ({"load_duration": "weekly"}, r"design_code\.load_duration: must be one of 'permanent'"),
        ({"gamma_M": 0.5}, r"design_code\.gamma_M: must be 1 \.\.\. 10, got 0\.5"),
        ({"k_mod": 0.0}, r"design_code\.k_mod: must be > 0 and <= 1\.5, got 0\.0"),
        ({"k_def": -1.0}, r"design_code\.k_def: must be >= 0 and <= 10"),
        ({"kmod": 0.6}, r"design_code\.kmod: unknown key; allowed in \[design_code\]: code"),
    ],
)
def test_design_code_errors_name_the_key(values, message):
    with pytest.raises(DesignError, match=message):
        Design(_with(design_code=values))


def test_design_code_defaults_and_values():
    d = Design(BASE)
    assert d.design_code.to_dict() == {
        "code": "EC5",
        "service_class": 1,
        "load_duration": "permanent",
        "gamma_M": None,
        "k_mod": None,
        "k_def": None,
    }
    assert d.design_factors().label == "EC5 SC1 permanent"
    d = Design(_with(design_code={"code": "characteristic"}, plates={"material": "gfrp"}))
    assert d.design_factors().strength_factor == 1.0  # gfrp needs no factors here
    d = Design(_with(design_code={"gamma_M": 1.3, "k_mod": 0.4}, plates={"material": "gfrp"}))
    assert d.design_factors().strength_factor == 0.4 / 1.3


def test_an_integer_for_a_float_key_is_shown_as_the_float_it_becomes():
    """The studio passes a typed "-1" as an int: the message reads like the CLI's."""
    from compas_ccu.design import Design
    from compas_ccu.errors import DesignError

    doc = {
        "crease": {"profile": "arc", "span": 2.0, "rise": -1},
        "rulings": {"type": "orthogonal"},
        "deployment": {"alpha": 30.0},
        "layout": {"width": 0.3},
    }
    with pytest.raises(DesignError, match=r"^crease\.rise: must be > 0 and <= 1e6, got -1\.0$"):
        Design(doc)
