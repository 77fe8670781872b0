"""The fold of every crease read from FE node positions, next to the kinematic fold.

A crease of the mesh is a row of tied node pairs (:attr:`ShellMesh.ties`); next to it, on each
plate, lies the first row of nodes across the plate. The fold angle of every element edge along
the crease is the angle between the two plates' directions from the crease edge towards those
rows, perpendicular to the edge (:func:`compas_ccu.geometry.edge_fold_angles`); half of it is the
reflection angle alpha of a CCU crease (docs/geometry.md, "Fold angles"). Because every mesh node
has an exact kinematic position, the same measure applied to :meth:`ShellMesh.kinematic`
positions gives the model's fold exactly: the FE and the kinematic folds are read the same way.

>>> from compas_ccu.design import load_design
>>> from compas_ccu.model import CCUModel
>>> from compas_ccu.fea.mesh import mesh_model
>>> model = CCUModel(load_design("examples/vault.toml"))
>>> mesh = mesh_model(model, element_size=0.5)
>>> x = mesh.kinematic(model.deploy(30.0).deployed)
>>> folds = crease_alphas(mesh, x[None])  # (steps, creases, edges)
>>> round(float(folds[0, 0].mean()), 3), folds.shape[1]
(30.006, 9)
"""

from __future__ import annotations

import numpy as np

from compas_ccu.fea.mesh import ShellMesh
from compas_ccu.geometry import edge_fold_angles
from compas_ccu.tolerances import ZERO_ANGLE

__all__ = ["crease_rows", "crease_alphas", "crease_fold_table"]


def crease_rows(mesh: ShellMesh) -> list:
    """Per crease id (0 .. C - 1): the node rows ``(crease, side_a, side_b)``.

    ``crease`` is plate a's row of hinge nodes along the crease; ``side_a`` / ``side_b`` the
    next row of nodes across plate a / plate b (one element away from the crease).
    """
    rows = []
    for c in np.unique(mesh.tie_crease):
        pairs = mesh.ties[mesh.tie_crease == c]
        sides = []
        for nodes in pairs.T:
            # nodes are numbered across the plate fastest: the next row is one index away,
            # inwards from the boundary the crease lies on (v = 0 or v = 1)
            step = np.where(mesh.node_uv[nodes, 1] < 0.5, 1, -1)
            sides.append(nodes + step)
        rows.append((pairs[:, 0], sides[0], sides[1]))
    return rows


def crease_alphas(mesh: ShellMesh, positions: np.ndarray) -> np.ndarray:
    """(k, C, E) half the fold angle of every element edge of every crease, degrees.

    Parameters
    ----------
    mesh : ShellMesh
    positions : (k, N, 3) float
        Node positions (FE or kinematic) at k states.
    """
    x = np.asarray(positions, dtype=float)
    out = [0.5 * edge_fold_angles(x[:, a], x[:, sa], x[:, sb]) for a, sa, sb in crease_rows(mesh)]
    return np.stack(out, axis=1)


def crease_fold_table(
    mesh: ShellMesh, positions: np.ndarray, kinematic: np.ndarray, *, start: int = 0
) -> list:
    """Per crease: the FE and kinematic alpha along the path and their residual, JSON-ready.

    Parameters
    ----------
    mesh : ShellMesh
    positions, kinematic : (k, N, 3) float
        FE and kinematic node positions at every step.
    start : int
        The 0-based step the drive starts from: ``follow`` is the FE increment of the crease's
        mean alpha from there to the last step over the kinematic increment (1: the crease
        follows the drive fully, 0: it does not move).

    Returns
    -------
    list of dict
        ``crease``; per step the crease's mean alpha ``fe_alpha`` and ``kinematic_alpha``
        (degrees), ``residual`` (their difference) and ``residual_max`` (the largest
        ``|FE - kinematic|`` over its edges); ``follow``.
    """
    fe = crease_alphas(mesh, positions)
    kin = crease_alphas(mesh, kinematic)
    rows = []
    for c in range(fe.shape[1]):
        f, k = fe[:, c].mean(axis=1), kin[:, c].mean(axis=1)
        dk = k[-1] - k[start]
        rows.append(
            {
                "crease": c,
                "fe_alpha": f.tolist(),
                "kinematic_alpha": k.tolist(),
                "residual": (f - k).tolist(),
                "residual_max": np.abs(fe[:, c] - kin[:, c]).max(axis=1).tolist(),
                "follow": float((f[-1] - f[start]) / dk) if abs(dk) > ZERO_ANGLE else None,
            }
        )
    return rows
