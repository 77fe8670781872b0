"""Optimisation studies (``ccu optimize``): study files and their errors, feasibility and
violations, a small study in-process, resuming, no feasible design, FE only after the cheap
checks, interruption, and a study on a local Dask cluster (slow)."""

from __future__ import annotations

import json
import math
import signal

import numpy as np
import pytest

from compas_ccu.design import load_design
from compas_ccu.errors import SweepError
from compas_ccu.explore import optimize as opt
from compas_ccu.explore import runner
from compas_ccu.explore.evaluate import evaluate_variant
from compas_ccu.explore.optimize import assess, run_study
from compas_ccu.explore.results import Journal, read_table
from compas_ccu.explore.study import Study, load_study
from compas_ccu.model import CCUModel
from conftest import EXAMPLES

optuna = pytest.importorskip("optuna")
pytest.importorskip("pyarrow")

# the kinematic problem of the tests: the lightest 4-plate vault (16 segments) with a rise of at
# least 0.9 m covering a width of 0.3 m (plan_y: 4 x spacing) whose plates do not break and do
# not collide. The optimum is inside the ranges of rise and spacing (0.9 m, 0.075 m), not on a
# grid point.
STUDY = """
[study]
name = "small"
base = "base.toml"
trials = 40
seed = 2

[parameters]
"plates.thickness" = {min = 0.004, max = 0.012}
"crease.rise" = {min = 0.6, max = 1.4}
"layout.spacing" = {min = 0.04, max = 0.1}
"plates.material" = ["plywood", "birch-plywood", "poplar-plywood"]

[checks]
path_states = 5
collisions = true

[objectives]
mass = "min"

[constraints]
bending_utilisation = {max = 1.0}
collision_free = true
rise = {min = 0.9}
plan_y = {min = 0.3}
"""


def write_base(folder, *, segments=16, plates=4, spacing=0.05):
    text = (EXAMPLES / "vault.toml").read_text()
    text = text.replace("spacing = 0.12", f"spacing = {spacing}")
    text = text.replace("segments = 64", f"segments = {segments}")
    text = text.replace("plates = 10", f"plates = {plates}")
    (folder / "base.toml").write_text(text)


def write_study(folder, text=STUDY, replace=None):
    """The study file ``text`` (with the ``replace`` old -> new texts) and its base design."""
    write_base(folder)
    for old, new in (replace or {}).items():
        assert old in text
        text = text.replace(old, new)
    (folder / "study.toml").write_text(text)
    return load_study(folder / "study.toml")


def study_of(parameters=None, **sections):
    doc = {"study": {"base": "vault.toml", **sections.pop("head", {})}}
    doc["parameters"] = (
        {"crease.rise": {"min": 0.6, "max": 1.4}} if parameters is None else (parameters)
    )
    doc.setdefault("objectives", {"mass": "min"})
    doc.update(sections)
    if doc["objectives"] is None:
        del doc["objectives"]
    return Study(doc, base_dir=EXAMPLES)


# -- study files ------------------------------------------------------------------------------
def test_a_study_file_is_parsed_into_a_search_space():
    s = study_of(
        {
            "plates.thickness": {"min": 0.004, "max": 0.02},
            "layout.plates": {"min": 4, "max": 12, "step": 2},
            "crease.rise": {"min": 0.6, "max": 1.4, "step": 0.2},
            "layout.spacing": {"min": 0.05, "max": 0.2, "log": True},
            "crease.segments": {"min": 16, "max": 64},
            "plates.material": ["plywood", "birch-plywood"],
        },
        head={"trials": 30, "seed": 4},
    )
    d = s.distributions()
    assert type(d["plates.thickness"]).__name__ == "FloatDistribution"
    assert (d["layout.plates"].low, d["layout.plates"].high, d["layout.plates"].step) == (4, 12, 2)
    assert d["crease.rise"].step == 0.2 and d["layout.spacing"].log
    assert type(d["crease.segments"]).__name__ == "IntDistribution"  # an integer key
    assert d["plates.material"].choices == ("plywood", "birch-plywood")
    assert (s.trials, s.seed, s.sampler_name, s.best) == (30, 4, "tpe", 5)
    assert s.constraints == {"bending_utilisation": {"max": 1.0}}  # the default
    settings = s.settings_of(
        {
            "plates.thickness": 0.0123456789123,
            "layout.plates": 6,
            "crease.rise": 0.6000000000000001,
            "layout.spacing": 0.1,
            "crease.segments": 20,
            "plates.material": "birch-plywood",
        }
    )
    assert settings["plates.thickness"] == 0.0123457 and settings["crease.rise"] == 0.6
    doc = s.document_for(s.variant(settings))
    assert doc["plates"]["material"] == "birch-plywood" and doc["layout"]["plates"] == 6
    assert doc["crease"]["segments"] == 20


