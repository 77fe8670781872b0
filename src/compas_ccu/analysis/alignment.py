"""Best-fit rigid motion between two point sets (Kabsch), to compare shapes up to placement.

>>> import numpy as np
>>> p = np.random.default_rng(0).normal(size=(10, 3))
>>> c, s = np.cos(0.3), np.sin(0.3)
>>> q = p @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]).T + [1.0, 2.0, 3.0]
>>> bool(np.allclose(rigid_align(p, q), q))
True
"""

from __future__ import annotations

import numpy as np

__all__ = ["rigid_align"]


def rigid_align(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``source`` moved by the rotation and translation that best fit it to ``target``.

    Parameters
    ----------
    source, target : (m, 3) float
        Corresponding points.

    Returns
    -------
    (m, 3) float
    """
    cs, ct = source.mean(axis=0), target.mean(axis=0)
    h = (source - cs).T @ (target - ct)
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    rot = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
    return (source - cs) @ rot.T + ct
