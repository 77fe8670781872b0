"""The assembly sheet: every cut pattern, the stack section and the assembly steps on one page.

:func:`write_assembly_sheet` draws an A3 landscape page with matplotlib (imported inside the
function; the figure is rendered off-screen, no pyplot): left, the cut patterns in a grid in
stack order (plate id in large type and stack position on each;
:mod:`compas_ccu.fabrication.assembly_patterns`); right, a schematic section of the flat-folded
stack (plates to scale in height, bottom to top, the creases joining them as arcs on alternating
sides: the accordion; :mod:`compas_ccu.fabrication.assembly_section`) above the assembly steps
(:mod:`compas_ccu.fabrication.assembly_text`); on top, the design name, material, thickness and
stack height. This module puts the page together and saves it with no date in it.
"""

from __future__ import annotations

from pathlib import Path

from compas_ccu.fabrication.assembly import assembly_steps
from compas_ccu.fabrication.assembly_patterns import draw_patterns, pattern_legend
from compas_ccu.fabrication.assembly_section import draw_stack
from compas_ccu.fabrication.assembly_text import assembly_text

__all__ = ["write_assembly_sheet", "write_assembly_sheets", "SHEET_FORMATS"]

#: File suffixes :func:`write_assembly_sheet` writes.
SHEET_FORMATS = (".pdf", ".svg", ".png")
A3_LANDSCAPE = (16.54, 11.69)  # inches
#: matplotlib settings of the page: text stays text, a fixed salt for the SVG's ids.
#: ``ps.fonttype`` 42 as well: matplotlib 3.11's PDF writer groups a font's characters into
#: subsets of ``ps.fonttype``'s size (256 for its default, 3), and each subset is one more
#: embedding of the font (a fontTools subsetting, ~0.17 s: a tenth of a small design's
#: ``ccu fabricate``), which a character past U+00FF (α, β, −) started.
_RC = {
    "svg.fonttype": "none",
    "pdf.fonttype": 42,
    "ps.fonttype": 42,
    "font.family": "DejaVu Sans",
    "svg.hashsalt": "compas_ccu",
}


def _no_ligatures(fig) -> None:
    """Every text of ``fig`` set without ligatures: matplotlib 3.11's PDF writer puts a glyph
    of several characters ("fl") in a second embedding of its font (see ``_RC``). Older
    matplotlib has no font features and draws no ligatures."""
    from matplotlib.text import Text

    for text in fig.findobj(Text):
        if hasattr(text, "set_fontfeatures"):
            text.set_fontfeatures(("-liga",))


def _stack_order(data) -> list:
    """Array indices of the plates, bottom of the stack first."""
    return sorted(range(len(data.plate_ids)), key=lambda i: int(data.stack_position[i]))


def _stack_height(data, stack) -> str:
    """The stack height in words, with the splice plates of ``stack`` if any."""
    p = len(data.plate_ids)
    t = float(data.thickness) * 1000.0
    records = [] if stack is None else stack["records"]
    height = f"stack height \u03a3t = {p * t:g} mm"
    if records:
        height += (
            f", {stack['stack_height'] * 1000:.4g} mm with the {len(records)} splice plates "
            f"(highest pile {stack['max_pile'] * 1000:.4g} mm)"
        )
    return height


