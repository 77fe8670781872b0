"""Layout ``patterns``: a whole structure given by the cut patterns of its plates.

``ccu import`` reads a folder of plate files back into a design file of this form
(docs/import.md). The leading plate is the ``[crease]`` polyline with its ``explicit``
``[rulings]`` (``state = "flat"``), as in a single-crease cut-pattern design; every other plate
is a ``[[layout.patterns]]`` table, in mechanism order::

    [[layout.patterns]]          # plate 1: the leading plate's partner
    parent = 0
    boundary = "near"
    near = [[x, y], ...]         # its crease row, in the order of the parent's row
    far = [[x, y], ...]          # the far end of every ruling

The mechanism attaches every plate as it attaches plates of any layout
(:class:`compas_ccu.kinematics.mechanism.Mechanism`): the mirror image of the parent's rulings
across the plane of their shared crease, with the plate's own ruling lengths. So a pattern is
valid when its crease row has the segment lengths of the parent's boundary row (the rulings of
both plates meet the crease at the same points) and when it is the pattern the mechanism
attaches: the same quads (sides and diagonals) to :data:`PATTERN_TOLERANCE` of the plate's
size. The design state of the structure is the flat-folded stack the mechanism places at 0
(``state = "flat"``).

>>> import numpy as np
>>> x = np.linspace(-1.0, 1.0, 5)
>>> near0 = np.c_[x, 0.2 * x**2, np.zeros(5)]
>>> far0 = near0 + [0.0, 0.3, 0.0]
>>> partner = {"parent": 0, "boundary": "near", "near": near0[:, :2].tolist(),
...            "far": (near0[:, :2] - [0.0, 0.3]).tolist(), "id": None}
>>> chain = pattern_chain([partner], near0, far0, None)
>>> len(chain.nears), chain.links, chain.plate_ids
(2, [(None, 'near', 'ccu', None), (0, 'near', 'ccu', 0)], [0, 1])
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from compas_ccu.errors import DesignError
from compas_ccu.kinematics.mechanism import CreaseLink

__all__ = ["PATTERN_TOLERANCE", "PatternChain", "pattern_chain", "check_patterns"]

#: Relative tolerance of a pattern against its parent and against the plate the mechanism
#: attaches: segment lengths (of the crease's length), quad sides and diagonals (of the plate's
#: size). The tolerance of ``ccu import``'s partner checks.
PATTERN_TOLERANCE = 1e-6

KEY = "layout.patterns"


class PatternChain(NamedTuple):
    """The plates of a ``patterns`` layout in mechanism order (leading plate first).

    ``nears``, ``fars``: (n + 1, 3) rows of every plate as given (z = 0; the leading plate in
    the local frame, the others in their own pattern coordinates); ``links``: (parent,
    boundary, relation, crease) per plate; ``creases``: CreaseLink per crease;
    ``plate_ids``: the output id of every plate.
    """

    nears: list
    fars: list
    links: list
    creases: list
    plate_ids: list


def _rows(near, far, boundary):
    return near if boundary == "near" else far


def _segments(row):
    return np.linalg.norm(np.diff(row[:, :2], axis=0), axis=1)


def pattern_chain(patterns: list, near0, far0, leading_id) -> PatternChain:
    """The mechanism's plates and creases of ``[[layout.patterns]]``, checked against each
    other.

    Parameters
    ----------
    patterns : list of dict
        The validated tables (``parent``, ``boundary``, ``near``, ``far``, ``id``), metres.
    near0, far0 : (n + 1, 3) float
        The leading plate's crease row and ruling ends (local frame, z = 0).
    leading_id : int or None
        ``layout.leading``: the leading plate's id.

    Raises
    ------
    DesignError
        A parent that is not an earlier plate, no leading plate's partner (parent 0, boundary
        'near'), a boundary that already holds a crease, a row of
        another number of points than the leading crease, a crease row whose segments differ
        from the parent's boundary row, ids that are not 0 ... p - 1 once each. The key is
        ``layout.patterns[i].KEY``.
    """
    n1 = len(near0)
    nears, fars = [np.asarray(near0, float)], [np.asarray(far0, float)]
    links = [(None, "near", "ccu", None)]
    creases = []
    taken = {}  # (plate, boundary) -> the plate joined there
    for i, table in enumerate(patterns):
        at, k = f"{KEY}[{i}]", i + 1
        parent, boundary = table["parent"], table["boundary"]
        if parent >= k:
            raise DesignError(
                f"must be an earlier plate, 0 (the leading plate) ... {k - 1} (pattern "
                f"{k - 2}), got {parent}: a plate hangs from a plate placed before it",
                key=f"{at}.parent",
            )
        if (parent, boundary) in taken:
            raise DesignError(
                f"the {boundary} boundary of plate {parent} already joins "
                f"{taken[(parent, boundary)]}: a boundary is one crease between two plates",
                key=f"{at}.boundary",
            )
        near = np.asarray(table["near"], dtype=float)
        far = np.asarray(table["far"], dtype=float)
        if len(near) != n1:
            raise DesignError(
                f"{len(near)} points, the leading crease has {n1} vertices (crease.segments + "
                "1): every plate has a ruling at every crease vertex",
                key=f"{at}.near",
            )
        row = _rows(nears[parent], fars[parent], boundary)
        ref, mine = _segments(row), _segments(near)
        miss = np.abs(mine - ref)
        if miss.max() > PATTERN_TOLERANCE * ref.sum():
            j = int(np.argmax(miss))
            hint = (
                "; reversed it matches: give the row in the order of the parent's"
                if np.abs(mine[::-1] - ref).max() <= PATTERN_TOLERANCE * ref.sum()
                else ""
            )
            raise DesignError(
                f"its segment {j} is {mine[j]:.9g} m, the parent's (plate {parent}, {boundary} "
                f"boundary) {ref[j]:.9g} m (difference {miss[j]:.3g} m > {PATTERN_TOLERANCE:g} "
                "of the crease's length): the rulings of both plates meet the crease at the "
                f"same points{hint}",
                key=f"{at}.near",
            )
        taken[(parent, boundary)] = f"plate {k} (pattern {i})"
        taken[(k, "near")] = f"its parent, plate {parent}"
        zeros = np.zeros((n1, 1))
        nears.append(np.c_[near, zeros])
        fars.append(np.c_[far, zeros])
        links.append((parent, boundary, "ccu", i))
        leading = (parent, boundary) == (0, "near")  # the leading crease: its plane is fixed
        creases.append(CreaseLink(parent, boundary, k, "ccu", leading, (0.0, 0.0, 1.0)))
    if (0, "near") not in taken:
        raise DesignError(
            "no pattern is the leading plate's partner across the leading crease (parent = 0, "
            "boundary = 'near'): a CCU structure mirrors the leading plate there",
            key=KEY,
        )
    return PatternChain(nears, fars, links, creases, _plate_ids(patterns, leading_id))


def _plate_ids(patterns, leading_id) -> list:
    ids = [t["id"] for t in patterns]
    if leading_id is None and all(i is None for i in ids):
        return list(range(len(patterns) + 1))
    if leading_id is None:
        raise DesignError(
            "required when the patterns have ids: the id of the leading plate",
            key="layout.leading",
        )
    missing = [i for i, pid in enumerate(ids) if pid is None]
    if missing:
        raise DesignError(
            "missing: give every pattern an id, or none (ids 0, 1, 2, ... in order)",
            key=f"{KEY}[{missing[0]}].id",
        )
    p = len(ids) + 1
    seen = {leading_id: "layout.leading"}
    for i, pid in enumerate(ids):
        where = f"{KEY}[{i}].id"
        if pid in seen:
            raise DesignError(f"{pid} is the id of {seen[pid]} too", key=where)
        if pid >= p:
            raise DesignError(
                f"must be 0 ... {p - 1} ({p} plates, each id once), got {pid}", key=where
            )
        seen[pid] = where
    if leading_id >= p:
        raise DesignError(
            f"must be 0 ... {p - 1} ({p} plates, each id once), got {leading_id}",
            key="layout.leading",
        )
    return [leading_id, *ids]


def _quads(near, far):
    """Sides and diagonals of every quad of a plate: (n, 6)."""
    a, b, c, d = near[:-1], near[1:], far[1:], far[:-1]
    pairs = ((a, b), (b, c), (c, d), (d, a), (a, c), (b, d))
    return np.stack([np.linalg.norm(q - p, axis=1) for p, q in pairs], axis=1)


def check_patterns(chain: PatternChain, placed_near, placed_far) -> None:
    """Every pattern against the plate the mechanism attaches (``placed_near``,
    ``placed_far``: (p, n + 1, 3), the flat-folded stack): the same quads.

    Raises
    ------
    DesignError
        A quad side or diagonal that differs by more than :data:`PATTERN_TOLERANCE` of the
        plate's size (``layout.patterns[i]`` named): its rulings do not make the angles with the
        crease that the mirror image of the parent's rulings makes.
    """
    for k in range(1, len(chain.nears)):
        given = _quads(chain.nears[k], chain.fars[k])
        placed = _quads(placed_near[k], placed_far[k])
        size = float(np.linalg.norm(np.ptp(np.r_[chain.nears[k], chain.fars[k]], axis=0)))
        miss = np.abs(given - placed)
        if miss.max() > PATTERN_TOLERANCE * size:
            j, e = np.unravel_index(int(np.argmax(miss)), miss.shape)
            what = ("crease segment", "ruling", "far edge", "ruling", "diagonal", "diagonal")[e]
            raise DesignError(
                f"plate {k} is not the mirror image of its parent's rulings across their "
                f"crease: in quad {j} its {what} is {given[j, e]:.9g} m, as the mechanism "
                f"attaches it {placed[j, e]:.9g} m (difference {miss[j, e]:.3g} m > "
                f"{PATTERN_TOLERANCE:g} of the plate's size); its rulings must make the same "
                "angles with the crease as the parent's",
                key=f"{KEY}[{k - 1}]",
            )
