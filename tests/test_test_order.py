"""The ``in_order`` marker: a module whose tests share one state keeps its file order when
pytest-randomly shuffles the run (tests/conftest.py)."""

from __future__ import annotations

from types import SimpleNamespace

from conftest import in_file_order


def item(path: str, line: int, *, in_order: bool):
    marker = object() if in_order else None
    return SimpleNamespace(
        location=(path, line, f"t{line}"), get_closest_marker=lambda name, m=marker: m
    )


def test_an_in_order_module_is_put_back_in_file_order_in_its_own_slots():
    a3, a1, a2 = (item("a.py", n, in_order=True) for n in (3, 1, 2))
    b2, b1 = (item("b.py", n, in_order=False) for n in (2, 1))
    items = [b2, a3, a1, b1, a2]
    in_file_order(items)
    assert items == [b2, a1, a2, b1, a3]  # b.py untouched, a.py's three slots in line order
