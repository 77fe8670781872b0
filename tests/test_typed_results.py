"""Typed results: a public function of the core packages (curves, strips, kinematics, model)
returns a dataclass or an array, not a bare dict; a dict is only a document (``__data__``,
``to_dict`` / ``as_dict``, a ``summary``, a profile's ``parameters``, a state's ``metrics``)."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "compas_ccu"
CORE = ("curves", "strips", "kinematics", "model")
#: The names whose dict is a document written to a file (JSON / TOML), not a result.
DOCUMENTS = {"__data__", "to_dict", "as_dict", "summary", "parameters", "metrics"}


def bare_dict_results(root: Path, packages=CORE) -> list:
    """``path:line name`` of every public function or method annotated ``-> dict`` (or
    ``dict | None``) under ``root/<package>`` whose name is not a document's."""
    found = []
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            for node in ast.walk(tree):
                if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    continue
                if node.returns is None or node.name in DOCUMENTS:
                    continue
                if node.name.startswith("_") and not node.name.startswith("__"):
                    continue  # private: never crosses a module
                returns = ast.unparse(node.returns).replace(" ", "")
                if returns in ("dict", "dict|None", "Optional[dict]"):
                    found.append(f"{path.relative_to(root)}:{node.lineno} {node.name}")
    return found


def test_the_core_packages_return_typed_results():
    assert bare_dict_results(SRC) == []


def test_the_check_finds_a_bare_dict_result(tmp_path):
    (tmp_path / "model").mkdir()
    (tmp_path / "model" / "a.py").write_text(
        "def round_trip(design) -> dict:\n    return {}\n"
        "def _options() -> dict:\n    return {}\n"
        "class M:\n    def __data__(self) -> dict:\n        return {}\n"
        "    def limits(self) -> dict | None:\n        return None\n"
    )
    assert bare_dict_results(tmp_path, ("model",)) == [
        "model/a.py:1 round_trip",
        "model/a.py:8 limits",
    ]
