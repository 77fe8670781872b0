"""The design-file keys of the workshop: stock sheets, cutter, nesting, splices and prices.

The section ``[fabrication]`` of :data:`compas_ccu.design.schema_table.SCHEMA`, the default
stock sheet :data:`STOCK_SHEET` and :func:`design_sheet`, the sheet a validated design prefers.
"""

from __future__ import annotations

from compas_ccu.design.key import Key, with_units

__all__ = ["FABRICATION_SECTIONS", "STOCK_SHEET", "design_sheet"]

#: The stock sheet of a design that names none ([fabrication] sheets), m: length (along the face
#: grain) and width. ``ccu fabricate``, ``ccu scale`` and the studio all start from it.
STOCK_SHEET = (2.5, 1.25)

#: The unit of every quantity key of ``[fabrication]``.
_UNITS = {
    "fabrication": {
        "sheets": "m", "kerf": "m", "tool_diameter": "m", "bridge": "m", "margin": "m",
        "splice_width": "m", "splice_thickness": "m", "fasteners_per_splice": "1",
        "roll_width": "m", "nesting_time": "s", "nesting_seed": "1", "nesting_steps": "1",
        "nesting_generations": "1", "sheet_price": "currency", "textile_price": "currency/m",
        "glue_price": "currency/m", "fastener_price": "currency",
    },
}  # fmt: skip

