"""Splice plates: staggered cuts, their piles in the flat stack, their mass and collisions,
and the one list of assembly steps (fabrication.json and the assembly sheet)."""

from __future__ import annotations

import re
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")
from shapely.geometry import Point, Polygon  # noqa: E402

from compas_ccu.fabrication.assembly import assembly_steps, step_items  # noqa: E402
from compas_ccu.fabrication.hinges import hinge_strips  # noqa: E402
from compas_ccu.fabrication.splices import (  # noqa: E402
    fitting_size,
    shifted_cuts,
    splice_pile,
    splice_records,
    splice_summary,
    stagger_cuts,
    sub_outline,
)
from compas_ccu.fabrication.workshop import WorkshopOptions, plan_workshop  # noqa: E402
from compas_ccu.thickness import ThickModel  # noqa: E402
from compas_ccu.thickness.splices import PileMap, footprints_contain, max_pile  # noqa: E402

T = 0.008  # the 8 mm vault's plates and splice plates (examples/overbent.toml)
#: The vault's cuts, measured: bottom-up, each next to the ones below, alternating sides.
VAULT_CUTS = {0: [32], 1: [28], 2: [36], 3: [24], 4: [40], 5: [20], 6: [44], 7: [16], 8: [48],
              9: [12]}  # fmt: skip


# ------------------------------------------------------------------------------- the pile map


def _square(x0, y0, size=1.0):
    return np.array([[x0, y0], [x0 + size, y0], [x0 + size, y0 + size], [x0, y0 + size]])


def test_pile_of_overlapping_touching_and_separate_footprints():
    a, b = _square(0, 0), _square(0.5, 0.5)  # overlap in [0.5, 1]²
    assert max_pile([a, b], [0.008, 0.004])[0] == pytest.approx(0.012, abs=1e-15)
    assert max_pile([a, _square(1, 0)], [0.008, 0.008])[0] == pytest.approx(0.016)  # an edge
    assert max_pile([a, _square(1 + 1e-6, 0)], [0.008, 0.008])[0] == pytest.approx(0.008)
    assert max_pile(np.zeros((0, 4, 2)), []) == (0.0, None)
    # a clockwise diamond over both squares' corner at (1, 1), its corners outside both
    diamond = np.array([[1.0, 0.8], [0.8, 1.0], [1.0, 1.2], [1.2, 1.0]])
    pile, point = max_pile([a, b, diamond], [1.0, 2.0, 4.0])
    assert pile == pytest.approx(7.0) and footprints_contain([point], [a, b, diamond]).all()


def test_pile_map_is_the_brute_force_maximum_and_a_trial_adds_nothing():
    rng = np.random.default_rng(3)
    quads = []
    for _ in range(12):
        c, w, h, turn = rng.uniform(0, 1, 2), *rng.uniform(0.1, 0.5, 2), rng.uniform(0, np.pi)
        r = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
        quads.append(c + np.array([[-w, -h], [w, -h], [w, h], [-w, h]]) @ r.T)
    thick = rng.uniform(1, 3, 12)
    piles = PileMap()
    piles.add(np.array(quads[:6]), thick[:6])
    before = piles.max
    trial = piles.trial(np.array(quads[6:]), thick[6:])
    assert piles.max == before  # a trial changes nothing
    piles.add(np.array(quads[6:]), thick[6:])
    assert piles.max == pytest.approx(trial, abs=1e-12)
    assert piles.max == pytest.approx(max_pile(np.array(quads), thick)[0], abs=1e-12)
    # no point of a fine grid piles higher; the reported point piles that high
    g = np.stack(np.meshgrid(*[np.linspace(-0.6, 1.6, 301)] * 2), axis=-1).reshape(-1, 2)
    grid = footprints_contain(g, np.array(quads), tol=0.0) @ thick
    assert grid.max() <= piles.max + 1e-12
    at = footprints_contain([piles.argmax], np.array(quads)) @ thick
    assert at[0] == pytest.approx(piles.max, abs=1e-12)


# -------------------------------------------------------------- staggered cuts, in closed form


def _strips(count: int, length: float = 3.0, width: float = 1.0, quads: int = 12):
    """``count`` equal strips stacked over each other (the plan of a flat stack)."""
    x = np.linspace(0.0, length, quads + 1)
    flat = np.r_[np.c_[x, 0.0 * x], np.c_[x, 0.0 * x + width]]
    return SimpleNamespace(
        plate_ids=list(range(count)), stack_position=list(range(count)), segments=quads,
        flat=np.array([flat] * count), thickness=T, hinge_width=0.05, metadata={"grain": 0.0},
    )  # fmt: skip


