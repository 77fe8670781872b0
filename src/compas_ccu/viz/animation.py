"""The deployment as an animation: GIF (Pillow) and MP4 (ffmpeg through imageio-ffmpeg)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from compas_ccu.errors import OptionError
from compas_ccu.viz.camera import path_frames
from compas_ccu.viz.render import draw_scene
from compas_ccu.viz.views import kind_legend_handles

__all__ = [
    "render_frames",
    "write_animation",
    "write_animations",
    "mp4_available",
    "ANIMATION_FORMATS",
]

ANIMATION_FORMATS = ("gif", "mp4")


def mp4_available() -> bool:
    """True if an MP4 encoder is available (the ``video`` extra: imageio-ffmpeg)."""
    try:
        import imageio_ffmpeg

        imageio_ffmpeg.get_ffmpeg_exe()
    except Exception:  # not installed, or no ffmpeg binary for this platform
        return False
    return True


def render_frames(
    model,
    *,
    frames: int = 48,
    alpha: float | None = None,
    view="perspective",
    color_by="kind",
    size=(8.0, 4.8),
    dpi: int = 100,
    progress: bool = False,
):
    """Render the deployment from α = 0 to ``alpha`` as RGB images.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    frames : int
        Number of frames (>= 2), equally spaced in α; the first is the flat-folded stack.
    alpha : float, optional
        Last frame, degrees (default: the design α).
    size, dpi
        Frame size in inches and dots per inch (the default gives 800 x 480 pixels, a
        multiple of 16 as video encoders like).
    progress : bool
        Show a progress bar on stderr.

    Yields
    ------
    (h, w, 3) uint8
        One image per frame; the camera and scale are fixed over the whole sequence and the
        lowest point stays on the floor.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    path = path_frames(model, frames, alpha, view, what="frames")
    alphas, structures, scenes = path.alphas, path.structures, path.scenes
    centre, scale, limits = path.centre, path.size, path.limits
    fig = Figure(figsize=size, dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes((0.0, 0.0, 1.0, 0.9))
    kinds = [c["kind"] for c in structures[-1].creases]
    bar = _progress(len(scenes), "animation frames", progress)
    try:
        for a, scene, s in zip(alphas, scenes, structures):
            ax.clear()
            draw_scene(ax, scene, view, color_by=color_by, centre=centre, size=scale, limits=limits)
            if kinds:
                ax.legend(
                    handles=kind_legend_handles(kinds), loc="lower left", fontsize=8, frameon=False
                )
            fig.suptitle(
                f"{model.design.name}   α = {a:5.2f}°   span {s.metrics['span']:.2f} m   "
                f"rise {s.metrics['rise']:.2f} m",
                fontsize=11,
                y=0.97,
            )
            canvas.draw()
            yield np.asarray(canvas.buffer_rgba())[..., :3].copy()
            bar.update(1)
    finally:
        bar.close()


def write_animation(
    model,
    path,
    *,
    frames: int = 48,
    fps: float = 12.0,
    alpha: float | None = None,
    view="perspective",
    color_by="kind",
    progress: bool = False,
) -> Path:
    """Write the deployment animation to ``path`` (``.gif`` or ``.mp4``).

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    path : str or Path
        The suffix chooses the format.
    frames, alpha, view, color_by, progress
        See :func:`render_frames`.
    fps : float
        Frames per second.

    Returns
    -------
    Path

    Raises
    ------
    compas_ccu.errors.OptionError
        Unknown format, or MP4 without an encoder (install ``compas_ccu[video]``).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "cone.gif"
    >>> gif = write_animation(load_model("examples/cone.toml"), out, frames=5)
    >>> Image.open(gif).n_frames
    5
    """
    (written,) = write_animations(
        model,
        [path],
        frames=frames,
        fps=fps,
        alpha=alpha,
        view=view,
        color_by=color_by,
        progress=progress,
    )
    return written


def write_animations(
    model,
    paths,
    *,
    frames: int = 48,
    fps: float = 12.0,
    alpha: float | None = None,
    view="perspective",
    color_by="kind",
    progress: bool = False,
) -> list:
    """Write the deployment animation to several files (``.gif``, ``.mp4``) from one rendering.

    The frames are rendered once (:func:`render_frames`) and every file is written from the
    same images: a GIF and an MP4 cost one rendering, not two. Every request is checked before
    the first frame is rendered.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    paths : sequence of str or Path
        The files to write; each suffix chooses its format (one file per format).
    frames, fps, alpha, view, color_by, progress
        See :func:`write_animation`.

    Returns
    -------
    list of Path
        The files written, in the order of ``paths``.

    Raises
    ------
    compas_ccu.errors.OptionError
        No path, an unknown format, or MP4 without an encoder (install ``compas_ccu[video]``).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> gif, = write_animations(load_model("examples/cone.toml"), [out / "cone.gif"], frames=3)
    >>> Image.open(gif).n_frames
    3
    """
    paths = [Path(p) for p in paths]
    if not paths:
        raise OptionError("write_animations needs at least one file to write, got none")
    for path in paths:
        fmt = path.suffix.lower().lstrip(".")
        if fmt not in ANIMATION_FORMATS:
            raise OptionError(
                f"animation format must be one of {ANIMATION_FORMATS}, got {path.name!r}"
            )
        if fmt == "mp4" and not mp4_available():
            raise OptionError(
                "MP4 needs an encoder: install the video extra (pip install "
                "'compas_ccu[video]', imageio-ffmpeg); GIF works without it"
            )
    if not fps > 0:
        raise OptionError(f"fps must be > 0, got {fps!r}")
    images = list(
        render_frames(
            model, frames=frames, alpha=alpha, view=view, color_by=color_by, progress=progress
        )
    )
    for path in paths:
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix.lower() == ".gif":
            _write_gif(path, images, fps)
        else:
            _write_mp4(path, images, fps)
    return paths


def _write_gif(path: Path, images, fps: float) -> None:
    from PIL import Image

    frames = [Image.fromarray(im) for im in images]
    # one palette for all frames (from the most colourful, the last), so colours do not flicker
    palette = frames[-1].quantize(colors=255, method=Image.Quantize.MEDIANCUT)
    indexed = [f.quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
    duration = [int(round(1000.0 / fps))] * len(indexed)
    duration[-1] = max(duration[-1], 1500)  # rest on the deployed state before looping
    indexed[0].save(
        path, save_all=True, append_images=indexed[1:], duration=duration, loop=0, optimize=False
    )


def _write_mp4(path: Path, images, fps: float) -> None:
    import imageio_ffmpeg

    writer = None
    try:
        for im in images:
            if writer is None:
                h, w = im.shape[:2]
                writer = imageio_ffmpeg.write_frames(
                    str(path),
                    (w, h),
                    fps=fps,
                    codec="libx264",
                    pix_fmt_out="yuv420p",
                    quality=7,
                    macro_block_size=16,
                    ffmpeg_log_level="error",
                )
                writer.send(None)
            writer.send(np.ascontiguousarray(im))
    finally:
        if writer is not None:
            writer.close()


def _progress(total: int, desc: str, enabled: bool):
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc, disable=not enabled, file=sys.stderr, leave=False)
