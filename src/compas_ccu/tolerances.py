"""Named tolerances: every numerical threshold the package uses, with what it means.

Relative tolerances are fractions of a length scale named where they are used (the structure
size, a crease length); absolute ones are in metres or radians. The invariant bar is the quality
bar of docs/kinematics.md: isometry, quad planarity, hinge coincidence and mirror symmetry hold
to ``EXACT_RELATIVE`` of the structure size.
"""

from __future__ import annotations

__all__ = [
    "EXACT_RELATIVE",
    "ZERO_LENGTH",
    "ZERO_ANGLE",
    "DIVISION_FLOOR",
    "SOLVER",
    "OBJECTIVE_RELATIVE",
]

#: The exactness bar: an invariant error below this fraction of the structure size is exact
#: (round-off); also the margin of sign tests on unit vectors (a ruling "points into" a plate).
EXACT_RELATIVE = 1e-9

#: A length or vector norm below this (relative to the scale named at the use) counts as zero:
#: repeated vertices, zero-length edges and rulings, parallel axes, a straight crease.
ZERO_LENGTH = 1e-12

#: Angles (radians) or angle differences below this count as zero (e.g. gamma = 90 deg).
ZERO_ANGLE = 1e-12

#: The floor of a denominator that may vanish only in degenerate input (keeps 0 / 0 finite);
#: also the absolute tolerance ``xtol`` of the root finders that stop on their relative one.
#: The one place this number is written (``tests/test_tolerances.py`` checks).
DIVISION_FLOOR = 1e-300

#: Convergence tolerance of the iterative solvers (least squares, root finding) in relative terms.
SOLVER = 1e-12

#: Two values of one objective closer than this fraction of the objective's scale (its largest
#: magnitude among the designs compared) are equal on a Pareto front: a design is dominated
#: when another is as good within it in every objective and better by more in one.
OBJECTIVE_RELATIVE = 1e-9
