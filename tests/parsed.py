"""Each source file parsed (and tokenized) once per test process: the architecture, typed-result
and tolerance checks walk the same ~280 modules several times (~0.4 s a walk).

A tree is shared between the checks: walk it, never change it. A file written again (the checks'
own "it can fail" tests write into a temporary folder) is parsed again: the key holds its size
and modification time.
"""

from __future__ import annotations

import ast
import functools
import io
import os
import tokenize


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


def float_literals(path) -> tuple:
    """``(line, literal)`` of every float literal in the code of the Python file ``path`` (a
    docstring or comment is a string to the tokenizer, not a number), cached like :func:`parse`.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as f:
    ...     _ = f.write("x = 2 * 1.5e-3 + 1j + 7  # 1e-300 in a comment")
    >>> float_literals(f.name)
    ((1, '1.5e-3'),)
    >>> os.remove(f.name)
    """
    stat = os.stat(path)
    return _float_literals(os.fspath(path), stat.st_size, stat.st_mtime_ns)


@functools.cache
def _float_literals(path: str, size: int, mtime_ns: int) -> tuple:
    with open(path, encoding="utf-8") as handle:
        text = handle.read()
    return tuple(
        (token.start[0], token.string)
        for token in tokenize.generate_tokens(io.StringIO(text).readline)
        if token.type == tokenize.NUMBER
        and not token.string.endswith(("j", "J"))
        and any(c in token.string for c in ".eE")
    )