def test_several_objectives_choose_nsga2_and_section_tables_are_choices():
    layouts = [
        {"label": "parallel", "type": "parallel", "plates": 4, "spacing": 0.1},
        {"label": "wide", "type": "parallel", "plates": 4, "spacing": 0.2},
    ]
    s = study_of({"layout": layouts}, objectives={"mass": "min", "rise": "max"})
    assert s.sampler_name == "nsga2"
    assert s.distributions()["layout"].choices == ("parallel", "wide")
    v = s.variant(s.settings_of({"layout": "wide"}))
    assert v.params == {"layout": "wide"} and s.document_for(v)["layout"]["spacing"] == 0.2


def test_the_fingerprint_is_the_study_but_not_its_name_budget_or_picks():
    a = study_of(head={"trials": 10})
    assert a.fingerprint == study_of(head={"trials": 99, "name": "x", "best": 2}).fingerprint
    assert a.fingerprint != study_of(head={"seed": 1}).fingerprint
    assert a.fingerprint != study_of(objectives={"mass": "max"}).fingerprint
    assert a.fingerprint != study_of(constraints={"rise": {"min": 1.0}}).fingerprint
    assert a.fingerprint != study_of({"crease.rise": {"min": 0.6, "max": 1.5}}).fingerprint
    assert a.fingerprint != study_of(head={"sampler": "random"}).fingerprint


