"""Work limits: requests that would run for minutes or exhaust memory are one-line errors that
name the limit and how to raise it, checked before the work starts."""

from __future__ import annotations

import time

import numpy as np
import pytest

from compas_ccu import limits
from compas_ccu.cli import main
from compas_ccu.design import Design
from compas_ccu.errors import LimitError, OptionError
from compas_ccu.explore import Sweep
from compas_ccu.model import CCUModel, load_model
from conftest import EXAMPLES

CONE = str(EXAMPLES / "cone.toml")


def design(segments=16, plates=4):
    return Design(
        {
            "crease": {"profile": "arc", "span": 2.5, "rise": 1.0, "segments": segments},
            "rulings": {"type": "orthogonal"},
            "deployment": {"alpha": 30.0},
            "layout": {"type": "parallel", "plates": plates, "spacing": 0.05},
        }
    )


def test_a_design_beyond_the_limits_is_refused_before_it_is_built():
    start = time.perf_counter()
    with pytest.raises(LimitError, match=r"2000000 crease segments \(crease\.segments\) exceed"):
        CCUModel(design(segments=2_000_000))
    with pytest.raises(LimitError, match=r"--limit plates=10000"):
        CCUModel(design(plates=10_000))
    with pytest.raises(LimitError, match=r"vertices \(500 plates x 2000 segments\) exceed"):
        CCUModel(design(segments=2000, plates=500))
    assert time.perf_counter() - start < 1.0  # refused, not attempted


def test_raised_limits_let_a_larger_design_through():
    with limits.raised(segments=30_000):
        model = CCUModel(design(segments=25_000, plates=2))
    assert model.segments == 25_000
    assert limits.LIMITS.segments == 20_000  # restored


def test_a_path_beyond_the_state_or_memory_limit(cone_model):
    with limits.raised(states=5):
        with pytest.raises(LimitError, match=r"6 states of one path exceed the limit of 5"):
            cone_model.path(np.linspace(0, 30, 6))
        assert len(cone_model.path(np.linspace(0, 30, 5), check=False)) == 5
    with limits.raised(memory_gib=1e-6):
        with pytest.raises(LimitError, match=r"a path of 100 states needs about .* GiB"):
            cone_model.vertices(np.linspace(0, 30, 100))


def test_cli_steps_beyond_the_limit_are_refused_before_any_work(tmp_path, capsys):
    out = tmp_path / "path"
    assert main(["path", CONE, "--steps", "1000000000", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "1000000001 states (--steps 1000000000) exceed the limit of 10000 states" in err
    assert "--limit states=1000000001" in err
    assert not out.exists()
    args = ["path", CONE, "--steps", "3", "--out", str(out), "--quiet"]
    assert main(args + ["--limit", "states=3"]) == 2
    assert main(args + ["--limit", "states=4"]) == 0  # the flat stack and 3 more


@pytest.mark.parametrize(
    "text,message",
    [
        ("bogus=2", r"--limit takes NAME=VALUE with NAME one of segments, plates"),
        ("states", r"--limit takes NAME=VALUE"),
        ("states=many", r"--limit states needs a number, got 'many'"),
        ("states=0", r"--limit states must be > 0"),
    ],
)
def test_bad_limit_options(text, message):
    with pytest.raises(OptionError, match=message):
        limits.parse_limit(text)


def test_a_huge_sweep_range_is_refused_before_linspace():
    doc = {
        "sweep": {"base": "vault.toml"},
        "parameters": {"crease.rise": {"min": 0.5, "max": 1.5, "num": 1_000_000_000}},
    }
    start = time.perf_counter()
    with pytest.raises(LimitError, match=r"1000000000 grid points of crease\.rise"):
        Sweep(doc, base_dir=EXAMPLES)
    assert time.perf_counter() - start < 1.0


def test_the_examples_are_far_inside_the_limits():
    for name in ("vault.toml", "cone.toml", "quadrants.toml"):
        load_model(EXAMPLES / name).path(np.linspace(0, 20, 200), check=False)
