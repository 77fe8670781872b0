"""A Griffe extension for the API reference (mkdocs.yml): the reStructuredText habits of the
numpy-style docstrings, as Markdown.

* Sphinx roles (``:class:`~compas_ccu.fea.FESettings```, ``:func:`load_model```,
  ``:mod:`.table```) become code spans of their target as Sphinx shows it: ``~a.b.C`` as ``C``,
  ``.table`` as ``table``, anything else whole.
* A doctest outside the ``Examples`` section (which the numpy parser reads itself) becomes a
  fenced ``pycon`` block; Markdown would read its ``>>>`` as quotes.
* A paragraph that ends with ``::`` before its literal block ends with ``:`` (the indented block
  is a code block in Markdown too).
"""

from __future__ import annotations

import re

from griffe import Extension

#: ``:role:`target``` and ``:py:role:`target```.
ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|obj|exc|const|term|ref):`([^`]+)`")

#: The underline of a numpy section title.
UNDERLINE = re.compile(r"^\s*-{3,}\s*$")


def _shown(target: str) -> str:
    """The text Sphinx shows for a role's target."""
    text = target.strip()
    if text.startswith("~"):
        return text[1:].rsplit(".", 1)[-1]
    return text.lstrip(".")


def plain_roles(text: str) -> str:
    """``text`` with every Sphinx role replaced by a Markdown code span.

    >>> plain_roles("a :class:`~compas_ccu.fea.FESettings` and :func:`.load`")
    'a `FESettings` and `load`'
    """
    return ROLE.sub(lambda m: f"`{_shown(m.group(1))}`", text)


def markdown_blocks(text: str) -> str:
    """``text`` with its doctests outside ``Examples`` fenced, and ``::`` before a blank line
    as ``:``."""
    lines = text.split("\n")
    out, section, i = [], None, 0
    while i < len(lines):
        line = lines[i]
        following = lines[i + 1] if i + 1 < len(lines) else ""
        if line.strip() and UNDERLINE.match(following):
            section = line.strip()
        if line.lstrip().startswith(">>>") and section != "Examples":
            indent = line[: len(line) - len(line.lstrip())]
            if out and out[-1].strip():
                out.append("")
            out.append(indent + "```pycon")
            while i < len(lines) and lines[i].strip():
                out.append(lines[i])
                i += 1
            out.append(indent + "```")
            continue
        if line.rstrip().endswith("::") and not following.strip():
            line = line.rstrip()[:-1]
        out.append(line)
        i += 1
    return "\n".join(out)


class RstToMarkdown(Extension):
    """Rewrite every docstring once the object tree is built (before any is parsed)."""

    def on_object(self, *, obj, **kwargs) -> None:
        docstring = obj.docstring
        if docstring is not None:
            docstring.value = markdown_blocks(plain_roles(docstring.value))
