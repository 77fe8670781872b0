"""Figures: the expected size, not blank (pixel statistics), the right colours and content."""

from __future__ import annotations

from xml.etree import ElementTree

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from matplotlib.transforms import Affine2D  # noqa: E402

from compas_ccu.design import load_design  # noqa: E402
from compas_ccu.key_figures import state_figures  # noqa: E402
from compas_ccu.model import load_model  # noqa: E402
from compas_ccu.strips.curvature import plate_curvature  # noqa: E402
from compas_ccu.viz import colors as C  # noqa: E402
from compas_ccu.viz.export import save_figure  # noqa: E402
from compas_ccu.viz.patterns import pattern_layout, plate_outline, plot_cut_patterns  # noqa: E402
from compas_ccu.viz.planarity import plot_planarity  # noqa: E402
from compas_ccu.viz.quadrants import plot_quadrants, quadrant_pairs  # noqa: E402
from compas_ccu.viz.render import Camera, camera, colour_scale, value_range  # noqa: E402
from compas_ccu.viz.scene import scene_from_structure  # noqa: E402
from compas_ccu.viz.sequence import plot_deployment_sequence  # noqa: E402
from compas_ccu.viz.sheet import plot_contact_sheet  # noqa: E402
from compas_ccu.viz.views import dimension_points, plot_views  # noqa: E402
from conftest import EXAMPLES  # noqa: E402
from imagecheck import assert_picture, has_colour, ink_fraction, load_rgb  # noqa: E402

DPI = 60


@pytest.fixture(scope="module")
def vault(vault_model):
    return vault_model.deploy()


def png(fig, tmp_path, name="fig"):
    (path,) = save_figure(fig, tmp_path / name, formats=("png",), dpi=DPI)
    return load_rgb(path)


def crop(rgb, fig, ax, dpi):
    """The pixels of one axes of a figure saved at ``dpi``."""
    box = ax.get_window_extent().transformed(Affine2D().scale(dpi / fig.dpi))
    h = rgb.shape[0]
    return rgb[int(h - box.y1) : int(h - box.y0), int(box.x0) : int(box.x1)]


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
    # the vault's plates are conical (orthogonal rulings): |kappa| varies across every plate,
    # 0.390 to 0.466 1/m at the vertices. The bar shows that range (not the 0.424-0.432 of face
    # means), the same maximum as the bending check (thickness_figures' bending_curvature)
    kappa = np.abs(plate_curvature(np.asarray(vault.deployed)))
    assert (lo, hi) == pytest.approx((kappa.min(), kappa.max()), rel=1e-12)
    assert lo == pytest.approx(0.3904, abs=1e-4) and hi == pytest.approx(0.4660, abs=1e-4)
    rgb = png(fig, tmp_path)
    assert_picture(rgb, size=expected_size(fig), min_ink=0.15)
    # painted per vertex (bilinear sub-quads): both ends of the map are on the plates
    assert has_colour(rgb, "#440154", tol=50) and has_colour(rgb, "#fde725", tol=50)


def test_a_constant_field_gets_a_wide_scale_that_says_constant(vault, tmp_path):
    # the vault's alpha is 30 deg along every crease: today drawn at the middle of a 29.7-30.3
    # scale, plasma's pink, next to the anticlastic pink of the kind colouring
    fig = plot_views(vault, color_by="alpha")
    bar = fig.axes[-1]
    assert bar.get_ylim() == pytest.approx((0.0, 30.0), abs=1e-9)
    assert bar.get_ylabel().endswith(": constant = 30")
    scene = crop(png(fig, tmp_path), fig, fig.axes[0], DPI)  # the perspective, not the bar
    assert has_colour(scene, "#f0f921", tol=30, min_pixels=200)  # plasma's top: yellow
    assert not has_colour(scene, C.KIND_COLORS["anticlastic"], tol=60, min_pixels=5)
    assert colour_scale(np.full(4, -2.0)) == (-2.0, 0.0, -2.0)
    assert colour_scale(np.zeros(3)) == (-1.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="vmin < vmax, got 3.0 to 1.0"):
        colour_scale([1.0, 2.0], vmin=3.0, vmax=1.0)


def test_stacked_plates_show_one_plate_not_stripes_of_another(vault_model, tmp_path):
    # alpha = 0: all plates coincide; depth ties went either way quad by quad, so stripes of
    # the lighter plate tone showed through the darker one (5.8 % of the plate pixels)
    fig = plot_views(vault_model.deploy(0.0), views=("perspective",), figsize=(8, 5))
    (path,) = save_figure(fig, tmp_path / "stack", formats=("png",), dpi=100)
    rgb = load_rgb(path).reshape(-1, 3).astype(int)
    tones = np.array([[int(t[i : i + 2], 16) for i in (1, 3, 5)] for t in C.PLATE_TONES])
    colours, counts = np.unique(rgb, axis=0, return_counts=True)
    plate = colours[np.argsort(-counts)[1]]  # the most common after the white background
    # the shading factor of the flat stack: the same for both tones, found from the tone on top
    shades = plate / tones  # (2, 3): one row is three equal ratios, that of the tone on top
    top = int(np.argmin(np.ptp(shades, axis=1)))
    other = np.round(tones[1 - top] * shades[top].mean())
    near_other = int((np.abs(rgb - other).max(axis=1) <= 3).sum())
    near_plate = int((np.abs(rgb - plate).max(axis=1) <= 3).sum())
    assert near_plate > 20_000 and near_other < 0.002 * near_plate, (near_plate, near_other)


