"""The one colour scheme of every picture: figures, animation, viewer and report.

Crease kinds follow the paper's Fig. 2: curved-crease folding (Q1, Q3) green, the synclastic
CCU crease (Q2, convex for both plates) blue, the anticlastic CCU crease (Q4, concave for both
plates) pink. Plates are two light plywood tones, alternating, so neighbours stay apart.
"""

from __future__ import annotations

__all__ = [
    "KIND_COLORS",
    "KIND_LABELS",
    "PLATE_TONES",
    "EDGE_COLOR",
    "RULING_COLOR",
    "FREE_EDGE_COLOR",
    "SEQUENTIAL_CMAP",
    "ANGLE_CMAP",
    "DIVERGING_CMAP",
    "kind_color",
    "plate_tone",
    "hex_to_rgb",
]

KIND_COLORS = {
    "synclastic": "#1f63d6",
    "anticlastic": "#d6307f",
    "ccf": "#229a4a",
    "mixed": "#8452c7",
}
KIND_LABELS = {
    "synclastic": "synclastic (CCU, Σβ < 2π)",
    "anticlastic": "anticlastic (CCU, Σβ > 2π)",
    "ccf": "curved-crease folding (Σβ = 2π)",
    "mixed": "mixed (kind changes along the crease)",
}
PLATE_TONES = ("#ecdcbc", "#d5bd93")
EDGE_COLOR = "#3b3326"
RULING_COLOR = "#9a8c74"
FREE_EDGE_COLOR = "#2b2b2b"
SEQUENTIAL_CMAP = "viridis"
ANGLE_CMAP = "plasma"
# paper Fig. 7: tension blue, compression red (positive values = tension)
DIVERGING_CMAP = "RdBu"


def kind_color(kind: str) -> str:
    """Hex colour of a crease kind (``synclastic``, ``anticlastic``, ``ccf``, ``mixed``)."""
    try:
        return KIND_COLORS[kind]
    except KeyError:
        raise ValueError(
            f"unknown crease kind {kind!r}; expected one of {sorted(KIND_COLORS)}"
        ) from None


def plate_tone(index: int) -> str:
    """Hex colour of plate ``index`` (two alternating tones)."""
    return PLATE_TONES[index % len(PLATE_TONES)]


def hex_to_rgb(color: str) -> tuple:
    """``'#rrggbb'`` to an (r, g, b) tuple of floats in [0, 1]."""
    c = color.lstrip("#")
    if len(c) != 6:
        raise ValueError(f"expected a colour '#rrggbb', got {color!r}")
    return tuple(int(c[i : i + 2], 16) / 255.0 for i in (0, 2, 4))
