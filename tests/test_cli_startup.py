"""A CLI that starts at once (issue 31 item 6): ``ccu --help`` and ``ccu --version`` import no
command module (no COMPAS, SciPy or Matplotlib), a command's module is imported when it runs or
its help is asked for, ``python -m compas_ccu`` is ``ccu``, and tab completion is wired
(argcomplete's protocol). Module sets, not timings: ``make bench-cli`` measures the time."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from compas_ccu import __version__
from compas_ccu.cli import build_parser, main
from compas_ccu.cli.table import TABLE, command_word

HEAVY = ("compas", "scipy", "matplotlib", "numpy", "shapely")
COMMAND_MODULES = sorted({e.module for e in TABLE})


def _run_ccu(argv) -> dict:
    """Run ``python -m compas_ccu ARGV`` in a fresh interpreter (runpy, as ``-m`` does) and
    return its exit status, output and the modules it imported."""
    code = (
        "import contextlib, io, json, runpy, sys\n"
        f"sys.argv = ['ccu', *{list(argv)!r}]\n"
        "out = io.StringIO()\n"
        "with contextlib.redirect_stdout(out):\n"
        "    try:\n"
        "        runpy.run_module('compas_ccu', run_name='__main__', alter_sys=True)\n"
        "        status = None\n"
        "    except SystemExit as exc:\n"
        "        status = exc.code\n"
        "run = {'status': status, 'out': out.getvalue(), 'modules': sorted(sys.modules)}\n"
        "print(json.dumps(run))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    return json.loads(result.stdout)


def _top(modules) -> set:
    return {m.split(".")[0] for m in modules}


@pytest.mark.parametrize("argv", [["--help"], ["--version"], [], ["bogus"]])
def test_help_and_version_import_no_command_module(argv):
    run = _run_ccu(argv)
    assert run["status"] == (0 if argv in (["--help"], ["--version"]) else 2)
    assert _top(run["modules"]) & set(HEAVY) == set()
    assert set(run["modules"]) & set(COMMAND_MODULES) == set()
    if argv == ["--help"]:
        listed = " ".join(run["out"].split())  # argparse wraps the long lines
        assert all(f"{e.name} {e.help}" in listed for e in TABLE)


def test_a_command_imports_its_own_module_only():
    run = _run_ccu(["new", "--help"])
    assert run["status"] == 0 and "--preset" in run["out"]
    assert set(run["modules"]) & set(COMMAND_MODULES) == {"compas_ccu.cli.new"}


@pytest.mark.slow  # a ccu process of its own (~1.7 s)
def test_python_m_compas_ccu_is_ccu():
    version = subprocess.run(
        [sys.executable, "-m", "compas_ccu", "--version"], capture_output=True, text=True
    )
    assert (version.returncode, version.stdout) == (0, f"compas_ccu {__version__}\n")
    both = [
        subprocess.run([*prefix, "deploy", "--help"], capture_output=True, text=True, check=True)
        for prefix in (
            [sys.executable, "-m", "compas_ccu"],
            [sys.executable, "-m", "compas_ccu.cli"],
        )
    ]
    assert both[0].stdout == both[1].stdout and "usage: ccu deploy" in both[0].stdout
    error = subprocess.run([sys.executable, "-m", "compas_ccu"], capture_output=True, text=True)
    assert error.returncode == 2 and "the following arguments are required: COMMAND" in error.stderr


@pytest.mark.parametrize("name", [e.name for e in TABLE])
def test_every_command_has_its_full_help(name, capsys):
    """``ccu NAME --help`` (only NAME's module loaded) says what the parser of every command
    says: its description, its options and ``--limit``."""
    with pytest.raises(SystemExit) as lazy:
        main([name, "--help"])
    text = capsys.readouterr().out
    assert lazy.value.code == 0 and text.startswith(f"usage: ccu {name} ")
    with pytest.raises(SystemExit):
        build_parser().parse_args([name, "--help"])  # every command loaded
    assert capsys.readouterr().out == text
    assert "--limit NAME=VALUE" in text


def test_the_command_word():
    assert command_word(["deploy", "a.toml", "--out", "o"]) == "deploy"
    assert command_word(["--", "info", "a.toml"]) == "info"
    assert command_word(["--version", "deploy"]) is None  # the ccu parser answers first
    assert command_word(["-h"]) is None and command_word([]) is None
    assert command_word(["bogus", "deploy"]) is None  # argparse refuses bogus


def _complete(line: str, tmp_path, *, prefix=("-m", "compas_ccu"), start="3") -> list:
    """The completions ``python -m compas_ccu`` gives the shell for ``line`` (the cursor at its
    end): argcomplete's protocol, as its bash / zsh hook runs it."""
    answer = tmp_path / "completions"
    env = dict(
        os.environ,
        _ARGCOMPLETE=start,  # where the arguments start: 3 for python -m compas_ccu ARGS
        _ARGCOMPLETE_IFS="\n",
        _ARGCOMPLETE_STDOUT_FILENAME=str(answer),
        COMP_LINE=line,
        COMP_POINT=str(len(line)),
    )
    result = subprocess.run(
        [sys.executable, *prefix], env=env, capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stderr
    return answer.read_text().split("\n")


@pytest.mark.slow  # a ccu process of its own (~1.7 s)
def test_completion_is_wired(tmp_path):
    pytest.importorskip("argcomplete")
    commands = _complete("python -m compas_ccu ", tmp_path)
    assert [e.name for e in TABLE] == [c for c in commands if not c.startswith("-")]
    assert {"--help", "--version"} <= set(commands)
    assert _complete("python -m compas_ccu fab", tmp_path) == ["fabricate "]
    options = _complete("python -m compas_ccu deploy --", tmp_path)
    assert {"--alpha", "--out", "--quiet", "--limit", "--help"} <= set(options)
    nesting = _complete("python -m compas_ccu fabricate --nesting", tmp_path)
    assert sorted(nesting) == ["--nesting", "--nesting-seed", "--nesting-steps"]