def test_crease_lines_stay_apart_at_small_alpha(vault_model, tmp_path):
    # the sequence's alpha = 6 deg panel at the CLI's 150 dpi: the five synclastic creases were
    # one blue band (no column of the panel crossed 4 separate blue lines); now thinner lines
    fig = plot_deployment_sequence(vault_model, count=6)
    (path,) = save_figure(fig, tmp_path / "seq", formats=("png",), dpi=150)
    ax = fig.axes[1]
    assert ax.get_title() == "α = 6°"
    panel = crop(load_rgb(path), fig, ax, 150).astype(int)
    blue = (panel[..., 2] - panel[..., 0]) > 40  # bluer than plates, page and pink
    runs = (blue[1:] & ~blue[:-1]).sum(axis=0) + blue[0]  # separate blue lines per column
    crossed = runs[blue.any(axis=0)]
    assert len(crossed) > 100
    assert (crossed >= 4).mean() > 0.5, np.bincount(crossed)


def test_views_carry_span_and_rise_dimensions_from_the_key_figures(vault, tmp_path):
    fig = plot_views(vault)
    figures = state_figures(vault)
    assert fig._suptitle.get_text().endswith("span 2.50 m · rise 1.00 m · plate length 2.72 m")
    assert figures["crease_span"] == pytest.approx(2.5) and figures["crease_rise"] == 1.0
    by_view = {
        ax.get_title(): [t.get_text().strip() for t in ax.texts if t.get_text()]
        for ax in fig.axes[:4]
    }
    assert by_view["elevation"] == ["span 2.50 m", "rise 1.00 m"]
    assert by_view["perspective"] == by_view["plan"] == by_view["side"] == []
    # the dimension lines are drawn where the key figures measure: the leading crease
    for name in ("vault", "cone", "quadrants"):
        s = load_model(EXAMPLES / f"{name}.toml").deploy()
        d = dimension_points(s.deployed, len(s.deployed[0]) // 2 - 1)
        f = state_figures(s)
        assert d.span.shape == d.rise.shape == (2, 3)
        assert np.linalg.norm(d.span[1] - d.span[0]) == pytest.approx(f["crease_span"])
        assert np.linalg.norm(d.rise[1] - d.rise[0]) == pytest.approx(f["crease_rise"])
    # SVG text as <text>, not outlines: read with the standard library's XML parser
    (svg,) = save_figure(fig, tmp_path / "v", formats=("svg",))
    root = ElementTree.parse(svg).getroot()
    texts = ["".join(t.itertext()).strip() for t in root.iter("{http://www.w3.org/2000/svg}text")]
    assert "span 2.50 m" in texts and "rise 1.00 m" in texts and "elevation" in texts
    assert len(texts) >= 10


@pytest.mark.slow  # an SVG of a field-coloured view (~1.5 s)
def test_a_field_coloured_view_is_one_image_in_svg_and_its_text_stays_text(vault, tmp_path):
    """The vault's curvature painted on sub-quads: 5.9 MB of SVG polygons before; now the
    plates are one embedded image per view and the labels are <text>."""
    fig = plot_views(vault, color_by="curvature")
    (svg,) = save_figure(fig, tmp_path / "c", formats=("svg",))
    assert svg.stat().st_size < 1.5e6
    root = ElementTree.parse(svg).getroot()
    ns = "{http://www.w3.org/2000/svg}"
    assert len(list(root.iter(ns + "image"))) == 5  # one per view and the colour bar
    texts = ["".join(t.itertext()).strip() for t in root.iter(ns + "text")]
    assert "span 2.50 m" in texts and "plan" in texts
    # a view coloured by crease kind has few polygons: it stays vector
    (kind,) = save_figure(plot_views(vault), tmp_path / "k", formats=("svg",))
    assert not list(ElementTree.parse(kind).getroot().iter(ns + "image"))  # no colour bar


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
    with pytest.raises(ValueError, match="unknown view 'above'"):
        plot_views(vault, views=("above",))
    with pytest.raises(ValueError, match="two numbers of degrees, got '30,x'"):
        plot_views(vault, views=("30,x",))


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
    assert fig.axes[0].get_title(loc="left").endswith("plate length 2.72 m")
    assert sum(t.endswith("\n2.72 m long") for t in texts) == 10
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


def test_named_views_and_azimuth_elevation():
    assert camera("top") == camera("plan") and camera("front") == camera("elevation")
    iso = camera("iso")
    # isometric: the three axes foreshortened alike
    lengths = np.linalg.norm(iso.axes()[:2].T, axis=1)
    np.testing.assert_allclose(lengths, lengths[0], rtol=1e-12)
    assert camera(" 30 , 20 ") == Camera(30.0, 20.0, None)


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
    assert value_range(np.full(5, 2.0)) == (0.0, 2.0)
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