def test_the_fe_stage_runs_only_after_the_cheap_constraints():
    s = study_of(
        fe={"element_size": 0.25, "area_load": 1884.0},
        checks={"collisions": True},
        constraints={
            "bending_utilisation": {"max": 1.0},
            "collision_free": True,
            "fe_buckling_factor": {"min": 3.0},
        },
    )
    assert s.cheap_constraints == {"bending_utilisation": {"max": 1.0}, "collision_free": True}
    assert s.fe_constraints == {"fe_buckling_factor": {"min": 3.0}}
    assert s.options["fe_when"] == s.cheap_constraints
    assert s.options["fe"]["area_load"] == 1884.0 and s.options["fe"]["steps"] == 4
    assert "fe_when" not in study_of().options


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: study_of(extra={}), r"extra: unknown section; allowed: study, parameters"),
        (lambda: study_of(head={"colour": 1}), r"study.colour: unknown key; allowed in \[study\]"),
        (
            lambda: study_of(head={"sampler": "cmaes"}),
            r"study.sampler: must be one of auto, tpe, nsga2, nsga3, random, got 'cmaes'",
        ),
        (lambda: study_of(head={"trials": 0}), r"study.trials: must be an integer >= 1, got 0"),
        (lambda: study_of(head={"population": 1}), r"study.population: must be an integer >= 2"),
        (lambda: study_of({}), r"\[parameters\]: needs at least one parameter to search"),
        (
            lambda: study_of({"crease.rise": {"min": 1.4, "max": 0.6}}),
            r"parameters.crease.rise: max 0.6 is below min 1.4",
        ),
        (
            lambda: study_of({"crease.rise": {"min": 0.6, "max": 1.4, "num": 5}}),
            r"parameters.crease.rise: num sets grid points of a sweep",
        ),
        (
            lambda: study_of({"crease.rise": {"min": 0.6}}),
            r"parameters.crease.rise: a range is \{min = ..., max = ..., step = ..., log = ..., "
            r"integer = ...\}",
        ),
        (
            lambda: study_of({"crease.rise": {"min": 0.6, "max": 1.4, "step": 0.3}}),
            r"parameters.crease.rise: step 0.3 does not divide the range 0.6 .. 1.4",
        ),
        (
            lambda: study_of({"crease.rise": {"min": 0.6, "max": 1.4, "step": -0.1}}),
            r"parameters.crease.rise.step: step must be a number > 0, got -0.1",
        ),
        (
            lambda: study_of({"crease.rise": {"min": 0.0, "max": 1.4, "log": True}}),
            r"parameters.crease.rise: a log-scale range needs min > 0, got 0.0",
        ),
        (
            lambda: study_of({"crease.rise": {"min": 0.5, "max": 1.5, "log": True, "step": 0.5}}),
            r"parameters.crease.rise: a range takes a step or a log scale, not both",
        ),
        (
            lambda: study_of({"crease.rise": {"min": 0.5, "max": 1.5, "log": "yes"}}),
            r"parameters.crease.rise.log: log must be true or false, got 'yes'",
        ),
        (
            lambda: study_of({"layout.plates": {"min": 4, "max": 8, "integer": False}}),
            r"parameters.layout.plates: layout.plates is an integer key: integer = false",
        ),
        (
            lambda: study_of({"crease.rise": {"min": 0.5, "max": 2, "integer": True}}),
            r"parameters.crease.rise: integer = true needs integer min and max",
        ),
        (
            lambda: study_of({"layout.plates": {"min": 4, "max": 8, "step": 1.5}}),
            r"parameters.layout.plates: an integer range needs an integer step, got 1.5",
        ),
        (
            lambda: study_of({"crease.profile": {"min": 1, "max": 2}}),
            r"parameters.crease.profile: a range needs a numeric design key, not str",
        ),
        (
            lambda: study_of({"plates.material": ["plywood", "plywood"]}),
            r"parameters.plates.material: values must be different",
        ),
        (
            lambda: study_of({"crease.height": [1.0]}),
            r"parameters.crease.height: unknown design key; allowed in \[crease\]",
        ),
        (
            lambda: study_of({"crease.rise": "high"}),
            r"parameters.crease.rise: must be a list of values or a range \{min, max, step\}",
        ),
        (lambda: study_of(objectives=None), r"\[objectives\]: missing: what to optimise"),
        (lambda: study_of(objectives={}), r"\[objectives\]: needs at least one metric"),
        (
            lambda: study_of(objectives={"beauty": "max"}),
            r"objectives.beauty: unknown metric; available: plates, creases",
        ),
        (
            lambda: study_of(objectives={"mass": "least"}),
            r"objectives.mass: must be 'min' or 'max', got 'least'",
        ),
        (
            lambda: study_of(objectives={"fe_deflection_ratio": "min"}),
            r"objectives.fe_deflection_ratio: an FE metric: measured only with an \[fe\] section",
        ),
        (
            lambda: study_of(constraints={"fe_buckling_factor": {"min": 3}}),
            r"constraints.fe_buckling_factor: an FE metric: measured only with an \[fe\]",
        ),
        (
            lambda: study_of(constraints={"collision_free": True}),
            r"constraints.collision_free: a metric of the collision check: measured only with "
            r"\[checks\] collisions = true",
        ),
        (
            lambda: study_of(constraints={"mass": {"below": 3}}),
            r"constraints.mass: must be true / false or a table \{min = ..., max = ...\}",
        ),
        (
            lambda: study_of(objectives={"bending_basis": "min"}),
            r"objectives.bending_basis: an objective must be a number; bending_basis is str",
        ),
        (lambda: study_of(fe={"meshing": 1}), r"fe.meshing: unknown key; allowed in \[fe\]"),
        (lambda: study_of(fe={"steps": 0}), r"\[fe\]: steps must be an integer >= 1"),
        (
            lambda: Study({"study": {}, "parameters": {"crease.rise": [1.0]}}, base_dir=EXAMPLES),
            r"study.base: missing: the base design file",
        ),
        (
            lambda: study_of(head={"base": "nope.toml"}),
            r"study.base: base design: cannot read design file",
        ),
    ],
)
def test_bad_studies_are_refused_with_the_key_and_the_value(make, match):
    with pytest.raises(SweepError, match=match):
        make()


