"""Each source file parsed once per test process: the architecture checks walk the same ~280
modules three times (~0.4 s a walk).

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
