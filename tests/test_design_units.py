"""[design] units: every length converted to metres, implausible lengths warned, write-back."""

from __future__ import annotations

import copy
import warnings

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.design.document import read_toml
from compas_ccu.design.inverse import write_design
from compas_ccu.design.schema import SCHEMA, validate
from compas_ccu.design.units import LENGTH_UNITS, convert_document, is_length, map_lengths
from compas_ccu.design.values import coerce_value
from compas_ccu.design.variants import quadrant_design
from compas_ccu.errors import DesignError, UnitsWarning
from compas_ccu.model import CCUModel, flat_design
from conftest import EXAMPLES

VAULT = EXAMPLES / "vault.toml"

#: A value in millimetres for every kind of length key, and the same in metres by hand.
SAMPLES = {
    "float": (80.0, 0.08),
    "float_or_list": ([80.0, 120.0], [0.08, 0.12]),
    "point2": ([100.0, -250.0], [0.1, -0.25]),
    "point3": ([100.0, -250.0, 5.0], [0.1, -0.25, 0.005]),
    "points2": ([[0.0, 0.0], [500.0, 250.0], [1000.0, 0.0]], [[0, 0], [0.5, 0.25], [1, 0]]),
    "polyline2": ([[0.0, 300.0], [1000.0, 250.0]], [[0.0, 0.3], [1.0, 0.25]]),
    "sizes2": ([[2500.0, 1250.0], [2440.0, 1220.0]], [[2.5, 1.25], [2.44, 1.22]]),
}
ROWS = {  # positions converted, load intensities kept
    "point_loads": ([[-250.0, 3.0], [400.0, 1.5]], [[-0.25, 3.0], [0.4, 1.5]]),
    "distributed_loads": ([[-500.0, 500.0, 2.0, 4.0]], [[-0.5, 0.5, 2.0, 4.0]]),
}


def length_keys():
    return [
        (section, name, key)
        for section, keys in SCHEMA.items()
        for name, key in keys.items()
        if not name.startswith("_") and is_length(key.unit)
    ]


def test_the_length_keys_are_the_expected_ones():
    names = {f"{s}.{n}" for s, n, _ in length_keys()}
    assert names == {
        "crease.span", "crease.rise", "crease.radius", "crease.points", "crease.point_loads",
        "crease.distributed_loads", "rulings.points", "rulings.apex", "layout.width",
        "layout.ccf_width", "layout.spacing", "layout.spacing_start", "layout.spacing_end",
        "layout.axis", "target.apex", "target.support", "target.support_end",
        "plates.thickness", "plates.hinge_width", "loads.concrete_thickness", "plane.origin",
        "fabrication.sheets", "fabrication.kerf", "fabrication.tool_diameter",
        "fabrication.bridge", "fabrication.margin", "fabrication.splice_width",
        "fabrication.roll_width", "layout.patterns", "fabrication.splice_thickness",
    }  # fmt: skip


@pytest.mark.parametrize("section, name, key", length_keys(), ids=lambda v: str(v)[:20])
def test_every_length_key_is_converted_to_metres(section, name, key):
    if key.kind == "patterns":  # the point rows of every table
        table = {"parent": 0, "boundary": "near", "near": [[0.0, 0.0], [500.0, 250.0]]}
        value = coerce_value(
            section, name, key, [{**table, "far": [[0.0, 100.0], [5.0, 0.0]]}], "mm"
        )
        assert value == [
            {"parent": 0, "boundary": "near", "near": [[0.0, 0.0], [0.5, 0.25]],
             "far": [[0.0, 0.1], [0.005, 0.0]], "id": None}
        ]  # fmt: skip
        return
    given, metres = ROWS[name] if key.kind == "rows" else SAMPLES[key.kind]
    value = coerce_value(section, name, key, given, "mm")
    assert np.allclose(value, metres, rtol=1e-15, atol=0.0)
    assert np.array_equal(coerce_value(section, name, key, metres, "m"), metres)


@pytest.mark.parametrize(
    "value, units, metres", [(12.0, "in", 0.3048), (1.0, "ft", 0.3048), (30.0, "cm", 0.3)]
)
def test_the_unit_factors(value, units, metres):
    assert coerce_value(
        "layout", "width", SCHEMA["layout"]["width"], value, units
    ) == pytest.approx(metres, rel=1e-15)


def test_non_length_keys_are_not_converted():
    mm = validate({**read_toml(VAULT), "design": {"units": "mm"}})
    m = validate(read_toml(VAULT))
    assert mm["deployment"]["alpha"] == m["deployment"]["alpha"] == 30.0
    assert mm["loads"]["live"] == m["loads"]["live"] == 750.0  # N/m², SI whatever the units
    assert mm["layout"]["plates"] == 10 and mm["crease"]["segments"] == 64
    assert mm["crease"]["span"] == pytest.approx(2.5e-3)  # 2.5 read as mm


