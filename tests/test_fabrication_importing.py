"""``ccu import``: plate DXFs back to a design that deploys (fabricate -> import -> deploy)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from compas_ccu.catalog import catalog_path
from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.errors import DesignError
from compas_ccu.model import CCUModel, load_model
from conftest import EXAMPLES

ezdxf = pytest.importorskip("ezdxf")
pytest.importorskip("shapely")
pytest.importorskip("rhino3dm")
pytest.importorskip("trimesh")

from compas_ccu.fabrication.fabricate import fabricate  # noqa: E402
from compas_ccu.fabrication.importing import (  # noqa: E402
    import_design,
    import_structure,
    read_plate_drawing,
    round_trip_error,
    structure_round_trip_error,
)
from compas_ccu.fabrication.workshop import WorkshopOptions  # noqa: E402

#: The sheets nested by shelves: fast, and the plate files do not depend on the nesting.
SHELF = WorkshopOptions(nesting="shelf")

R, WIDTH, SWEEP, N, ALPHA = 2.0, 0.4, 90.0, 48, 40.0


def sector(msp, *, radius=R, rulings=None, far=None, crease_entity="ARC", layers=None):
    """An annular sector drawn by hand (mm): crease = outer arc, rulings radial."""
    layers = layers or {"CUT": "CUT", "CREASE": "CREASE", "RULING_SCORE": "RULING_SCORE"}
    k = 1000.0
    a0, a1 = 45.0, 45.0 + SWEEP
    inner = radius - WIDTH
    bulge = math.tan(math.radians(SWEEP) / 4.0)

    def at(r, deg):
        return (r * k * math.cos(math.radians(deg)), r * k * math.sin(math.radians(deg)))

    if layers["CUT"]:
        msp.add_lwpolyline(
            [(*at(radius, a0), bulge), (*at(radius, a1), 0.0), (*at(inner, a1), -bulge),
             (*at(inner, a0), 0.0)],
            format="xyb",
            close=True,
            dxfattribs={"layer": layers["CUT"]},
        )  # fmt: skip
    if crease_entity == "ARC":
        msp.add_arc((0, 0), radius * k, a0, a1, dxfattribs={"layer": layers["CREASE"]})
    angles = np.linspace(a0, a1, N + 1)[1:-1] if rulings is None else rulings
    if layers["RULING_SCORE"]:
        for j, deg in enumerate(angles):
            end = at(inner, deg) if far is None else far(j, deg)
            msp.add_line(at(radius, deg), end, dxfattribs={"layer": layers["RULING_SCORE"]})


def hand_drawn(folder, **partner):
    folder.mkdir(exist_ok=True)
    for name, options in (("plate_a.dxf", {}), ("plate_b.dxf", partner)):
        doc = ezdxf.new("R2010")
        doc.units = ezdxf.units.MM
        sector(doc.modelspace(), **options)
        doc.saveas(folder / name)
    return folder


def crease_radius_error(points, radius):
    """Largest distance of the points from the circle through the first, middle and last."""
    a, b, c = points[0], points[len(points) // 2], points[-1]
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal)
    m = np.array([b - a, c - a, normal])
    rhs = np.array([(b - a) @ (b + a) / 2.0, (c - a) @ (c + a) / 2.0, normal @ a])
    centre = np.linalg.solve(m, rhs)
    return float(np.abs(np.linalg.norm(points - centre, axis=1) - radius).max())


def test_hand_drawn_circular_crease_deploys_to_the_cone(tmp_path):
    """One ARC crease, 47 radial LINE rulings, bulged outlines, no XDATA, no fabrication.json:
    the plates pair by their creases' lengths and the design deploys to the cone, the crease a
    circle of radius r3D = R cos(alpha), and equals examples/cone.toml's structure."""
    folder = hand_drawn(tmp_path / "drawn")
    document, report = import_design(folder, alpha=ALPHA)
    assert report["segments"] == N and report["partner_error"] < 1e-12
    near = np.asarray(document["crease"]["points"])
    assert np.abs(np.linalg.norm(near, axis=1) - R).max() < 1e-12  # vertices on the arc
    structure = CCUModel(Design(document)).deploy(ALPHA)
    deployed = np.asarray(structure.deployed)
    expected = R * math.cos(math.radians(ALPHA))
    assert crease_radius_error(deployed[0, : N + 1], expected) < 1e-12
    assert crease_radius_error(
        deployed[0, N + 1 :], (R - WIDTH) * math.cos(math.radians(ALPHA))
    ) < (1e-12)
    cone = load_model(EXAMPLES / "cone.toml").deploy(ALPHA)
    # the same plates up to a rigid motion: compare the (rigid-invariant) pairwise distances
    a = deployed.reshape(-1, 3)[::7]
    b = np.asarray(cone.deployed).reshape(-1, 3)[::7]
    da = np.linalg.norm(a[:, None] - a[None], axis=2)
    db = np.linalg.norm(b[:, None] - b[None], axis=2)
    assert np.abs(da - db).max() < 1e-12


