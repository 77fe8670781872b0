"""Named tolerances: the division floor is written once, in ``tolerances.py``."""

from __future__ import annotations

import io
import tokenize
from pathlib import Path

from compas_ccu.tolerances import DIVISION_FLOOR

SRC = Path(__file__).resolve().parents[1] / "src" / "compas_ccu"


def literal_floors(root: Path) -> list:
    """Every number literal equal to 1e-300 (``1e-300``, ``1.0e-300``, ``1E-300`` ...) in the
    Python files under ``root`` except ``tolerances.py``: ``path:line`` each."""
    found = []
    for path in sorted(root.rglob("*.py")):
        if path.name == "tolerances.py":
            continue
        text = path.read_text(encoding="utf-8")
        for token in tokenize.generate_tokens(io.StringIO(text).readline):
            if token.type == tokenize.NUMBER and not token.string.endswith(("j", "J")):
                value = token.string.replace("_", "")
                if any(c in value for c in ".eE") and float(value) == DIVISION_FLOOR:
                    found.append(f"{path.relative_to(root)}:{token.start[0]}")
    return found


def test_no_literal_division_floor_outside_tolerances():
    """Use ``compas_ccu.tolerances.DIVISION_FLOOR``, not the number."""
    assert literal_floors(SRC) == []


def test_the_check_finds_a_literal(tmp_path):
    (tmp_path / "tolerances.py").write_text("DIVISION_FLOOR = 1e-300\n")
    (tmp_path / "a.py").write_text('"""1e-300 in a docstring is words."""\nx = max(y, 1e-300)\n')
    (tmp_path / "b.py").write_text("t = brentq(f, 0, 1, xtol=1.0E-300)  # 1e-300\n")
    assert literal_floors(tmp_path) == ["a.py:2", "b.py:1"]
    assert DIVISION_FLOOR == 1e-300
