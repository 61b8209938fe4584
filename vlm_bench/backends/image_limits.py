"""Pixel and tile limits (``-M min_pixels``, ``max_pixels``, ``max_tiles``) on an image processor.

Processors fall in three kinds, told apart by what they hold rather than by class name (the
PIL and torchvision variants share their attributes):

- a pixel budget: Qwen2-VL, Qwen2.5-VL, Qwen3-VL, GLM-4.1V resize each image to between
  ``size["shortest_edge"]`` and ``size["longest_edge"]`` pixels (both are pixel counts);
- tiles: InternVL cuts each image into at most ``max_patches`` tiles (plus a thumbnail);
- neither: LLaVA (one fixed-size crop), LLaVA-OneVision (an anyres grid that the model's own
  config must match, so it cannot change at load time) and others; a limit there is an error.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from vlm_bench.errors import ConfigError


class ImageLimits(BaseModel):
    """The limits a user asked for (None = the processor's own)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    min_pixels: int | None = Field(default=None, gt=0, description="Fewest pixels per image.")
    max_pixels: int | None = Field(default=None, gt=0, description="Most pixels per image.")
    max_tiles: int | None = Field(default=None, gt=0, description="Most tiles per image.")

    def given(self) -> dict[str, int]:
        """The limits that are set, by name."""
        return {k: v for k, v in self.model_dump().items() if v is not None}


def _edge(size: Any, key: str) -> Any:
    return size.get(key) if isinstance(size, dict) else getattr(size, key, None)


def has_pixel_budget(image_processor: Any) -> bool:
    """True for processors that resize to a pixel count (the Qwen2-VL family, GLM-4.1V)."""
    size = getattr(image_processor, "size", None)
    return (
        hasattr(image_processor, "merge_size")
        and _edge(size, "shortest_edge") is not None
        and _edge(size, "longest_edge") is not None
    )


def has_tiles(image_processor: Any) -> bool:
    """True for processors that cut images into tiles (InternVL's GotOcr2 processor)."""
    return hasattr(image_processor, "max_patches") and hasattr(image_processor, "min_patches")


def _refuse(what: str, model: str, image_processor: Any, use: str) -> ConfigError:
    kind = type(image_processor).__name__
    return ConfigError(f"-M {what}: {model}'s image processor ({kind}) {use}")


def apply_image_limits(image_processor: Any, limits: ImageLimits, model: str) -> dict[str, int]:
    """Set the limits on a loaded image processor, in place.

    Returns:
        The processor settings now in force (for the log and the tests).

    Raises:
        ConfigError: A limit the processor has no setting for; the message says what it has.
    """
    given = limits.given()
    if not given:
        return {}
    if has_pixel_budget(image_processor):
        if limits.max_tiles is not None:
            raise _refuse(
                "max_tiles", model, image_processor, "limits pixels, not tiles; use max_pixels"
            )
        lo = limits.min_pixels or int(_edge(image_processor.size, "shortest_edge"))
        hi = limits.max_pixels or int(_edge(image_processor.size, "longest_edge"))
        if lo > hi:
            raise ConfigError(f"-M min_pixels={lo} is above max_pixels={hi}")
        image_processor.size = {"shortest_edge": lo, "longest_edge": hi}
        for name, value in (("min_pixels", lo), ("max_pixels", hi)):
            if getattr(image_processor, name, None) is not None:  # older transformers read these
                setattr(image_processor, name, value)
        return {"min_pixels": lo, "max_pixels": hi}
    if has_tiles(image_processor):
        pixel_keys = sorted(set(given) - {"max_tiles"})
        if pixel_keys:
            raise _refuse(
                pixel_keys[0], model, image_processor, "cuts images into tiles; use max_tiles"
            )
        tiles = int(given["max_tiles"])
        if tiles < image_processor.min_patches:
            raise ConfigError(
                f"-M max_tiles={tiles} is below the processor's minimum of "
                f"{image_processor.min_patches} tiles"
            )
        image_processor.max_patches = tiles
        return {"max_tiles": tiles}
    first = sorted(given)[0]
    raise _refuse(
        first,
        model,
        image_processor,
        "has no pixel or tile limit (it resizes every image to a fixed size); drop the argument",
    )
