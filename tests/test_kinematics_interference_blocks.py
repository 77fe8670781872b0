"""The block pairs of the certificate's scan that may hold an event
(compas_ccu.kinematics.interference_blocks): the box bound before the heights keeps exactly the
pairs that the heights of every candidate keep, and the edge planes of all quads computed at once
are each quad's own."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from compas_ccu.errors import CCUError
from compas_ccu.kinematics import interference_events
from compas_ccu.kinematics.interference_blocks import block_tables, sided_blocks
from compas_ccu.model import load_model
from compas_ccu.tolerances import ZERO_LENGTH
from conftest import EXAMPLES

DATA = Path(__file__).resolve().parents[1] / "src" / "compas_ccu" / "data"
CORPUS = sorted(list(EXAMPLES.glob("*.toml")) + list((DATA / "catalog").glob("*.toml")))


def heights_of_every_candidate(g, candidates, quad_block, local, excluded):
    """The block pairs kept without the box bound: every vertex's height over every quad's
    plane of every candidate, in both states, then the quad near the block's box."""
    ks, a, jb, b, ib = candidates
    margin = ZERO_LENGTH * float(np.abs(g.vertices).max())
    quads, verts = quad_block[jb], local[ib]  # (N, B), (N, V)
    skip = excluded[a[:, None], b[:, None], verts][..., None]  # (N, V, 1)
    sides = []
    for state in (ks, ks + 1):
        x = g.vertices[state[:, None], b[:, None], verts]  # (N, V, 3)
        nrm = g.normal[state[:, None], a[:, None], quads]  # (N, B, 3)
        h = np.einsum("nvi,nbi->nvb", x, nrm)
        off = g.offset[state[:, None], a[:, None], quads][:, None]
        t = g.touch[state[:, None], a[:, None], quads][:, None] - margin
        up = ((h > off + t) & ~skip).any(axis=1)
        down = ((h < off - t) & ~skip).any(axis=1)
        sides.append((up, down, x))
    (up0, down0, _), (up1, down1, x1) = sides
    sided = (up1 & down1) | (up0 & down1) | (down0 & up1)  # (N, B)
    lo = np.where(skip, np.inf, x1).min(axis=1)[:, None]
    hi = np.where(skip, -np.inf, x1).max(axis=1)[:, None]
    at = (ks[:, None] + 1, a[:, None], quads)
    gap = np.maximum(lo - g.centre[at], 0.0) + np.maximum(g.centre[at] - hi, 0.0)
    reach = np.sqrt(g.radius2[at]) + g.reach[ks][:, None] + margin
    return (sided & ((gap**2).sum(axis=-1) <= reach**2)).any(axis=1)


def compare_on(path, monkeypatch) -> int:
    """Run the whole range of ``path``'s certificate, comparing :func:`sided_blocks` with
    :func:`heights_of_every_candidate` on every run of states; the candidate pairs compared."""
    compared = []

    def both(g, candidates, shape, quad_block, local, excluded):
        live = sided_blocks(g, candidates, shape, quad_block, local, excluded)
        if len(candidates[0]):
            expected = heights_of_every_candidate(g, candidates, quad_block, local, excluded)
            assert np.array_equal(live, expected), path.name
        compared.append(len(candidates[0]))
        return live

    monkeypatch.setattr(interference_events, "sided_blocks", both)
    certificate = load_model(path).certificate
    for start in range(0, len(certificate.alphas) - 1, 16):
        vertices = certificate._vertices_at(certificate.alphas[start : start + 17])
        interference_events.path_events(
            vertices, certificate._n, certificate._excluded, certificate._tol
        )
    return sum(compared)


@pytest.mark.parametrize("name", ["quadrants.toml", "vault.toml"])
def test_the_box_bound_keeps_the_pairs_the_heights_keep(name, monkeypatch):
    assert compare_on(EXAMPLES / name, monkeypatch) > 1000


@pytest.mark.slow
@pytest.mark.parametrize("path", CORPUS, ids=[p.stem for p in CORPUS])
def test_the_box_bound_keeps_the_pairs_the_heights_keep_on_every_design(path, monkeypatch):
    """Every example and catalog design, the whole range (~1-6 s each)."""
    try:
        compare_on(path, monkeypatch)
    except CCUError:
        pytest.skip("not a model here")


def test_the_hinge_patterns_leave_out_the_hinge_rows():
    """A plate's block against its hinged neighbour leaves out its hinge row, against any other
    plate none: one pattern per case, the boxes of the vertices off the hinge."""
    certificate = load_model(EXAMPLES / "vault.toml").certificate
    vertices = certificate._vertices_at(certificate.alphas[:3])
    captured = {}

    def keep(g, candidates, shape, quad_block, local, excluded):
        captured.update(g=g, quad_block=quad_block, local=local, excluded=excluded)
        return sided_blocks(g, candidates, shape, quad_block, local, excluded)

    interference_events.sided_blocks, before = keep, interference_events.sided_blocks
    try:
        interference_events.path_events(
            vertices, certificate._n, certificate._excluded, certificate._tol
        )
    finally:
        interference_events.sided_blocks = before
    g, local = captured["g"], captured["local"]
    t = block_tables(g, captured["quad_block"], local, captured["excluded"])
    assert len(t.masks) == 3 and t.masks.sum(axis=1).tolist() == [0, 9, 9]
    k, p = g.vertices.shape[:2]
    lo = t.lo.reshape(k, p, len(local), len(t.masks), 3)
    for i, mask in enumerate(t.masks):
        expected = g.vertices[:, :, local[:, ~mask]].min(axis=3)
        assert np.array_equal(lo[:, :, :, i], expected)


def test_the_edge_planes_of_all_quads_are_each_quads_own():
    """The events read the edge planes of every quad computed at once: bit for bit those of
    the quads computed alone, or a few together in any order."""
    certificate = load_model(EXAMPLES / "quadrants.toml").certificate
    vertices = certificate._vertices_at(certificate.alphas[:5])
    corners, normal = interference_events._quads(vertices, certificate._n)[:2]
    inward, sides = interference_events._edge_planes(corners, normal)
    rng = np.random.default_rng(3)
    at = tuple(rng.integers(0, size, 200) for size in corners.shape[:3])
    some_inward, some_sides = interference_events._edge_planes(corners[at], normal[at])
    assert np.array_equal(some_inward, inward[at]) and np.array_equal(some_sides, sides[at])
    one_inward, one_sides = interference_events._edge_planes(corners[0, 0, :1], normal[0, 0, :1])
    assert np.array_equal(one_inward, inward[0, 0, :1])
    assert np.array_equal(one_sides, sides[0, 0, :1])
