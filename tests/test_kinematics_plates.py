"""The plate index: vertex rows, quads, rulings, both plate orders and crease boundaries."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.kinematics.plates import (
    PlateIndex,
    boundary_rows,
    hinge_and_rulings,
    plate_quads,
    plate_rulings,
    stack_rows,
)
from compas_ccu.model import load_model
from conftest import EXAMPLES


def test_rows_quads_and_rulings_of_one_plate():
    index = PlateIndex(segments=3, ids=(0,), crease_plates=(), crease_boundaries=())
    assert index.vertex_count == 8
    assert index.near_rows.tolist() == [0, 1, 2, 3]
    assert index.far_rows.tolist() == [4, 5, 6, 7]
    assert index.rows("far").tolist() == [4, 5, 6, 7]
    assert index.quads.tolist() == [[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6]]
    assert index.rulings.tolist() == [[0, 4], [1, 5], [2, 6], [3, 7]]
    assert plate_quads(3).tolist() == index.quads.tolist()
    assert plate_rulings(3).tolist() == index.rulings.tolist()
    with pytest.raises(ValueError, match="'near' or 'far', got 'middle'"):
        index.rows("middle")


def test_orders_map_mechanism_plates_to_ids():
    index = PlateIndex(segments=1, ids=(2, 0, 1), crease_plates=(), crease_boundaries=())
    assert index.order.tolist() == [1, 2, 0]
    assert index.output_ids == [0, 1, 2]
    assert index.output_positions().tolist() == [2, 0, 1]
    values = np.array([20.0, 0.0, 10.0])  # by mechanism plate
    assert index.to_output(values).tolist() == [0.0, 10.0, 20.0]


def test_boundaries_and_hinge_rulings():
    near = np.zeros((3, 3))
    far = np.array([[0.0, 2.0, 0.0], [0.0, 0.0, 3.0], [4.0, 0.0, 0.0]])
    row, other = boundary_rows(near, far, "far")
    assert row is far and other is near
    row, away = hinge_and_rulings(near, far, "near")
    assert np.allclose(np.linalg.norm(away, axis=1), 1.0)
    assert away.tolist() == [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
    assert stack_rows(near, far).shape == (6, 3)


@pytest.mark.parametrize("name", ["vault.toml", "cone.toml", "quadrants.toml"])
def test_the_index_agrees_with_the_structure_contract(name):
    """Crease plates and vertex rows of the index are what structure.json says, and the hinge
    rows of plate a and plate b coincide in the deployed geometry."""
    model = load_model(EXAMPLES / name)
    s = model.deploy()
    index = model.plates
    assert index.output_ids == s.plate_ids
    position = {pid: i for i, pid in enumerate(s.plate_ids)}
    for ci, crease in enumerate(s.creases):
        rows_a, rows_b = index.crease_rows(ci)
        assert list(index.crease_ids(ci)) == crease["plates"]
        assert [rows_a.tolist(), rows_b.tolist()] == crease["vertices"]
        a, b = (position[p] for p in crease["plates"])
        gap = np.abs(s.deployed[a][rows_a] - s.deployed[b][rows_b]).max()
        assert gap < 1e-12 * model.size
