"""Sweep files: parameters, sampling (grid, list, random, LHS), variant ids, and their errors."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.errors import SweepError
from compas_ccu.explore import Sweep, load_sweep
from conftest import EXAMPLES


def sweep(parameters=None, **sections):
    doc = {"sweep": {"base": "vault.toml", **sections.pop("head", {})}}
    if parameters is not None:
        doc["parameters"] = parameters
    doc.update(sections)
    return Sweep(doc, base_dir=EXAMPLES)


def test_grid_is_the_cartesian_product_in_file_order():
    s = sweep({"crease.rise": [0.8, 1.0, 1.2], "layout.plates": [4, 6]})
    assert len(s.variants) == 6
    assert [v.params for v in s.variants[:3]] == [
        {"crease.rise": 0.8, "layout.plates": 4},
        {"crease.rise": 0.8, "layout.plates": 6},
        {"crease.rise": 1.0, "layout.plates": 4},
    ]
    assert [v.index for v in s.variants] == list(range(6))
    assert len({v.id for v in s.variants}) == 6


def test_range_grid_is_linspace_rounded_and_integer_keys_stay_integers():
    s = sweep(
        {
            "crease.rise": {"min": 0.6, "max": 1.4, "num": 5},
            "layout.plates": {"min": 4, "max": 10, "num": 4},
        }
    )
    rises = sorted({v.params["crease.rise"] for v in s.variants})
    assert rises == [0.6, 0.8, 1.0, 1.2, 1.4]  # not 0.7999999999999999
    plates = sorted({v.params["layout.plates"] for v in s.variants})
    assert plates == [4, 6, 8, 10] and all(isinstance(p, int) for p in plates)


def test_tables_dotted_keys_are_flattened():
    s = Sweep(
        {"sweep": {"base": "vault.toml"}, "parameters": {"crease": {"rise": [1.0, 1.1]}}},
        base_dir=EXAMPLES,
    )
    assert s.parameter_names == ["crease.rise"]


def test_document_for_applies_sections_then_keys_and_names_the_variant():
    layouts = [
        {"label": "wide", "type": "parallel", "plates": 4, "spacing": 0.2},
        {"type": "parallel", "plates": 6, "spacing": 0.1},
    ]
    s = sweep({"layout": layouts, "layout.plates": [5]})
    assert [v.params["layout"] for v in s.variants] == [
        "wide",
        "type=parallel, plates=6, spacing=0.1",
    ]
    doc = s.document_for(s.variants[0])
    assert doc["layout"] == {"type": "parallel", "plates": 5, "spacing": 0.2}  # key on top
    assert doc["design"]["name"] == f"vault-{s.variants[0].id}"
    assert s.base_document["layout"]["plates"] == 10  # the base is not modified


def test_list_sampling_takes_the_variants_tables():
    s = sweep(
        head={"sampling": "list"},
        variants=[{"crease.rise": 0.9}, {"crease.rise": 1.1, "layout.plates": 4}],
    )
    assert s.parameter_names == ["crease.rise", "layout.plates"]
    assert [v.params for v in s.variants] == [
        {"crease.rise": 0.9},
        {"crease.rise": 1.1, "layout.plates": 4},
    ]


@pytest.mark.parametrize("sampling", ["random", "lhs"])
def test_random_and_lhs_are_reproducible_and_inside_the_ranges(sampling):
    params = {
        "crease.rise": {"min": 0.5, "max": 1.5},
        "layout.plates": {"min": 3, "max": 9},
        "crease.profile": ["arc", "catenary"],
    }
    a = sweep(params, head={"sampling": sampling, "samples": 40, "seed": 3})
    b = sweep(params, head={"sampling": sampling, "samples": 40, "seed": 3})
    c = sweep(params, head={"sampling": sampling, "samples": 40, "seed": 4})
    assert [v.id for v in a.variants] == [v.id for v in b.variants]
    assert [v.id for v in a.variants] != [v.id for v in c.variants]
    rise = np.array([v.params["crease.rise"] for v in a.variants])
    plates = np.array([v.params["layout.plates"] for v in a.variants])
    assert rise.min() >= 0.5 and rise.max() <= 1.5
    assert set(plates) <= set(range(3, 10)) and plates.dtype.kind == "i"
    assert {v.params["crease.profile"] for v in a.variants} == {"arc", "catenary"}


def test_lhs_puts_one_sample_in_every_stratum():
    s = sweep(
        {"crease.rise": {"min": 0.0 + 1.0, "max": 2.0}},
        head={"sampling": "lhs", "samples": 20, "seed": 0},
    )
    rise = np.array([v.params["crease.rise"] for v in s.variants])
    strata = np.floor((rise - 1.0) * 20).astype(int)
    assert sorted(strata.tolist()) == list(range(20))


def test_repeated_random_choices_are_computed_once():
    s = sweep({"layout.plates": [4, 6]}, head={"sampling": "random", "samples": 30, "seed": 1})
    assert len(s.variants) == 2 and s.duplicates == 28


def test_ids_depend_on_the_values_only_so_a_grown_sweep_keeps_its_variants():
    small = sweep({"crease.rise": [0.8, 1.0]})
    grown = sweep({"crease.rise": [0.8, 0.9, 1.0]})
    assert {v.id for v in small.variants} <= {v.id for v in grown.variants}
    assert small.fingerprint == grown.fingerprint
    other = sweep({"crease.rise": [0.8, 1.0]}, checks={"collisions": True})
    assert other.fingerprint != small.fingerprint


def test_the_example_sweep_has_at_least_200_variants():
    s = load_sweep(EXAMPLES / "sweeps" / "vault.toml")
    assert len(s.variants) == 270 and s.collisions and s.path_states == 11
    assert s.objectives == {"rise": "max", "bending_utilisation": "min", "stack_height": "min"}
    assert s.constraints == {"bending_utilisation": {"max": 1.0}, "collision_free": True}


@pytest.mark.parametrize(
    "make, match",
    [
        (
            lambda: sweep({"crease.height": [1.0]}),
            r"parameters.crease.height: unknown design key; allowed in \[crease\]",
        ),
        (
            lambda: sweep({"roof.rise": [1.0]}),
            r"parameters.roof.rise: unknown design section 'roof'",
        ),
        (lambda: sweep({}), r"\[parameters\]: needs at least one parameter"),
        (lambda: sweep({"crease.rise": []}), r"needs at least one value"),
        (lambda: sweep({"crease.rise": [1.0, "high"]}), r"values must all be of one type"),
        (
            lambda: sweep({"crease.rise": {"min": 1.0}}),
            r"a range is \{min = ..., max = ..., num = ...\}",
        ),
        (
            lambda: sweep({"crease.rise": {"min": 2.0, "max": 1.0, "num": 3}}),
            r"max 1.0 is below min 2.0",
        ),
        (
            lambda: sweep({"crease.rise": {"min": 1.0, "max": 2.0}}),
            r"a range needs num \(grid points\) for grid sampling",
        ),
        (
            lambda: sweep({"crease.profile": {"min": 1, "max": 2, "num": 2}}),
            r"a range needs a numeric design key",
        ),
        (
            lambda: sweep({"layout.plates": {"min": 4.5, "max": 8, "num": 2}}),
            r"an integer key needs integer min and max",
        ),
        (lambda: sweep({"layout": [1, 2]}), r"a section parameter takes a list of tables"),
        (lambda: sweep({"layout": [{"label": "a"}, {"label": "a"}]}), r"labels must be different"),
        (
            lambda: sweep({"crease.rise": [1.0]}, head={"sampling": "sobol"}),
            r"sweep.sampling: must be one of grid, list, random, lhs, got 'sobol'",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, head={"sampling": "lhs"}),
            r"sweep.samples: sampling 'lhs' needs samples",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, head={"samples": 0}),
            r"sweep.samples: must be an integer >= 1, got 0",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, head={"colour": "red"}),
            r"sweep.colour: unknown key",
        ),
        (lambda: sweep({"crease.rise": [1.0]}, extra={}), r"extra: unknown section"),
        (
            lambda: sweep({"crease.rise": [1.0]}, checks={"collisions": "yes"}),
            r"checks.collisions: must be true or false",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, checks={"path_states": 1}),
            r"checks.path_states: must be an integer >= 2",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, objectives={"beauty": "max"}),
            r"objectives.beauty: unknown metric; available: plates",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, objectives={"rise": "most"}),
            r"objectives.rise: must be 'min' or 'max'",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, objectives={"collision_free": "max"}),
            r"objectives.collision_free: a metric of the collision check: measured only with "
            r"\[checks\] collisions = true",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, constraints={"fe_buckling_factor": {"min": 3}}),
            r"constraints.fe_buckling_factor: an FE metric: measured only with an \[fe\] section",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, objectives={"material": "min"}),
            r"objectives.material: an objective must be a number; material is str",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, constraints={"rise": {"above": 1}}),
            r"constraints.rise: must be true / false or a table",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, fe={"engine": "abaqus"}),
            r"fe.engine: engine must be 'kratos' or 'opensees'",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, fe={"steps": 0}),
            r"\[fe\]: steps must be an integer >= 1",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, fe={"thickness": 0.01}),
            r"fe.thickness: unknown key",
        ),
        (
            lambda: sweep({"crease.rise": [1.0]}, variants=[{}]),
            r"variants: \[\[variants\]\] needs sampling = 'list'",
        ),
        (lambda: sweep(head={"sampling": "list"}), r"sampling 'list' needs \[\[variants\]\]"),
        (
            lambda: sweep(head={"sampling": "list"}, variants=[{"layout": "single"}]),
            r"variants\[0\].layout: list variants set design keys",
        ),
        (
            lambda: Sweep({"sweep": {}, "parameters": {"crease.rise": [1.0]}}, base_dir=EXAMPLES),
            r"sweep.base: missing",
        ),
        (
            lambda: Sweep({"sweep": {"base": "nope.toml"}}, base_dir=EXAMPLES),
            r"sweep.base: base design: cannot read design file",
        ),
    ],
)
def test_bad_sweeps_are_refused_with_the_key_and_the_value(make, match):
    with pytest.raises(SweepError, match=match):
        make()


def test_an_invalid_base_design_is_refused(tmp_path):
    (tmp_path / "bad.toml").write_text('[crease]\nprofile = "blob"\n')
    (tmp_path / "s.toml").write_text(
        '[sweep]\nbase = "bad.toml"\n[parameters]\n"crease.rise" = [1.0]\n'
    )
    with pytest.raises(SweepError, match=r"s.toml: sweep.base: base design: .*crease.profile"):
        load_sweep(tmp_path / "s.toml")


def test_load_sweep_names_missing_files_and_bad_toml(tmp_path):
    with pytest.raises(SweepError, match="cannot read sweep file"):
        load_sweep(tmp_path / "missing.toml")
    (tmp_path / "s.toml").write_text("[sweep\n")
    with pytest.raises(SweepError, match="not valid TOML"):
        load_sweep(tmp_path / "s.toml")
