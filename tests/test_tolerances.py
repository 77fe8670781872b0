"""Named tolerances: the division floor and every round-off tolerance are written once, in
``tolerances.py``."""

from __future__ import annotations

from pathlib import Path

from compas_ccu.tolerances import DIVISION_FLOOR
from parsed import float_literals

SRC = Path(__file__).resolve().parents[1] / "src" / "compas_ccu"


def number_literals(root: Path, keep) -> list:
    """``(path:line, literal)`` of every float literal in code under ``root`` except
    ``tolerances.py`` whose value ``keep(value)`` accepts (docstrings and comments are words, not
    numbers: the tokenizer gives them as strings)."""
    found = []
    for path in sorted(root.rglob("*.py")):
        if path.name == "tolerances.py":
            continue
        for line, literal in float_literals(path):
            if keep(float(literal.replace("_", ""))):
                found.append((f"{path.relative_to(root)}:{line}", literal))
    return found


def literal_floors(root: Path) -> list:
    """Every number literal equal to 1e-300 (``1e-300``, ``1.0e-300``, ``1E-300`` ...) in the
    Python files under ``root`` except ``tolerances.py``: ``path:line`` each."""
    return [where for where, _ in number_literals(root, lambda v: v == DIVISION_FLOOR)]


def test_no_literal_division_floor_outside_tolerances():
    """Use ``compas_ccu.tolerances.DIVISION_FLOOR``, not the number."""
    assert literal_floors(SRC) == []


def test_the_check_finds_a_literal(tmp_path):
    (tmp_path / "tolerances.py").write_text("DIVISION_FLOOR = 1e-300\n")
    (tmp_path / "a.py").write_text('"""1e-300 in a docstring is words."""\nx = max(y, 1e-300)\n')
    (tmp_path / "b.py").write_text("t = brentq(f, 0, 1, xtol=1.0E-300)  # 1e-300\n")
    assert literal_floors(tmp_path) == ["a.py:2", "b.py:1"]
    assert DIVISION_FLOOR == 1e-300


def literal_tolerances(root: Path) -> list:
    """Every number literal between 1e-16 and 1e-9 (the round-off family: ``1e-9``, ``1e-12``,
    ``1.0E-14`` ...) in code under ``root`` except ``tolerances.py``: ``path:line literal``."""
    found = number_literals(root, lambda v: 1e-16 <= v <= 1e-9)
    return [f"{where} {literal}" for where, literal in found]


def test_every_round_off_tolerance_is_named_in_tolerances():
    """``EXACT_RELATIVE``, ``ZERO_LENGTH``, ``ROUND_OFF``, ``MACHINE`` ... not the number."""
    assert literal_tolerances(SRC) == []


def test_the_tolerance_check_finds_each_spelling(tmp_path):
    (tmp_path / "tolerances.py").write_text("EXACT_RELATIVE = 1e-9\n")
    (tmp_path / "a.py").write_text('"""to 1e-12 of the size"""\nok = err < 1e-12 * size  # 1e-9\n')
    (tmp_path / "b.py").write_text("x = brentq(f, 0, 1, xtol=1.0E-15)\ny = 1e-6\nz = 1e-18\n")
    (tmp_path / "c.py").write_text("TOUCH = 0.000000001\n")
    assert literal_tolerances(tmp_path) == ["a.py:2 1e-12", "b.py:1 1.0E-15", "c.py:1 0.000000001"]
