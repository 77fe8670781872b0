"""Work limits: requests that would run for minutes or exhaust memory are refused up front.

Every limit has a default that a normal design stays far below; a user who really wants more
raises it, on the command line with ``--limit NAME=VALUE`` (any command) or in Python::

    from compas_ccu import limits
    with limits.raised(segments=100_000):
        model = CCUModel(design)

>>> LIMITS.segments, LIMITS.states
(20000, 10000)
>>> with raised(states=20):
...     check("states", 21, what="path states")
Traceback (most recent call last):
...
compas_ccu.errors.LimitError: 21 path states exceed the limit of 20 states; raise it with ...
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass, fields

from compas_ccu.errors import LimitError, OptionError

__all__ = ["Limits", "LIMITS", "check", "check_memory", "raised", "parse_limit", "apply"]


@dataclass
class Limits:
    """The work limits in force (one shared, mutable instance: :data:`LIMITS`)."""

    #: Crease segments (quads per plate).
    segments: int = 20_000
    #: Plates of a design.
    plates: int = 1_000
    #: Vertices of all plates of one state (plates x (2 segments + 2)).
    vertices: int = 500_000
    #: States of one path, animation or planarity table.
    states: int = 10_000
    #: Variants of a design-space sweep, trials of a study, spans of a scaling study.
    variants: int = 1_000_000
    #: Points of one curve file (CSV rows, DXF coordinate tags) or of one sampled curve.
    points: int = 200_000
    #: Worker processes of a local Dask cluster (explore, optimize --workers).
    workers: int = 256
    #: Estimated memory of one computation, GiB.
    memory_gib: float = 4.0
    #: Bytes of a design file opened in the studio (an upload or a file of the design folder).
    upload_bytes: int = 1_000_000


#: The limits in force.
LIMITS = Limits()

_NAMES = tuple(f.name for f in fields(Limits))
_UNITS = {"memory_gib": "GiB"}


def _advice(name: str, value) -> str:
    v = math.ceil(value) if name != "memory_gib" else round(float(value) + 0.05, 1)
    return f"raise it with --limit {name}={v} (Python: compas_ccu.limits.raised({name}={v}))"


def _number(value) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def check(name: str, value, *, what: str) -> None:
    """Refuse ``value`` of limit ``name`` above the limit in force.

    Raises
    ------
    LimitError
        Names the request, the limit and how to raise it.
    """
    limit = getattr(LIMITS, name)
    if value > limit:
        unit = _UNITS.get(name, name)
        raise LimitError(
            f"{_number(value)} {what} exceed the limit of {_number(limit)} {unit}; "
            f"{_advice(name, value)}"
        )


def check_memory(nbytes: float, *, what: str) -> None:
    """Refuse a computation whose arrays are estimated at ``nbytes`` above the memory limit."""
    gib = nbytes / 2**30
    if gib > LIMITS.memory_gib:
        raise LimitError(
            f"{what} needs about {gib:.3g} GiB, more than the limit of {LIMITS.memory_gib:g} "
            f"GiB; {_advice('memory_gib', gib)}"
        )


@contextmanager
def raised(**values):
    """Set limits for the duration of a block (any of :class:`Limits`' fields)."""
    previous = {}
    try:
        for name, value in values.items():
            if name not in _NAMES:
                raise OptionError(f"unknown limit {name!r}; limits: {', '.join(_NAMES)}")
            previous[name] = getattr(LIMITS, name)
            setattr(LIMITS, name, value)
        yield LIMITS
    finally:
        for name, value in previous.items():
            setattr(LIMITS, name, value)


def parse_limit(text: str) -> tuple:
    """``"segments=100000"`` -> ``("segments", 100000)``; a bad text is an OptionError."""
    name, sep, value = str(text).partition("=")
    name = name.strip()
    if not sep or name not in _NAMES:
        raise OptionError(
            f"--limit takes NAME=VALUE with NAME one of {', '.join(_NAMES)}, got {text!r}"
        )
    try:
        number = float(value) if name == "memory_gib" else int(value)
    except ValueError:
        raise OptionError(f"--limit {name} needs a number, got {value!r}") from None
    if not (math.isfinite(number) and number > 0):
        raise OptionError(f"--limit {name} must be > 0, got {value!r}")
    return name, number


def apply(texts) -> dict[str, int | float]:
    """The limits of ``--limit`` texts as keyword arguments of :func:`raised`: name -> value,
    the names given only.

    >>> apply(["segments=100000", "memory_gib=2.5"])
    {'segments': 100000, 'memory_gib': 2.5}
    """
    return dict(parse_limit(t) for t in texts or ())
