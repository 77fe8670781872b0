"""The start of an as-built registration (docs/fit.md, ``ccu asbuilt`` steps 1 and 2).

1. **Global start.** The scan's principal axes are matched to the model's at a coarse grid of α
   from the flat stack to the first collision, trying all 24 signed axis permutations (the
   ambiguities of principal axes) and the scan's centroid or its ends on the model's, each
   followed by a few trimmed point-to-plane ICP iterations against a sampling of the plates
   (all starts of one α at once, :func:`icp_many`).
2. **Continuation in α.** The best starts followed along a fine grid of α, each α starting
   from its neighbour's pose.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fit.distance import PlateSurface
from compas_ccu.fit.rigid import axis_rotations, matrix, rotations
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["global_starts", "icp", "icp_many", "lstsq_many", "principal_axes", "START_EPS"]

#: The global start's ICP pairs a point with a sample at most (1 + START_EPS) times as far as
#: its nearest (cKDTree's approximate search: the rough search of many poor starts, most of
#: whose points lie far from the plates, is over 2 times faster).
START_EPS = 1.0


def global_starts(model, scan_start, scan_few, coarse, lo, hi, alpha_grid, refine) -> list:
    """The starts of the robust fit, best first (module docstring, steps 1 and 2).

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    scan_start : (m, 3) float
        Scan points of the continuation (500 of the fit's subset).
    scan_few : (k, 3) float
        Scan points of the global start (the first 200 of those).
    coarse : compas_ccu.fit.robust_fit.PlateStates
        The plates sampled coarsely, by α.
    lo, hi : float
        The range of α, degrees.
    alpha_grid : int
        α values of the global start.
    refine : int
        Best global starts followed in α.

    Returns
    -------
    list of (float, float, (4, 4) float)
        ``(score, alpha, motion)``: the ICP score (m), α (degrees) and the motion from scan to
        design coordinates, lowest score first.
    """
    # 1. global start: principal axes, 24 axis rotations, a coarse alpha grid, the scan's
    # centroid or its ends put on the model's (a partial scan), scored, the best refined by ICP
    cs, es = principal_axes(scan_start)
    cap = model.size / 60.0
    scored = []
    for alpha in np.linspace(lo + 0.5, hi - 0.5, int(alpha_grid)):
        surf = coarse(float(alpha))
        cm, em = principal_axes(surf.samples, surf.sample_weight)
        model_proj = (surf.samples - cm) @ em
        m_lo, m_hi = model_proj.min(axis=0), model_proj.max(axis=0)
        tried = []
        for q in axis_rotations():
            rot = em @ q @ es.T
            x = (scan_start - cs) @ rot.T
            proj = x @ em
            shifts = [np.zeros(3)]
            for k in range(3):
                shifts += [(m_lo[k] - proj[:, k].min()) * em[:, k]]
                shifts += [(m_hi[k] - proj[:, k].max()) * em[:, k]]
            tried += [matrix(rot, cm + shift - rot @ cs) for shift in shifts]
        motions, scores = icp_many(np.array(tried), scan_few, surf, 5, 0.6, cap, eps=START_EPS)
        scored += [(float(s), float(alpha), m) for s, m in zip(scores, motions)]
    scored.sort(key=lambda s: s[0])
    # 2. the best starts followed along a fine alpha grid (continuation: each alpha starts from
    # the pose of its neighbour), a few ICP iterations at each
    fine_grid = np.linspace(lo + 0.5, hi - 0.5, max(2, int(round((hi - lo) / 2.0))))
    starts = []
    for _, alpha0, m0 in scored[: int(refine)]:
        at = int(np.argmin(np.abs(fine_grid - alpha0)))
        m_at, _ = icp(m0, scan_start, coarse(float(fine_grid[at])), 10, 0.6, cap)
        for direction in (range(at, len(fine_grid)), range(at, -1, -1)):
            m = m_at
            for j in direction:
                alpha = float(fine_grid[j])
                m, score = icp(m, scan_start, coarse(alpha), 4, 0.6, cap)
                starts.append((score, alpha, m))
    starts.sort(key=lambda s: s[0])
    return starts


def principal_axes(points, weights=None):
    """Weighted centroid and principal axes of ``points`` (n, 3).

    Returns
    -------
    centre : (3,) float
    axes : (3, 3) float
        Columns by decreasing variance, a proper rotation (determinant +1).
    """
    w = np.ones(len(points)) if weights is None else weights
    w = w / w.sum()
    c = w @ points
    cov = (points - c).T @ ((points - c) * w[:, None])
    _, vec = np.linalg.eigh(cov)
    axes = vec[:, ::-1].copy()
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1.0
    return c, axes


def icp(start, scan, surf: PlateSurface, iterations: int, keep: float, cap: float):
    """Trimmed point-to-plane ICP against the samples of ``surf`` (the share ``keep`` of
    nearest pairs); returns the motion and its score, the mean point-to-plane distance capped
    at ``cap`` over all points (a partial fit of few points scores badly).

    Parameters
    ----------
    start : (4, 4) float
        Motion from scan to design coordinates to start from.
    scan : (n, 3) float
    surf : PlateSurface
    iterations : int
    keep : float
        Share of the nearest pairs each iteration fits.
    cap : float
        m: the score's largest distance per point.

    Returns
    -------
    motion : (4, 4) float
    score : float
    """
    m, score = icp_many(start[None], scan, surf, iterations, keep, cap)
    return m[0], float(score[0])


def icp_many(
    starts, scan, surf: PlateSurface, iterations: int, keep: float, cap: float, eps: float = 0.0
):
    """:func:`icp` from every motion of ``starts`` (b, 4, 4) at once (one tree query per
    iteration for all of them); returns the motions (b, 4, 4) and scores (b,). ``eps``: a
    point's pair may lie up to ``1 + eps`` times as far as its nearest sample (cKDTree)."""
    m = np.array(starts, dtype=np.float64)
    b, n = len(m), len(scan)
    normals = surf.normals[surf.sample_triangle]
    for _ in range(iterations):
        x = np.einsum("bij,nj->bni", m[:, :3, :3], scan) + m[:, None, :3, 3]
        d, i = surf.tree.query(x.reshape(-1, 3), eps=eps)
        d, i = d.reshape(b, n), i.reshape(b, n)
        w = (d <= np.quantile(d, keep, axis=1)[:, None]).astype(np.float64)
        nrm = normals[i]
        a = np.concatenate([np.cross(x, nrm), nrm], axis=2)  # (b, n, 6)
        rhs = ((surf.samples[i] - x) * nrm).sum(axis=2)
        lhs = np.einsum("bni,bn,bnj->bij", a, w, a) + EXACT_RELATIVE * np.eye(6)
        step = lstsq_many(lhs, np.einsum("bni,bn->bi", a, w * rhs))
        move = np.tile(np.eye(4), (b, 1, 1))
        move[:, :3, :3] = rotations(step[:, :3])
        move[:, :3, 3] = step[:, 3:]
        m = move @ m
    x = np.einsum("bij,nj->bni", m[:, :3, :3], scan) + m[:, None, :3, 3]
    _, i = surf.tree.query(x.reshape(-1, 3), eps=eps)
    i = i.reshape(b, n)
    d = np.abs(((x - surf.samples[i]) * normals[i]).sum(axis=2))
    return m, np.minimum(d, cap).mean(axis=1)


def lstsq_many(lhs, rhs):
    """``numpy.linalg.lstsq`` of every system ``lhs`` (b, k, k), ``rhs`` (b, k): the
    minimum-norm solution, singular values below ``k`` eps of the largest dropped (a singular
    system, such as a diverged start's, does not raise)."""
    u, sv, vt = np.linalg.svd(lhs)
    keep = sv > np.finfo(np.float64).eps * lhs.shape[-1] * sv[:, :1]
    inv = np.where(keep, 1.0 / np.where(keep, sv, 1.0), 0.0)
    return np.einsum("bji,bj->bi", vt, inv * np.einsum("bji,bj->bi", u, rhs))
