"""Each source file parsed once per test process: the architecture, typed-result
and tolerance checks walk the same ~280 modules several times (~0.4 s a walk).

A tree is shared between the checks: walk it, never change it. A file written again (the checks'
own "it can fail" tests write into a temporary folder) is parsed again: the key holds its size
and modification time.
"""

from __future__ import annotations

import ast
import functools
import os


def parse(path) -> ast.Module:
    """The syntax tree of the Python file ``path`` (cached by path, size and modification time).

    Examples
    --------
    >>> parse(__file__).body[0].value.value.startswith("Each source file")
    True
    """
    stat = os.stat(path)
    return _parse(os.fspath(path), stat.st_size, stat.st_mtime_ns)


@functools.cache
def _parse(path: str, size: int, mtime_ns: int) -> ast.Module:
    with open(path, encoding="utf-8") as handle:
        return ast.parse(handle.read())


def nodes(path) -> tuple:
    """Every node of the tree of the Python file ``path`` (:func:`parse`) in ``ast.walk``'s
    order, cached like it: the checks iterate a tuple instead of walking the tree again.

    Examples
    --------
    >>> import ast
    >>> sum(isinstance(n, ast.FunctionDef) for n in nodes(__file__)) >= 4
    True
    """
    stat = os.stat(path)
    return _nodes(os.fspath(path), stat.st_size, stat.st_mtime_ns)


@functools.cache
def _nodes(path: str, size: int, mtime_ns: int) -> tuple:
    return tuple(ast.walk(_parse(path, size, mtime_ns)))


def float_literals(path) -> tuple:
    """``(line, literal)`` of every float literal in the code of the Python file ``path``, as
    written (a docstring or comment is a string, not a number), read from the tree of
    :func:`parse` (which the other checks share) and cached like it.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as f:
    ...     _ = f.write("x = 2 * 1.5e-3 + 1j + 7 + 0x1e  # 1e-300 in a comment")
    >>> float_literals(f.name)
    ((1, '1.5e-3'),)
    >>> os.remove(f.name)
    """
    stat = os.stat(path)
    return _float_literals(os.fspath(path), stat.st_size, stat.st_mtime_ns)


@functools.cache
def _float_literals(path: str, size: int, mtime_ns: int) -> tuple:
    with open(path, encoding="utf-8") as handle:
        lines = handle.read().splitlines()
    found = []
    for node in _nodes(path, size, mtime_ns):
        if isinstance(node, ast.Constant) and type(node.value) is float:
            line = lines[node.lineno - 1].encode("utf-8")  # offsets count UTF-8 bytes
            literal = line[node.col_offset : node.end_col_offset].decode()
            found.append((node.lineno, node.col_offset, literal))
    return tuple((lineno, literal) for lineno, _, literal in sorted(found))