def test_cuts_step_aside_by_one_quad_when_it_clears_the_splice_width():
    data = _strips(3)  # 0.25 m quads, 150 mm splices: a neighbouring ruling is clear
    o = WorkshopOptions()
    assert stagger_cuts(data, o, stagger=False) == {0: [6], 1: [6], 2: [6]}
    assert stagger_cuts(data, o) == {0: [6], 1: [5], 2: [7]}
    piles = [splice_pile(splice_records(data, stagger_cuts(data, o, stagger=s), o)) for s in (0, 1)]
    assert piles == pytest.approx([6 * T, 2 * T], abs=1e-15)
    # 2.452 m a part at most on 2.5 m sheets: a 3 m strip is cut at rulings 3 .. 9
    assert shifted_cuts(data.flat[0], o, 0.0, [6]) == [[6], [5], [7], [4], [8], [3], [9]]
    wide = replace(o, splice_width=0.3)  # wider than a quad: every second ruling
    assert stagger_cuts(data, wide) == {0: [6], 1: [4], 2: [8]}


# ------------------------------------------------------------------------------------ the vault


@pytest.fixture(scope="module")
def vault(overbent_model, overbent_fab_data):
    """The vault in 8 mm on the default 2.5 x 1.25 m sheets: every plate is spliced."""
    vault_model, vault_fab_data = overbent_model, overbent_fab_data
    thick = ThickModel(vault_model)
    o = WorkshopOptions(nesting="shelf")
    plan = plan_workshop(
        vault_fab_data,
        hinge_strips(vault_fab_data),
        o,
        density=float(thick.material.density),
        pairing=vault_fab_data.metadata["pairing"],
    )
    summary = splice_summary(thick, vault_fab_data, plan.splices, plan.splits, o)
    return SimpleNamespace(thick=thick, data=vault_fab_data, options=o, plan=plan, splices=summary)


def test_vault_cuts_are_staggered_deterministically_and_every_part_fits(vault):
    d, o = vault.data, vault.options
    assert vault.plan.splits == VAULT_CUTS
    assert stagger_cuts(d, o) == VAULT_CUTS  # the same design, the same cuts
    n = d.segments
    for i, pid in enumerate(d.plate_ids):
        bounds = [0, *VAULT_CUTS[pid], n]
        for a, b in zip(bounds, bounds[1:]):
            assert fitting_size(sub_outline(d.flat[i], n, a, b), o, 0.0) is not None
    names = [r.name for r in vault.plan.splices]
    assert names == [f"S{k}.1{f}" for k in range(10) for f in "DU"]
    assert sorted(names) == sorted(p.name for p in vault.plan.parts if p.kind == "splice")


def _under(point, polygons) -> int:
    return sum(Polygon(p).buffer(1e-9).contains(Point(*point)) for p in polygons)


