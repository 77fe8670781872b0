"""Undoing the thickness correction of drawn cut patterns (``ccu import``): ``ccu fabricate``
draws the patterns of plates with thickness (axis-shift hinges, docs/thickness.md); the import
iterates the shifts back to the zero-thickness patterns the design is made of.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from compas_ccu.errors import DesignError, GeometryError
from compas_ccu.fabrication.crease_pairs import (
    stack_upper_leads,
)
from compas_ccu.fabrication.import_tree import (
    TreeMember,
    assemble_structure,
    structure_tree,
    tree_depth,
)
from compas_ccu.fabrication.plate_drawings import (
    SNAP,
)
from compas_ccu.geometry import fit_planes, unit
from compas_ccu.kinematics.mechanism import Mechanism
from compas_ccu.kinematics.plates import hinge_and_rulings
from compas_ccu.thickness.axis_shift import crease_sides, place_thick, vertex_offsets
from compas_ccu.tolerances import EXACT_RELATIVE, UNDO_ABSOLUTE, UNDO_RELATIVE

__all__ = [
    "thickness_shifts",
    "UNDO_TOLERANCE",
    "UNDO_RELATIVE",
    "UNDO_ITERATIONS",
    "PATIENCE_CHANGE",
    "undo_correction",
    "drawn_thickness",
    "zero_thickness_rows",
]


def thickness_shifts(mechanism: Mechanism, thickness: float, alpha: float):
    """The thickness correction of cut patterns: how far every crease vertex of every plate
    moves along its ruling into the plate (paper §5.3), as ``ccu fabricate`` applies it.

    The axis-shift hinges of :class:`compas_ccu.thickness.ThickModel` at the design state: the
    thick plates are placed at the reference angle ``alpha``, and every crease's correction
    (:class:`compas_ccu.thickness.axis_shift.HingePlanes`) moves the crease rows of both its
    plates.

    Parameters
    ----------
    mechanism : Mechanism
        The zero-thickness mechanism.
    thickness : float
        Plate thickness, m.
    alpha : float
        Design reflection angle, degrees.

    Returns
    -------
    near, far : (p, n + 1) float
        Shifts of the near and the far row of every mechanism plate, m (0 on free boundaries).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")  # rulings orthogonal to the crease
    >>> near, far = thickness_shifts(model.mechanism, 0.008, model.alpha_design)
    >>> near.shape, bool(np.abs(near).max() < 1e-15)  # planar offset creases: no correction
    ((2, 49), True)
    """
    s0 = np.atleast_1d(mechanism.leading.s0_for_alpha(math.radians(alpha)))
    sides = crease_sides(mechanism, mechanism.place(s0))
    corrections = place_thick(mechanism, s0, thickness, sides).corrections[0]
    p, m = len(mechanism.plates), mechanism.segments + 1
    near, far = np.zeros((p, m)), np.zeros((p, m))
    for ci, link in enumerate(mechanism.creases):
        (near if link.boundary_a == "near" else far)[link.plate_a] = corrections[ci]
        near[link.plate_b] = corrections[ci]
    return near, far


#: Undoing the thickness correction: the shifts are iterated until they change by less than
#: this (m) or :data:`UNDO_RELATIVE` times the largest plate's size (both from
#: :mod:`compas_ccu.tolerances`) ...
UNDO_TOLERANCE = UNDO_ABSOLUTE


#: ... within this many iterations.
UNDO_ITERATIONS = 20


#: A leading crease whose shifts still change by more than this (m) after the attachment
#: tree's depth + 3 iterations is not the one the correction was computed from: the next is
#: tried (the design angle is the reflection angle of the design's leading crease).
PATIENCE_CHANGE = 1e-6


def _shift_update(mechanism: Mechanism, near_shift, far_shift, thickness: float, alpha: float):
    """One step of undoing the thickness correction: the shifts that take the zero-thickness
    crease rows (planar) to the corrected rows read, measured on the current mechanism.

    ``ccu fabricate``'s corrected crease points ``M`` (the rows read: the current rows moved
    along their rulings by the current shifts) lie on the rulings, and their facing-face points
    ``M + σ t/2 ν`` lie in the hinge plane P (:class:`~compas_ccu.thickness.axis_shift.
    HingePlanes`): P is the plane through them. The zero-thickness crease lies in the plane Q,
    P moved back by the mean offset ``mean(σ t/2 ν · n)``; it is where the rulings cross Q.
    Only the placed ruling lines of the current patterns are used, not their crease rows: the
    step fixes where a row lies along its rulings, which the forward correction
    (:func:`thickness_shifts`) hardly sees (:func:`undo_correction`).
    """
    s0 = np.atleast_1d(mechanism.leading.s0_for_alpha(math.radians(alpha)))
    placed = mechanism.place(s0)
    sides = crease_sides(mechanism, placed)
    near, far = placed.near[0], placed.far[0]
    half = 0.5 * float(thickness)
    new_near, new_far = np.zeros_like(near_shift), np.zeros_like(far_shift)
    for ci, link in enumerate(mechanism.creases):
        a = link.plate_a
        row, away = hinge_and_rulings(near[a], far[a], link.boundary_a)
        shift = (near_shift if link.boundary_a == "near" else far_shift)[a]
        offset = sides[ci, 0] * half * vertex_offsets(near[a], far[a])
        hinge = row + shift[:, None] * away + offset
        origin, normal, _ = fit_planes(hinge[None], np.asarray(link.design_normal))
        origin, normal = origin[0], normal[0]
        origin = origin - float((offset @ normal).mean()) * normal  # P back to Q
        slope = away @ normal
        with np.errstate(divide="ignore", invalid="ignore"):
            along = -((row - origin) @ normal) / slope
        new = np.where(np.abs(slope) > EXACT_RELATIVE, shift - along, 0.0)
        (new_near if link.boundary_a == "near" else new_far)[a] = new
        new_near[link.plate_b] = new
    return new_near, new_far


def undo_correction(folder, members, links, thickness, *, alpha, reference, name, patience=None):
    """The zero-thickness patterns whose thickness-corrected patterns are those read.

    ``ccu fabricate`` moves every crease vertex along its ruling into the plate by the
    correction ``F(P0)`` of the zero-thickness patterns ``P0`` (:func:`thickness_shifts`); the
    rulings keep their lines, so ``P0 = P_read - s u`` with ``u`` the rulings' directions read
    and ``s`` the solution of ``s = F(P_read - s u)``. Iterating ``F`` alone does not find it:
    ``F`` hardly changes when a crease row slides along its rulings (the corrected crease is
    where the rulings cross the hinge plane, wherever the row was), so that iteration stops
    anywhere along such a slide (fig11a: 1.7e-5 m from the original). The planar step
    :func:`_shift_update` fixes exactly those slides (a CCU crease is planar) but is nearly
    blind to others (fig12b: it stops 1.2e-7 m off); each step alternates the two, which
    converges to the common solution (one plate of the attachment tree per step).

    Returns
    -------
    patterns : list of (near, far)
    info : dict
        ``thickness``, ``iterations``, ``largest`` (largest shift, m), ``change`` (the last
        iteration's, m): the forward correction of the patterns returned differs from the
        shifts undone by at most ``change``.

    Raises
    ------
    DesignError
        No convergence within :data:`UNDO_ITERATIONS` (folder, thickness and last change named).
    """
    read = [(m.near, m.far) for m in members]
    ruling = [unit(far - near) for near, far in read]
    p, m = len(members), len(members[0].near)
    shifts = (np.zeros((p, m)), np.zeros((p, m)))

    def undone(near_shift, far_shift):
        return [
            (near - sn[:, None] * u, far + sf[:, None] * u)
            for (near, far), u, sn, sf in zip(read, ruling, near_shift, far_shift)
        ]

    def mechanism(near_shift, far_shift):
        patterns = undone(near_shift, far_shift)
        return assemble_structure(
            members, links, patterns, alpha=alpha, reference=reference, name=name
        )[1]

    change = math.inf
    tolerance = max(UNDO_TOLERANCE, UNDO_RELATIVE * max(m.plate.size for m in members))
    for iteration in range(1, UNDO_ITERATIONS + 1):
        planar = _shift_update(mechanism(*shifts), *shifts, thickness, alpha)
        forward = thickness_shifts(mechanism(*planar), thickness, alpha)
        change = float(
            max(
                np.abs(np.subtract(planar, shifts)).max(),
                np.abs(np.subtract(forward, planar)).max(),
            )
        )
        shifts = forward
        if patience is not None and iteration >= patience and change > PATIENCE_CHANGE:
            break  # this leading crease is not the one the correction was made with
        if change <= tolerance:
            info = {
                "thickness": float(thickness),
                "iterations": iteration,
                "largest": float(np.abs(shifts).max()),
                "change": change,
            }
            return undone(*shifts), info
    raise DesignError(
        f"{folder}: undoing the thickness correction of the cut patterns ({thickness:g} m "
        f"plates, fabrication.json) did not converge in {iteration} iterations (the "
        f"shifts still change by {change:.3g} m > {tolerance:.3g} m); import the patterns "
        "as drawn (as_drawn=True, ccu import --as-drawn)"
    )


def drawn_thickness(folder, manifest: dict, as_drawn: bool):
    """The plate thickness whose correction the patterns carry: ``fabrication.json``'s, None
    for hand-drawn folders (no ``fabrication.json``) and ``as_drawn``."""
    if as_drawn:
        return None
    t = manifest.get("thickness")
    if t is None:
        return None
    if isinstance(t, bool) or not isinstance(t, (int, float)) or not (math.isfinite(t) and t > 0):
        raise DesignError(
            f"{folder}: fabrication.json's thickness must be a length > 0 m, got {t!r} (as_drawn / "
            "--as-drawn imports the patterns as drawn)"
        )
    return float(t)


def _rows_as(member: TreeMember, other: TreeMember, undone) -> tuple:
    """``undone`` (the zero-thickness rows of ``other``, the same plate in another attachment
    tree) in the rows of ``member``: the same rows, swapped (the tree reaches the plate from
    its other crease) and / or reversed, matched on the points read."""
    best = None
    for near_o, far_o, near_u, far_u in (
        (other.near, other.far, *undone),
        (other.far, other.near, undone[1], undone[0]),
    ):
        for step in (1, -1):
            d = max(
                np.abs(member.near - near_o[::step]).max(),
                np.abs(member.far - far_o[::step]).max(),
            )
            if best is None or d < best[0]:
                best = (d, near_u[::step], far_u[::step])
    if best[0] > SNAP * member.plate.size:  # pragma: no cover - the same drawing read twice
        raise DesignError(f"{member.plate.label}: its rows differ between two crease trees")
    return best[1], best[2]


def _chain(first: list, rest):
    """The items of ``first``, then those of ``rest()`` (called only when they are needed)."""
    yield from first
    yield from rest()


def zero_thickness_rows(folder, manifest, pairs, pair, patterns, *, alpha, reference, as_drawn):
    """The members of the structure led by ``pair``, their zero-thickness patterns and the
    undoing report (``None`` when the patterns are taken as drawn).

    The correction is undone on the attachment tree of the design's leading crease, whose
    reflection angle ``alpha`` is: ``pair``'s first, then every other crease's (the first that
    converges; a folder records no leading crease). ``info["leading"]`` names it.
    """
    a_pattern, b_pattern = patterns[pair.key]
    members, links = structure_tree(pair, pairs, a_pattern, b_pattern)
    thickness = drawn_thickness(folder, manifest, as_drawn)
    name = manifest.get("design") or Path(folder).name
    if thickness is None:
        return members, links, [(m.near, m.far) for m in members], None

    def others():
        # the other creases from the shallowest tree (a mechanism grows from the middle of
        # its layout)
        roots = []
        for other in pairs:
            if other.key != pair.key:  # (``pair`` may be a reordered copy)
                other = stack_upper_leads(other, patterns, manifest)
                roots.append((other, *structure_tree(other, pairs, *patterns[other.key])))
        return sorted(roots, key=lambda root: tree_depth(root[1]))

    first = None
    for root, tree, tree_links in _chain([(pair, members, links)], others):
        try:
            undone, info = undo_correction(
                folder, tree, tree_links, thickness, alpha=alpha, reference=reference,
                name=name, patience=tree_depth(tree) + 3,
            )  # fmt: skip
        except DesignError as exc:
            first = first or exc
            continue
        except GeometryError as exc:  # diverged until a pattern degenerated: not this crease
            first = first or DesignError(
                f"{folder}: undoing the thickness correction with {root.key} as the leading "
                f"crease diverged ({exc}); import the patterns as drawn (as_drawn=True, ccu "
                "import --as-drawn)"
            )
            continue
        info["leading"] = root.key
        if tree is members:
            return members, links, undone, info
        where = {id(m.plate): k for k, m in enumerate(tree)}
        mapped = [
            _rows_as(m, tree[where[id(m.plate)]], undone[where[id(m.plate)]]) for m in members
        ]
        return members, links, mapped, info
    raise DesignError(
        f"{first} (tried every crease of the folder as the design's leading crease)"
    ) from first