def test_load_study_names_the_file_and_takes_a_seed(tmp_path):
    with pytest.raises(SweepError, match="cannot read study file"):
        load_study(tmp_path / "missing.toml")
    study = write_study(tmp_path)
    assert study.seed == 2 and load_study(tmp_path / "study.toml", seed=7).seed == 7
    (tmp_path / "bad.toml").write_text(STUDY.replace('mass = "min"', 'mass = "less"'))
    with pytest.raises(SweepError, match=r"bad.toml: objectives.mass: must be 'min' or 'max'"):
        load_study(tmp_path / "bad.toml")


def test_the_example_studies_are_valid():
    concrete = load_study(EXAMPLES / "optimize" / "vault-concrete.toml")
    assert concrete.objectives == {"mass": "min"}
    assert concrete.fe["load_cases"] == ["wet-concrete"]  # the base vault's [loads]
    assert concrete.fe_constraints == {
        "fe_utilisation": {"max": 1.0},
        "fe_deflection_ratio": {"max": 1.0},
        "fe_buckling_factor": {"min": 3.0},
    }
    assert set(concrete.cheap_constraints) >= {"bending_utilisation", "collision_free"}
    area = load_study(EXAMPLES / "optimize" / "vault-sheets.toml")
    assert area.fe is None and area.objectives == {"plan_area": "max"}


# -- feasibility ------------------------------------------------------------------------------
def test_assess_tells_feasibility_violations_and_the_samplers_values():
    s = study_of(
        fe={},
        checks={"collisions": True},
        objectives={"mass": "min", "fe_buckling_factor": "max"},
        constraints={
            "bending_utilisation": {"max": 1.0},
            "collision_free": True,
            "fe_buckling_factor": {"min": 4.0},
        },
    )
    good = {
        "status": "ok",
        "mass": 20.0,
        "bending_utilisation": 0.5,
        "collision_free": True,
        "fe_buckling_factor": 5.0,
        "t_fe": 3.0,
    }
    a = assess(good, s)
    assert (a.feasible, a.violation, a.details, a.gated, a.values) == (
        True,
        0.0,
        (),
        False,
        (20, 5),
    )
    assert a.constraints["bending_utilisation"] == -0.5 and a.constraints["evaluation"] == 0.0
    weak = assess({**good, "fe_buckling_factor": 3.0}, s)
    assert not weak.feasible and weak.violation == pytest.approx(0.25)
    assert weak.details == ("fe_buckling_factor 3 < min 4",)
    # a cheap check failed: no FE, the FE constraints count 0, objectives stand in as +-inf
    gated = assess({**good, "collision_free": False, "fe_buckling_factor": None, "t_fe": None}, s)
    assert gated.gated and not gated.feasible and gated.violation == 1.0
    assert gated.details == (
        "collision_free is False (required True)",
        "no FE: a cheap check failed",
    )
    assert gated.values == (20.0, -math.inf) and gated.constraints["fe_buckling_factor"] == 0.0
    # measured nothing (FE ran, but no buckling factor): infeasible by the unmeasured violations
    missing = assess({**good, "fe_buckling_factor": None}, s)
    assert missing.violation == 2 * opt.UNMEASURED_VIOLATION
    assert missing.details == (
        "fe_buckling_factor not measured",
        "objective fe_buckling_factor not measured",
    )
    failed = assess({"status": "failed", "stage": "model", "error_type": "DesignError",
                     "error": "crease.rise: must be > 0"}, s)  # fmt: skip
    assert failed.violation == opt.FAILED_VIOLATION and failed.values == (math.inf, -math.inf)
    assert failed.details == ("failed at stage model: DesignError: crease.rise: must be > 0",)
    assert set(failed.constraints) == set(a.constraints)  # the same keys for every trial


