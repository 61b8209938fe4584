"""Procedural texture images (labels, wood grain, stickers) and the materials that carry them.

Images are deterministic (fixed seeds) so renders are reproducible. MuJoCo maps a 2-D texture
onto every face of a box and wraps it around a cylinder's side with image row 0 at the top.
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.sim.materials import textured_material, to_u8
from vlm_bench.types.base import RGBA

Image = NDArray[np.uint8]
GOLD: RGBA = (0.85, 0.66, 0.2, 1.0)
WHITE: RGBA = (0.95, 0.95, 0.93, 1.0)
INK: RGBA = (0.1, 0.1, 0.12, 1.0)


def _canvas(h: int, w: int, rgba: RGBA) -> Image:
    img = np.empty((h, w, 3), np.uint8)
    img[:] = to_u8(rgba)
    return img


def _tint(rgba: RGBA, levels: NDArray[np.float64]) -> Image:
    """Pixels of colour ``rgba`` scaled by ``levels`` (an (H, W) brightness field)."""
    base = np.asarray(rgba[:3], dtype=np.float64)
    return np.clip(levels[..., None] * base * 255.0, 0, 255).astype(np.uint8)


def wood_grain(rgba: RGBA) -> Image:
    """Long wavy grain lines with a few darker streaks, tinted by the wood colour."""
    rng = np.random.default_rng(7)
    h, w = 128, 256
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    warp = 6.0 * np.sin(x / 37.0) + 3.0 * np.sin(x / 13.0 + 1.0)
    rings = np.sin((y + warp) / 2.6) * 0.5 + 0.5
    streak = np.sin((y + 0.5 * warp) / 11.0) * 0.5 + 0.5
    noise = rng.normal(0.0, 0.03, (h, w))
    levels = 0.78 + 0.22 * rings**3 + 0.12 * streak + noise
    return _tint(rgba, np.clip(levels, 0.5, 1.25))


def cardboard(rgba: RGBA) -> Image:
    """Faint corrugation lines and fibre noise."""
    rng = np.random.default_rng(11)
    h, w = 64, 64
    x = np.mgrid[0:h, 0:w][1].astype(np.float64)
    levels = 0.96 + 0.03 * np.sin(x / 1.6) + rng.normal(0.0, 0.025, (h, w))
    return _tint(rgba, levels)


def sticker_face(rgba: RGBA) -> Image:
    """A 3 × 3 grid of rounded-looking stickers of one colour on a black body."""
    n, gap = 96, 4
    img = _canvas(n, n, INK)
    cell = n // 3
    for i in range(3):
        for j in range(3):
            img[i * cell + gap : (i + 1) * cell - gap, j * cell + gap : (j + 1) * cell - gap] = (
                to_u8(rgba)
            )
    return img


def soup_label(rgba: RGBA) -> Image:
    """Soup-can label: colour over white, with a script band and a gold medallion."""
    h, w = 128, 256
    img = _canvas(h, w, WHITE)
    img[: int(h * 0.52)] = to_u8(rgba)
    img[int(h * 0.22) : int(h * 0.32), 20:236:2] = to_u8(WHITE)  # "lettering"
    img[int(h * 0.52) : int(h * 0.56)] = to_u8(GOLD)
    yy, xx = np.mgrid[0:h, 0:w]
    for cx in (64, 192):
        img[(yy - 92) ** 2 + (xx - cx) ** 2 < 13**2] = to_u8(GOLD)
    return img


def tin_label(rgba: RGBA) -> Image:
    """Potted-meat label: main colour, a yellow band and white title blocks."""
    h, w = 128, 128
    img = _canvas(h, w, rgba)
    img[40:88] = to_u8((0.97, 0.82, 0.12, 1.0))
    img[48:80, 16:112] = to_u8(WHITE)
    for x0 in range(22, 106, 22):
        img[54:74, x0 : x0 + 14] = to_u8(rgba)  # the brand "letters"
    img[100:106, 30:98] = to_u8(WHITE)
    return img


def bottle_label(rgba: RGBA) -> Image:
    """White label with a coloured title bar, a logo dot and grey text lines."""
    h, w = 160, 96
    img = _canvas(h, w, WHITE)
    img[14:54, 6:90] = to_u8(rgba)
    yy, xx = np.mgrid[0:h, 0:w]
    img[(yy - 34) ** 2 + (xx - 48) ** 2 < 14**2] = to_u8(WHITE)
    img[(yy - 34) ** 2 + (xx - 48) ** 2 < 9**2] = to_u8((0.1, 0.45, 0.85, 1.0))
    for y0 in range(70, 150, 14):
        img[y0 : y0 + 5, 14:82] = to_u8((0.55, 0.55, 0.58, 1.0))
    return img


def shipping_label(rgba: RGBA) -> Image:
    """White address label with text lines and a barcode (``rgba`` is the ink colour)."""
    h, w = 64, 96
    img = _canvas(h, w, WHITE)
    for y0 in (8, 18, 28):
        img[y0 : y0 + 4, 8:70] = to_u8(rgba)
    rng = np.random.default_rng(3)
    bars = rng.integers(0, 2, 80).astype(bool)
    img[42:58, 8:88][:, bars] = to_u8(rgba)
    return img


def threads(rgba: RGBA) -> Image:
    """Screw thread: alternating light and dark rings (rows) along a cylinder."""
    h, w = 64, 8
    levels = np.where(np.arange(h) % 8 < 4, 1.05, 0.55)[:, None] * np.ones((1, w))
    return _tint(rgba, levels)


def textured_look(
    spec: mujoco.MjSpec,
    painter: Callable[[RGBA], Image],
    rgba: RGBA,
    specular: float = 0.15,
) -> str:
    """Material named after ``painter`` and the colour, carrying ``painter(rgba)``."""
    key = "_".join(f"{c:.3f}" for c in rgba)
    name = f"{painter.__name__}_{key}"
    return textured_material(spec, name, painter(rgba), specular=specular)
