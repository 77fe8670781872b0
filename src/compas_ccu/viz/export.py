"""Write matplotlib figures to files."""

from __future__ import annotations

from pathlib import Path

from compas_ccu.errors import OptionError

__all__ = ["save_figure", "FIGURE_FORMATS"]

FIGURE_FORMATS = ("png", "svg", "pdf")


def save_figure(fig, stem, *, formats=("png", "svg"), dpi: int = 150, size=None) -> list:
    """Save ``fig`` as ``stem.png``, ``stem.svg``, ... and return the paths.

    SVG text stays text (``<text>`` elements, searchable and editable), not outlines.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    stem : str or Path
        Path without suffix; its folder is created.
    formats : sequence of {"png", "svg", "pdf"}
    dpi : int
        Resolution of raster formats (a PNG is ``size x dpi`` pixels).
    size : (float, float), optional
        Figure size, inches (width, height); default: the figure's own.

    Raises
    ------
    compas_ccu.errors.OptionError
        An unknown format, a ``dpi`` below 10 or above 2400, a size not positive.

    Examples
    --------
    >>> import tempfile
    >>> from matplotlib.figure import Figure
    >>> fig = Figure()
    >>> _ = fig.add_subplot().set_title("span 2.50 m")
    >>> (png, svg) = save_figure(fig, tempfile.mkdtemp() + "/f", dpi=50, size=(4, 3))
    >>> from PIL import Image; Image.open(png).size, "<text" in svg.read_text()
    ((200, 150), True)
    """
    formats = [formats] if isinstance(formats, str) else list(formats)
    bad = [f for f in formats if f not in FIGURE_FORMATS]
    if bad or not formats:
        raise OptionError(f"figure formats must be among {FIGURE_FORMATS}, got {formats}")
    if isinstance(dpi, bool) or not isinstance(dpi, (int, float)) or not 10 <= dpi <= 2400:
        raise OptionError(f"dpi must be a number from 10 to 2400, got {dpi!r}")
    if size is not None:
        try:
            w, h = (float(x) for x in size)
        except (TypeError, ValueError):
            raise OptionError(f"size must be (width, height) in inches, got {size!r}") from None
        if not (0.0 < w <= 200.0 and 0.0 < h <= 200.0):
            raise OptionError(f"size must be positive inches up to 200, got {size!r}")
        fig.set_size_inches(w, h)
    import matplotlib

    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = []
    with matplotlib.rc_context({"svg.fonttype": "none"}):  # SVG text as <text>
        for fmt in formats:
            path = stem.with_name(stem.name + "." + fmt)
            meta = None if fmt != "png" else {"Software": "compas_ccu"}
            fig.savefig(path, dpi=dpi, metadata=meta)
            paths.append(path)
    return paths