def test_a_millimetre_vault_is_the_metre_vault():
    document = convert_document(read_toml(VAULT), SCHEMA, to="mm")
    assert document["design"]["units"] == "mm"
    assert document["crease"]["span"] == 2500.0 and document["plates"]["thickness"] == 6.0
    assert document["loads"]["concrete_thickness"] == 80.0 and document["layout"]["spacing"] == 120
    mm, m = Design(document), load_design(VAULT)
    assert mm.units == "mm" and m.units == "m"
    assert mm.sections.to_values() == {
        **m.sections.to_values(),
        "design": {**m.sections.design.to_dict(), "units": "mm"},
    }
    a = CCUModel(mm).deploy().deployed
    b = CCUModel(m).deploy().deployed
    assert np.array_equal(a, b)


@pytest.mark.parametrize("units", sorted(LENGTH_UNITS))
def test_write_design_round_trips_in_the_users_units(units, tmp_path):
    vault = load_design(VAULT)
    path = tmp_path / "v.toml"
    write_design(vault, path, units=units)
    again = load_design(path)
    assert again.units == units
    assert again.crease.span == pytest.approx(2.5, rel=1e-14)
    assert again.plates.thickness == pytest.approx(0.006, rel=1e-14)
    write_design(again, tmp_path / "w.toml")  # its own units: the text is unchanged
    assert (tmp_path / "w.toml").read_text() == path.read_text()


def test_unknown_units_are_named_with_the_allowed_ones():
    doc = {**read_toml(VAULT), "design": {"units": "km"}}
    with pytest.raises(DesignError, match=r"design\.units: must be one of 'm', 'mm', 'cm', "):
        Design(doc)
    with pytest.raises(DesignError, match=r"got 'km'"):
        Design(doc)


def test_a_value_out_of_range_in_other_units_shows_both():
    doc = read_toml(VAULT)
    doc["design"]["units"] = "mm"
    doc["plates"] = {"thickness": 800}
    with pytest.raises(
        DesignError,
        match=r"plates\.thickness: must be > 0 and <= 0\.1 m, got 800\.0 mm \(= 0\.8 m\)",
    ):
        Design(doc)


def test_a_millimetre_value_in_a_metre_file_suggests_the_units():
    doc = read_toml(VAULT)
    doc["plates"] = {"thickness": 8}
    with pytest.raises(DesignError, match=r'got 8\.0: did you mean units = "mm"\?'):
        Design(doc)


def test_an_implausible_span_warns_with_the_likely_units():
    doc = read_toml(VAULT)
    doc["crease"].update(span=2500, rise=1000)
    with pytest.warns(UnitsWarning) as caught:
        Design(doc)
    messages = [str(w.message) for w in caught]
    assert messages[0] == (
        "crease.span = 2500 m is implausible for a curved-crease structure (plausible: "
        '0.05 ... 200 m): did you mean units = "mm" (2.5 m)?'
    )
    assert messages[1].startswith("crease.rise = 1000 m is implausible")


def test_a_tiny_design_warns_and_names_the_metres():
    doc = read_toml(VAULT)
    doc["design"]["units"] = "mm"
    doc["plates"] = {"thickness": 0.008}
    doc["layout"]["spacing"] = 120.0
    doc["crease"].update(span=2500, rise=1000)
    doc["loads"]["concrete_thickness"] = 80.0
    with pytest.warns(UnitsWarning) as caught:
        Design(doc)
    assert [str(w.message) for w in caught] == [
        "plates.thickness = 0.008 mm (8e-06 m) is implausible for a curved-crease structure "
        '(plausible: 0.0002 ... 0.1 m): did you mean units = "m" (0.008 m)?'
    ]


@pytest.mark.parametrize("name", ["vault", "cone", "quadrants"])
def test_the_examples_raise_no_units_warning(name):
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitsWarning)
        load_design(EXAMPLES / f"{name}.toml")


def test_points_extent_is_checked(tmp_path):
    doc = read_toml(EXAMPLES / "cone.toml")
    doc["crease"] = {"profile": "spline", "points": [[0, 0], [1000, 400], [2000, 0]]}
    with pytest.warns(UnitsWarning, match=r"crease\.points = extent 2000 m is implausible"):
        Design(doc)


def test_the_cli_prints_the_warning_as_one_line(tmp_path, capsys):
    doc = read_toml(VAULT)
    doc["crease"].update(span=250, rise=100)
    doc["layout"]["spacing"] = 12.0
    doc.pop("loads")
    path = tmp_path / "big.toml"
    write_design(_quiet(doc), path)
    assert main(["info", str(path)]) == 0
    err = capsys.readouterr().err
    assert err.startswith(
        "ccu: warning: crease.span = 250 m is implausible for a curved-crease structure"
    )
    assert 'did you mean units = "cm" (2.5 m)?' in err


