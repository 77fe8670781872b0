"""Pixel statistics of pictures: a picture is judged by its pixels, not by its file existing."""

from __future__ import annotations

import numpy as np
from PIL import Image


def load_rgb(path_or_image) -> np.ndarray:
    """(h, w, 3) uint8 of an image file (or PIL image)."""
    im = path_or_image if isinstance(path_or_image, Image.Image) else Image.open(path_or_image)
    return np.asarray(im.convert("RGB"))


def _packed(rgb: np.ndarray) -> np.ndarray:
    c = rgb.reshape(-1, 3).astype(np.int32)
    return (c[:, 0] << 16) | (c[:, 1] << 8) | c[:, 2]


def ink_fraction(rgb: np.ndarray, tol: int = 12) -> float:
    """Fraction of pixels that differ from the most common (background) colour by > tol."""
    colours, counts = np.unique(_packed(rgb), return_counts=True)
    b = int(colours[np.argmax(counts)])
    background = np.array([(b >> 16) & 255, (b >> 8) & 255, b & 255])
    flat = rgb.reshape(-1, 3).astype(int)
    return float((np.abs(flat - background).max(axis=1) > tol).mean())


def distinct_colours(rgb: np.ndarray) -> int:
    return int(len(np.unique(_packed(rgb))))


def has_colour(rgb: np.ndarray, hex_colour: str, tol: int = 40, min_pixels: int = 20) -> bool:
    """True if at least ``min_pixels`` pixels are within ``tol`` (per channel) of the colour."""
    target = np.array([int(hex_colour.lstrip("#")[i : i + 2], 16) for i in (0, 2, 4)])
    close = np.abs(rgb.reshape(-1, 3).astype(int) - target).max(axis=1) <= tol
    return int(close.sum()) >= min_pixels


def assert_picture(rgb: np.ndarray, *, size=None, min_ink=0.03, min_colours=50):
    """The picture has the expected size, is not blank and is not flat colour."""
    if size is not None:
        assert (rgb.shape[1], rgb.shape[0]) == tuple(size), (rgb.shape, size)
    ink = ink_fraction(rgb)
    assert ink >= min_ink, f"only {ink:.2%} of the pixels differ from the background"
    colours = distinct_colours(rgb)
    assert colours >= min_colours, f"only {colours} distinct colours"
