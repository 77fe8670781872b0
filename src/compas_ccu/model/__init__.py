"""The deployable model: one object that carries a design through every layer above it.

>>> from compas_ccu.model import load_model
>>> load_model("examples/vault.toml").deploy().alpha
30.0
"""

from __future__ import annotations

from compas_ccu.model.ccu_model import CCUModel, load_model
from compas_ccu.model.inverse import RoundTrip, flat_design, patterns_design, round_trip

__all__ = [
    "CCUModel",
    "load_model",
    "flat_design",
    "patterns_design",
    "round_trip",
    "RoundTrip",
]
