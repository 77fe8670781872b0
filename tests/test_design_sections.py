"""Typed design sections generated from the schema, the rules between keys, and the design as a
COMPAS data object."""

from __future__ import annotations

import copy
import dataclasses

import compas
import pytest

from compas_ccu.design import Design, load_design
from compas_ccu.design.rules import RULES
from compas_ccu.design.schema import SCHEMA, validate
from compas_ccu.design.sections import SECTION_TYPES, DesignSections
from compas_ccu.errors import DesignError
from conftest import EXAMPLES

BASE = {
    "crease": {"profile": "arc", "span": 2.0, "rise": 0.6},
    "rulings": {"type": "orthogonal"},
    "deployment": {"alpha": 30.0},
    "layout": {"width": 0.3},
}


def test_one_typed_section_per_schema_section_with_every_key():
    # and the named tables [materials.NAME] (compas_ccu.design.sections.MaterialsSection)
    assert [f.name for f in dataclasses.fields(DesignSections)] == [*SCHEMA, "materials"]
    for section, keys in SCHEMA.items():
        names = [f.name for f in dataclasses.fields(SECTION_TYPES[section])]
        assert names == [k for k in keys if not k.startswith("_")]


def test_typed_sections_hold_the_validated_values():
    design = load_design(EXAMPLES / "vault.toml")
    assert design.sections.to_values() == design.values
    assert design.crease.span == design.values["crease"]["span"]
    assert design.layout.type == "parallel" and design.layout.plates == 10
    assert design.plates.material == design.values["plates"]["material"]
    with pytest.raises(dataclasses.FrozenInstanceError):
        design.crease.span = 3.0
    with pytest.raises(AttributeError):
        design.crease.spam  # noqa: B018 - a misspelt key is an error, not None


def _doc(**sections):
    doc = copy.deepcopy(BASE)
    for name, values in sections.items():
        doc[name] = {**doc.get(name, {}), **values}
    return doc


