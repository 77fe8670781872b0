"""The controls and the layout of the viewer's figure: slider, Play / Pause, toggles, camera,
the 3D box, the title and the state read-out.

Plain dictionaries of plotly layout keys, no plotly object: the figure is put together by
:mod:`compas_ccu.viz.viewer_plot`.
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu.key_figures import state_figures
from compas_ccu.tolerances import EXACT_RELATIVE
from compas_ccu.viz.camera import camera
from compas_ccu.viz.viewer_traces import FONT_COLOR
from compas_ccu.viz.views import readout

__all__ = [
    "figure_layout",
    "slider",
    "play_buttons",
    "toggle_menus",
    "readout_annotation",
    "readouts",
    "eye",
    "axis_ranges",
    "scene_layout",
    "figure_title",
    "GROUPS",
]

_PAD = 0.04  # axis padding, fraction of the largest extent
_PAPER = "#ffffff"
_PANE = "#f3f1ec"
_GRID = "#dedad2"
_SLIDER_LABELS = 6  # slider steps labelled (about; the ends always)
_ON, _OFF = "☑", "☐"
_TOGGLES = (
    ("plates", "Plates"),
    ("creases", "Creases"),
    ("rulings", "Rulings"),
    ("cut", "Cut patterns"),
)
#: The legend groups: the first three change with the state, the cut patterns are static.
GROUPS = ("plates", "creases", "rulings", "cut")
_ANIMATE = {"mode": "immediate", "transition": {"duration": 0}}
_BUTTON_STYLE = {
    "type": "buttons",
    "showactive": True,
    "bgcolor": "#f7f4ee",
    "bordercolor": "#9a8c74",
    "borderwidth": 1,
    "font": {"size": 13, "color": FONT_COLOR},
    "pad": {"r": 12, "t": 0, "l": 0, "b": 0},
    "xanchor": "right",
    "yanchor": "top",
    "x": 0.0,
}

_DEFAULT_CAMERA = {
    "eye": {"x": 0.7, "y": -1.05, "z": 0.5},
    "center": {"x": 0.0, "y": 0.0, "z": -0.08},
    "up": {"x": 0.0, "y": 0.0, "z": 1.0},
    "projection": {"type": "perspective"},
}
_READOUT_NAME = "ccu-readout"


def readout_annotation(text: str) -> dict:
    """The state read-out above the slider (α, span, rise, plate length)."""
    return {
        "name": _READOUT_NAME,
        "text": text,
        "xref": "paper",
        "yref": "paper",
        "x": 0.0,
        "y": 0.0,
        "xanchor": "left",
        "yanchor": "bottom",
        "yshift": 4,
        "showarrow": False,
        "font": {"size": 15, "color": FONT_COLOR},
        "bgcolor": "rgba(255,255,255,0.85)",
    }


def readouts(structures) -> list:
    """One line per state: α, then span, rise and plate length (the state's key figures)."""
    return [f"α = {s.alpha:.4g}° · {readout(state_figures(s))}" for s in structures]


def eye(view) -> dict:
    """A plotly scene camera for a view name or ``"azimuth,elevation"`` (see render.camera)."""
    cam = camera(view)
    az, el = math.radians(cam.azimuth), math.radians(cam.elevation)
    r = 1.9
    position = {
        "x": r * math.cos(el) * math.cos(az),
        "y": r * math.cos(el) * math.sin(az),
        "z": r * math.sin(el),
    }
    up = {"x": 0.0, "y": 0.0, "z": 1.0}
    if abs(cam.elevation) > 89.0:  # from above: y up the screen
        up = {"x": 0.0, "y": 1.0, "z": 0.0}
    kind = "perspective" if cam.distance is not None else "orthographic"
    return {
        "eye": position,
        "up": up,
        "center": {"x": 0.0, "y": 0.0, "z": 0.0},
        "projection": {"type": kind},
    }


def axis_ranges(lo: np.ndarray, hi: np.ndarray):
    """Padded axis ranges and the matching manual aspect ratio of a box (lo, hi : (3,))."""
    ext = np.maximum(hi - lo, EXACT_RELATIVE)
    pad = _PAD * float(ext.max())
    lo, hi = lo - pad, hi + pad
    ext = hi - lo
    ratio = ext / ext.max()
    ranges = [[float(a), float(b)] for a, b in zip(lo, hi)]
    return ranges, {"x": float(ratio[0]), "y": float(ratio[1]), "z": float(ratio[2])}


def scene_layout(ranges, ratio) -> dict:
    """Relayout keys that set the 3D box (fixed ranges, manual aspect)."""
    out = {"scene.aspectmode": "manual", "scene.aspectratio": ratio}
    for name, r in zip("xyz", ranges):
        out[f"scene.{name}axis.range"] = r
    return out


def figure_title(model, kinds: list, counts: dict, alphas: np.ndarray) -> dict:
    """The title: the design's name, then its plates, creases by kind, angles and the path."""
    name = getattr(model.design, "name", None) or "design"
    ncreases = sum(counts.values())
    by_kind = ", ".join(f"{counts[k]} {k}" for k in kinds)
    plates = len(model.plate_ids)
    sub = (
        f"{plates} plates · {ncreases} creases ({by_kind}) · design α = "
        f"{model.alpha_design:.4g}° · deployment limit α = {model.alpha_limit:.4g}° · "
        f"path α = 0° → {alphas[-1]:.4g}° in {len(alphas) - 1} steps"
    )
    return {
        "text": f"<b>{name}</b> — curved-crease unfolding",
        "subtitle": {"text": sub, "font": {"size": 13, "color": "#555555"}},
        "x": 0.01,
        "xanchor": "left",
        "y": 0.985,
        "yanchor": "top",
        "font": {"size": 20, "color": FONT_COLOR},
    }


def _label(alpha: float) -> str:
    return f"{alpha:.4g}°"


def _slider_labels(alphas) -> list:
    """About :data:`_SLIDER_LABELS` labelled steps (the ends always), the others blank."""
    every = max(1, math.ceil((len(alphas) - 1) / _SLIDER_LABELS))
    labels = [
        _label(a) if k % every == 0 or k == len(alphas) - 1 else "" for k, a in enumerate(alphas)
    ]
    if len(alphas) > 1 and (len(alphas) - 1) % every and (len(alphas) - 1) % every < every / 2:
        labels[(len(alphas) - 1) // every * every] = ""  # too close to the last label
    return labels


def slider(alphas) -> dict:
    """The slider through the states (frames ``"0" .. str(m - 1)``), on the last one."""
    return {
        "active": len(alphas) - 1,
        "x": 0.0,
        "len": 1.0,
        "xanchor": "left",
        "y": 0.0,
        "yanchor": "top",
        "pad": {"t": 8, "b": 8, "l": 0, "r": 10},
        "currentvalue": {"visible": False},  # the read-out annotation shows the state
        "font": {"size": 11, "color": FONT_COLOR},
        "bgcolor": "#efe9dc",
        "activebgcolor": "#d5bd93",
        "bordercolor": "#9a8c74",
        "tickcolor": "#9a8c74",
        "transition": {"duration": 0},
        "steps": [
            {
                "label": label,
                "method": "animate",
                "args": [[str(k)], {**_ANIMATE, "frame": {"duration": 0, "redraw": True}}],
            }
            for k, label in enumerate(_slider_labels(alphas))
        ],
    }


def play_buttons() -> dict:
    """The Play / Pause menu: Play runs the whole path from α = 0."""
    return {
        **_BUTTON_STYLE,
        "direction": "left",
        "showactive": False,
        "y": -0.005,
        "pad": {"r": 12, "t": 28},
        "buttons": [
            {
                "label": "▶ Play",
                "method": "animate",
                "args": [
                    None,
                    {
                        **_ANIMATE,
                        "fromcurrent": False,
                        "frame": {"duration": 140, "redraw": True},
                    },
                ],
            },
            {
                "label": "❚❚ Pause",
                "method": "animate",
                "args": [[None], {**_ANIMATE, "frame": {"duration": 0, "redraw": False}}],
            },
        ],
    }


def toggle_menus(groups: list, structure_box: tuple, whole_box: tuple) -> list:
    """One toggle menu per legend group (:data:`GROUPS`), after the Play / Pause menu.

    Parameters
    ----------
    groups : list of str
        The legend group of every trace of the figure, in trace order.
    structure_box, whole_box : (ranges, ratio)
        :func:`axis_ranges` of the structure's box and of the box with the cut patterns:
        showing the cut patterns widens the box, hiding them narrows it again.
    """
    toggles = []
    for row, (group, label) in enumerate(_TOGGLES):
        ids = [i for i, x in enumerate(groups) if x == group]
        # a one-button menu per group: the button is "active" while the group is shown, and a
        # click on the active button runs args2 (hide); its label shows the state (☑ / ☐)
        key = f"updatemenus[{1 + row}].buttons[0].label"
        # hidden groups stay in the legend (greyed, a click there shows them again), except the
        # cut patterns: they need the wider box that only this button sets
        off = False if group == "cut" else "legendonly"
        show = [{"visible": True}, {key: f"{_ON} {label}"}, ids]
        hide = [{"visible": off}, {key: f"{_OFF} {label}"}, ids]
        if group == "cut":
            show[1].update(scene_layout(*whole_box))
            hide[1].update(scene_layout(*structure_box))
        shown = group != "cut"
        toggles.append(
            {
                **_BUTTON_STYLE,
                "name": f"toggle {group}",
                "active": 0 if shown else -1,
                "y": 1.0 - 0.085 * row,
                "buttons": [
                    {
                        "label": f"{_ON if shown else _OFF} {label}",
                        "method": "update",
                        "args": show,
                        "args2": hide,
                    }
                ],
            }
        )
    return toggles


def _axis(name: str) -> dict:
    """One axis of the 3D scene, in metres."""
    return {
        "showbackground": True,
        "backgroundcolor": _PANE,
        "gridcolor": _GRID,
        "zerolinecolor": "#c9c3b6",
        "color": "#666666",
        "tickfont": {"size": 13},
        "nticks": 6,
        "ticksuffix": " m",
        "title": {"text": name, "font": {"size": 16}},
    }


def figure_layout(heading: dict, view, alphas, last_readout: str, menus: list) -> dict:
    """The figure's layout: title, legend, 3D scene and camera, slider, read-out, menus.

    Parameters
    ----------
    heading : dict
        :func:`figure_title`.
    view : str or None
        The opening camera (:func:`eye`); None: a perspective from the front right.
    alphas : (m,) float
        The states (:func:`slider`).
    last_readout : str
        The read-out of the state the figure opens on.
    menus : list of dict
        The update menus: :func:`play_buttons`, then :func:`toggle_menus`.
    """
    return {
        "template": "none",
        "title": heading,
        "paper_bgcolor": _PAPER,
        "font": {"family": "Helvetica, Arial, sans-serif", "color": FONT_COLOR},
        "margin": {"l": 140, "r": 10, "t": 88, "b": 110},
        "showlegend": True,
        "legend": {
            "x": 1.0,
            "xanchor": "right",
            "y": 1.0,
            "yanchor": "top",
            "bgcolor": "rgba(255,255,255,0.85)",
            "bordercolor": "#d9d3c6",
            "borderwidth": 1,
            "font": {"size": 12},
            "groupclick": "togglegroup",
            "itemsizing": "constant",
        },
        "scene": {
            "xaxis": _axis("x"),
            "yaxis": _axis("y"),
            "zaxis": _axis("z"),
            "camera": _DEFAULT_CAMERA if view is None else eye(view),
            "dragmode": "turntable",
        },
        "sliders": [slider(alphas)],
        "annotations": [readout_annotation(last_readout)],
        "updatemenus": menus,
        "uirevision": "ccu-viewer",
        "hoverlabel": {"bgcolor": "#ffffff", "font": {"size": 12}},
    }