def test_round_trip_cone_fabricate_import_deploy(tmp_path):
    model = load_model(EXAMPLES / "cone.toml")
    fabricate(model, tmp_path / "fab", workshop=SHELF)
    result = round_trip_error(model, tmp_path / "fab")
    assert result["max_relative"] < 1e-9
    assert result["plate_ids"] == [0, 1] and result["crease_id"] == 0


@pytest.mark.slow
def test_round_trip_vault_every_crease_pair(tmp_path):
    """The vault's orthogonal rulings need no offset-crease correction: every one of its nine
    crease pairs comes back to rounding (measured 1.1e-15 ... 1.6e-15 relative)."""
    model = load_model(EXAMPLES / "vault.toml")
    fabricate(model, tmp_path / "fab", workshop=SHELF)
    errors = [round_trip_error(model, tmp_path / "fab", crease=c)["max_relative"] for c in range(9)]
    assert max(errors) < 1e-9
    with pytest.raises(DesignError, match="9 creases .*one crease pair: choose one"):
        import_design(tmp_path / "fab")
    # the whole vault, all ten plates joined into one mechanism (measured 1.4e-15)
    whole = structure_round_trip_error(model, tmp_path / "fab", crease=4)
    assert whole["plates"] == 10 and whole["max_relative"] < 1e-9
    assert whole["report"]["attached"][:2] == ["plate_5.dxf", "plate_4.dxf"]  # upper plate leads


@pytest.mark.slow
def test_round_trip_fig11a_whole_structure_is_the_thickness_correction(tmp_path):
    """fig11a's inclined planes need the offset-crease correction, which the cut patterns carry
    (linear in the thickness): with 1e-8 m plates the whole structure comes back to 3e-10
    relative (measured), with 8 mm plates to 2.4e-4; its plates alternate in width, so no
    single crease pair but the whole structure is imported."""
    model = load_model(catalog_path("fig11a-constant-apex"))
    fabricate(
        model,
        tmp_path / "thin",
        thickness=1e-8,
        hinge_width=0.03,
        allow_collisions=True,
        workshop=SHELF,
    )
    assert structure_round_trip_error(model, tmp_path / "thin", crease=4)["max_relative"] < 1e-9
    with pytest.raises(DesignError, match=r"RULING_SCORE #\w+ \(end ruling\): the ruling at"):
        import_design(tmp_path / "thin", crease=0)
    structure = import_structure(tmp_path / "thin", crease=4)
    assert len(structure.plate_ids) == 10 and structure.design.alpha == 30.0


def test_missing_layer_is_refused_naming_the_file(tmp_path):
    folder = tmp_path / "drawn"
    folder.mkdir()
    doc = ezdxf.new("R2010")
    sector(doc.modelspace(), layers={"CUT": "CUT", "CREASE": "CREASE", "RULING_SCORE": None})
    doc.saveas(folder / "plate_a.dxf")
    with pytest.raises(DesignError, match="plate_a.dxf: no entity on layer RULING_SCORE"):
        read_plate_drawing(folder / "plate_a.dxf")


