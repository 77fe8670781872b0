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
    "ROUND_OFF",
    "MACHINE",
    "ARC_PARAMETER",
    "UNDO_ABSOLUTE",
    "UNDO_RELATIVE",
    "FIT_OBJECTIVE",
]

#: The exactness bar: an invariant error below this fraction of the structure size is exact
#: (round-off); also the margin of sign tests on unit vectors (a ruling "points into" a plate),
#: of comparisons of lengths and depths of order 1 m (m), of the boxes widened against round-off
#: and the floor of a bound's range or of a frame's radius.
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
#: Floating-point rounding of a computed length or value, relative: the target of the arc-length
#: quadratures and Newton inversions of the profiles, and a segment this short of its curve's
#: length is noise (a repeated point).
ROUND_OFF = 1e-14
#: A few units in the last place of a quantity of order 1: the tolerance of the root finders on
#: unit-scale parameters, the floor of a damping, a coordinate this small is zero.
MACHINE = 1e-15
#: An arc-length argument outside ``[0, length]`` by less than this fraction of the length is
#: round-off and clipped (a profile's ``s``).
ARC_PARAMETER = 1e-10
#: Undoing the thickness correction of an imported drawing: the shifts are iterated until they
#: change by less than ``UNDO_ABSOLUTE`` (m) or ``UNDO_RELATIVE`` times the largest plate's size
#: (rounding: the 22-plate dome's planar steps stop at changes of 3e-12 to 6e-12 m, plates 2.3 m
#: across).
UNDO_ABSOLUTE = 1e-13
UNDO_RELATIVE = 1e-11
#: ``ftol`` of the design fit's least squares (relative change of the objective).
FIT_OBJECTIVE = 1e-10
