"""The documentation site (docs/index.md, `make docs`): the CLI reference generated from the
command table has every command with its usage, description and every option; every page of
docs/ is in the site's navigation and the generated page is not committed; the glossary is
linked from the pages that first use its words. The site itself is built by `make docs`
(mkdocs build --strict), a stage of `make test`."""

from __future__ import annotations

import html
import importlib.util
import re
from pathlib import Path

import pytest

from compas_ccu.cli.table import TABLE, load_all

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def _tool(name: str):
    """A module of tools/, imported from its file (tools/ is not a package)."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "tools" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def page() -> str:
    return _tool("cli_reference").markdown()


def _sections(page: str) -> dict:
    """The page's sections by command name (the text after ``## `ccu NAME` ``)."""
    parts = re.split(r"^## `ccu ([a-z]+)`$", page, flags=re.MULTILINE)
    return dict(zip(parts[1::2], parts[2::2]))


def _flags(section: str) -> set:
    """Every flag and positional name in a section's argument and option tables."""
    names = set()
    for cell in re.findall(r"^\| `([^`]+)` \|", section, flags=re.MULTILINE):
        for invocation in cell.split(", "):
            names.add(invocation.split(" ")[0])
    return names


def _plain(markdown: str) -> str:
    """Markdown text as read: backslash escapes and HTML entities resolved."""
    return html.unescape(re.sub(r"\\(.)", r"\1", markdown))


def test_every_command_of_the_table_is_on_the_page_in_its_order(page):
    assert list(_sections(page)) == [e.name for e in TABLE]
    for entry in TABLE:  # the index table links every section
        assert f"[`{entry.name}`](#ccu-{entry.name})" in page


def test_every_command_has_its_usage_description_and_every_option(page):
    sections = _sections(page)
    for command in load_all():
        text = sections[command.name]
        assert f"usage: ccu {command.name} " in text, command.name
        assert " ".join(command.description.split()) in _plain(text), command.name
        flags = _flags(text)
        for option in command.options:
            first = option.flags[0]  # a positional is shown by its metavar, if it has one
            name = first if first.startswith("-") else option.settings.get("metavar", first)
            assert name in flags, f"ccu {command.name}: {name} is not on the CLI reference"
        assert {"-h", "--limit"} <= flags


def test_a_known_option_with_its_help(page):
    validate = _sections(page)["validate"]
    row = next(line for line in validate.splitlines() if line.startswith("| `--element-size"))
    assert row == "| `--element-size ELEMENT_SIZE` | m (default 0.1) |"
    assert "| `--out OUT` | output folder (required) |" in validate
    assert "| `--engine {kratos,opensees}` |" in validate


def test_the_generated_page_is_not_committed_and_every_page_is_in_the_nav():
    page = _tool("cli_reference").PAGE
    assert not (DOCS / page).exists(), f"docs/{page} is generated when the site is built"
    nav = set(re.findall(r":\s+(\S+\.md)\s*$", (ROOT / "mkdocs.yml").read_text(), re.MULTILINE))
    pages = {p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.md")}
    assert pages | {page} == nav


def test_the_glossary_is_linked_where_its_words_are_first_used():
    for name in ("index.md", "geometry.md", "kinematics.md"):
        assert "](glossary.md" in (DOCS / name).read_text(encoding="utf-8"), name
    assert "docs/glossary.md" in (ROOT / "README.md").read_text(encoding="utf-8")
    glossary = (DOCS / "glossary.md").read_text(encoding="utf-8")
    entries = re.split(r"^### .+$", glossary, flags=re.MULTILINE)[1:]
    assert len(entries) >= 30
    for entry in entries:  # every entry says where it is explained
        assert re.search(r"\]\([a-z-]+\.md", entry), entry


def test_docstrings_read_as_markdown():
    rst = _tool("griffe_rst")
    text = ":class:`~compas_ccu.fea.FESettings`, :func:`.load` and :mod:`compas_ccu.cli.table`"
    assert rst.plain_roles(text) == "`FESettings`, `load` and `compas_ccu.cli.table`"
    doc = "Load it::\n\n    x = 1\n\nA model.\n>>> 1 + 1\n2\n\nExamples\n--------\n>>> 2\n2"
    assert rst.markdown_blocks(doc).split("\n") == [
        "Load it:",
        "",
        "    x = 1",
        "",
        "A model.",
        "",
        "```pycon",
        ">>> 1 + 1",
        "2",
        "```",
        "",
        "Examples",
        "--------",
        ">>> 2",
        "2",
    ]
