"""The layering of the package (docs/architecture.md): contracts kept, every module in a layer,
no function-local imports of the package's own modules, and the contracts catch what they must."""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from compas_ccu.design.document import parse_toml
from parsed import nodes

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "compas_ccu"
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")


def _contracts() -> list:
    return parse_toml((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]


def _layered_modules() -> set:
    layers = next(c for c in _contracts() if c["type"] == "layers")["layers"]
    return {m.strip() for layer in layers for m in layer.split("|")}


def _lint(root: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(LINT_IMPORTS), "--no-cache"],
        cwd=root,
        env={"PYTHONPATH": str(root / "src"), "PATH": "/usr/bin:/bin"},
        capture_output=True,
        text=True,
    )


def test_every_top_level_module_is_in_a_layer():
    top = {
        f"compas_ccu.{p.stem if p.is_file() else p.name}"
        for p in SRC.iterdir()
        if (p.suffix == ".py" and p.stem != "__init__") or (p / "__init__.py").exists()
    }
    assert top - _layered_modules() == set(), "add these modules to a layer in pyproject.toml"
    assert _layered_modules() - top == set(), "these layers name modules that do not exist"


def function_local_imports(root: Path) -> list:
    """``path:line`` of every import of the package (``compas_ccu`` or ``compas_ccu.*``) inside
    a function of a Python file under ``root``."""
    local = []
    for path in sorted(root.rglob("*.py")):
        functions = [
            (n.lineno, n.end_lineno)
            for n in nodes(path)
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))
        ]
        for node in nodes(path):
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            names = (
                [node.module or ""]
                if isinstance(node, ast.ImportFrom)
                else [a.name for a in node.names]
            )
            if not any(n == "compas_ccu" or n.startswith("compas_ccu.") for n in names):
                continue
            # local: a function's lines enclose it (a statement lies within its block's lines)
            if any(first <= node.lineno <= last for first, last in functions):
                local.append(f"{path.relative_to(root).as_posix()}:{node.lineno}")
    return local


def test_no_function_local_imports_of_the_package(tmp_path):
    """Intra-package imports are module-level: only optional third-party extras load lazily
    (and the command modules of the ccu command table, by name: the next tests)."""
    assert function_local_imports(SRC) == []
    # the check can fail: imports in a function, a method and a nested function are found;
    # module-level ones (under ``if`` or ``try`` too) and other packages' are not
    (tmp_path / "bad.py").write_text(
        "import compas_ccu.model\ntry:\n    from compas_ccu import errors\nexcept ImportError:\n"
        "    pass\n\n\ndef f():\n    import numpy\n    from compas_ccu.model import load_model\n"
        "\n\nclass A:\n    def g(self):\n        def h():\n            import compas_ccu\n"
    )
    assert function_local_imports(tmp_path) == ["bad.py:10", "bad.py:16"]


#: The modules that import a module named by a variable (``importlib.import_module(name)``), and
#: what they import. The command table is the one place the package imports its own modules by
#: name (docs/architecture.md): ``ccu --help`` lists the commands without importing them.
IMPORTS_BY_NAME = {
    "cli/table.py": "the command modules of the ccu command table (compas_ccu.cli.*)",
    "curves/candidates.py": "the optional readers of curve files: ezdxf, svgelements, rhino3dm",
    "ghpython/convert.py": "Rhino's modules, where they import (Rhino, compas_rhino)",
}


def _names_package(node) -> bool:
    """A string (literal, f-string, sum) that holds ``compas_ccu``."""
    return any(
        isinstance(n, ast.Constant) and isinstance(n.value, str) and "compas_ccu" in n.value
        for n in ast.walk(node)
    )


def imports_by_name(root: Path) -> dict:
    """``{"path:line": what}`` of every call of ``import_module`` / ``__import__`` under ``root``:
    ``"compas_ccu"`` if its argument names the package in a string, ``"name"`` if it is a
    variable (a literal naming another package is not listed)."""
    found = {}
    for path in sorted(root.rglob("*.py")):
        for node in nodes(path):
            if not isinstance(node, ast.Call) or not node.args:
                continue
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if name not in ("import_module", "__import__"):
                continue
            where = f"{path.relative_to(root).as_posix()}:{node.lineno}"
            if _names_package(node.args[0]):
                found[where] = "compas_ccu"
            elif not isinstance(node.args[0], ast.Constant):
                found[where] = "name"
    return found


