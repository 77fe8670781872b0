"""The interpenetration certificate (compas_ccu.kinematics.interference) against an independent
brute-force triangle test (tests/intersection_oracle.py): no state the library returns has two
plates crossing, and no state clear of crossings is refused."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from compas_ccu.design import Design
from compas_ccu.errors import CCUError, SelfIntersectionError
from compas_ccu.kinematics import interference_events
from compas_ccu.kinematics.interference import ANGLE_TOLERANCE
from compas_ccu.model import CCUModel, load_model
from conftest import EXAMPLES, property_examples
from intersection_oracle import crossing_pairs

DATA = Path(__file__).resolve().parents[1] / "src" / "compas_ccu" / "data"
CORPUS = sorted(
    list(EXAMPLES.glob("*.toml"))
    + list((DATA / "catalog").glob("*.toml"))
    + list((DATA / "presets").glob("*.toml"))
)


def ring(plates: int, angle: float, *, segments: int = 24, alpha: float = 30.0) -> CCUModel:
    """A radial ring of ``plates`` plates ``angle`` degrees apart (the dome preset's crease)."""
    return CCUModel(
        Design(
            {
                "design": {"name": f"ring-{plates}"},
                "crease": {
                    "profile": "spline",
                    "points": [[0.25, 1.2], [1.0, 1.0], [1.6, 0.5], [1.9, 0.0]],
                    "segments": segments,
                },
                "rulings": {"type": "orthogonal", "side": "inside"},
                "deployment": {"alpha": alpha},
                "layout": {"type": "radial", "plates": plates, "angle": angle, "axis": 0.0},
            }
        )
    )


def oracle(model: CCUModel, alpha: float, *, warp: float = 2.0) -> list:
    """Plate id pairs that the brute-force triangle test finds crossing at ``alpha`` (deg)."""
    ids = model.plate_ids
    pairs = crossing_pairs(model.vertices([alpha])[0], warp=warp)
    return sorted({tuple(sorted((ids[a], ids[b]))) for a, b in pairs})


def certified_states_are_clear(model: CCUModel, count: int = 6) -> None:
    """Every returned state from the flat stack to the certified angle passes the oracle, and
    a state at most 0.1 deg past a crossing the certificate found fails it.

    The two agree to the warp of the quads: where creases leave their planes (radial and
    inclined layouts) the quads are planar only to 1e-6 of the size at the design and to 1e-2
    near the limit, and a quad and its two triangles differ by that much. So a returned state
    must be clear to the oracle with 4 times the warp as touching, and the state past a
    crossing cross to it with twice the warp.
    """
    free = model.collision_free_alpha
    for alpha in np.linspace(0.0, free - 1e-4, count)[1:]:
        structure = model.deploy(alpha)  # accepted: so it must be clear
        assert oracle(model, structure.alpha, warp=4.0) == [], (model.name, alpha)
    found = model.interference
    if found.hit is not None and math.degrees(found.hit) < model.overlap_alpha:
        with pytest.raises(SelfIntersectionError):
            model.deploy(math.degrees(found.hit) + 0.01)
        beyond = [math.degrees(found.hit) + d for d in (0.01, 0.03, 0.1)]
        assert any(oracle(model, a) for a in beyond), (model.name, beyond)


def test_the_ring_that_wraps_through_itself_is_refused_from_where_its_ends_meet():
    """12 plates x 29 deg = 348 deg at alpha = 30: its last plate reaches round to its first."""
    model = ring(12, 29.0, segments=48)
    found = model.interference
    assert found.kind == "crossing"
    assert {model.plates.output_id(i) for i in found.plates} == {0, 11}
    assert 32.70 < model.collision_free_alpha < 32.73
    assert found.hit - found.clear <= ANGLE_TOLERANCE
    model.deploy(32.7)
    with pytest.raises(SelfIntersectionError) as info:
        model.deploy(33.0)
    message = str(info.value)
    assert message.startswith("self-intersection at alpha = 33 deg: plates 11 and 0 cross at ")
    assert "without any two plates crossing is 32.7" in message and "\n" not in message
    assert set(info.value.plates) == {0, 11} and info.value.alpha == 33.0
    assert oracle(model, 32.70) == [] and oracle(model, 33.0) == [(0, 11)]
    with pytest.raises(SelfIntersectionError):  # a path is refused as a whole
        model.path([10.0, 20.0, 40.0])


def test_a_certificate_asked_in_parts_is_the_certificate_asked_at_once():
    """The scan's states are fixed for the whole range: deploying to the design first, then
    asking the key figure, gives the same angle to the last bit as asking it at once."""
    whole = ring(12, 29.0)
    parts = ring(12, 29.0)
    parts.deploy(10.0)
    parts.deploy(30.0)
    assert parts.collision_free_alpha == whole.collision_free_alpha
    assert parts.interference.plates == whole.interference.plates


def test_the_cone_never_crosses_and_the_vault_first_overlaps_a_crease():
    cone = load_model(EXAMPLES / "cone.toml")
    assert cone.interference.hit is None
    assert cone.interference.clear == pytest.approx(math.radians(cone.alpha_limit), rel=1e-12)
    assert cone.collision_free_alpha == cone.overlap_alpha  # the crease overlap comes first
    vault = load_model(EXAMPLES / "vault.toml")
    assert vault.collision_free_alpha == pytest.approx(68.153, abs=1e-3)


def test_the_key_figures_carry_the_certified_angle():
    from compas_ccu.key_figures import key_figures

    model = ring(12, 29.0)
    k = key_figures(model)
    assert k.collision_free_alpha == model.collision_free_alpha
    assert k.limit_margin == pytest.approx(model.collision_free_alpha - 30.0, rel=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("path", CORPUS, ids=[p.stem for p in CORPUS])
def test_every_shipped_design_is_clear_up_to_its_certified_angle(path):
    try:
        model = load_model(path)
    except CCUError:  # designs that only some commands take (e.g. a curve file missing here)
        pytest.skip("not a model here")
    certified_states_are_clear(model)


@pytest.mark.slow
@pytest.mark.parametrize("plates", [6, 8, 12, 16])
@pytest.mark.parametrize("total", [350.0, 358.0])
def test_rings_near_a_full_turn_are_clear_up_to_their_certified_angle(plates, total):
    model = ring(plates, total / plates)
    free = model.collision_free_alpha
    assert free < model.overlap_alpha  # the ends meet before any crease overlaps
    certified_states_are_clear(model, count=4)


@st.composite
def layouts(draw):
    kind = draw(st.sampled_from(["radial", "parallel", "inclined"]))
    plates = draw(st.integers(2, 10))
    if kind == "radial":
        layout = {"type": "radial", "plates": plates, "axis": 0.0}
        layout["angle"] = draw(st.floats(300.0 / plates, 359.0 / plates))
    else:
        layout = {"type": kind, "plates": plates, "spacing": draw(st.floats(0.05, 0.3))}
        if kind == "inclined":
            layout["spacing_start"] = draw(st.floats(0.0, 0.3))
            layout["spacing_end"] = draw(st.floats(0.0, 0.3))
    rise = draw(st.floats(0.3, 1.0))
    return {
        "design": {"name": "random"},
        "crease": {"profile": "arc", "span": 2.5, "rise": rise, "segments": 16},
        "rulings": {"type": "orthogonal", "side": "inside"},
        "deployment": {"alpha": draw(st.floats(10.0, 40.0))},
        "layout": layout,
    }, draw(st.floats(0.02, 0.98))


@pytest.mark.slow
@settings(
    max_examples=property_examples(25), deadline=None, suppress_health_check=list(HealthCheck)
)
@given(layouts())
def test_every_returned_state_of_random_layouts_passes_the_oracle(case):
    document, where = case
    try:
        model = CCUModel(Design(document))
    except CCUError:
        return
    alpha = where * model.alpha_limit
    try:
        structure = model.deploy(alpha)
    except SelfIntersectionError:
        assert alpha > model.collision_free_alpha
        return
    assert crossing_pairs(np.asarray(structure.deployed), warp=4.0) == []


# -- the candidate blocks left out before the exact tests (issue 31, item 3) ------------------


def every_event(certificate, sided: bool) -> list:
    """Every event of ``certificate``'s whole range, chunk by chunk as the scan takes them:
    ``(chunk start, state, kind, a, b, point bytes)``; ``sided=False`` runs the exact tests on
    every candidate block pair (no block left out, as before the filter)."""
    keep = interference_events.sided_blocks
    if not sided:
        interference_events.sided_blocks = lambda g, found, *_: np.ones(len(found[0]), dtype=bool)
    try:
        out = []
        for start in range(0, len(certificate.alphas) - 1, 16):
            vertices = certificate._vertices_at(certificate.alphas[start : start + 17])
            events, tol = interference_events.path_events(
                vertices, certificate._n, certificate._excluded, certificate._tol
            )
            out += [(start, k, kind, a, b, point.tobytes()) for k, kind, a, b, point in events]
            out.append((start, tol))
        return out
    finally:
        interference_events.sided_blocks = keep


@pytest.mark.parametrize(
    "path",
    [
        EXAMPLES / "quadrants.toml",
        # every block pair of its whole range tested (~4 s)
        pytest.param(DATA / "catalog" / "fig11c-alternating.toml", marks=pytest.mark.slow),
    ],
)
def test_the_blocks_left_out_hold_no_event(path):
    """The scan tests only the block pairs with vertices on both sides of a quad's plane near
    it; every event of the whole range (crossings, pass-throughs, their order, plates and
    points) is that of the exact tests on every block pair, bit for bit."""
    certificate = load_model(path).certificate
    found = every_event(certificate, sided=True)
    assert len(found) > 100  # ranges beyond the first crossing: many events of both kinds
    assert {e[2] for e in found if len(e) > 2} == {"crossing", "pass-through"}
    assert found == every_event(certificate, sided=False)


@pytest.mark.parametrize("name", ["vault.toml", "quadrants.toml", "cone.toml"])
def test_the_states_kept_from_the_set_up_are_the_states_placed_again(name):
    """The scan reads the states of its set-up (the ends of its steps) instead of placing them
    again: the same vertices, bit for bit, and the same result as a scan that places them."""
    model = load_model(EXAMPLES / name)
    certificate = model.certificate
    kept = certificate._initial >= 0
    assert kept.sum() == 33 and kept[0] and kept[-1]
    for start in range(0, len(certificate.alphas) - 1, 16):
        stop = min(start + 17, len(certificate.alphas))
        placed = certificate._vertices_at(certificate.alphas[start:stop])
        assert np.array_equal(certificate._states(start, stop), placed)
    fresh = load_model(EXAMPLES / name).certificate
    fresh._initial[:] = -1  # every state placed
    found, expected = certificate.result(), fresh.result()
    assert (found.clear, found.hit, found.plates, found.kind) == (
        expected.clear,
        expected.hit,
        expected.plates,
        expected.kind,
    )
    assert certificate._placed is None  # released once the scan is over