# -- runs -------------------------------------------------------------------------------------
@pytest.mark.slow  # a whole study (2-5 s)
def test_a_small_study_finds_a_feasible_design_better_than_the_grid(tmp_path):
    """40 trials of TPE (seed 2) beat the best of a 3 x 3 x 3 x 3 grid (81 designs, ccu explore
    with num = 3 for every range) of the same problem: 4.6251 kg (4 mm poplar plywood, rise
    1.0 m, spacing 0.1 m; the grid has no spacing between 0.07 m, too narrow, and 0.1 m)."""
    study = write_study(tmp_path)
    r = run_study(study, tmp_path / "out", in_process=True, progress=False)
    assert (r.computed, r.earlier, r.interrupted) == (40, 0, False)
    s = r.summary
    best = s["best"][0]
    assert best["objectives"]["mass"] < 4.6251
    row = next(x for x in r.rows if x["trial"] == best["trial"])
    assert row["feasible"] and row["bending_utilisation"] <= 1 and row["collision_free"]
    assert row["rise"] >= 0.9 and row["plan_y"] >= 0.3 and row["layout.spacing"] < 0.1
    assert s["convergence"][-1] == best["objectives"]["mass"]
    assert s["trials"] == 40 and s["feasible"] == sum(x["feasible"] for x in r.rows)
    # the best design's file reproduces its numbers
    folder = tmp_path / "out" / "best" / f"1-{best['variant']}"
    design = load_design(folder / "design.toml")
    assert design.plates.thickness == best["parameters"]["plates.thickness"]
    again = evaluate_variant(design.document, path_states=5, collisions=True)
    assert again["mass"] == pytest.approx(best["objectives"]["mass"], rel=1e-12)
    assert (folder / "structure.json").exists() and CCUModel(design).plates.count == 4
    # the table: one row per trial, the parameters and the study's columns first
    import pyarrow.parquet as pq

    schema = pq.read_schema(tmp_path / "out" / "results.parquet")
    assert schema.names[:6] == [
        "trial",
        "variant",
        "plates.thickness",
        "crease.rise",
        "layout.spacing",
        "plates.material",
    ]
    assert str(schema.field("feasible").type) == "bool" and "fe_buckling_factor" not in schema.names
    table = read_table(tmp_path / "out" / "results.parquet")
    assert [t["trial"] for t in table] == list(range(40))
    assert json.loads(schema.metadata[b"ccu.sweep"])["fingerprint"] == study.fingerprint
    assert (tmp_path / "out" / "plots" / "convergence.png").stat().st_size > 10_000


@pytest.mark.slow  # a whole study (2-5 s)
def test_the_same_seed_gives_the_same_study(tmp_path):
    study = write_study(tmp_path, replace={"trials = 40": "trials = 8"})
    a = run_study(study, tmp_path / "a", in_process=True, progress=False, summary=False)
    b = run_study(study, tmp_path / "b", in_process=True, progress=False, summary=False)
    assert [r["variant"] for r in a.rows] == [r["variant"] for r in b.rows]
    assert [r["mass"] for r in a.rows] == [r["mass"] for r in b.rows]


@pytest.mark.slow  # a whole study (2-5 s)
def test_a_study_resumes_and_evaluates_only_the_new_trials(tmp_path):
    study = write_study(tmp_path)
    out = tmp_path / "out"
    first = run_study(study, out, trials=6, in_process=True, progress=False, summary=False)
    assert (first.computed, first.earlier) == (6, 0)
    again = run_study(study, out, trials=10, in_process=True, progress=False)
    assert (again.computed, again.evaluations, again.earlier) == (4, 4, 6)
    assert [r["run"] for r in again.rows] == [1] * 6 + [2] * 4
    assert [r["trial"] for r in again.rows] == list(range(10))
    assert len(Journal(out / "journal.jsonl", key="trial").read()) == 10
    # the sampler's history holds all ten, and the second run did not replay the first
    stored = optuna.load_study(
        study_name=f"ccu-{study.fingerprint}",
        storage=optuna.storages.JournalStorage(
            optuna.storages.journal.JournalFileBackend(str(out / "optuna.journal"))
        ),
    )
    assert len(stored.trials) == 10 and all(t.state.name == "COMPLETE" for t in stored.trials)
    assert len({r["variant"] for r in again.rows}) == 10
    nothing = run_study(study, out, trials=10, in_process=True, progress=False)
    assert (nothing.computed, nothing.seconds) == (0, 0.0) and nothing.summary["trials"] == 10
    fewer = run_study(study, out, trials=3, in_process=True, progress=False)
    assert fewer.computed == 0 and len(fewer.rows) == 10  # a smaller budget deletes nothing