def _draw_page(fig, data, order, steps, stack) -> None:
    """The title, the pattern panel, the stack section and the assembly panel on ``fig``."""
    p = len(order)
    t = float(data.thickness) * 1000.0
    records = [] if stack is None else stack["records"]
    gs = fig.add_gridspec(
        2,
        2,
        width_ratios=[2.15, 1.0],
        height_ratios=[0.9, 1.35],
        left=0.025,
        right=0.985,
        top=0.885,
        bottom=0.03,
        wspace=0.12,
        hspace=0.16,
    )
    fig.suptitle(
        f"{data.name}: cut patterns and assembly",
        x=0.025,
        y=0.975,
        ha="left",
        fontsize=20,
        fontweight="bold",
    )
    fig.text(
        0.025,
        0.925,
        f"{p} plates of {data.material}, thickness t = {t:g} mm, "
        f"{_stack_height(data, stack)}; hinge strips {data.hinge_width * 1000:g} mm wide; "
        f"design reflection angle \u03b1 = {data.alpha:g}\u00b0",
        ha="left",
        va="center",
        fontsize=12,
    )
    draw_patterns(fig.add_subplot(gs[:, 0]), data, order, records)
    draw_stack(fig.add_subplot(gs[0, 1]), data, order)
    ax = fig.add_subplot(gs[1, 1])
    ax.set_axis_off()
    ax.set_title("Assembly", fontsize=11, loc="left")
    ax.text(
        0.0,
        0.97,
        assembly_text(data, order, steps),
        transform=ax.transAxes,
        ha="left",
        va="top",
        fontsize=7.5,
        linespacing=1.3,
    )
    pattern_legend(ax, data, spliced=bool(records))


def _metadata(data, suffix: str) -> dict:
    """The file's metadata for its format: title and creator, no date."""
    title = f"{data.name} assembly sheet"
    if suffix == ".svg":
        return {"Title": title, "Creator": "compas_ccu", "Date": None}
    if suffix == ".png":
        return {"Title": title, "Software": "compas_ccu"}
    return {"Title": title, "Creator": "compas_ccu", "CreationDate": None}


def write_assembly_sheet(data, path, *, steps=None, stack=None) -> Path:
    """Write the assembly sheet of a design as PDF, SVG or PNG (by the suffix of ``path``).

    Parameters
    ----------
    data : compas_ccu.fabrication.data.FabricationData
    path : str or Path
        Output file, ``.pdf``, ``.svg`` or ``.png``. SVG text stays text (searchable).
    steps : list of dict, optional
        The assembly steps (:func:`compas_ccu.fabrication.assembly.assembly_steps`, as in
        ``fabrication.json``); default: the steps of the plates whole.
    stack : dict, optional
        ``fabrication.json``'s ``splices`` (:func:`compas_ccu.fabrication.splices.splice_summary`):
        the splice plates drawn on their plates and the stack height with them.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If the suffix is not one of :data:`SHEET_FORMATS`.
    """
    return write_assembly_sheets(data, [path], steps=steps, stack=stack)[0]


def write_assembly_sheets(data, paths, *, steps=None, stack=None) -> list:
    """Write the assembly sheet of a design to several files, the page drawn once.

    The same bytes as :func:`write_assembly_sheet` called once per file (a page is drawn in
    ~0.1-0.3 s; drawing it once saves that for every format after the first).

    Parameters
    ----------
    data : compas_ccu.fabrication.data.FabricationData
    paths : sequence of str or Path
        Output files, each ``.pdf``, ``.svg`` or ``.png``.
    steps, stack
        As in :func:`write_assembly_sheet`.

    Returns
    -------
    list of Path
        ``paths``, as :class:`~pathlib.Path`.

    Raises
    ------
    ValueError
        If a suffix is not one of :data:`SHEET_FORMATS` (before anything is written).
    """
    import matplotlib
    from matplotlib.figure import Figure

    paths = [Path(path) for path in paths]
    for path in paths:
        if path.suffix.lower() not in SHEET_FORMATS:
            raise ValueError(
                f"assembly sheet format must be one of {SHEET_FORMATS}, got {path.suffix!r} "
                f"({path})"
            )
    order = _stack_order(data)
    steps = assembly_steps(data, {}) if steps is None else steps
    # a fixed salt for the SVG's ids and no date in the PDF: the same design, the same bytes
    with matplotlib.rc_context(_RC):
        fig = Figure(figsize=A3_LANDSCAPE, dpi=100)
        _draw_page(fig, data, order, steps, stack)
        _no_ligatures(fig)
        for path in paths:
            fig.savefig(path, metadata=_metadata(data, path.suffix.lower()))
    return paths
