"""Compact TOML of design documents: one point per line, valid TOML that reads back equal."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.catalog import CATALOG_DIR
from compas_ccu.design import load_design
from compas_ccu.design.document import parse_toml, read_toml
from compas_ccu.design.inverse import write_design
from compas_ccu.design.writer import design_toml, toml_value
from compas_ccu.errors import DesignError
from compas_ccu.model import CCUModel, flat_design
from conftest import EXAMPLES


def test_a_short_point_list_is_one_line():
    text = design_toml({"crease": {"points": [[0.25, 1.2], [1.0, 1.0], [1.9, 0.0]]}})
    assert text == "[crease]\npoints = [[0.25, 1.2], [1.0, 1.0], [1.9, 0.0]]\n"


def test_a_long_point_list_is_one_point_per_line(tmp_path):
    pattern = flat_design(load_design(EXAMPLES / "cone.toml"))
    path = tmp_path / "pattern.toml"
    write_design(pattern, path)
    text = path.read_text()
    lines = text.splitlines()
    n = len(pattern.document["crease"]["points"])
    assert n == 49
    start = lines.index("points = [")
    rows = lines[start + 1 : start + 1 + n]
    assert all(r.startswith("    [") and r.endswith("],") and r.count(",") == 2 for r in rows)
    assert lines[start + 1 + n] == "]"
    numbers = [line.strip().rstrip(",").replace(".", "").lstrip("-") for line in lines]
    assert not any(number.isdigit() for number in numbers)  # no line holds a lone number
    assert len(lines) < 2 * 49 + 40  # tomli_w wrote 4 lines per point
    again = load_design(path)
    assert again.document == pattern.document
    assert np.array_equal(CCUModel(again).deploy().deployed, CCUModel(pattern).deploy().deployed)


@pytest.mark.parametrize("path", sorted(CATALOG_DIR.glob("*.toml")), ids=lambda p: p.stem)
def test_every_catalog_design_reads_back_equal(path):
    document = read_toml(path)
    assert parse_toml(design_toml(document)) == document


def test_scalars_tables_and_order():
    doc = {
        "plates": {"material": "myply", "thickness": 0.008},
        "materials": {"myply": {"base": "plywood", "E": 1e10}},
        "design": {"name": 'a "quoted" name', "units": "mm"},
        "layout": {"spacing": [0.1, 0.2], "quadrants": True, "leading": None},
    }
    text = design_toml(doc, header="line one\nline two")
    assert text.startswith("# line one\n# line two\n\n[design]\nname = ")
    assert "[materials]" not in text and '[materials.myply]\nbase = "plywood"' in text
    assert "spacing = [0.1, 0.2]\nquadrants = true\n" in text and "leading" not in text
    assert parse_toml(text) == {**doc, "layout": {"spacing": [0.1, 0.2], "quadrants": True}}


def test_a_non_finite_number_is_refused():
    with pytest.raises(DesignError, match=r"cannot write a non-finite number nan"):
        toml_value([[0.0, math.nan]])
