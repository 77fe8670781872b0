"""FE pictures: the deformed shell coloured by stress / deviation, and the deployment curves."""

from __future__ import annotations

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

from matplotlib.collections import PolyCollection  # noqa: E402

from compas_ccu.viz.fea import plot_fe_curves, plot_fe_shape  # noqa: E402
from imagecheck import assert_picture, has_colour, load_rgb  # noqa: E402

DPI = 60


def strip(nu: int = 20, nv: int = 4, radius: float = 2.0, angle: float = 2.0, width: float = 1.0):
    """A cylindrical strip of nu x nv quads, bent about the y axis (crown up).

    Returns positions (N, 3), elements (E, 4), the element centres (E, 3).
    """
    t = np.linspace(-angle / 2, angle / 2, nu + 1)
    y = np.linspace(0.0, width, nv + 1)
    tt, yy = np.meshgrid(t, y, indexing="ij")
    positions = np.c_[radius * np.sin(tt.ravel()), yy.ravel(), radius * np.cos(tt.ravel()) - radius]
    i = (np.arange(nu)[:, None] * (nv + 1) + np.arange(nv)).ravel()
    elements = np.c_[i, i + nv + 1, i + nv + 2, i + 1]
    return positions, elements, positions[elements].mean(axis=1)


def faces(fig) -> PolyCollection:
    (collection,) = [c for ax in fig.axes for c in ax.collections if hasattr(c, "element_index")]
    return collection


def save(fig, path):
    fig.savefig(path, dpi=DPI)
    assert path.exists() and path.stat().st_size > 2000
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    return load_rgb(path)


def test_stress_tension_blue_compression_red(tmp_path):
    positions, elements, centres = strip()
    # +12 MPa on the y < 0.5 half, -8 MPa on the other: clearly signed, asymmetric magnitudes
    values = np.where(centres[:, 1] < 0.5, 12e6, -8e6)
    fig = plot_fe_shape(positions, elements, values, title="bent strip")
    coll = faces(fig)
    idx = coll.element_index
    assert sorted(idx) == list(range(len(elements)))
    rgb = coll.get_facecolor()[:, :3]
    positive = values[idx] > 0
    assert np.all(rgb[positive, 2] > rgb[positive, 0])  # tension bluish
    assert np.all(rgb[~positive, 0] > rgb[~positive, 2])  # compression reddish
    bar = fig.axes[-1]
    assert bar.get_ylabel() == "bending stress, top surface [MPa]"
    lo, hi = bar.get_ylim()
    assert lo == pytest.approx(-12.0) and hi == pytest.approx(12.0)  # symmetric, in MPa
    picture = save(fig, tmp_path / "stress.png")
    assert_picture(picture, min_ink=0.1)
    assert has_colour(picture, "#2166ac", tol=70) and has_colour(picture, "#d6604d", tol=70)


def test_stress_per_node_values_and_given_range(tmp_path):
    positions, elements, _ = strip()
    per_node = 5e6 * np.sign(positions[:, 0] + 1e-9)  # + for x > 0
    fig = plot_fe_shape(positions, elements, per_node, vmax=10.0, label="σ [MPa]", view="plan")
    coll = faces(fig)
    mean = per_node[elements].mean(axis=1)[coll.element_index]
    rgb = coll.get_facecolor()[:, :3]
    assert np.all(rgb[mean > 0, 2] > rgb[mean > 0, 0])
    assert np.all(rgb[mean < 0, 0] > rgb[mean < 0, 2])
    bar = fig.axes[-1]
    assert bar.get_ylabel() == "σ [MPa]"
    assert bar.get_ylim() == pytest.approx((-10.0, 10.0))
    save(fig, tmp_path / "nodes.png")


