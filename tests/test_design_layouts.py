"""Radial layouts: an open ring below 360 degrees; a full ring is refused, naming the key."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.design import Design
from compas_ccu.errors import DesignError, SelfIntersectionError
from compas_ccu.model import CCUModel

DOME = {
    "crease": {
        "profile": "spline",
        "points": [[0.25, 1.2], [1.0, 1.0], [1.6, 0.5], [1.9, 0.0]],
        "segments": 24,
    },
    "rulings": {"type": "orthogonal", "side": "inside"},
    "deployment": {"alpha": 30.0},
}


def dome(**layout):
    return CCUModel(Design({**DOME, "layout": {"type": "radial", "axis": 0.0, **layout}}))


def plane_turns(structure) -> np.ndarray:
    """Angles (degrees) between the planes of neighbouring creases, in plane order."""
    creases = sorted(structure.creases, key=lambda c: min(c["plates"]))
    normals = np.array([c["plane"]["normal"] for c in creases])
    return np.degrees(np.arccos(np.clip(np.sum(normals[1:] * normals[:-1], axis=1), -1, 1)))


@pytest.mark.parametrize(
    "plates, angle, total, each",
    [
        (12, 30.0, "360", "12 plates x 30 deg"),
        (4, [90.0, 90.0, 100.0, 80.0], "360", "4 plates x the given angles"),
        (3, 150.0, "450", "3 plates x 150 deg"),
    ],
)
def test_a_full_ring_is_refused_naming_the_key_and_the_value(plates, angle, total, each):
    with pytest.raises(DesignError) as info:
        dome(plates=plates, angle=angle)
    assert info.value.key == "layout.angle"
    assert str(info.value).startswith(
        f"layout.angle: the planes turn by {total} deg in total ({each}); a radial layout is an "
        "open ring of less than 360 deg: a closed ring cannot deploy"
    )


def test_a_ring_just_below_360_degrees_deploys():
    model = dome(plates=12, angle=29.9)
    structure = model.deploy()
    assert structure.max_invariant_error < 1e-12
    assert plane_turns(structure) == pytest.approx(29.9, abs=1e-9)  # the design angles


def test_the_angle_between_the_planes_changes_along_the_deployment():
    """Why a closed ring cannot exist: 12 plates x 29 deg = 348 deg at the design alpha = 30 deg
    turn by 10 x 18.8 deg between the 11 creases at alpha = 15 deg and by 10 x 32.5 deg at
    45 deg, so a ring closed at the design would have to open or overlap as it deploys."""
    model = dome(plates=12, angle=29.0)

    def turns(alpha):
        return plane_turns(model.deploy(alpha, check=False))

    assert turns(30.0) == pytest.approx(29.0, abs=1e-9)
    assert 18.0 < turns(15.0).min() and turns(15.0).max() < 19.5
    assert 32.0 < turns(45.0).min() and turns(45.0).max() < 33.0
    # ... and so it does: the last plate reaches round to the first at 32.72 deg
    with pytest.raises(SelfIntersectionError, match="plates 11 and 0 cross at alpha = 32.7"):
        model.deploy(45.0)