def test_crossing_rulings_are_refused_naming_both_entities(tmp_path):
    inner = R - WIDTH

    def crossed(j, deg):  # rulings 10 and 11 swap their far ends
        other = {10: 1, 11: -1}.get(j, 0)
        d = math.radians(deg + other * SWEEP / N)
        return (inner * 1000 * math.cos(d), inner * 1000 * math.sin(d))

    folder = hand_drawn(tmp_path / "drawn", far=crossed)
    with pytest.raises(
        DesignError, match=r"plate_b.dxf RULING_SCORE #\w+ and #\w+: the rulings cross"
    ):
        import_design(folder, alpha=ALPHA)


def test_partner_creases_of_different_length_are_refused(tmp_path):
    folder = hand_drawn(tmp_path / "drawn", radius=2.1)
    with pytest.raises(
        DesignError,
        match=r"partner creases of different length: plate_a.dxf CREASE #\w+ is 3.14159265 m "
        r"long, plate_b.dxf CREASE #\w+ 3.29867229 m",
    ):
        import_design(folder, alpha=ALPHA)


def test_partner_that_is_not_the_mirror_image_is_refused(tmp_path):
    inner = R - WIDTH - 0.05

    def longer(j, deg):
        d = math.radians(deg)
        r = inner if j == 20 else R - WIDTH
        return (r * 1000 * math.cos(d), r * 1000 * math.sin(d))

    folder = hand_drawn(tmp_path / "drawn", far=longer)
    with pytest.raises(
        DesignError, match=r"plate_b.dxf RULING_SCORE #\w+: the ruling at crease vertex 21 is"
    ):
        import_design(folder, alpha=ALPHA)


def test_no_angle_without_fabrication_json(tmp_path):
    with pytest.raises(DesignError, match=r"give the design reflection angle \(--alpha DEG\)"):
        import_design(hand_drawn(tmp_path / "drawn"))


def test_cli_import_writes_a_design_that_loads(tmp_path, capsys):
    folder = hand_drawn(tmp_path / "drawn")
    out = tmp_path / "cone-imported.toml"
    assert main(["import", str(folder), "--out", str(out), "--alpha", "40", "--quiet"]) == 0
    design = load_design(out)
    assert design.crease.state == "flat" and design.rulings.type == "explicit"
    assert len(design.crease.points) == N + 1 and design.alpha == ALPHA
    assert main(["import", str(folder), "--out", str(out), "--alpha", "40"]) == 2
    assert "exists; give --force" in capsys.readouterr().err


def test_open_outline_ruling_off_the_crease_and_crease_off_the_outline(tmp_path):
    folder = tmp_path / "drawn"
    folder.mkdir()
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    msp = doc.modelspace()
    sector(msp, layers={"CUT": None, "CREASE": "CREASE", "RULING_SCORE": "RULING_SCORE"})
    msp.add_lwpolyline([(0, 0), (100, 0), (100, 100)], dxfattribs={"layer": "CUT"})
    doc.saveas(folder / "plate_a.dxf")
    with pytest.raises(DesignError, match=r"plate_a.dxf CUT #\w+: the outline is not closed"):
        read_plate_drawing(folder / "plate_a.dxf")

    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    sector(doc.modelspace())
    stray = doc.modelspace().add_line((0, 0), (10, 10), dxfattribs={"layer": "RULING_SCORE"})
    doc.saveas(folder / "plate_a.dxf")
    doc.saveas(folder / "plate_b.dxf")
    with pytest.raises(
        DesignError,
        match=rf"plate_a.dxf RULING_SCORE #{stray.dxf.handle}: the ruling does not start on the "
        r"crease #\w+ \(its ends are 1.\d+ m from it\)",
    ):
        import_design(folder, alpha=ALPHA)

    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    sector(doc.modelspace(), crease_entity=None)
    doc.modelspace().add_arc((0, 0), 2000.0, 44.0, 136.0, dxfattribs={"layer": "CREASE"})
    doc.saveas(folder / "plate_a.dxf")
    doc.saveas(folder / "plate_b.dxf")
    with pytest.raises(DesignError, match=r"plate_a.dxf CREASE #\w+: its end point .* is not a "):
        import_design(folder, alpha=ALPHA)
