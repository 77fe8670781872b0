"""Figures: the expected size, not blank (pixel statistics), the right colours and content."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from compas_ccu.design import load_design  # noqa: E402
from compas_ccu.model import load_model
from compas_ccu.viz import colors as C  # noqa: E402
from compas_ccu.viz.export import save_figure  # noqa: E402
from compas_ccu.viz.patterns import pattern_layout, plate_outline, plot_cut_patterns  # noqa: E402
from compas_ccu.viz.planarity import plot_planarity  # noqa: E402
from compas_ccu.viz.quadrants import plot_quadrants, quadrant_pairs  # noqa: E402
from compas_ccu.viz.render import Camera, camera, value_range  # noqa: E402
from compas_ccu.viz.scene import scene_from_structure  # noqa: E402
from compas_ccu.viz.sequence import plot_deployment_sequence  # noqa: E402
from compas_ccu.viz.sheet import plot_contact_sheet  # noqa: E402
from compas_ccu.viz.views import plot_views  # noqa: E402
from conftest import EXAMPLES  # noqa: E402
from imagecheck import assert_picture, has_colour, ink_fraction, load_rgb  # noqa: E402

DPI = 60


@pytest.fixture(scope="module")
def vault(vault_model):
    return vault_model.deploy()


def png(fig, tmp_path, name="fig"):
    (path,) = save_figure(fig, tmp_path / name, formats=("png",), dpi=DPI)
    return load_rgb(path)


def expected_size(fig):
    w, h = fig.get_size_inches()
    return (round(w * DPI), round(h * DPI))


def test_views_by_kind_show_both_crease_kinds(vault, tmp_path):
    fig = plot_views(vault)
    rgb = png(fig, tmp_path)
    assert_picture(rgb, size=expected_size(fig), min_ink=0.15)
    assert has_colour(rgb, C.KIND_COLORS["synclastic"])
    assert has_colour(rgb, C.KIND_COLORS["anticlastic"])
    assert not has_colour(rgb, C.KIND_COLORS["ccf"], tol=25)
    assert [ax.get_title() for ax in fig.axes] == ["perspective", "plan", "elevation", "side"]


def test_views_by_curvature_have_a_colour_bar_with_the_plate_curvature(vault, tmp_path):
    fig = plot_views(vault, color_by="curvature")
    bar = fig.axes[-1]
    assert "curvature" in bar.get_ylabel()
    lo, hi = bar.get_ylim()
    # the vault's plates are cylinders: |kappa| = 0.4282 1/m everywhere (a constant field gets
    # a +-1 % range, not a gradient of rounding noise)
    assert lo == pytest.approx(0.4282 * 0.99, rel=1e-3) and hi == pytest.approx(
        0.4282 * 1.01, rel=1e-3
    )
    assert_picture(png(fig, tmp_path), size=expected_size(fig), min_ink=0.15)


def test_views_by_a_per_vertex_value(vault, tmp_path):
    values = np.asarray(vault.deployed)[..., 2]  # height as a stand-in for a stress
    fig = plot_views(vault, color_by=values, label="height (m)", views=("perspective",))
    assert fig.axes[-1].get_ylabel() == "height (m)"
    rgb = png(fig, tmp_path)
    assert_picture(rgb, size=expected_size(fig), min_ink=0.1)
    # viridis ends: dark purple feet and yellow crowns are both on the picture
    assert has_colour(rgb, "#fde725", tol=60) and has_colour(rgb, "#440154", tol=60)


def test_views_refuse_bad_values_and_modes(vault):
    with pytest.raises(ValueError, match="per-vertex values must have shape"):
        plot_views(vault, color_by=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="color_by must be one of"):
        plot_views(vault, color_by="stress")
    with pytest.raises(ValueError, match="unknown view 'top'"):
        plot_views(vault, views=("top",))


def test_cut_patterns_do_not_overlap_and_show_every_plate(vault, tmp_path):
    offsets = pattern_layout(vault.flat)
    from shapely.geometry import Polygon

    polys = [Polygon(plate_outline(f[:, :2] + o)) for f, o in zip(vault.flat, offsets)]
    assert all(p.is_valid for p in polys)
    for i in range(len(polys)):
        for j in range(i + 1, len(polys)):
            assert polys[i].intersection(polys[j]).area == 0.0
    fig = plot_cut_patterns(vault)
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert sum(t.startswith("P") for t in texts) == 10
    assert sum(t.startswith("c") for t in texts) == 2 * 9  # each crease on both of its plates
    total = sum(p.area for p in polys)
    assert f"{total:.2f} m²" in fig.axes[0].get_title(loc="left")
    rgb = png(fig, tmp_path)
    assert_picture(rgb, size=expected_size(fig), min_ink=0.1)
    assert has_colour(rgb, C.KIND_COLORS["anticlastic"]) and has_colour(
        rgb, C.KIND_COLORS["synclastic"]
    )


def test_cut_pattern_areas_are_the_developed_areas(cone_model):
    # annular sector, R = 2.0 to 1.6 m over 90 degrees, inscribed polygon of 48 segments
    s = cone_model.deploy()
    outline = plate_outline(np.asarray(s.flat)[0])
    x, y = outline[:, 0], outline[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    h = np.pi / 2 / 48
    exact = 0.5 * 48 * np.sin(h) * (2.0**2 - 1.6**2)
    assert area == pytest.approx(exact, rel=1e-12)


def test_deployment_sequence_states_share_one_scale(vault_model, tmp_path):
    fig = plot_deployment_sequence(vault_model, count=4)
    assert [ax.get_title() for ax in fig.axes] == ["α = 0°", "α = 10°", "α = 20°", "α = 30°"]
    limits = {(ax.get_xlim(), ax.get_ylim()) for ax in fig.axes}
    assert len(limits) == 1
    rgb = png(fig, tmp_path)
    assert_picture(rgb, size=expected_size(fig), min_ink=0.05)
    # the panels differ: the first (flat stack) has less ink than the last (open vault)
    w = rgb.shape[1] // 4
    assert ink_fraction(rgb[:, :w]) < 0.8 * ink_fraction(rgb[:, -w:])
    with pytest.raises(ValueError, match="count must be an integer >= 2"):
        plot_deployment_sequence(vault_model, count=1)


def test_quadrants_figure_labels_and_sum_of_sector_angles(tmp_path):
    design = load_design(EXAMPLES / "quadrants.toml")
    fig = plot_quadrants(design)
    titles = [ax.get_title() for ax in fig.axes[::2]]  # top row; bottom row between
    assert [t[:2] for t in titles] == ["Q1", "Q2", "Q3", "Q4"]
    assert "Σβ = 360°, mean 360.00°" in titles[0] and "Σβ = 360°" in titles[2]
    q2 = float(titles[1].split("mean ")[1].rstrip("°"))
    q4 = float(titles[3].split("mean ")[1].rstrip("°"))
    assert q2 < 360.0 < q4
    rgb = png(fig, tmp_path)
    assert_picture(rgb, size=expected_size(fig), min_ink=0.1)
    for kind in ("ccf", "synclastic", "anticlastic"):
        assert has_colour(rgb, C.KIND_COLORS[kind]), kind


def test_quadrant_pairs_refuses_other_structures(vault):
    with pytest.raises(ValueError, match="not a four-quadrant structure"):
        quadrant_pairs(vault)


def test_planarity_plot_reads_the_mechanism(vault_model, tmp_path):
    fig = plot_planarity(vault_model, steps=12)
    ax = fig.axes[0]
    assert len(ax.lines) == 9 + 1
    worst = vault_model.crease_planarity(np.linspace(0, 30, 13)).max()
    assert f"largest {worst:.2e} m" in ax.get_title()
    assert worst < 1e-14
    assert_picture(png(fig, tmp_path), size=expected_size(fig), min_ink=0.02, min_colours=20)


def test_contact_sheet_has_one_panel_per_design(vault, tmp_path):
    others = [load_model(EXAMPLES / f"{n}.toml").deploy() for n in ("cone", "quadrants")]
    fig = plot_contact_sheet([vault, *others], title="examples")
    assert [ax.get_title() for ax in fig.axes] == ["vault", "cone", "quadrants"]
    assert_picture(png(fig, tmp_path), size=expected_size(fig), min_ink=0.08)
    with pytest.raises(ValueError, match="one entry per structure"):
        plot_contact_sheet([vault], titles=["a", "b"])
    with pytest.raises(ValueError, match="at least one"):
        plot_contact_sheet([])


def test_save_figure_formats(vault, tmp_path):
    fig = plot_cut_patterns(vault)
    paths = save_figure(fig, tmp_path / "sub" / "p", formats=("png", "svg", "pdf"), dpi=30)
    assert [p.suffix for p in paths] == [".png", ".svg", ".pdf"]
    assert paths[1].read_text().lstrip().startswith("<?xml")
    assert paths[2].read_bytes()[:5] == b"%PDF-"
    with pytest.raises(ValueError, match="figure formats"):
        save_figure(fig, tmp_path / "x", formats=("jpeg",))


def test_camera_projection_and_views():
    # orthographic plan: x right, y up; elevation: x right, z up
    xy, depth = camera("plan").project(np.array([[1.0, 2.0, 3.0]]), np.zeros(3), 1.0)
    np.testing.assert_allclose(xy, [[1.0, 2.0]], atol=1e-15)
    assert depth[0] == pytest.approx(3.0)
    xy, _ = camera("elevation").project(np.array([[1.0, 2.0, 3.0]]), np.zeros(3), 1.0)
    np.testing.assert_allclose(xy, [[1.0, 3.0]], atol=1e-15)
    # perspective: nearer points look larger
    cam = Camera(-90.0, 0.0, 3.0)
    near, _ = cam.project(np.array([[1.0, -1.0, 0.0]]), np.zeros(3), 1.0)
    far, _ = cam.project(np.array([[1.0, 1.0, 0.0]]), np.zeros(3), 1.0)
    assert near[0, 0] > 1.0 > far[0, 0]


def test_value_range_of_a_constant_field():
    assert value_range(np.full(5, 2.0)) == pytest.approx((1.98, 2.02))
    assert value_range(np.array([1.0, 3.0])) == (1.0, 3.0)
    assert value_range(np.array([1.0, 3.0]), vmin=0.0) == (0.0, 3.0)


def test_ground_puts_the_lowest_point_on_the_floor(vault):
    scene = scene_from_structure(vault, ground=True)
    assert scene.bounds()[0, 2] == 0.0
    raw = scene_from_structure(vault)
    shift = scene.vertices - raw.vertices  # one translation along z, nothing else
    np.testing.assert_array_equal(shift[..., :2], 0.0)
    assert np.ptp(shift[..., 2]) < 1e-15 and shift[0, 0, 2] > 0.0
    with pytest.raises(ValueError, match="state must be"):
        scene_from_structure(vault, state="folded")