def test_a_trial_left_running_by_a_killed_run_is_failed_and_not_counted(tmp_path):
    study = write_study(tmp_path)
    out = tmp_path / "out"
    run_study(study, out, trials=3, in_process=True, progress=False, summary=False)
    storage = optuna.storages.JournalStorage(
        optuna.storages.journal.JournalFileBackend(str(out / "optuna.journal"))
    )
    stored = optuna.load_study(study_name=f"ccu-{study.fingerprint}", storage=storage)
    stored.ask(study.distributions())  # asked, then the process died
    r = run_study(study, out, trials=5, in_process=True, progress=False, summary=False)
    assert r.computed == 2 and [x["trial"] for x in r.rows] == [0, 1, 2, 4, 5]
    states = [t.state.name for t in optuna.load_study(
        study_name=f"ccu-{study.fingerprint}", storage=storage).trials]  # fmt: skip
    assert states == ["COMPLETE"] * 3 + ["FAIL"] + ["COMPLETE"] * 2


def test_a_journalled_trial_the_sampler_never_heard_of_is_told_again(tmp_path):
    study = write_study(tmp_path)
    out = tmp_path / "out"
    run_study(study, out, trials=4, in_process=True, progress=False, summary=False)
    (out / "optuna.journal").unlink()  # the sampler's history is lost, the journal is not
    r = run_study(study, out, trials=6, in_process=True, progress=False, summary=False)
    assert (r.earlier, r.computed) == (4, 2)
    storage = optuna.storages.JournalStorage(
        optuna.storages.journal.JournalFileBackend(str(out / "optuna.journal"))
    )
    stored = optuna.load_study(study_name=f"ccu-{study.fingerprint}", storage=storage)
    assert len(stored.trials) == 6
    feasible = [t for t in stored.trials[:4] if all(v <= 0 for v in t.constraints.values())]
    assert len(feasible) == sum(x["feasible"] for x in r.rows[:4])
    # the trial told again is not told a third time
    stored.ask(study.distributions())  # and one left running
    again = run_study(study, out, trials=6, in_process=True, progress=False, summary=False)
    assert again.computed == 0
    stored = optuna.load_study(study_name=f"ccu-{study.fingerprint}", storage=storage)
    assert [t.state.name for t in stored.trials] == ["COMPLETE"] * 6 + ["FAIL"]


def test_a_folder_of_another_study_is_refused_naming_both_fingerprints(tmp_path):
    study = write_study(tmp_path)
    run_study(study, tmp_path / "out", trials=2, in_process=True, progress=False, summary=False)
    other = load_study(tmp_path / "study.toml", seed=9)
    with pytest.raises(SweepError) as info:
        run_study(other, tmp_path / "out", in_process=True, progress=False)
    text = str(info.value)
    assert "holds results of a different study" in text
    assert study.fingerprint in text and other.fingerprint in text


@pytest.mark.slow  # a whole study (2-5 s)
def test_no_feasible_design_lists_the_least_violating(tmp_path):
    study = write_study(tmp_path, replace={"rise = {min = 0.9}": "rise = {min = 2.0}"})
    r = run_study(study, tmp_path / "out", trials=8, in_process=True, progress=False)
    s = r.summary
    assert s["feasible"] == 0 and s["best"] == [] and s["convergence"] == [None] * 8
    least = s["least_violating"]
    assert len(least) == 5
    assert [e["violation"] for e in least] == sorted(e["violation"] for e in least)
    assert least[0]["violation"] == min(x["violation"] for x in r.rows)
    for e in least:
        assert "rise " in e["violations"] and "< min 2" in e["violations"]
        row = next(x for x in r.rows if x["trial"] == e["trial"])
        assert e["violation"] >= (2.0 - row["rise"]) / 2.0 - 1e-12
    assert not (tmp_path / "out" / "best").exists()
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["least_violating"][0]["trial"] == least[0]["trial"]


def test_a_design_proposed_again_is_not_evaluated_again(tmp_path):
    text = STUDY.replace(
        '"plates.thickness" = {min = 0.004, max = 0.012}\n"crease.rise" = {min = 0.6, max = 1.4}\n'
        '"layout.spacing" = {min = 0.04, max = 0.1}\n',
        "",
    )
    study = write_study(tmp_path, text)
    assert study.parameter_names == ["plates.material"]
    r = run_study(study, tmp_path / "out", trials=7, in_process=True, progress=False, plots=False)
    assert (r.computed, r.evaluations) == (7, 3)  # three materials
    reused = [x for x in r.rows if x["reused"]]
    assert len(reused) == 4
    for x in reused:
        first = next(y for y in r.rows if y["variant"] == x["variant"] and not y["reused"])
        assert x["mass"] == first["mass"] and x["trial"] > first["trial"]
    assert r.summary["evaluations"] == 3 and len(r.summary["best"]) <= 3