def _quiet(doc):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitsWarning)
        return Design(doc)


def test_a_metre_concrete_thickness_in_a_millimetre_file_warns():
    document = convert_document(read_toml(VAULT), SCHEMA, to="mm")
    document["loads"]["concrete_thickness"] = 0.08  # written in metres by mistake
    with pytest.warns(UnitsWarning) as caught:
        Design(document)
    assert [str(w.message) for w in caught] == [
        "loads.concrete_thickness = 0.08 mm (8e-05 m) is implausible for a curved-crease "
        'structure (plausible: 0.005 ... 2 m): did you mean units = "m" (0.08 m)?'
    ]


def test_derived_designs_keep_the_units():
    cone = load_design(EXAMPLES / "cone.toml")
    cone_mm = Design(convert_document(cone.document, SCHEMA, to="mm"))
    pattern, pattern_mm = flat_design(cone), flat_design(cone_mm)
    assert pattern_mm.units == "mm" and pattern.units == "m"
    assert pattern_mm.document["crease"]["points"][0] == pytest.approx(
        [1e3 * v for v in pattern.document["crease"]["points"][0]], rel=1e-14
    )
    a = CCUModel(pattern_mm).deploy().deployed
    b = CCUModel(pattern).deploy().deployed
    assert np.abs(a - b).max() < 1e-12
    quadrants = quadrant_design(cone_mm)
    assert quadrants.units == "mm" and quadrants.document["layout"]["width"] == 400.0
    assert quadrants.layout.width == pytest.approx(0.4, rel=1e-15)


def _sample_document():
    """One value (mm) of every length key of the schema, in a document as read from TOML."""
    doc = {}
    for section, name, key in length_keys():
        if key.kind == "patterns":
            value = [{"parent": 0, "boundary": "near", "near": [[0.0, 10.0], [500.0, 250.0]],
                      "far": [[0.0, 100.0], [5.0, 0.0]], "id": 3}]  # fmt: skip
        else:
            value = (ROWS[name] if key.kind == "rows" else SAMPLES[key.kind])[0]
        doc.setdefault(section, {})[name] = value
    return doc


def test_one_walk_over_the_length_keys():
    """``map_lengths`` reaches every length key (arrays of tables, point lists, load rows) as
    the loader converts them, and nothing else; ``skip`` leaves sections and keys."""
    doc = _sample_document()
    doc["crease"].update(profile="funicular", segments=40)
    doc["plates"]["grain"] = 30.0
    doc["rulings"]["gamma"] = 80.0
    doc["layout"]["_note"] = 5.0
    doc["extra"] = {"span": 1.0}  # a table not in the schema
    before = copy.deepcopy(doc)
    out = map_lengths(doc, SCHEMA, lambda v: v * 1e-3)
    for section, name, key in length_keys():  # the loader's conversion, key by key
        value = coerce_value(section, name, key, doc[section][name], "mm")
        if key.kind == "patterns":
            assert out[section][name] == value
            continue
        assert np.allclose(out[section][name], value, rtol=0.0, atol=0.0), (section, name)
    assert out["crease"]["segments"] == 40 and out["crease"]["profile"] == "funicular"
    assert out["plates"]["grain"] == 30.0 and out["rulings"]["gamma"] == 80.0
    assert out["layout"]["_note"] == 5.0 and out["extra"] == {"span": 1.0}
    assert out["crease"]["point_loads"] == [[-0.25, 3.0], [0.4, 1.5]]  # intensities kept
    assert out["layout"]["patterns"][0]["id"] == 3 and out["layout"]["patterns"][0]["parent"] == 0
    assert doc == before  # the input is not changed
    kept = map_lengths(doc, SCHEMA, lambda v: -v, skip=("loads", "plates.thickness"))
    assert kept["loads"] == doc["loads"] and kept["plates"]["thickness"] == 80.0
    assert kept["plates"]["hinge_width"] == -80.0 and kept["crease"]["span"] == -80.0


def test_a_curve_file_reference_is_kept_by_the_walk():
    """A curve file has its own units: the walk keeps the reference (it failed on a str)."""
    doc = {"design": {"units": "mm"}, "crease": {"points": "c.csv", "span": 2000},
           "target": {"apex": {"file": "t.dxf", "layer": "APEX"}}}  # fmt: skip
    out = convert_document(doc, SCHEMA, to="m")
    assert out == {"design": {}, "crease": {"points": "c.csv", "span": 2.0},
                   "target": {"apex": {"file": "t.dxf", "layer": "APEX"}}}  # fmt: skip