def test_the_package_imports_its_own_modules_by_name_only_in_the_command_table(tmp_path):
    found = imports_by_name(SRC)
    assert [k for k, v in found.items() if v == "compas_ccu"] == []
    assert {k.split(":")[0] for k in found} == set(IMPORTS_BY_NAME)
    # the check can fail: a module that imports one of the package's modules by name is found
    (tmp_path / "bad.py").write_text(
        "import importlib\n\n\ndef f(x):\n"
        "    importlib.import_module('compas_ccu.model')\n"
        "    __import__(f'compas_ccu.{x}')\n"
        "    importlib.import_module(x)\n"
        "    importlib.import_module('ezdxf')\n"
    )
    assert imports_by_name(tmp_path) == {
        "bad.py:5": "compas_ccu",
        "bad.py:6": "compas_ccu",
        "bad.py:7": "name",
    }


def test_the_command_table_names_command_modules_only():
    """What the table imports by name is a ``compas_ccu.cli`` module, the layer's own: the
    import contracts, which see ``import`` statements only, lose nothing."""
    from compas_ccu.cli import table

    modules = {e.module for e in table.TABLE} | set(table.EXPORTS.values())
    for module in modules:
        package, _, name = module.rpartition(".")
        assert package == "compas_ccu.cli" and (SRC / "cli" / f"{name}.py").exists(), module
    with pytest.raises(ValueError, match="not a module of the command table"):
        table._module("compas_ccu.model")


def private_imports(root: Path) -> list:
    """``path:line name`` of every ``_private`` name imported from another compas_ccu module."""
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in nodes(path):
            if not isinstance(node, ast.ImportFrom) or not (node.module or "").startswith(
                "compas_ccu"
            ):
                continue
            for alias in node.names:
                if alias.name.startswith("_") and not alias.name.startswith("__"):
                    found.append(f"{path.relative_to(root)}:{node.lineno} {alias.name}")
    return found


def test_no_private_name_is_imported_from_another_module(tmp_path):
    """A module's ``_private`` names are its own: another module imports public ones only."""
    assert private_imports(SRC) == []
    # the check can fail: a module that takes another's private helper is found
    (tmp_path / "bad.py").write_text("from compas_ccu.fabrication.dxf import _fixed_metadata\n")
    assert private_imports(tmp_path) == ["bad.py:1 _fixed_metadata"]


def test_the_import_contracts_are_kept():
    result = _lint(ROOT)
    assert result.returncode == 0, result.stdout[-3000:]
    assert "0 broken" in result.stdout


@pytest.fixture()
def copy_of_the_project(tmp_path):
    shutil.copytree(SRC, tmp_path / "src" / "compas_ccu")
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    return tmp_path


def test_an_upward_import_breaks_the_layers_contract(copy_of_the_project):
    schema = copy_of_the_project / "src" / "compas_ccu" / "design" / "schema.py"
    schema.write_text(schema.read_text() + "\nimport compas_ccu.model  # noqa\n")
    result = _lint(copy_of_the_project)
    assert result.returncode == 1
    assert "Layers: a module imports only from the layers below its own BROKEN" in result.stdout
    assert "compas_ccu.design.schema -> compas_ccu.model" in result.stdout


def test_a_cycle_breaks_the_acyclic_contract(copy_of_the_project):
    leading = copy_of_the_project / "src" / "compas_ccu" / "kinematics" / "leading.py"
    leading.write_text(leading.read_text() + "\nimport compas_ccu.kinematics.mechanism  # noqa\n")
    result = _lint(copy_of_the_project)
    assert result.returncode == 1
    assert "No import cycles between the modules of any package BROKEN" in result.stdout
    assert "compas_ccu.kinematics" in result.stdout
