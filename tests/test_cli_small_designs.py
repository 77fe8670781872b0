"""The smallest designs the schema accepts work in every command the way the others do:
``ccu info`` is the first command a user runs, so it must not fail where deploy succeeds."""

from __future__ import annotations

import pytest

from compas_ccu.cli import main

SMALL = {
    "two segments": ("parallel", 4, 2),
    "two plates": ("parallel", 2, 16),
    "two plates, two segments": ("parallel", 2, 2),
    "single crease, two segments": ("single", None, 2),
}


def write(tmp_path, layout, plates, segments):
    lines = [
        "[crease]",
        'profile = "arc"',
        "span = 2.5",
        "rise = 1.0",
        f"segments = {segments}",
        "[rulings]",
        'type = "orthogonal"',
        "[deployment]",
        "alpha = 30.0",
        "[layout]",
        f'type = "{layout}"',
    ]
    lines += [f"plates = {plates}", "spacing = 0.1"] if plates else ["width = 0.3"]
    path = tmp_path / "small.toml"
    path.write_text("\n".join(lines) + "\n")
    return str(path)


@pytest.mark.parametrize(
    "case",
    # the two smallest of one kind each in the quick loop (~0.7 s a case)
    [
        c if c in ("two segments", "two plates") else pytest.param(c, marks=pytest.mark.slow)
        for c in SMALL
    ],
)
def test_info_deploy_and_fabricate_accept_the_smallest_designs(tmp_path, capsys, case):
    design = write(tmp_path, *SMALL[case])
    assert main(["info", design]) == 0
    info = capsys.readouterr().out
    assert "span              2.5000 m" in info
    assert main(["deploy", design, "--out", str(tmp_path / "d"), "--quiet"]) == 0
    fab = ["fabricate", design, "--out", str(tmp_path / "f"), "--quiet", "--nesting", "shelf"]
    fab.append("--allow-exceeded")  # the bending of these small designs exceeds: exit 3
    assert main(fab) == 0


def test_one_plate_is_not_a_ccu_structure(tmp_path, capsys):
    design = write(tmp_path, "parallel", 1, 16)
    assert main(["info", design]) == 2
    assert "layout.plates: must be 2 ... 10000, got 1" in capsys.readouterr().err
