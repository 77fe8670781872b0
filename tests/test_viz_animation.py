"""The deployment animation: frame count, frame size, frames that change, MP4 where possible."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from PIL import Image  # noqa: E402

from compas_ccu.viz.animation import mp4_available, render_frames, write_animation  # noqa: E402
from imagecheck import assert_picture, ink_fraction, load_rgb  # noqa: E402


@pytest.fixture(scope="module")
def gif(vault_model, tmp_path_factory):
    return write_animation(vault_model, tmp_path_factory.mktemp("anim") / "v.gif", frames=9)


def test_gif_has_the_expected_frames_and_size(gif):
    im = Image.open(gif)
    assert im.n_frames == 9
    assert im.size == (800, 480)
    assert im.info["loop"] == 0
    frames = []
    for k in range(im.n_frames):
        im.seek(k)
        frames.append(load_rgb(im))
    for rgb in frames:
        assert_picture(rgb, size=(800, 480), min_ink=0.02, min_colours=30)
    # the vault opens: the frames change, and the open vault covers more of the picture
    diffs = [np.abs(a.astype(int) - b.astype(int)).mean() for a, b in zip(frames, frames[1:])]
    assert min(diffs) > 0.5
    assert ink_fraction(frames[-1]) > 1.5 * ink_fraction(frames[0])


def test_frames_keep_one_camera(vault_model):
    images = list(render_frames(vault_model, frames=3, alpha=20.0, size=(4.0, 2.4), dpi=50))
    assert [im.shape for im in images] == [(120, 200, 3)] * 3
    assert images[0].dtype == np.uint8


@pytest.mark.skipif(not mp4_available(), reason="no MP4 encoder (video extra)")
def test_mp4_has_the_expected_frame_count(cone_model, tmp_path):
    import imageio_ffmpeg

    path = write_animation(cone_model, tmp_path / "c.mp4", frames=7, fps=7)
    count, seconds = imageio_ffmpeg.count_frames_and_secs(str(path))
    assert count == 7
    assert seconds == pytest.approx(1.0, abs=0.05)


def test_bad_animation_requests(cone_model, tmp_path):
    with pytest.raises(ValueError, match="animation format must be one of"):
        write_animation(cone_model, tmp_path / "c.avi")
    with pytest.raises(ValueError, match="frames must be an integer >= 2, got 1"):
        write_animation(cone_model, tmp_path / "c.gif", frames=1)
    with pytest.raises(ValueError, match="fps must be > 0"):
        write_animation(cone_model, tmp_path / "c.gif", fps=0)
    with pytest.raises(ValueError, match="alpha must be > 0 degrees"):
        write_animation(cone_model, tmp_path / "c.gif", alpha=0.0)
