"""How a model's processor turns a square view into prompt tokens, as data on its model card.

Each kind restates its processor's rule (transformers' or the checkpoint's own), so that the
tokens a view costs follow from the card's settings: :meth:`tokens` of a ``size`` px view when
the prompt holds ``n_images`` images. The counts are the image positions of the prompt (what the
context length is spent on): image tokens plus the separators the processor inserts for them.
The rules are checked against the real processors on tiny models
(``tests/backends/test_vision_tokens.py``).
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field

from vlm_bench.types.base import Frozen


class PixelBudget(Frozen):
    """Qwen2.5-VL, Qwen3-VL, GLM-4.1V: the image is resized to multiples of ``patch x merge``
    px within a pixel budget; one token per merged patch (``smart_resize``)."""

    kind: Literal["pixel_budget"] = "pixel_budget"
    patch: int = Field(ge=1, description="Vision patch side (px).")
    merge: int = Field(default=2, ge=1, description="Patches merged per token along a side.")
    min_pixels: int = Field(ge=1, description="Smallest pixel count (frames x height x width).")
    max_pixels: int = Field(ge=1, description="Largest pixel count (frames x height x width).")
    frames: int = Field(default=1, ge=1, description="Frames an image counts as (GLM-4.1V: 2).")

    def tokens(self, size: int, n_images: int = 1) -> int:
        """Tokens of one ``size`` px square view (the number of images does not matter)."""
        factor = self.patch * self.merge
        side = round(size / factor) * factor
        pixels = self.frames * size * size
        if self.frames * side * side > self.max_pixels:
            side = max(
                factor, math.floor(size / math.sqrt(pixels / self.max_pixels) / factor) * factor
            )
        elif self.frames * side * side < self.min_pixels:
            side = math.ceil(size * math.sqrt(self.min_pixels / pixels) / factor) * factor
        return (side // factor) ** 2


class Tiles(Frozen):
    """InternVL: a grid of ``tile`` px tiles as close to the image's aspect ratio as the tile
    limit allows, plus a thumbnail when there is more than one tile."""

    kind: Literal["tiles"] = "tiles"
    tile: int = Field(ge=1, description="Tile side (px).")
    tokens_per_tile: int = Field(ge=1, description="Tokens of one tile.")
    max_tiles: int = Field(ge=1, description="Most tiles per image.")

    def tokens(self, size: int, n_images: int = 1) -> int:
        """Tokens of one square view: the largest k x k grid within ``max_tiles`` whose tiles'
        area stays below twice the image's (the processor's tie-break among square grids)."""
        k = 1
        while (k + 1) ** 2 <= self.max_tiles and size * size > 0.5 * (self.tile * (k + 1)) ** 2:
            k += 1
        return (k * k + (1 if k > 1 else 0)) * self.tokens_per_tile


class AnyRes(Frozen):
    """LLaVA-OneVision: an image alone is the whole image as one tile plus a grid of tiles from
    ``pinpoints`` (with a newline token per row, at most ``max_patches`` tiles' worth); each of
    several images is one tile and a newline token (transformers' ``need_patching`` is for a
    single image only)."""

    kind: Literal["anyres"] = "anyres"
    tile: int = Field(ge=1, description="Tile side (px).")
    tokens_per_tile: int = Field(ge=1, description="Tokens of one tile (a square number).")
    pinpoints: tuple[tuple[int, int], ...] = Field(
        min_length=1, description="Grid resolutions (height, width) a single image may take."
    )
    max_patches: int = Field(default=9, ge=1, description="anyres_max_N of the processor.")

    def tokens(self, size: int, n_images: int = 1) -> int:
        """Tokens of one square view when the prompt holds ``n_images`` images."""
        if n_images > 1:
            return self.tokens_per_tile + 1
        height, width = max(self.pinpoints, key=lambda p: self._fit(p, size))
        side = math.isqrt(self.tokens_per_tile)
        rows, cols = side * (height // self.tile), side * (width // self.tile)
        if cols > rows:  # a square image in a wide grid: the padding columns are dropped
            cols -= 2 * ((cols - rows) // 2)
        elif rows > cols:
            rows -= 2 * ((rows - cols) // 2)
        ratio = math.sqrt(rows * cols / (self.max_patches * side * side))
        if ratio > 1.1:
            rows, cols = int(rows // ratio), int(cols // ratio)
        return rows * cols + rows + self.tokens_per_tile

    @staticmethod
    def _fit(pinpoint: tuple[int, int], size: int) -> tuple[int, int]:
        """transformers' ``select_best_resolution`` order: most image pixels kept, then least
        padding."""
        height, width = pinpoint
        scale = min(width / size, height / size)
        kept = min(int(size * scale) ** 2, size * size)
        return kept, -(width * height - kept)


class OverlapCrops(Frozen):
    """Molmo: overlapping ``crop`` px crops (margins of ``margin`` patches on each side) tiling
    the image, pooled 2x2, plus the whole image as one low-resolution crop; each row of tokens
    ends in a column token and each block has start and end tokens."""

    kind: Literal["overlap_crops"] = "overlap_crops"
    crop: int = Field(ge=1, description="Crop side (px).")
    patch: int = Field(ge=1, description="Vision patch side (px).")
    margin: int = Field(ge=0, description="Overlap margin (patches) on each side of a crop.")
    pool: int = Field(default=2, ge=1, description="Patches pooled per token along a side.")
    max_crops: int = Field(ge=1, description="Most crops per image.")

    def tokens(self, size: int, n_images: int = 1) -> int:
        """Prompt positions of one square view."""
        patches = self.crop // self.patch
        window = patches - 2 * self.margin
        inner = size - 2 * self.margin * self.patch
        tiles = self._tiling(inner, window * self.patch)
        if tiles == 1:
            grid = (patches + self.pool - 1) // self.pool * self.pool
        else:
            edge = (window + self.margin + self.pool - 1) // self.pool * self.pool
            middle = (window + self.pool - 1) // self.pool * self.pool
            grid = 2 * edge + (tiles - 2) * middle
        high = (grid + 1) // self.pool
        low = patches // self.pool
        return high * (high + 1) + 2 + low * (low + 1) + 2

    def _tiling(self, inner: int, window: int) -> int:
        """Tiles along a side: the smallest square tiling that covers the image unscaled (or
        the largest allowed)."""
        k = 1
        while k * window < inner and (k + 1) ** 2 <= self.max_crops:
            k += 1
        return k


class Fixed(Frozen):
    """GLM-4V-9B: every image resized to one size, a fixed number of tokens."""

    kind: Literal["fixed"] = "fixed"
    image_tokens: int = Field(ge=1, description="Tokens of every image.")

    def tokens(self, size: int, n_images: int = 1) -> int:
        """Tokens of any view."""
        return self.image_tokens


VisionTokens = Annotated[
    PixelBudget | Tiles | AnyRes | OverlapCrops | Fixed, Field(discriminator="kind")
]
"""One of the processor rules, by ``kind``."""