def test_the_cheap_checks_gate_the_fe(tmp_path):
    """A design that misses a cheap constraint gets no FE: t_fe and the FE metrics are empty
    (here every design: the bending check fails for plates of 3 to 4 cm), and it is infeasible
    with its violations; no FE engine runs at all."""
    text = STUDY.replace(
        '"plates.thickness" = {min = 0.004, max = 0.012}',
        '"plates.thickness" = {min = 0.03, max = 0.04}',
    ).replace("[objectives]", "[fe]\nelement_size = 0.25\narea_load = 1884.0\n\n[objectives]")
    text = text.replace("[constraints]", "[constraints]\nfe_buckling_factor = {min = 3.0}")
    study = write_study(tmp_path, text)
    assert study.options["fe_when"] == study.cheap_constraints
    r = run_study(study, tmp_path / "out", trials=4, in_process=True, progress=False, plots=False)
    assert r.gated == 4 and r.summary["fe_gated"] == 4
    for row in r.rows:
        assert row["status"] == "ok" and row["t_fe"] is None and row["fe_buckling_factor"] is None
        assert row["fe_gated"] and not row["feasible"]
        assert row["bending_utilisation"] > 1.0
        assert "bending_utilisation" in row["violations"] and "no FE" in row["violations"]
        expected = row["bending_utilisation"] - 1.0
        expected += max(0.0, (0.9 - row["rise"]) / 0.9) + max(0.0, (0.3 - row["plan_y"]) / 0.3)
        assert row["violation"] == pytest.approx(expected, rel=1e-9)


@pytest.mark.slow  # a whole study (2-5 s)
def test_several_objectives_give_a_pareto_front(tmp_path):
    study = write_study(
        tmp_path,
        replace={
            'mass = "min"': 'mass = "min"\nrise = "max"',
            "seed = 2": "population = 8\nbest = 3",
        },
    )
    assert study.sampler_name == "nsga2"
    r = run_study(study, tmp_path / "out", trials=24, in_process=True, progress=False)
    s = r.summary
    assert s["feasible"] >= 2 and 1 <= len(s["pareto"]) <= s["feasible"]
    front = [x for x in r.rows if x["trial"] in s["pareto"]]
    good = [x for x in r.rows if x["feasible"]]
    for f in front:  # no feasible design is lighter and higher
        assert not any(g["mass"] < f["mass"] and g["rise"] > f["rise"] for g in good)
    assert {b["trial"] for b in s["best"]} <= set(s["pareto"]) and len(s["best"]) <= 3
    assert (tmp_path / "out" / "plots" / "pareto.png").exists()


@pytest.mark.slow  # a whole study (2-5 s)
def test_ctrl_c_stops_between_trials_and_keeps_what_is_done(tmp_path, monkeypatch):
    study = write_study(tmp_path)
    calls = []

    def evaluate(document, **options):
        calls.append(1)
        if len(calls) == 3:
            signal.raise_signal(signal.SIGINT)  # Ctrl-C while the third design is evaluated
        return evaluate_variant(document, **options)

    monkeypatch.setattr(runner, "evaluate_variant", evaluate)  # the shared runner evaluates
    r = run_study(study, tmp_path / "out", trials=10, in_process=True, progress=False)
    assert (
        r.interrupted
        and r.computed == 3
        and len(read_table(tmp_path / "out" / "results.parquet")) == 3
    )
    monkeypatch.undo()
    again = run_study(study, tmp_path / "out", trials=10, in_process=True, progress=False)
    assert (again.earlier, again.computed, again.interrupted) == (3, 7, False)


