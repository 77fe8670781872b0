"""The source distribution a release would upload: what it holds, and that it installs whole.

The sdist is built from a copy of the tracked files (``git ls-files``) with ``python -m build``
(setuptools, in its own build environment, as a release would), then read back with
:mod:`tarfile`, an independent reader of what was written. It ships the package with its data,
the licence, the changelog and the citation file, and not the tests (they need the repository:
``MANIFEST.in``); installed from the sdist alone, the package imports and finds its catalog,
presets and Grasshopper components.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tarfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def sdist(tmp_path_factory) -> Path:
    """The sdist built from the tracked files of this checkout."""
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout: the tracked files are unknown")
    tracked = (
        subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True)
        .stdout.decode()
        .split("\0")
    )
    source = tmp_path_factory.mktemp("source")
    for name in filter(None, tracked):
        if (ROOT / name).is_file():
            (source / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, source / name)
    out = tmp_path_factory.mktemp("dist")
    done = subprocess.run(
        [sys.executable, "-m", "build", "--sdist", "--outdir", str(out), str(source)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    (archive,) = out.glob("compas_ccu-*.tar.gz")
    return archive


def members(archive: Path) -> set:
    """The archive's file names, without the leading ``compas_ccu-<version>/``."""
    with tarfile.open(archive) as tar:
        return {m.name.split("/", 1)[1] for m in tar.getmembers() if m.isfile()}


def test_sdist_ships_the_package_and_its_papers_not_the_tests(sdist):
    names = members(sdist)
    for paper in ("LICENSE", "CHANGELOG.md", "CITATION.cff", "README.md", "pyproject.toml"):
        assert paper in names
    assert not [n for n in names if n.startswith(("tests/", "examples/", "benchmarks/"))]
    # every tracked module and data file of the package is in it
    tracked = subprocess.run(
        ["git", "ls-files", "src/compas_ccu"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.split()
    missing = sorted(set(tracked) - names)
    assert missing == []


def test_sdist_installs_a_package_that_finds_its_data(sdist, tmp_path):
    target = tmp_path / "site"
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--quiet",
            "--no-deps",
            "--target",
            str(target),
            str(sdist),
        ],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    probe = (
        "import compas_ccu, pathlib;"
        "from compas_ccu.catalog import catalog_entries;"
        "from compas_ccu.design.presets import PRESETS;"
        "root = pathlib.Path(compas_ccu.__file__).parent;"
        "print(compas_ccu.__file__, len(catalog_entries()), len(PRESETS),"
        " len(list((root / 'ghpython' / 'components').glob('*/code.py'))))"
    )
    run = subprocess.run(
        [sys.executable, "-c", probe],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={"PYTHONPATH": str(target), "PATH": "/usr/bin:/bin"},
    )
    assert run.returncode == 0, run.stderr[-2000:]
    where, entries, presets, components = run.stdout.split()
    assert where.startswith(str(target))  # the installed copy, not the checkout
    catalog_dir = ROOT / "src" / "compas_ccu" / "data" / "catalog"
    assert int(entries) == len(list(catalog_dir.glob("*.toml")))
    assert int(presets) == len(list((ROOT / "src/compas_ccu/data/presets").glob("*.toml")))
    components_dir = ROOT / "src" / "compas_ccu" / "ghpython" / "components"
    assert int(components) == len(list(components_dir.glob("*/code.py")))
