"""The offline viewer: one self-contained HTML page to explore a deployment in 3D.

:func:`viewer_figure` builds a plotly figure of a model along its deployment path, from the
flat-folded stack (α = 0) to a target angle: plates, creases coloured by kind, rulings and
(hidden at first) the cut patterns laid out on the ground behind the structure, or the sheets of
the fabrication output with every part at its nested place (``sheets=``: a workshop plan or the
``sheets.json`` that ``ccu fabricate`` writes). A slider (with
Play / Pause) moves through the states; toggle buttons show and hide plates,
creases, rulings and cut patterns. :func:`write_viewer` writes it as a single HTML file that works
offline (plotly.js is bundled, nothing is loaded from the network).

Everything is drawn from :func:`compas_ccu.viz.scene.scene_from_structure` in the colours of
:mod:`compas_ccu.viz.colors`, like every other picture of the package. Plotly is imported only
when a figure is built.

The page is written here; the figure is :mod:`compas_ccu.viz.viewer_plot`, its arrays
:mod:`compas_ccu.viz.viewer_data`, its traces :mod:`compas_ccu.viz.viewer_traces`, its
controls and layout :mod:`compas_ccu.viz.viewer_controls`, and the places of the cut patterns
and sheets on the ground :mod:`compas_ccu.viz.viewer_ground` (their public names are
importable from here too).
"""

from __future__ import annotations

from html import escape as html_escape
from pathlib import Path

from compas_ccu.viz.viewer_ground import cut_pattern_layout, sheet_document, sheet_grid_layout
from compas_ccu.viz.viewer_plot import viewer_figure

__all__ = [
    "viewer_figure",
    "write_viewer",
    "cut_pattern_layout",
    "sheet_grid_layout",
    "sheet_document",
    "VIEWER_DIV_ID",
]

VIEWER_DIV_ID = "ccu-viewer"
"""``id`` of the plot ``<div>`` in the page written by :func:`write_viewer`."""


def write_viewer(
    model,
    path,
    *,
    steps: int = 24,
    alpha: float | None = None,
    title: str | None = None,
    view=None,
    pattern_offsets=None,
    sheets=None,
) -> Path:
    """Write the viewer of :func:`viewer_figure` as one self-contained, offline HTML page.

    plotly.js is bundled in the page (no CDN, no MathJax) and the page loads nothing from the
    network. Coordinates are stored as float32 binary arrays (≲ 1e-6 m at metre scale), so the
    page is plotly.js (4.8 MB) plus ~63 kB per state for the 10-plate, 64-segment vault: 5.9 MB
    at ``steps=12`` and 6.7 MB at the default ``steps=24`` (the 2-plate cone: 5.2 MB at 24).
    The plot ``<div>`` has the id :data:`VIEWER_DIV_ID` (``"ccu-viewer"``).

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    path : str or pathlib.Path
        The ``.html`` file to write (its folder is created).
    steps, alpha, title, view, pattern_offsets, sheets
        As in :func:`viewer_figure`.

    Returns
    -------
    pathlib.Path
        The written file.

    Examples
    --------
    >>> import tempfile
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/vault.toml")
    >>> out = write_viewer(model, tempfile.mkdtemp() + "/vault.html", steps=6)
    >>> out.stat().st_size > 4_000_000, "cdn.plot.ly/plotly" in out.read_text(encoding="utf-8")
    (True, False)
    """
    fig = viewer_figure(
        model,
        steps=steps,
        alpha=alpha,
        title=title,
        view=view,
        pattern_offsets=pattern_offsets,
        sheets=sheets,
    )
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    html = fig.to_html(
        include_plotlyjs=True,
        include_mathjax=False,
        full_html=True,
        auto_play=False,
        div_id=VIEWER_DIV_ID,
        default_width="100%",
        default_height="max(680px, 100vh)",  # the whole window, with room for the menus
        config={"displaylogo": False, "responsive": True},
    )
    # a tab title, and no page margin: the plot fills the window without scroll bars
    name = title if title is not None else getattr(model.design, "name", None) or "design"
    name = html_escape(f"{name} — CCU viewer")
    head = f"<title>{name}</title>\n<style>body {{margin: 0;}}</style>\n</head>"
    html = html.replace("</head>", head, 1)
    path.write_text(html, encoding="utf-8")
    return path
