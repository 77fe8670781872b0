"""A PDF document of text, rows, tables and pictures on A4 pages (matplotlib's PDF backend).

The report (:mod:`compas_ccu.viz.report`) composes its PDF from blocks; :func:`write_pdf` lays
them out top-down, breaks pages, wraps long lines and numbers the pages. The text is real PDF
text (searchable, extractable), in a monospace font so that rows and tables line up as in the
terminal.

Blocks are tuples:

``("title", text, subtitle)``, ``("heading", text)``, ``("paragraph", text)``,
``("rows", [(label, text), ...])`` (the rows of :mod:`compas_ccu.key_figures.text`; a text
marked ``** ... **`` is printed red), ``("lines", [text, ...])``, ``("code", text)``,
``("table", columns, [[cell, ...], ...])``, ``("image", path, caption)``.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

from compas_ccu.errors import OptionError
from compas_ccu.key_figures.text import LABEL_WIDTH, row_failed

__all__ = ["write_pdf", "A4"]

#: Page size, inches (portrait).
A4 = (8.27, 11.69)
_MARGIN = 0.6  # inches
_FONT = 7.5  # points, monospace
_LINE = _FONT * 1.45 / 72.0  # inches per line
_CHAR = _FONT * 0.602 / 72.0  # width of a DejaVu Sans Mono character, inches
_BAD = "#b00020"
_DPI = 150  # largest resolution of a picture on the page


def write_pdf(path, blocks, *, footer: str = "") -> Path:
    """Write ``blocks`` (see the module) as a PDF of A4 pages.

    Parameters
    ----------
    path : str or Path
    blocks : sequence of tuple
    footer : str
        Printed at the foot of every page with the page number.

    Returns
    -------
    Path

    Raises
    ------
    compas_ccu.errors.OptionError
        An unknown block kind (the message names it).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = write_pdf(pathlib.Path(tempfile.mkdtemp()) / "a.pdf",
    ...               [("title", "cone", "a test"), ("rows", [("span", "2.0 m")])])
    >>> p.read_bytes()[:5]
    b'%PDF-'
    """
    from matplotlib.backends.backend_pdf import PdfPages

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    layout = _Layout(footer)
    for block in blocks:
        kind = block[0]
        draw = getattr(layout, f"_{kind}", None)
        if draw is None:
            raise OptionError(f"unknown PDF block {kind!r}")
        draw(*block[1:])
    metadata = {"Title": footer or path.stem, "Creator": "compas_ccu"}
    with PdfPages(path, metadata=metadata) as pdf:
        for fig in layout.finish():
            pdf.savefig(fig)
    return path


class _Layout:
    """Top-down layout on A4 figures (y measured in inches from the top)."""

    def __init__(self, footer: str):
        self.footer = footer
        self.pages = []
        self.fig = None
        self.y = 0.0
        self.width = A4[0] - 2 * _MARGIN
        self.columns = int(self.width / _CHAR)

    # -- pages
    def _new_page(self):
        from matplotlib.figure import Figure

        self.fig = Figure(figsize=A4)
        self.pages.append(self.fig)
        self.y = _MARGIN

    def _room(self, height: float):
        if self.fig is None or self.y + height > A4[1] - _MARGIN - 0.3:
            self._new_page()

    def _text(self, x, text, *, size=_FONT, color="#222", weight="normal", family="monospace"):
        self.fig.text(
            x / A4[0],
            1.0 - self.y / A4[1],
            text,
            fontsize=size,
            color=color,
            weight=weight,
            family=family,
            va="top",
            ha="left",
        )

    def _line(self, text, *, indent=0.0, color="#222", weight="normal"):
        self._room(_LINE)
        self._text(_MARGIN + indent, text, color=color, weight=weight)
        self.y += _LINE

    def finish(self) -> list:
        n = len(self.pages)
        for i, fig in enumerate(self.pages, start=1):
            fig.text(
                0.5,
                0.35 / A4[1],
                f"{self.footer} · page {i} of {n}" if self.footer else f"page {i} of {n}",
                fontsize=7,
                color="#666",
                ha="center",
                va="bottom",
            )
        return self.pages

    def _wrap(self, text: str, width: int) -> list:
        out = []
        for line in str(text).splitlines() or [""]:
            out += textwrap.wrap(
                line, width, break_long_words=True, drop_whitespace=False, replace_whitespace=False
            ) or [""]
        return out

    # -- blocks
    def _title(self, text, subtitle=""):
        self._room(0.9)
        self._text(_MARGIN, text, size=18, weight="bold", family="sans-serif")
        self.y += 0.38
        for line in self._wrap(subtitle, int(self.columns * 0.85)):
            self._text(_MARGIN, line, size=9, color="#555", family="sans-serif")
            self.y += 9 * 1.45 / 72.0
        self.y += 0.1

    def _heading(self, text):
        self._room(0.45 + 3 * _LINE)  # no heading alone at the foot of a page
        self.y += 0.12
        self._text(_MARGIN, text, size=12, weight="bold", family="sans-serif")
        self.y += 0.28

    def _paragraph(self, text):
        for line in self._wrap(text, self.columns):
            self._line(line)
        self.y += _LINE * 0.5

    def _lines(self, lines):
        for text in lines:
            wrapped = self._wrap(text, self.columns)
            for i, line in enumerate(wrapped):
                self._line(line, indent=2 * _CHAR if i else 0.0)
        self.y += _LINE * 0.5

    def _code(self, text):
        for i, line in enumerate(str(text).splitlines(), start=1):
            wrapped = self._wrap(line, self.columns - 5) or [""]
            for j, part in enumerate(wrapped):
                number = f"{i:>4} " if j == 0 else "     "
                self._line(number + part, color="#333")
        self.y += _LINE * 0.5

    def _rows(self, rows):
        for label, text in rows:
            color = _BAD if row_failed(text) else "#222"
            wrapped = self._wrap(text, self.columns - LABEL_WIDTH)
            for i, line in enumerate(wrapped):
                self._line(f"{label if i == 0 else '':<{LABEL_WIDTH}}{line}", color=color)
        self.y += _LINE * 0.5

    def _table(self, columns, rows):
        cells = [[str(c) for c in columns]] + [[str(c) for c in r] for r in rows]
        widths = [max(len(r[j]) if j < len(r) else 0 for r in cells) for j in range(len(columns))]
        limit = max(8, (self.columns - 2 * len(columns)) // max(len(columns), 1))
        widths = [
            min(w, limit) if sum(widths) + 2 * len(widths) > self.columns else w for w in widths
        ]
        for k, r in enumerate(cells):
            # a cell wider than its column wraps onto more lines; nothing is cut off
            parts = [
                self._wrap(r[j] if j < len(r) else "", widths[j]) or [""]
                for j in range(len(widths))
            ]
            for i in range(max(len(p) for p in parts)):
                text = "  ".join(
                    (p[i] if i < len(p) else "").strip().ljust(w) for p, w in zip(parts, widths)
                )
                self._line(text.rstrip(), weight="bold" if k == 0 else "normal")
        self.y += _LINE * 0.5

    def _image(self, path, caption=""):
        import numpy as np
        from PIL import Image

        with Image.open(path) as im:  # RGB on white, at most _DPI dots per inch on the page
            rgba = im.convert("RGBA")
            flat = Image.new("RGBA", rgba.size, "white")
            flat.alpha_composite(rgba)
            picture = flat.convert("RGB")
            picture.thumbnail((int(self.width * _DPI), int(self.width * _DPI)), Image.LANCZOS)
            image = np.asarray(picture)
        h, w = image.shape[:2]
        width = self.width
        height = width * h / w
        top_room = A4[1] - 2 * _MARGIN - 0.6
        if height > top_room:  # a tall picture: fit the page height
            height = top_room
            width = height * w / h
        self._room(height + 2 * _LINE)
        ax = self.fig.add_axes(
            (
                _MARGIN / A4[0],
                1.0 - (self.y + height) / A4[1],
                width / A4[0],
                height / A4[1],
            )
        )
        ax.imshow(image, interpolation="none")  # embedded as it is, not resampled
        ax.set_axis_off()
        self.y += height + 0.08
        for line in self._wrap(caption, self.columns):
            self._line(line, color="#444")
        self.y += _LINE * 0.5
