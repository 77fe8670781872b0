"""Splice plates as part of the thick plates: the records, their piles in the flat stack.

A plate cut to fit the sheets is joined again by two splice plates across each cut, one on each
face (:mod:`compas_ccu.fabrication.splices` chooses the cuts). In the flat-folded stack a splice
plate lies between its plate and the neighbouring one, so the stack is higher where splice
plates lie over each other: the **pile** at a point of the plan is the sum of the thicknesses of
the splice plates whose footprints hold the point, and the stack height with splices is the
plates' stack plus the highest pile (the plates bend over the splices under them: each plate
lies on what is under it; an upper bound where a plate does not cover the pile).

The plan of the flat stack is the cut-pattern plane (``FabricationData.flat``,
:meth:`compas_ccu.thickness.ThickModel.cut_patterns`: the patterns are drawn as stacked, seen
from above), so a footprint is a convex quadrilateral in cut-pattern coordinates, m.

**The highest pile, exactly.** The pile is a sum of indicator functions of closed convex
polygons; its largest value is taken on a vertex of the intersection of some of them, and every
such vertex is a footprint corner or the crossing of two footprint edges. :class:`PileMap`
keeps those points with their piles and adds footprints one set at a time (the new corners and
crossings are evaluated against every footprint, the old points gain the new footprints), so a
greedy choice of cuts tries a candidate without recomputing the map.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.geometry import cross3, unit3
from compas_ccu.thickness.cells import point_gaps
from compas_ccu.tolerances import EXACT_RELATIVE, ZERO_LENGTH

__all__ = [
    "Splice",
    "PileMap",
    "max_pile",
    "footprints_contain",
    "slab_points",
    "splice_gaps",
    "gap_summary",
    "SpliceClearance",
    "SpliceGaps",
    "GRID",
]

#: Lateral tolerance of the footprint test, m: footprints that only touch along an edge pile.
TOUCH = EXACT_RELATIVE


@dataclass(frozen=True)
class Splice:
    """One splice plate glued across a cut of a plate.

    Attributes
    ----------
    name : str
        Its part name (``S3.1U``: plate 3, cut 1, upper face).
    plate : int
        The plate's id.
    ruling : int
        The ruling the cut follows.
    face : str
        ``"upper"`` (the UP face: the top in the flat stack) or ``"lower"``.
    footprint : (4, 2) float
        Its outline in the plate's cut pattern (the plan of the flat stack), m.
    thickness : float
        m.
    """

    name: str
    plate: int
    ruling: int
    face: str
    footprint: np.ndarray
    thickness: float

    def __post_init__(self):
        if self.face not in ("upper", "lower"):
            raise ValueError(
                f"splice {self.name}: face must be 'upper' or 'lower', got {self.face!r}"
            )
        if not (self.thickness > 0.0 and np.isfinite(self.thickness)):
            raise ValueError(f"splice {self.name}: thickness must be > 0 m, got {self.thickness!r}")

    @property
    def area(self) -> float:
        """Footprint area, m²."""
        x, y = self.footprint[:, 0], self.footprint[:, 1]
        return float(0.5 * abs(x @ np.roll(y, -1) - y @ np.roll(x, -1)))

    def to_dict(self) -> dict:
        """Plain data (strict JSON)."""
        return {
            "name": self.name,
            "plate": int(self.plate),
            "ruling": int(self.ruling),
            "face": self.face,
            "footprint": np.asarray(self.footprint, dtype=float).tolist(),
            "thickness": float(self.thickness),
        }


def _ccw(quads: np.ndarray) -> np.ndarray:
    """(m, 4, 2) convex quads turned counter-clockwise."""
    x, y = quads[..., 0], quads[..., 1]
    area = (x * np.roll(y, -1, axis=1) - y * np.roll(x, -1, axis=1)).sum(axis=1)
    return np.where((area < 0.0)[:, None, None], quads[:, ::-1], quads)


def footprints_contain(points, quads, *, tol: float = TOUCH) -> np.ndarray:
    """(P, m) True where a point lies in a closed convex footprint (widened by ``tol``).

    Parameters
    ----------
    points : (P, 2) float
    quads : (m, 4, 2) float
        Convex quadrilaterals, either orientation.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    quads = _ccw(np.asarray(quads, dtype=float).reshape(-1, 4, 2))
    a = quads
    edge = np.roll(quads, -1, axis=1) - a  # (m, 4, 2)
    length = np.linalg.norm(edge, axis=2)
    rel = pts[:, None, None, :] - a[None]  # (P, m, 4, 2)
    side = edge[None, ..., 0] * rel[..., 1] - edge[None, ..., 1] * rel[..., 0]
    return (side >= -tol * length[None]).all(axis=2)


