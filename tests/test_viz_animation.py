"""The deployment animation: frame count, frame size, frames that change, MP4 where possible."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from PIL import Image  # noqa: E402

from compas_ccu.errors import OptionError  # noqa: E402
from compas_ccu.viz.animation import (  # noqa: E402
    mp4_available,
    render_frames,
    write_animation,
    write_animations,
)
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


@pytest.mark.skipif(not mp4_available(), reason="no MP4 encoder (video extra)")
def test_gif_and_mp4_come_from_one_rendering(cone_model, tmp_path, monkeypatch):
    import imageio_ffmpeg

    from compas_ccu.viz import animation

    calls = []
    real = animation.render_frames

    def counting(*args, **kwargs):
        calls.append(kwargs["frames"])
        return real(*args, **kwargs)

    monkeypatch.setattr(animation, "render_frames", counting)
    gif, mp4 = write_animations(cone_model, [tmp_path / "c.gif", tmp_path / "c.mp4"], frames=5)
    assert calls == [5]  # rendered once for both files
    assert Image.open(gif).n_frames == 5
    assert imageio_ffmpeg.count_frames_and_secs(str(mp4))[0] == 5
    # the same pictures: the MP4's last frame matches the GIF's (lossy encoders: close, not equal)
    reader = imageio_ffmpeg.read_frames(str(mp4))
    meta = next(reader)
    *_, last = reader
    w, h = meta["size"]
    video = np.frombuffer(last, dtype=np.uint8).reshape(h, w, 3).astype(int)
    im = Image.open(gif)
    im.seek(4)
    picture = load_rgb(im).astype(int)
    assert np.abs(video - picture).mean() < 6.0


def test_write_animations_checks_every_request_before_rendering(cone_model, tmp_path, monkeypatch):
    from compas_ccu.viz import animation

    monkeypatch.setattr(animation, "render_frames", lambda *a, **k: pytest.fail("rendered"))
    with pytest.raises(OptionError, match="at least one file to write, got none"):
        write_animations(cone_model, [])
    with pytest.raises(OptionError, match="animation format must be one of .*'c.avi'"):
        write_animations(cone_model, [tmp_path / "c.gif", tmp_path / "c.avi"])
    with pytest.raises(OptionError, match="fps must be > 0, got -1"):
        write_animations(cone_model, [tmp_path / "c.gif"], fps=-1)
    assert not any(tmp_path.iterdir())
