"""The CLI reference: one Markdown page with every ``ccu`` command's usage, description and
options, generated from the command table (``compas_ccu.cli.table``) and the argparse parser
that ``ccu COMMAND --help`` prints (``compas_ccu.cli.build_parser``), so it cannot disagree with
the command line.

Two uses, one generator:

* ``python tools/cli_reference.py [--out FILE]`` prints the page (or writes it to FILE);
* as an MkDocs hook (``hooks:`` in mkdocs.yml) it adds the page to the site as
  ``cli-reference.md`` at build time. Nothing generated is committed: the page exists only in
  the built site (``make docs``).

tests/test_docs_site.py checks that every command of the table is on the page with every option
its ``Command`` declares.
"""

from __future__ import annotations

import argparse
import functools
import html
import re
import sys
from pathlib import Path

#: The package's source in this checkout: the page documents it, installed or not.
SRC = Path(__file__).resolve().parents[1] / "src"

#: The page's path in the site (docs_dir-relative); mkdocs.yml's nav names it.
PAGE = "cli-reference.md"

#: The width the usage lines are wrapped to (argparse otherwise reads the terminal's).
WIDTH = 96

INTRO = """# CLI reference

Every `ccu` command with its usage, description and options, in the order `ccu --help` lists
them. This page is generated when the site is built (`tools/cli_reference.py`, from the command
table `compas_ccu.cli.table` and the parser `ccu COMMAND --help` prints), so it says what the
installed `ccu` says. The exit status, tab completion and how commands are declared are in
[The command line](cli.md); the design-file keys the options override are in
[Design files](design-files.md).
"""


def _subparsers(parser: argparse.ArgumentParser) -> dict:
    """The command parsers of the ``ccu`` parser, by name (argparse keeps them in its
    subparsers action; there is no public accessor)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    raise RuntimeError("the ccu parser has no commands")


def _text(text: str) -> str:
    """Plain text as Markdown: one line, HTML-escaped, Markdown's markup characters escaped (a
    help text's ``*``, ``_``, ``[`` or ``|`` is literal)."""
    text = html.escape(" ".join(str(text).split()), quote=False)
    return re.sub(r"([\\`*_\[\]|])", r"\\\1", text)


def _code(text: str) -> str:
    """Text as a Markdown code span in a table cell (pipes escaped for the table)."""
    return "`" + " ".join(str(text).split()).replace("|", "\\|") + "`"


def _help(formatter: argparse.HelpFormatter, action: argparse.Action) -> str:
    """An option's help as ``--help`` prints it (``%(default)s`` and the like expanded)."""
    if not action.help or action.help == argparse.SUPPRESS:
        return ""
    return formatter._expand_help(action)


def _command_section(entry, parser: argparse.ArgumentParser) -> list:
    parser.formatter_class = functools.partial(argparse.HelpFormatter, width=WIDTH)
    formatter = parser._get_formatter()
    lines = [f"## `ccu {entry.name}`", "", f"*{_text(entry.help)}*", ""]
    lines += ["```text", parser.format_usage().strip(), "```", ""]
    if parser.description:
        lines += [_text(parser.description), ""]
    positionals = [a for a in parser._actions if not a.option_strings]
    optionals = [a for a in parser._actions if a.option_strings]
    if positionals:
        lines += ["| argument | description |", "|---|---|"]
        for a in positionals:
            lines.append(f"| {_code(a.metavar or a.dest)} | {_text(_help(formatter, a))} |")
        lines.append("")
    lines += ["| option | description |", "|---|---|"]
    for a in optionals:
        text = _text(_help(formatter, a)) + (" (required)" if a.required else "")
        lines.append(f"| {_code(formatter._format_action_invocation(a))} | {text.strip()} |")
    lines.append("")
    return lines


def markdown() -> str:
    """The CLI reference page, Markdown: every command of the table, in its order."""
    if str(SRC) not in sys.path:
        sys.path.insert(0, str(SRC))
    from compas_ccu.cli import build_parser
    from compas_ccu.cli.table import TABLE

    parsers = _subparsers(build_parser())  # every command's module loaded: all options
    lines = [INTRO]
    lines += ["| command | what |", "|---|---|"]
    lines += [f"| [`{e.name}`](#ccu-{e.name}) | {_text(e.help)} |" for e in TABLE]
    lines.append("")
    for entry in TABLE:
        lines += _command_section(entry, parsers[entry.name])
    return "\n".join(lines)


# --- MkDocs hook ----------------------------------------------------------------------------


def on_files(files, config):
    """Add the generated CLI reference to the site's files (MkDocs >= 1.6)."""
    from mkdocs.structure.files import File

    if files.get_file_from_path(PAGE) is not None:
        raise RuntimeError(f"docs/{PAGE} is generated at build time: do not commit it")
    files.append(File.generated(config, PAGE, content=markdown()))
    return files


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="Write the ccu CLI reference (Markdown).")
    parser.add_argument("--out", help="write to this file instead of stdout")
    args = parser.parse_args(argv)
    text = markdown()
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