def test_bad_options_are_refused_before_anything_is_written(tmp_path):
    study = write_study(tmp_path)
    for kwargs, match in (
        ({"workers": 0}, "--workers must be >= 1"),
        ({"workers": 2, "scheduler": "tcp://x:1"}, "--workers sizes the local cluster"),
        ({"in_process": True, "workers": 2}, "in-process runs without Dask"),
        ({"trials": 0}, "--trials must be an integer >= 1"),
    ):
        with pytest.raises(SweepError, match=match):
            run_study(study, tmp_path / "out", progress=False, **kwargs)
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_a_study_with_fe_on_a_local_dask_cluster(tmp_path):
    """Two workers, two trials in flight; the FE runs for the designs that pass the cheap
    checks and for no other; every row is the in-process evaluation of its design."""
    pytest.importorskip("distributed")
    pytest.importorskip("KratosMultiphysics")
    fe = "[fe]\nelement_size = 0.25\nsteps = 2\narea_load = 1884.0\n\n[objectives]"
    replace = {"[objectives]": fe, "plan_y = {min = 0.3}\n": "fe_buckling_factor = {min = 3.0}\n"}
    study = write_study(tmp_path, replace=replace)
    r = run_study(study, tmp_path / "out", trials=6, workers=2, progress=False)
    assert (r.scheduler, r.workers, r.computed) == ("local", 2, 6)
    assert len({x["worker"] for x in r.rows}) == 2
    # the 6 random start-up trials of seed 2: rise 0.62, 0.66 and 0.76 m miss rise >= 0.9
    assert sorted(round(x["rise"], 2) for x in r.rows if x["fe_gated"]) == [0.62, 0.66, 0.76]
    assert r.gated == 3 and r.summary["fe_gated"] == 3
    for x in r.rows:
        cheap_ok = x["bending_utilisation"] <= 1.0 and x["collision_free"] and x["rise"] >= 0.9
        assert x["fe_gated"] == (not cheap_ok)
        if not cheap_ok:  # no FE time spent
            assert x["status"] == "ok" and x["t_fe"] is None and x["fe_elements"] is None
        elif x["status"] == "ok":
            assert x["t_fe"] > 0 and x["fe_buckling_factor"] > 0 and x["fe_elements"] > 0
            assert x["feasible"] == (x["fe_buckling_factor"] >= 3.0)
        else:  # the FE of a 5 cm wide plate may not converge: infeasible, with its error
            assert (x["stage"], x["error_type"]) == ("fe", "ConvergenceError")
            assert not x["feasible"] and x["violation"] == opt.FAILED_VIOLATION
    one = next(x for x in r.rows if x["status"] == "ok" and x["t_fe"] is not None)
    doc = study.document_for(study.variant_of_row(one))
    again = evaluate_variant(doc, **study.options)
    keys = ("mass", "bending_utilisation", "fe_buckling_factor", "fe_deflection_ratio")
    assert {k: again[k] for k in keys} == pytest.approx({k: one[k] for k in keys}, rel=1e-6)
    assert np.isfinite(r.summary["run"]["seconds"])


@pytest.mark.slow  # a whole study (2-5 s)
def test_the_trials_do_not_depend_on_the_order_the_workers_finish_in(tmp_path, monkeypatch):
    """Three trials in flight, finished in the order asked or in reverse, one at a time: the
    sampler is told each batch in trial order, so it proposes the same designs."""
    from contextlib import contextmanager

    study = write_study(
        tmp_path, replace={"trials = 40": "trials = 12", "seed = 2": "seed = 2\nstartup = 3"}
    )

    class Workers:
        window = 3

        def __init__(self, reverse):
            self.reverse, self.queued = reverse, []

        def submit(self, key, document):
            self.queued.append((key, evaluate_variant(document, **study.options)))

        def collect(self):
            if not self.queued:
                return []
            return [self.queued.pop(-1 if self.reverse else 0)]

        def cancel(self, key):
            pass

    def run(folder, reverse):
        @contextmanager
        def evaluator(*args, **kwargs):
            yield Workers(reverse), "fake", 3

        monkeypatch.setattr(runner, "open_evaluator", evaluator)
        return run_study(study, tmp_path / folder, progress=False, summary=False)

    a, b = run("in-order", False), run("reversed", True)
    assert [r["trial"] for r in a.rows] == list(range(12))
    assert [r["variant"] for r in a.rows] == [r["variant"] for r in b.rows]
    journal = [json.loads(line)["trial"] for line in (tmp_path / "reversed" / "journal.jsonl")
               .read_text().splitlines()]  # fmt: skip
    assert journal == list(range(12))  # journalled in trial order too
