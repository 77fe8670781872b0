"""Write the design-file reference, ``docs/design-files.md``, from the key table and the rules.

:func:`schema_markdown` lists every section and key of
:data:`~compas_ccu.design.schema_table.SCHEMA` (type, unit, default, allowed values, meaning) and
every rule of :data:`~compas_ccu.design.rules.RULES`, so the documentation cannot drift from the
code. ``python -m compas_ccu.design.schema > docs/design-files.md`` regenerates the page;
``tests/test_design_schema.py`` checks that it is current.
"""

from __future__ import annotations

from compas_ccu.design.rules import RULES
from compas_ccu.design.schema_table import NAMED_SECTIONS, REQUIRED_SECTIONS, SCHEMA

__all__ = ["schema_markdown"]


#: The text above the tables: how design files are read (units, errors, templates).
_INTRO = (
    "# Design files",
    "",
    "Designs are TOML files. Every key is listed here (this page is generated from",
    "`compas_ccu.design.schema.SCHEMA`; regenerate it with",
    "`python -m compas_ccu.design.schema > docs/design-files.md`).",
    "Lengths are metres, angles degrees. An unknown section or key, a wrong type or an",
    "impossible value is an error that names the key, the value and what is allowed.",
    "",
    "**Units.** `[design] units` (`m` default, `mm`, `cm`, `ft`, `in`) sets the units of",
    "every length of the file: the keys whose unit below is `m`, and the positions x of",
    "the crease loads (unit `m, load`). They are converted to metres when the file is read;",
    "inside compas_ccu and in every output (structure.json, reports, `ccu info`) lengths are",
    "metres. Angles stay degrees; forces, pressures, densities and stiffnesses stay SI",
    "(N, Pa, kg/m³), whatever the units. The allowed ranges and the defaults below are in",
    "metres (a file in mm without `[plates] thickness` has 8 mm plates). A length",
    "that is implausible for a curved-crease structure (a crease span outside 0.05 ... 200 m,",
    "a plate thinner than 0.2 mm, ...) is a warning that names the key, the value and the",
    'units that fit (`crease.span = 2500 m is implausible ...: did you mean units = "mm"`).',
    "Writing a design back (`compas_ccu.design.inverse.write_design`) keeps its units;",
    "sweep and study parameters that set a length of a base design are in its units.",
    "`ccu new --preset vault|dome|funnel|cone|quadrants NAME.toml` writes a commented",
    "template to start from.",
    "",
)


def schema_markdown() -> str:
    """The design-file reference as Markdown, generated from :data:`SCHEMA` and :data:`RULES`.

    Examples
    --------
    >>> text = schema_markdown()
    >>> text.splitlines()[0], "| `span` | float | m |" in text
    ('# Design files', True)
    """
    lines = list(_INTRO)
    for section, keys in [*SCHEMA.items(), *NAMED_SECTIONS.items()]:
        lines += _section_table(section, keys)
    lines += [
        "## Rules between keys",
        "",
        "Checked in this order once every key is valid on its own; the error names the key.",
        "",
        "| key | rule |",
        "|---|---|",
    ]
    lines += [f"| `{rule.key}` | {rule.doc} |" for rule in RULES]
    lines.append("")
    return "\n".join(lines)


def _section_table(section: str, keys: dict) -> list:
    """The lines of one section: its title, its text and the table of its keys."""
    req = " (required)" if section in REQUIRED_SECTIONS else ""
    title = f"[{section}.NAME]" if section in NAMED_SECTIONS else f"[{section}]"
    lines = [
        f"## {title}{req}",
        "",
        keys["_doc"],
        "",
        "| key | type | unit | default | allowed | applies to | meaning |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, key in keys.items():
        if name.startswith("_"):
            continue
        allowed = ", ".join(f"`{c}`" for c in key.choices) or key.check_doc
        default = (
            "required"
            if key.required
            else ("" if key.default is None else f"`{key.default!r}`".replace("'", '"'))
        )
        lines.append(
            f"| `{name}` | {key.kind} | {key.unit} | {default} | {allowed} | "
            f"{key.when or 'all'} | "
            f"{key.doc} |"
        )
    lines.append("")
    return lines