#: A design that breaks each rule of RULES, and the message.
BROKEN = {
    ("rulings.direction", "type 'cylindrical'"): (
        _doc(rulings={"type": "cylindrical"}),
        r"rulings\.direction: required for type 'cylindrical'",
    ),
    ("rulings.apex", "type 'conical'"): (
        _doc(rulings={"type": "conical"}),
        r"rulings\.apex: required for type 'conical'",
    ),
    ("rulings.gamma", "type 'angle'"): (
        _doc(rulings={"type": "angle"}),
        r"rulings\.gamma: required for type 'angle'",
    ),
    ("rulings.points", "type 'explicit'"): (
        _doc(rulings={"type": "explicit"}, crease={"state": "flat"}),
        r"rulings\.points: required for type 'explicit'",
    ),
    ("rulings.points", "state"): (
        _doc(rulings={"type": "explicit", "points": [[0, 1], [1, 1], [2, 1]]}),
        r"rulings\.points: explicit rulings describe a cut pattern: they need crease\.state = "
        r"'flat' and layout type 'single' or 'patterns', got state 'deployed' and layout 'single'",
    ),
    ("layout.type", "patterns"): (
        _doc(
            layout={
                "type": "patterns",
                "patterns": [
                    {
                        "parent": 0,
                        "boundary": "near",
                        "near": [[0, 0], [1, 0]],
                        "far": [[0, 1], [1, 1]],
                    }
                ],
            },
        ),  # fmt: skip
        r"layout\.type: layout 'patterns' lists cut patterns: the leading plate is one too, so "
        r"it needs rulings\.type = 'explicit' and crease\.state = 'flat', got rulings "
        r"'orthogonal' and state 'deployed'",
    ),
    ("layout.patterns", "patterns"): (
        _doc(
            crease={"state": "flat"},
            rulings={"type": "explicit", "points": [[0, 1], [1, 1], [2, 1]]},
            layout={"type": "patterns"},
        ),
        r"layout\.patterns: required for layout type 'patterns'",
    ),
    ("[target]", "layout"): (
        _doc(target={"apex": [[0.0, 1.0], [1.0, 1.2]]}),
        r"\[target\]: target curves need layout type 'parallel' or 'inclined', got 'single'",
    ),
    ("target.support_end", "support"): (
        _doc(
            layout={"type": "parallel", "plates": 4, "spacing": 0.1},
            target={"support_end": [[0.0, 1.0], [1.0, 1.2]]},
        ),
        r"target\.support_end: needs target\.support as well",
    ),
    ("crease.state", "multi"): (
        _doc(crease={"state": "flat"}, layout={"type": "parallel", "plates": 4, "spacing": 0.1}),
        r"crease\.state: layout 'parallel' needs crease\.state = 'deployed'",
    ),
    ("layout.width", "single"): (
        {**_doc(), "layout": {"type": "single"}},
        r"layout\.width: required for layout type 'single'",
    ),
    ("layout.plates", "multi"): (
        _doc(layout={"type": "radial", "angle": 10.0, "axis": 3.0}),
        r"layout\.plates: required for layout type 'radial'",
    ),
    ("layout.spacing", "parallel"): (
        _doc(layout={"type": "inclined", "plates": 4}),
        r"layout\.spacing: required for layout type 'inclined'",
    ),
    ("layout.angle", "radial"): (
        _doc(layout={"type": "radial", "plates": 4, "axis": 3.0}),
        r"layout\.angle: required for layout type 'radial'",
    ),
    ("layout.axis", "radial"): (
        _doc(layout={"type": "radial", "plates": 4, "angle": 10.0}),
        r"layout\.axis: required for layout type 'radial'",
    ),
    ("plates.material", "unknown"): (
        _doc(plates={"material": "oak"}, materials={"myply": {"base": "plywood"}}),
        r"plates\.material: unknown material 'oak'; known: 'plywood', .*'aluminium', 'myply'",
    ),
    ("design_code.gamma_M", "gfrp"): (
        _doc(plates={"material": "gfrp"}, design_code={"k_mod": 0.5}),
        r"design_code\.gamma_M: required for code 'EC5' with plate material 'gfrp' of kind "
        r"'gfrp' \(no default design factors\); or code = 'characteristic'",
    ),
    ("design_code.k_mod", "other"): (
        _doc(
            plates={"material": "resin"},
            design_code={"gamma_M": 1.4},
            materials={"resin": {"E": 3e9, "nu12": 0.35, "density": 1200.0, "f": 60e6}},
        ),
        r"design_code\.k_mod: required for code 'EC5' with plate material 'resin' of kind "
        r"'other'",
    ),
}


@pytest.mark.parametrize("case", list(BROKEN), ids=["-".join(c) for c in BROKEN])
def test_every_rule_between_keys_names_its_key(case):
    document, message = BROKEN[case]
    with pytest.raises(DesignError, match=message) as err:
        validate(document)
    assert err.value.key == case[0]


def test_every_rule_is_tested():
    assert sorted(r.key for r in RULES) == sorted(key for key, _ in BROKEN)


def test_a_valid_design_passes_every_rule():
    values = validate(BASE)
    assert all(rule.holds(values) for rule in RULES if rule.applies(values))


def test_load_design_keeps_the_key_of_the_error(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[crease]\nprofile = "arc"\nspan = -1.0\nrise = 0.5\n')
    with pytest.raises(DesignError) as err:
        load_design(path)
    assert err.value.key == "crease.span"
    assert str(err.value).startswith(f"{path}: crease.span: must be > 0")


def test_design_round_trips_through_compas_json():
    design = load_design(EXAMPLES / "vault.toml")
    again = compas.json_loads(compas.json_dumps(design))
    assert isinstance(again, Design)
    assert again.values == design.values and again.name == design.name
    assert again.sha256() == design.sha256()