def test_vault_stack_height_with_splices_is_what_lies_under_the_crown(vault):
    """Every plate and every splice plate over the middle of the crown's ruling, counted with
    shapely: 10 plates + 2 splice plates = 96 mm staggered, 10 + 20 = 240 mm all at ruling 32."""
    d, o, n = vault.data, vault.options, vault.data.segments
    crown = 0.5 * (d.flat[0][n // 2] + d.flat[0][n + 1 + n // 2])  # the plan is shared
    plates = _under(crown, [d.outline(i) for i in range(10)])
    assert plates == 10
    model_ids = d.metadata["model_plate_ids"]
    for records, spliced, height in (
        (vault.plan.splices, 2, 0.096),
        (splice_records(d, stagger_cuts(d, o, stagger=False), o), 20, 0.240),
    ):
        under = _under(crown, [r.footprint for r in records])
        assert under == spliced
        in_model = [replace(r, plate=model_ids[r.plate]) for r in records]
        stack = vault.thick.splice_stack(in_model)
        assert stack.stack_height == pytest.approx(plates * T + under * T, abs=1e-12)
        assert stack.stack_height == pytest.approx(height, abs=1e-12)
        assert stack.stack_height_plates == pytest.approx(0.080, abs=1e-12)
    s = vault.splices
    assert (s["max_pile_unstaggered"], s["max_pile"]) == pytest.approx((0.160, 0.016), abs=1e-12)
    assert s["stack_height"] == pytest.approx(0.096, abs=1e-12)


def test_vault_splice_mass_is_their_volume_times_the_density(vault):
    s, thick = vault.splices, vault.thick
    area = sum(Polygon(r["footprint"]).area for r in s["records"])
    assert s["count"] == 20 and s["area"] == pytest.approx(area, rel=1e-12)
    # 150 mm x (240 mm ruling - 2 x 50 mm hinge insets) = 0.021 m² each
    assert area == pytest.approx(20 * 0.15 * 0.14, rel=1e-9)
    assert s["mass"] == pytest.approx(area * T * thick.material.density, rel=1e-12)
    bom = sum(r["mass_kg"] for r in vault.plan.bom["rows"] if r["kind"] == "splice")
    assert s["mass"] == pytest.approx(bom, rel=1e-12)  # the BOM's splice rows


def test_vault_splices_hold_the_flat_stack_open_and_clear_the_neighbours_when_deployed(vault):
    c = vault.splices["collisions"]
    # in the closed thick stack a splice plate's mid-height points lie in its neighbour's mid
    # plane: t/2 deep; clear before the design state, 37 mm apart there
    assert c["max_depth"] == pytest.approx(0.5 * T, abs=1e-9)
    assert c["interpenetration"] is False
    assert 0.0 < c["clear_from_alpha"] < 30.0
    assert c["clearance_design"] > 0.0
    outside = [row["name"] for row in c["splices"] if row["neighbour"] is None]
    assert outside == ["S0.1D", "S9.1U"]  # under the bottom plate, on the top one
    assert all(row["neighbour"] == int(row["name"][1]) + 1 for row in c["splices"][1:-1:2])
    # 10 cm splice plates still reach into their neighbours at the design state: the check fails
    model_ids = vault.data.metadata["model_plate_ids"]
    thick_splices = [
        replace(r, plate=model_ids[r.plate], thickness=0.1) for r in vault.plan.splices
    ]
    deep = vault.thick.splice_collisions(thick_splices)
    assert deep.interpenetration is True and deep.clear_from_alpha is None


# ------------------------------------------------------------------------------------ assembly


def test_vault_assembly_names_every_bom_item_with_its_face_and_place(vault):
    steps = vault.plan.assembly
    assert len(steps) == 10 * 3 + 10 + 9  # per plate: splice, join, splice; lay; glue
    assert [s["step"] for s in steps] == list(range(1, 50))
    bom = [r["item"] for r in vault.plan.bom["rows"]]
    assert sorted(step_items(steps)) == sorted(bom)
    for k in range(10):
        lower, join, upper = steps[3 * k : 3 * k + 3]
        j = VAULT_CUTS[k][0]
        assert (lower["parts"], lower["face"], lower["where"]["ruling"]) == (
            [f"S{k}.1D"],
            "lower",
            j,
        )
        assert (join["parts"], join["face"]) == ([f"P{k}.1", f"P{k}.2"], "UP")
        assert (upper["parts"], upper["face"], upper["where"]["ruling"]) == (
            [f"S{k}.1U"],
            "upper",
            j,
        )
        flat = vault.data.flat[k]
        along = np.linalg.norm(np.diff(flat[: j + 1], axis=0), axis=1).sum()
        assert lower["where"]["along"] == pytest.approx(along, rel=1e-12)
    assert steps == assembly_steps(vault.data, vault.plan.splits)  # the pairing of the data


def test_the_assembly_sheet_lists_every_bom_item(vault, tmp_path):
    pytest.importorskip("matplotlib")
    from compas_ccu.fabrication.sheet import write_assembly_sheet

    path = write_assembly_sheet(
        vault.data, tmp_path / "assembly.svg", steps=vault.plan.assembly, stack=vault.splices
    )
    texts = re.findall(r"<text[^>]*>([^<]*)</text>", path.read_text(encoding="utf-8"))
    text = re.sub(r"\s+", " ", " ".join(texts))
    for item in (r["item"] for r in vault.plan.bom["rows"]):
        assert re.search(rf"(?<![\w.]){re.escape(item)}(?![\w.])", text), item
    assert "96 mm with the 20 splice plates (highest pile 16 mm)" in text
    assert (
        "1-3. P0 on the table: S0.1D under, P0.1 + P0.2 UP face up, cut edges at ruling 32" in text
    )


def test_without_splices_the_stack_is_the_plates_and_nothing_collides(cone_model):
    thick = ThickModel(cone_model)
    stack = thick.splice_stack([])
    assert stack.stack_height == stack.stack_height_plates == thick.stack_height
    assert (stack.max_pile, stack.pile_point, stack.count, stack.mass) == (0.0, None, 0, 0.0)
    c = thick.splice_collisions([], [0.0, 10.0])
    assert (c.max_depth, c.clear_from_alpha, c.interpenetration) == (0.0, 0.0, False)
    assert c.clearance_design is None and c.splices == ()
    assert c.to_dict() == {
        "alphas": [0.0, 10.0, 2], "tolerance": 1e-6, "max_depth": 0.0,
        "clear_from_alpha": 0.0, "interpenetration": False, "clearance_design": None,
        "splices": [],
    }  # fmt: skip
    assert list(stack.to_dict()) == [
        "stack_height", "stack_height_plates", "max_pile", "pile_point", "count", "area", "mass"
    ]  # fmt: skip