def test_deviation_mode_into_given_axes_with_edges(tmp_path):
    from matplotlib.figure import Figure

    positions, elements, centres = strip()
    dev = np.abs(centres[:, 0]) * 1.5  # % of span, >= 0
    crease = np.stack([positions[0:-1:5][:-1], positions[5::5]], axis=1)  # along y = 0
    fig = Figure(figsize=(10, 4))
    ax1, ax2 = fig.subplots(1, 2)
    out = plot_fe_shape(positions, elements, dev, mode="deviation", ax=ax2, edges=crease)
    assert out is fig
    coll = faces(fig)
    assert coll.axes is ax2
    assert np.count_nonzero(coll.element_index == -1) == len(crease)
    bar = fig.axes[-1]
    assert bar.get_ylabel() == "deviation from kinematic model [% of span]"
    assert bar.get_ylim()[0] == 0.0 and bar.get_ylim()[1] == pytest.approx(dev.max())
    assert_picture(save(fig, tmp_path / "deviation.png"), min_ink=0.05)


def test_bad_shapes_raise_naming_the_shape():
    positions, elements, _ = strip()
    e, n = len(elements), len(positions)
    with pytest.raises(ValueError, match=rf"values must have shape \({e},\).*got \(7,\)"):
        plot_fe_shape(positions, elements, np.zeros(7))
    with pytest.raises(ValueError, match=r"elements must have shape \(E, 4\).*got \(80, 3\)"):
        plot_fe_shape(positions, elements[:, :3], np.zeros(e))
    with pytest.raises(ValueError, match=r"positions must have shape \(N, 3\).*got \(105, 2\)"):
        plot_fe_shape(positions[:, :2], elements, np.zeros(n))
    with pytest.raises(ValueError, match=r"edges must have shape \(K, 2, 3\).*got \(4, 3\)"):
        plot_fe_shape(positions, elements, np.zeros(e), edges=np.zeros((4, 3)))
    with pytest.raises(ValueError, match="node indices must lie in"):
        plot_fe_shape(positions, elements + n, np.zeros(e))
    with pytest.raises(ValueError, match="mode must be one of"):
        plot_fe_shape(positions, elements, np.zeros(e), mode="strain")
    with pytest.raises(ValueError, match="deviation values must be >= 0"):
        plot_fe_shape(positions, elements, -np.ones(e), mode="deviation")
    with pytest.raises(ValueError, match=r"deviation_mean must have shape \(3,\).*got \(2,\)"):
        plot_fe_curves([0, 1, 2], deviation_max=[0, 1, 2], deviation_mean=[0, 1])


def test_a_large_mesh_is_drawn_as_one_collection(tmp_path):
    """10,000 quads become one polygon collection, not an artist per element (what keeps the
    plot fast: a timing here would only measure how busy the machine is)."""
    positions, elements, centres = strip(nu=200, nv=50)  # 10,000 quads
    values = 1e7 * np.sin(3 * centres[:, 0]) * np.cos(4 * centres[:, 1])
    fig = plot_fe_shape(positions, elements, values)
    ax = fig.axes[0]
    sizes = [len(c.get_paths()) for c in ax.collections]
    assert len(ax.collections) <= 3 and max(sizes) == len(elements), sizes
    fig.savefig(tmp_path / "large.png", dpi=DPI)
    assert (tmp_path / "large.png").stat().st_size > 10_000


def test_curves_with_and_without_load_data(tmp_path):
    a = np.linspace(0.0, 40.0, 9)
    fig = plot_fe_curves(
        a,
        deviation_max=0.05 * a,
        deviation_mean=0.02 * a,
        force=3.0 * a,
        energy=0.03 * a**2,
        title="vault",
    )
    left, right, twin = fig.axes
    assert len(left.lines) == 2 and left.get_ylim()[0] == 0.0
    assert "% of span" in left.get_ylabel()
    assert right.get_ylabel() == "generalised force dW/dα [J/rad]"
    assert twin.get_ylabel() == "strain energy W [J]"
    assert_picture(save(fig, tmp_path / "curves.png"), min_ink=0.03)

    bare = plot_fe_curves(a, deviation_max=0.05 * a, deviation_mean=0.02 * a)
    assert len(bare.axes) == 2
    assert [t.get_text() for t in bare.axes[1].texts] == ["no load data"]
    save(bare, tmp_path / "bare.png")

    energy_only = plot_fe_curves(
        a, deviation_max=0.05 * a, deviation_mean=0.02 * a, energy=0.03 * a**2
    )
    assert len(energy_only.axes) == 2 and energy_only.axes[1].get_ylabel() == "strain energy W [J]"
