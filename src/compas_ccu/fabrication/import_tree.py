"""The attachment tree of an imported structure (``ccu import``): every plate joined to the
leading crease pair through the creases the drawings share, and the mechanism and design
document (``[[layout.patterns]]``) built from it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compas_ccu.design import Design
from compas_ccu.design.build import build
from compas_ccu.errors import DesignError
from compas_ccu.fabrication.crease_pairs import (
    PARTNER_TOLERANCE,
    CreasePair,
    crease_pattern,
    distance_to_polyline,
)
from compas_ccu.fabrication.plate_drawings import (
    SNAP,
    CreaseDrawing,
    PlateDrawing,
)
from compas_ccu.kinematics.mechanism import CreaseLink, Mechanism, PlateLink
from compas_ccu.strips.intrinsics import strip_intrinsics

__all__ = [
    "ImportedStructure",
    "row_order",
    "TreeMember",
    "structure_tree",
    "leading_document",
    "structure_document",
    "assemble_structure",
    "tree_depth",
]


@dataclass
class ImportedStructure:
    """Every plate of a folder of plate files, joined into one mechanism.

    Attributes
    ----------
    mechanism : Mechanism
        The leading crease pair's mechanism (:func:`import_design`, built) with every other
        plate attached where the drawings join it: it deploys the whole structure.
    plate_ids : list
        The plate id (XDATA; else the file name) of every mechanism plate.
    design : Design
        The whole structure's design (``document``): alpha, reference vertex, plate section.
    report : dict
        :func:`import_design`'s report, with ``attached`` (plate files joined to the pair),
        ``ids_written`` (whether the document keeps the plate ids).
    document : dict
        The design document of the whole structure (``layout.type = "patterns"``): what
        ``ccu import`` writes; its mechanism is ``mechanism``.
    """

    mechanism: Mechanism
    plate_ids: list
    design: Design
    report: dict
    document: dict = field(default_factory=dict)


def row_order(plate, crease, near, reference, where: str):
    """``near`` (the plate's crease vertices) in the order of ``reference`` (the same crease's
    vertices on the other plate): reversed or not, by the segment lengths; refused if they
    differ."""
    if len(near) != len(reference):
        raise DesignError(
            f"{plate.label} CREASE #{crease.handle}: {len(near) - 2} interior rulings, "
            f"{len(reference) - 2} on its partner {where}: the two plates of a crease have "
            "their rulings at the same crease points"
        )
    ref = np.linalg.norm(np.diff(reference, axis=0), axis=1)
    errors = []
    for flip in (False, True):
        mine = np.linalg.norm(np.diff(near[::-1] if flip else near, axis=0), axis=1)
        errors.append(float(np.abs(mine - ref).max()))
    flip = errors[1] < errors[0]
    if min(errors) > PARTNER_TOLERANCE * float(ref.sum()):
        j = int(np.argmax(np.abs(ref - np.linalg.norm(np.diff(near, axis=0), axis=1))))
        raise DesignError(
            f"{plate.label} CREASE #{crease.handle}: its segments differ from its partner's "
            f"{where} by {min(errors):.3g} m (segment {j}): the rulings do not meet the two "
            "creases at the same points"
        )
    return flip


@dataclass
class TreeMember:
    """A plate of the imported structure in mechanism order, its pattern as read (m).

    ``near`` is the plate's row on the crease with its parent (the leading crease for the
    leading pair), in the parent's order; ``far`` the other ends of its rulings.
    """

    plate: PlateDrawing
    crease: CreaseDrawing
    near: np.ndarray
    far: np.ndarray
    parent: int | None = None
    boundary: str = "near"
    flipped: bool = False


def structure_tree(pair: CreasePair, pairs: list, a_pattern, b_pattern):
    """The plates of a folder in mechanism order from the crease ``pair`` (its plate ``a``
    leads), and the creases between them: (plate_a, boundary_a, plate_b) member indices."""
    near_a, far_a, _ = a_pattern
    near_b, far_b, _ = b_pattern
    flip = row_order(pair.b, pair.crease_b, near_b, near_a, f"in {pair.a.label}")
    if flip:
        near_b, far_b = near_b[::-1], far_b[::-1]
    members = [
        TreeMember(pair.a, pair.crease_a, near_a, far_a),
        TreeMember(pair.b, pair.crease_b, near_b, far_b, 0, "near", flip),
    ]
    links = [(0, "near", 1)]
    done = {id(pair.a), id(pair.b)}
    by_plate: dict = {}
    for p in pairs:
        by_plate.setdefault(id(p.a), []).append((p.crease_a, p.b, p.crease_b))
        by_plate.setdefault(id(p.b), []).append((p.crease_b, p.a, p.crease_a))
    k = 0
    while k < len(members):
        member = members[k]
        plate = member.plate
        others = [item for item in by_plate.get(id(plate), []) if item[0] is not member.crease]
        if len(others) > 1:
            raise DesignError(
                f"{plate.label}: {len(others) + 1} creases; a CCU plate joins two creases "
                "(its near and far boundary)"
            )
        for own, child, child_crease in others:
            if id(child) in done:
                continue  # a loop closes here: the mechanism places every plate once
            d, _ = distance_to_polyline(member.far, own.points)
            if d.max() > SNAP * plate.size:
                raise DesignError(
                    f"{plate.label} CREASE #{own.handle}: the rulings of the plate do not end on "
                    f"it ({d.max():.3g} m off)"
                )
            near_c, far_c, _ = crease_pattern(child, child_crease)
            flip = row_order(child, child_crease, near_c, member.far, f"in {plate.label}")
            if flip:
                near_c, far_c = near_c[::-1], far_c[::-1]
            links.append((k, "far", len(members)))
            members.append(TreeMember(child, child_crease, near_c, far_c, k, "far", flip))
            done.add(id(child))
        k += 1
    return members, links


def leading_document(near, far, *, alpha, reference, name) -> dict:
    """The flat design of a leading plate: polyline crease, explicit rulings, single layout."""
    return {
        "design": {"name": name},
        "crease": {
            "profile": "polyline",
            "points": np.asarray(near).tolist(),
            "segments": len(near) - 1,
            "reference": float(reference),
            "state": "flat",
        },
        "rulings": {"type": "explicit", "points": np.asarray(far).tolist()},
        "deployment": {"alpha": float(alpha)},
        "layout": {"type": "single"},
    }


def structure_document(members, patterns, ids, *, alpha, reference, name) -> dict:
    """The design document of a whole structure: the leading plate's flat design and every
    other plate as a ``[[layout.patterns]]`` table (:mod:`compas_ccu.design.patterns`).

    ``members`` in mechanism order, ``patterns`` their (near, far) rows (m), ``ids`` their
    plate ids: written (``layout.leading`` and ``id``) when they are the integers 0 ... p - 1.
    """
    document = leading_document(*patterns[0], alpha=alpha, reference=reference, name=name)
    keep = sorted(str(i) for i in ids) == sorted(str(i) for i in range(len(ids))) and all(
        isinstance(i, int) for i in ids
    )
    layout: dict = {"type": "patterns"}
    if keep:
        layout["leading"] = int(ids[0])
    tables = []
    for member, (near, far), pid in zip(members[1:], patterns[1:], ids[1:]):
        table = {"parent": int(member.parent), "boundary": member.boundary}
        if keep:
            table["id"] = int(pid)
        table["near"] = np.asarray(near, dtype=float).tolist()
        table["far"] = np.asarray(far, dtype=float).tolist()
        tables.append(table)
    layout["patterns"] = tables
    document["layout"] = layout
    return document


def assemble_structure(members, links, patterns, *, alpha, reference, name):
    """The design of the leading plate and the mechanism of every member, from ``patterns``
    ((near, far) per member, in the members' order)."""
    design = Design(leading_document(*patterns[0], alpha=alpha, reference=reference, name=name))
    geometry = build(design)
    plates = [geometry.mechanism.plates[0]]
    for k, (member, (near, far)) in enumerate(zip(members[1:], patterns[1:]), start=1):
        plates.append(
            PlateLink(strip_intrinsics(near, far), member.parent, member.boundary, "ccu", k - 1)
        )
    creases = [
        CreaseLink(a, boundary, b, "ccu", k == 0, (0.0, 0.0, 1.0))
        for k, (a, boundary, b) in enumerate(links)
    ]
    return design, Mechanism(geometry.mechanism.leading, plates, creases)


def tree_depth(members) -> int:
    """Depth of the attachment tree (the leading plate: 0)."""
    depth = [0] * len(members)
    for k, member in enumerate(members[1:], start=1):
        depth[k] = depth[member.parent] + 1
    return max(depth)