def _edges(quads: np.ndarray) -> tuple:
    """Start points and vectors of the edges of quads (m, 4, 2): (4m, 2) each."""
    return quads.reshape(-1, 2), (np.roll(quads, -1, axis=1) - quads).reshape(-1, 2)


def _crossings(p, d, q, e, tol: float = TOUCH) -> np.ndarray:
    """(K, 2) crossing points of the segments ``p + s d`` (A) with ``q + u e`` (B), s, u in
    [0, 1] (parallel segments give none: their meeting points are segment ends)."""
    if not (len(p) and len(q)):
        return np.zeros((0, 2))
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]  # (A, B)
    w = q[None] - p[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (w[..., 0] * e[None, :, 1] - w[..., 1] * e[None, :, 0]) / den
        u = (w[..., 0] * d[:, None, 1] - w[..., 1] * d[:, None, 0]) / den
    scale = np.linalg.norm(d, axis=1)[:, None] * np.linalg.norm(e, axis=1)[None]
    ok = (
        (np.abs(den) > ZERO_LENGTH * scale)
        & (s >= -tol)
        & (s <= 1 + tol)
        & (u >= -tol)
        & (u <= 1 + tol)
    )
    i, _ = np.nonzero(ok)
    return p[i] + s[ok][:, None] * d[i]


class PileMap:
    """The piles of a growing set of footprints at every point where the highest can be.

    Examples
    --------
    Two 2 x 1 footprints overlapping by half, 8 mm each, then a third over both:

    >>> sq = np.array([[0.0, 0], [2, 0], [2, 1], [0, 1]])
    >>> piles = PileMap()
    >>> piles.add(np.stack([sq, sq + [1, 0]]), [0.008, 0.008])
    >>> round(piles.max, 9), piles.trial(sq[None] + [0.5, 0], [0.004])
    (0.016, 0.02)
    >>> piles.max  # a trial adds nothing
    0.016
    """

    def __init__(self):
        self.quads = np.zeros((0, 4, 2))
        self.thickness = np.zeros(0)
        self.points = np.zeros((0, 2))
        self.piles = np.zeros(0)

    @property
    def max(self) -> float:
        """The highest pile, m (0 without footprints)."""
        return float(self.piles.max()) if len(self.piles) else 0.0

    @property
    def argmax(self):
        """(2,) a point of the highest pile (the first found), or None without footprints."""
        return self.points[int(np.argmax(self.piles))] if len(self.piles) else None

    def _new(self, quads, thickness):
        quads = _ccw(np.asarray(quads, dtype=float).reshape(-1, 4, 2))
        thickness = np.broadcast_to(np.asarray(thickness, dtype=float), (len(quads),))
        p, d = _edges(quads)
        q, e = _edges(self.quads)
        points = np.concatenate([p, _crossings(p, d, p, d), _crossings(p, d, q, e)])
        inside_new = footprints_contain(points, quads)
        piles = inside_new @ thickness
        if len(self.quads):
            piles = piles + footprints_contain(points, self.quads) @ self.thickness
        gained = footprints_contain(self.points, quads) @ thickness if len(self.points) else 0.0
        return quads, thickness, points, piles, self.piles + gained

    def trial(self, quads, thickness) -> float:
        """The highest pile, m, if ``quads`` (m, 4, 2) of ``thickness`` (m,) were added."""
        _, _, _, piles, old = self._new(quads, thickness)
        return float(max(piles.max(initial=0.0), np.max(old, initial=0.0)))

    def add(self, quads, thickness) -> None:
        """Add footprints ``quads`` (m, 4, 2) of ``thickness`` (m,) m."""
        quads, thickness, points, piles, old = self._new(quads, thickness)
        self.quads = np.concatenate([self.quads, quads])
        self.thickness = np.concatenate([self.thickness, thickness])
        self.points = np.concatenate([self.points, points])
        self.piles = np.concatenate([old, piles])


def max_pile(quads, thickness) -> tuple:
    """The highest pile of footprints and a point where it is.

    Parameters
    ----------
    quads : (m, 4, 2) float
        Convex footprints in the plan, m.
    thickness : (m,) float
        Their thicknesses, m.

    Returns
    -------
    pile : float
        m (0 without footprints).
    point : (2,) float or None
    """
    piles = PileMap()
    if len(np.asarray(quads).reshape(-1, 8)):
        piles.add(quads, thickness)
    return piles.max, piles.argmax


# ------------------------------------------------------------------------ slabs along the path

#: Sample points of a splice plate: ``GRID`` x ``GRID`` over its footprint, at half and at its
#: whole thickness over its plate's face.
GRID = 9


def _bilinear(quads: np.ndarray, grid: int) -> np.ndarray:
    """(s, grid², 2) points of a grid over quads (s, 4, 2), corners included."""
    u, v = (x.ravel() for x in np.meshgrid(np.linspace(0, 1, grid), np.linspace(0, 1, grid)))
    w = np.stack([(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v], axis=1)  # (g², 4)
    return np.einsum("gc,scd->sgd", w, quads)


def slab_points(splices, near2, far2, mid_near, mid_far, offsets, plate_thickness, up, *,
                grid: int = GRID) -> np.ndarray:  # fmt: skip
    """Sample points of splice plates on their bent plates in every state.

    A point of the footprint lies in a quad of the cut pattern (between two rulings); the quad
    maps rigidly onto the plate's planar quad in the state (the thick plates are isometries of
    their cut patterns), and the point is lifted off the plate's face along the quad normal by
    half and by the whole splice thickness.

    Parameters
    ----------
    splices : list of Splice
    near2, far2 : (s, n + 1, 2) float
        Cut-pattern rows of every splice's plate (with the crease corrections), m.
    mid_near, mid_far, offsets : (k, s, n + 1, 3) float
        Every splice's plate in ``k`` states: mid-surface rows (corrected) and face offsets.
    plate_thickness : float
        m.
    up : (s,) float
        +1 where the plate's offset vectors point to the top of the flat stack, else -1.
    grid : int

    Returns
    -------
    (k, s, 2 grid², 3) float
    """
    s = len(splices)
    quads = np.array([sp.footprint for sp in splices], dtype=float).reshape(s, 4, 2)
    pts = _bilinear(quads, grid)  # (s, g, 2)
    n = near2.shape[1] - 1
    r2 = far2 - near2
    rel = pts[:, :, None, :] - near2[:, None]  # (s, g, n + 1, 2)
    side = r2[:, None, :, 0] * rel[..., 1] - r2[:, None, :, 1] * rel[..., 0]
    e = near2[:, 1] - near2[:, 0]
    o = np.sign(r2[:, 0, 0] * e[:, 1] - r2[:, 0, 1] * e[:, 0])  # the side the plate is on
    j = np.clip((o[:, None, None] * side >= 0.0).sum(axis=2) - 1, 0, n - 1)  # (s, g)
    rows = np.arange(s)[:, None]
    a2 = near2[rows, j]
    u2, v2, w = near2[rows, j + 1] - a2, far2[rows, j] - a2, pts - a2
    det = u2[..., 0] * v2[..., 1] - u2[..., 1] * v2[..., 0]
    al = (w[..., 0] * v2[..., 1] - w[..., 1] * v2[..., 0]) / det
    be = (u2[..., 0] * w[..., 1] - u2[..., 1] * w[..., 0]) / det
    a, b = mid_near[:, rows, j], mid_near[:, rows, j + 1]  # (k, s, g, 3)
    c, d = mid_far[:, rows, j + 1], mid_far[:, rows, j]
    x = a + al[..., None] * (b - a) + be[..., None] * (d - a)
    normal = unit3(cross3(c - a, d - b))
    nu = offsets[:, rows, j] + offsets[:, rows, j + 1]
    normal = normal * np.sign(np.einsum("...i,...i", normal, nu))[..., None]
    sign = np.array([1.0 if sp.face == "upper" else -1.0 for sp in splices]) * np.asarray(up)
    ts = np.array([sp.thickness for sp in splices])
    lift = sign[:, None] * (0.5 * plate_thickness + np.outer(ts, [0.5, 1.0]))  # (s, 2)
    out = x[:, :, None] + lift[None, :, :, None, None] * normal[:, :, None]
    return out.reshape(out.shape[0], s, -1, 3)


def splice_gaps(points, targets, mid_near, mid_far, offsets, thickness) -> np.ndarray:
    """(k, s) smallest gap of every splice plate's points over its neighbouring plate in every
    state (:func:`~compas_ccu.thickness.cells.point_gaps`; negative: it lies inside it by
    that depth; inf where no point lies over it or there is no neighbour).

    Parameters
    ----------
    points : (k, s, P, 3) float
        :func:`slab_points`.
    targets : (s,) int
        The plate (index into the plate axis below) each splice faces, -1 for none.
    mid_near, mid_far, offsets : (k, p, n + 1, 3) float
    thickness : float
        The plates', m.
    """
    k, s = points.shape[:2]
    gaps = np.full((k, s), np.inf)
    targets = np.asarray(targets, dtype=int)
    for b in np.unique(targets[targets >= 0]):
        mine = np.flatnonzero(targets == b)
        pts = points[:, mine].reshape(k, -1, 3)
        g = point_gaps(pts, mid_near[:, b], mid_far[:, b], offsets[:, b], thickness)
        gaps[:, mine] = g.reshape(k, len(mine), -1).min(axis=2)
    return gaps


@dataclass(frozen=True)
class SpliceClearance:
    """How one splice plate clears its neighbouring plate along the path (:class:`SpliceGaps`).

    Attributes
    ----------
    name : str
        The splice plate's part name (:attr:`Splice.name`).
    neighbour : int or None
        The plate it faces in the flat stack (plate id), None on the outside of the stack.
    clear_from_alpha : float or None
        The reference angle (degrees) from which it stays clear of its neighbour to the design
        state; None if it is not clear at the design state.
    """

    name: str
    neighbour: int | None
    clear_from_alpha: float | None

    def to_dict(self) -> dict:
        """Plain data (strict JSON): ``name``, ``neighbour``, ``clear_from_alpha``."""
        return {
            "name": self.name,
            "neighbour": self.neighbour,
            "clear_from_alpha": self.clear_from_alpha,
        }


@dataclass(frozen=True)
class SpliceGaps:
    """The splice plates against their neighbouring plates along a path from the flat stack
    (:func:`gap_summary`).

    Attributes
    ----------
    alphas : list
        ``[first, last, count]``: the reference angles sampled (degrees, degrees, int).
    tolerance : float
        The depth a splice plate may reach into its neighbour, m.
    max_depth : float
        The deepest sample point inside a neighbouring plate along the path, m (``t/2 - |d|``
        as the plates' own check, so at most half the plate thickness): near the flat stack
        the splice plates hold the plates apart, which the stack height with splices counts.
    clear_from_alpha : float or None
        The angle (degrees) from which every splice plate stays clear of its neighbour to the
        design state; None if one is not clear at the design state.
    interpenetration : bool
        A splice plate reaches into its neighbour at the design state.
    clearance_design : float or None
        The smallest gap at the design state, m; None if no splice plate lies over a neighbour.
    splices : tuple of SpliceClearance
        Per splice plate, in the order given.
    """

    alphas: list
    tolerance: float
    max_depth: float
    clear_from_alpha: float | None
    interpenetration: bool
    clearance_design: float | None
    splices: tuple = ()

    def to_dict(self) -> dict:
        """Plain data (strict JSON), the fields in order (``splices`` as a list of dicts)."""
        return {
            "alphas": list(self.alphas),
            "tolerance": self.tolerance,
            "max_depth": self.max_depth,
            "clear_from_alpha": self.clear_from_alpha,
            "interpenetration": self.interpenetration,
            "clearance_design": self.clearance_design,
            "splices": [sp.to_dict() for sp in self.splices],
        }


def gap_summary(splices, neighbours, alphas, gaps, tolerance: float) -> SpliceGaps:
    """:func:`splice_gaps` along a path from the flat stack, summed up (:class:`SpliceGaps`).

    Parameters
    ----------
    splices : list of Splice
    neighbours : list of int or None
        Per splice plate: the plate it faces (plate id), None for none.
    alphas : (k,) float
        The reference angles of the states, degrees, from the flat stack to the design.
    gaps : (k, s) float
        :func:`splice_gaps`, m.
    tolerance : float
        The depth a splice plate may reach into its neighbour, m.
    """
    alphas = np.asarray(alphas, dtype=float)
    bad = -gaps > tolerance  # (k, s)
    per = []
    for q, sp in enumerate(splices):
        hits = np.flatnonzero(bad[:, q])
        last = int(hits[-1]) if len(hits) else -1
        clear = None if last == len(alphas) - 1 else float(alphas[last + 1])
        per.append(SpliceClearance(sp.name, neighbours[q], clear))
    hits = np.flatnonzero(bad.any(axis=1))
    last = int(hits[-1]) if len(hits) else -1
    design = gaps[-1][np.isfinite(gaps[-1])]
    return SpliceGaps(
        alphas=[float(alphas[0]), float(alphas[-1]), len(alphas)],
        tolerance=tolerance,
        max_depth=float(max(0.0, -gaps.min(initial=np.inf))),
        clear_from_alpha=None if last == len(alphas) - 1 else float(alphas[last + 1]),
        interpenetration=bool(bad[-1].any()),
        clearance_design=float(design.min()) if len(design) else None,
        splices=tuple(per),
    )
