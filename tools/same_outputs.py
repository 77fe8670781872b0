"""Do two revisions of compas_ccu write the same files? The byte-identity check of a refactoring.

Checks out each revision into a temporary git worktree, runs the same commands with that
revision's source first on the path (the current virtual environment's packages otherwise) and
compares the SHA-256 of every file written:

* ``ccu deploy`` of every design of ``examples/`` and of the rule catalog (structure.json,
  OBJ, COMPAS JSON);
* ``ccu fabricate --nesting shelf`` of the vault, the 8 mm vault and the cone (DXF per plate
  and per sheet, BOM, hinge strips, OBJ / glTF, FOLD, assembly sheet, fabrication.json), and
  ``ccu import`` of each of those folders (the design file it writes).

The ``.3dm`` files are left out: rhino3dm stamps the archive with its path and the minute it
was written (docs/fabrication.md). Usage::

    python tools/same_outputs.py HEAD~1 HEAD      # exit 0: every file the same, 1: a list
"""

from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FABRICATED = ("vault", "overbent", "cone")


def designs(tree: Path) -> list:
    """The design files deployed: ``examples/*.toml`` and the catalog's, by name."""
    found = sorted((tree / "examples").glob("*.toml"))
    found += sorted((tree / "src" / "compas_ccu" / "data" / "catalog").glob("*.toml"))
    return found


def run(tree: Path, out: Path) -> None:
    """Every command of the check, with ``tree``'s source, writing below ``out``."""
    env = {**os.environ, "PYTHONPATH": str(tree / "src")}
    ccu = [sys.executable, "-c", "import sys; from compas_ccu.cli import main; sys.exit(main())"]

    def call(*args, ok=(0,)):
        done = subprocess.run([*ccu, *map(str, args)], env=env, cwd=tree, capture_output=True)
        if done.returncode not in ok:
            raise SystemExit(f"{' '.join(map(str, args))}: exit {done.returncode}\n{done.stderr}")

    for design in designs(tree):
        call("deploy", design, "--out", out / "deploy" / design.stem, "--quiet", ok=(0, 2))
    for name in FABRICATED:
        fab = out / "fabricate" / name
        call("fabricate", tree / "examples" / f"{name}.toml", "--out", fab, "--quiet",
             "--nesting", "shelf", ok=(0, 3))  # fmt: skip
        call("import", fab, "--out", out / "import" / f"{name}.toml")


def digests(out: Path) -> dict:
    """``{relative path: sha256}`` of every file below ``out`` but the ``.3dm`` archives."""
    return {
        p.relative_to(out).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(out.rglob("*"))
        if p.is_file() and p.suffix != ".3dm"
    }


def outputs(rev: str, scratch: Path, keep: Path | None = None) -> dict:
    """The digests of what ``rev`` writes; both revisions run in the same folders (a path may
    be written into a file), ``keep`` receives the files."""
    tree, out = scratch / "tree", scratch / "out"
    subprocess.run(["git", "-C", ROOT, "worktree", "add", "--detach", "-q", tree, rev], check=True)
    try:
        run(tree, out)
        found = digests(out)
        if keep is not None:
            shutil.copytree(out, keep / rev.replace("/", "_"), dirs_exist_ok=True)
        shutil.rmtree(out)
        return found
    finally:
        subprocess.run(["git", "-C", ROOT, "worktree", "remove", "--force", tree], check=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", help="a git revision")
    parser.add_argument("after", help="another git revision")
    parser.add_argument("--keep", type=Path, help="a folder to keep both revisions' files in")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as scratch:
        a = outputs(args.before, Path(scratch), args.keep)
        b = outputs(args.after, Path(scratch), args.keep)
    differ = sorted(k for k in a.keys() & b.keys() if a[k] != b[k])
    only = sorted(a.keys() ^ b.keys())
    print(f"{len(a)} files from {args.before}, {len(b)} from {args.after}: "
          f"{len(differ)} differ, {len(only)} in one only")  # fmt: skip
    for name in differ:
        print(f"differs: {name}")
    for name in only:
        print(f"only in {'before' if name in a else 'after'}: {name}")
    return 1 if differ or only else 0


if __name__ == "__main__":
    sys.exit(main())
