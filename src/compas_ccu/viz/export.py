"""Write matplotlib figures to files."""

from __future__ import annotations

from pathlib import Path

from compas_ccu.errors import OptionError

__all__ = ["save_figure", "FIGURE_FORMATS"]

FIGURE_FORMATS = ("png", "svg", "pdf")


def save_figure(fig, stem, *, formats=("png", "svg"), dpi: int = 150) -> list:
    """Save ``fig`` as ``stem.png``, ``stem.svg``, ... and return the paths.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    stem : str or Path
        Path without suffix; its folder is created.
    formats : sequence of {"png", "svg", "pdf"}
    dpi : int
        Resolution of raster formats.
    """
    formats = [formats] if isinstance(formats, str) else list(formats)
    bad = [f for f in formats if f not in FIGURE_FORMATS]
    if bad or not formats:
        raise OptionError(f"figure formats must be among {FIGURE_FORMATS}, got {formats}")
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = []
    for fmt in formats:
        path = stem.with_name(stem.name + "." + fmt)
        fig.savefig(path, dpi=dpi, metadata=None if fmt != "png" else {"Software": "compas_ccu"})
        paths.append(path)
    return paths
