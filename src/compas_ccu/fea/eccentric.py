"""Axis-shift hinges in the FE model: the hinge lines on the plates' faces, not their mid-surfaces.

The built structures hinge on the plates' faces (paper §5.3, Fig. 8c;
:mod:`compas_ccu.thickness.axis_shift`): the hinge line of a crease lies on the two facing
faces, ``t/2`` from each plate's mid-surface. With ``[hinges] eccentricity = "axis-shift"``
the FE model is built that way, with **eccentric shell sections** and no extra elements:

* the shells' nodes lie on a *reference surface* that passes through the hinge lines: along
  every ruling, the straight line from the hinge point of one crease to the hinge point of the
  other (a free edge's point on the mid-surface) — for an inner plate, from its lower face at
  one crease to its upper face at the other. Along a ruling the thick placement is rigid
  (:meth:`compas_ccu.thickness.ThickModel.hinge_points`), so this surface deploys exactly with
  the plates and the supports follow it;
* every element's material lies off its nodes by the offset between the reference surface and
  the mid-surface, averaged over the element's nodes (:attr:`FEProblem.offsets`, the shell
  section's ``SHELL_OFFSET`` in Kratos): a hinge force acts on the plate with its lever arm;
* the hinges tie the crease nodes of the two plates (they coincide: the two plates' hinge
  points are the same points, the ``hinge_gap`` of the thick model is 0 along the whole path).

The offset varies linearly across an inner plate (from ``-t/2`` to ``+t/2``) and the elements
take their mean: a staircase of ``t / rows`` per element row. Element forces are reported
about the mid-surface (the engine converts them).

Only the Kratos engine has eccentric shell sections; the OpenSees engine refuses them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compas_ccu.fea.mesh import ShellMesh

__all__ = ["ECCENTRICITIES", "FaceHinges"]

#: The hinge models of the FE: on the mid-surfaces, or on the faces (axis shift).
ECCENTRICITIES = ("none", "axis-shift")


@dataclass
class FaceHinges:
    """The reference surface and element offsets of a mesh with axis-shift hinges.

    Attributes
    ----------
    thick : compas_ccu.thickness.ThickModel
        The thick placement (thickness, which face each crease hinges on).
    offsets : (E,) float
        Every element's material offset from its nodes along the element normal
        ``(x2 - x0) × (x3 - x1)``: the mid-surface lies at ``-offset`` (m).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> from compas_ccu.thickness import ThickModel
    >>> from compas_ccu.fea.mesh import mesh_model
    >>> model = load_model("examples/cone.toml")
    >>> mesh = mesh_model(model, element_size=0.1)
    >>> faces = FaceHinges.build(mesh, ThickModel(model, thickness=0.008))
    >>> round(float(abs(faces.offsets).max()), 6)  # the elements at the crease: t/2 - t/8
    0.0035
    """

    thick: object
    offsets: np.ndarray

    @classmethod
    def build(cls, mesh: ShellMesh, thick) -> FaceHinges:
        """The offsets of ``mesh`` (nodes on the mid-surfaces) for the thick placement."""
        mid, face = thick.hinge_points([0.0])
        on_mid, on_face = mesh.kinematic(mid[0]), mesh.kinematic(face[0])
        normals = mesh.element_normals(on_face)
        shift = on_face - on_mid  # (N, 3) from the mid-surface to the reference surface
        offsets = np.einsum("ekj,ej->e", shift[mesh.elements], normals) / 4.0
        return cls(thick, offsets)

    def positions(self, mesh: ShellMesh, alphas) -> np.ndarray:
        """(k, N, 3) the nodes on the reference surface at reference angles ``alphas``
        (degrees): the exact thick kinematics."""
        _, face = self.thick.hinge_points(np.atleast_1d(np.asarray(alphas, dtype=float)))
        return mesh.kinematic(face)