#: ``{"fabrication": {name: Key}}``.
FABRICATION_SECTIONS: dict = {
    "fabrication": {
        "_doc": "The workshop (`ccu fabricate`, docs/fabrication.md): the plywood sheets in "
        "stock, the cutter, the nesting of every part onto the sheets, the textile roll of the "
        "hinge strips and the unit prices of the bill of materials. A plate longer than every "
        "sheet is split along rulings (straight lines on the plate: a splice there does not "
        "fight the bending) and joined by splice plates on both faces.",
        "sheets": Key(
            "sizes2",
            "Sheet sizes in stock, [[length, width], ...], m; the face grain runs along the "
            "length. Every part is nested onto the first size it fits (the order is the "
            "preference).",
            default=[list(STOCK_SHEET)],
            check=lambda v: all(0.0 < x <= 100.0 for p in v for x in p),
            check_doc="every size > 0 and <= 100",
        ),
        "kerf": Key(
            "float",
            "Width of the cut, m: toolpaths run kerf / 2 outside the parts; default: "
            "tool_diameter.",
            check=lambda v: 0.0 <= v <= 0.1,
            check_doc=">= 0 and <= 0.1",
        ),
        "tool_diameter": Key(
            "float",
            "Diameter of the router bit, m: the kerf when kerf is unset (a router's cut is as "
            "wide as its bit).",
            default=0.006,
            check=lambda v: 0.0 < v <= 0.1,
            check_doc="> 0 and <= 0.1",
        ),
        "bridge": Key(
            "float",
            "Least material left between the kerfs of two parts, m (parts lie at least kerf + "
            "bridge apart).",
            default=0.01,
            check=lambda v: 0.0 <= v <= 1.0,
            check_doc=">= 0 and <= 1",
        ),
        "margin": Key(
            "float",
            "Least distance from a sheet's edge to a toolpath, m.",
            default=0.01,
            check=lambda v: 0.0 <= v <= 1.0,
            check_doc=">= 0 and <= 1",
        ),
        "grain": Key(
            "str",
            "How the parts may turn on a sheet: 'along': every plate's face grain "
            "([plates] grain) along the sheet's length, turned by 0 or 180 degrees; 'across': "
            "across it; 'free': any angle (isotropic sheets).",
            default="along",
            choices=("along", "across", "free"),
        ),
        "splice_width": Key(
            "float",
            "Width of a splice plate across the cut of a split plate, m (half on each part); "
            "two splice plates per cut, one on each face.",
            default=0.15,
            check=lambda v: 0.0 < v <= 2.0,
            check_doc="> 0 and <= 2",
        ),
        "splice_thickness": Key(
            "float",
            "Thickness of the splice plates, m; default the plates' thickness. Glued across a "
            "cut, the splice plates bend with the plate: the three layers' outer fibres lie "
            "(t + 2 t_s) / 2 from the middle, so the bending utilisation there is the plate's "
            "times (t + 2 t_s) / t (checked by `ccu fabricate`). Thinner splice plates are "
            "nested on sheets of their own thickness.",
            check=lambda v: 0.0 < v <= 0.1,
            check_doc="> 0 and <= 0.1",
        ),
        "fasteners_per_splice": Key(
            "int",
            "Screws through every splice plate (bill of materials), besides the glue.",
            default=8,
            check=lambda v: 0 <= v <= 1000,
            check_doc="0 ... 1000",
        ),
        "roll_width": Key(
            "float",
            "Width of the textile roll the hinge strips are cut from, m.",
            default=1.4,
            check=lambda v: 0.0 < v <= 10.0,
            check_doc="> 0 and <= 10",
        ),
        "score_rulings": Key(
            "bool",
            "Score every interior ruling on the sheets (layer SCORE). Off by default: 8 mm "
            "plywood must bend along them, and a score weakens it; the per-plate files keep "
            "the rulings on the reference layer RULING_SCORE either way.",
            default=False,
        ),
        "nesting": Key(
            "str",
            "'auto': the first true-shape nester installed, compas_nest then spyrrow, else "
            "the shelves with a warning; 'compas_nest': compas_nest's no-fit polygons and "
            "genetic search, onto the sheets directly (wheels for Python 3.9 too); 'spyrrow': "
            "spyrrow's strip packing (sparrow; Python >= 3.10), the strip cut into sheets; "
            "'shelf': the parts' bounding boxes in rows (fast, wasteful). A nester named but "
            "not installed is replaced by the other one, or the shelves, with a warning.",
            default="auto",
            choices=("auto", "compas_nest", "spyrrow", "shelf"),
        ),
        "nesting_time": Key(
            "float",
            "Safety limit of one packing, s: a packing that has not searched its "
            "nesting_steps (or nesting_generations) by then is refused (never cut short: "
            "the files do not depend on the machine's speed or load).",
            default=600.0,
            check=lambda v: 0.0 < v <= 86400.0,
            check_doc="> 0 and <= 86400",
        ),
        "nesting_seed": Key(
            "int",
            "Random seed of the nesting search (compas_nest, spyrrow): the same seed and "
            "steps (generations) give the same nesting; another seed searches other layouts.",
            default=0,
            check=lambda v: 0 <= v <= 2**32 - 1,
            check_doc="0 ... 4294967295",
        ),
        "nesting_steps": Key(
            "int",
            "Steps spyrrow's search takes per packing (sparrow's separations; a packing "
            "stops sooner at its second failed step): more steps, shorter strips and "
            "more time.",
            default=500,
            check=lambda v: 1 <= v <= 100_000,
            check_doc="1 ... 100000",
        ),
        "nesting_generations": Key(
            "int",
            "Generations of compas_nest's genetic search per packing (each places 10 orders "
            "of the parts, on one thread, from nesting_seed): more generations, sometimes "
            "fewer sheets, more time.",
            default=3,
            check=lambda v: 1 <= v <= 1000,
            check_doc="1 ... 1000",
        ),
        "currency": Key("str", "Currency of the prices below (text).", default="EUR"),
        "sheet_price": Key(
            "float",
            "Price of one sheet (every size in stock), currency per sheet.",
            default=60.0,
            check=lambda v: 0.0 <= v <= 1.0e9,
            check_doc=">= 0 and <= 1e9",
        ),
        "textile_price": Key(
            "float",
            "Price of the hinge textile, currency per metre of roll.",
            default=12.0,
            check=lambda v: 0.0 <= v <= 1.0e9,
            check_doc=">= 0 and <= 1e9",
        ),
        "glue_price": Key(
            "float",
            "Price of glue, currency per metre of glue line.",
            default=0.3,
            check=lambda v: 0.0 <= v <= 1.0e9,
            check_doc=">= 0 and <= 1e9",
        ),
        "fastener_price": Key(
            "float",
            "Price of one fastener, currency.",
            default=0.05,
            check=lambda v: 0.0 <= v <= 1.0e9,
            check_doc=">= 0 and <= 1e9",
        ),
    },
}
with_units(FABRICATION_SECTIONS, _UNITS)


def design_sheet(values: dict) -> tuple:
    """The preferred stock sheet (length, width) m of validated design ``values``: the first
    of [fabrication] sheets (:data:`STOCK_SHEET` by default)."""
    sheets = (values.get("fabrication") or {}).get("sheets") or [STOCK_SHEET]
    return tuple(float(x) for x in sheets[0])
