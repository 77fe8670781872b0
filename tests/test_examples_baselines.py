"""Regression net: key numbers of every example, compared with JSON baselines.

Regenerate after an intended change with ``CCU_UPDATE_BASELINES=1 make test`` and review the
diff of ``tests/baselines/``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from compas_ccu.model import load_model
from conftest import EXAMPLES

BASELINES = Path(__file__).resolve().parent / "baselines"
ALPHAS = [0.0, 10.0, 20.0, 30.0, 40.0]


def summary(name: str) -> dict:
    model = load_model(EXAMPLES / f"{name}.toml")
    out = {
        "alpha_limit": model.alpha_limit,
        "overlap_alpha": model.overlap_alpha,
        "collision_free_alpha": model.collision_free_alpha,
        "limit_vertex": model.limit_vertex,
        "states": [],
    }
    for s in model.path(ALPHAS):
        out["states"].append(
            {
                "alpha": s.alpha,
                "span": s.metrics["span"],
                "rise": s.metrics["rise"],
                "bounding_box": s.metrics["bounding_box"],
                "kinds": [c["kind"] for c in s.creases],
                "first_plate_corners": np.asarray(s.deployed[0])[[0, -1]].tolist(),
                "centroid": np.asarray(s.deployed).reshape(-1, 3).mean(axis=0).tolist(),
            }
        )
    return out


def compare(got, want, path="") -> None:
    if isinstance(want, dict):
        assert set(got) == set(want), path
        for k in want:
            compare(got[k], want[k], f"{path}.{k}")
    elif isinstance(want, list):
        assert len(got) == len(want), path
        for i, (g, w) in enumerate(zip(got, want)):
            compare(g, w, f"{path}[{i}]")
    elif isinstance(want, float):
        assert got == pytest.approx(want, rel=1e-9, abs=1e-10), path
    else:
        assert got == want, path


@pytest.mark.parametrize("name", ["vault", "cone", "quadrants"])
def test_example_matches_baseline(name):
    got = summary(name)
    path = BASELINES / f"{name}.json"
    if os.environ.get("CCU_UPDATE_BASELINES"):
        path.write_text(json.dumps(got, indent=1) + "\n", encoding="utf-8")
    compare(got, json.loads(path.read_text(encoding="utf-8")))
