"""-M min_pixels / max_pixels / max_tiles reach every image processor that has such a limit
(measured in what the processor then produces) and are an error on those that have none."""

from __future__ import annotations

from typing import Any

import pytest

pytest.importorskip("transformers")

from PIL import Image

from vlm_bench.backends.image_limits import ImageLimits, apply_image_limits
from vlm_bench.errors import ConfigError

VIEW = Image.new("RGB", (224, 224), (90, 120, 30))
WIDE = Image.new("RGB", (672, 224), (90, 120, 30))


def _qwen() -> Any:
    from transformers.models.qwen2_vl.image_processing_pil_qwen2_vl import (
        Qwen2VLImageProcessorPil,
    )

    return Qwen2VLImageProcessorPil()


def _glm() -> Any:
    from transformers.models.glm4v.image_processing_pil_glm4v import Glm4vImageProcessorPil

    return Glm4vImageProcessorPil()


def _internvl() -> Any:
    from transformers.models.got_ocr2.image_processing_pil_got_ocr2 import (
        GotOcr2ImageProcessorPil,
    )

    return GotOcr2ImageProcessorPil(crop_to_patches=True, size={"height": 224, "width": 224})


def _clip() -> Any:
    from transformers import CLIPImageProcessor

    return CLIPImageProcessor()


def _onevision() -> Any:
    from transformers.models.llava_onevision.image_processing_pil_llava_onevision import (
        LlavaOnevisionImageProcessorPil,
    )

    return LlavaOnevisionImageProcessorPil()


def _grid_cells(processor: Any) -> int:
    return int(processor([VIEW])["image_grid_thw"].prod())


@pytest.mark.parametrize(
    ("make", "frames"), [(_qwen, 1), (_glm, 2)], ids=["qwen2-vl-family", "glm-4.1v"]
)
def test_pixel_limits_reach_pixel_budget_processors(make: Any, frames: int) -> None:
    """The budget bounds patches x 14 px x 14 px (x 2 frames for GLM-4.1V, whose processor
    counts an image as two identical frames)."""
    processor = make()
    before = _grid_cells(processor)
    set_to = apply_image_limits(processor, ImageLimits(max_pixels=112 * 112), "m")
    assert set_to["max_pixels"] == 112 * 112
    after = _grid_cells(processor)
    assert after < before and after * 14 * 14 * frames <= 112 * 112
    apply_image_limits(processor, ImageLimits(min_pixels=336 * 336, max_pixels=448 * 448), "m")
    assert _grid_cells(processor) * 14 * 14 * frames >= 336 * 336  # a floor raises small views


def test_tile_limits_reach_tiling_processors() -> None:
    processor = _internvl()
    assert processor([WIDE])["num_patches"] == [4]  # 3 tiles and a thumbnail
    apply_image_limits(processor, ImageLimits(max_tiles=2), "m")
    assert processor([WIDE])["num_patches"] == [3]


@pytest.mark.parametrize(
    ("make", "limits", "says"),
    [
        (_clip, ImageLimits(max_pixels=50_000), "CLIPImageProcessor.*no pixel or tile limit"),
        (_onevision, ImageLimits(max_tiles=2), "LlavaOnevision.*no pixel or tile limit"),
        (_qwen, ImageLimits(max_tiles=2), "limits pixels, not tiles; use max_pixels"),
        (_internvl, ImageLimits(max_pixels=50_000), "cuts images into tiles; use max_tiles"),
        (_qwen, ImageLimits(min_pixels=9_000, max_pixels=4_000), "min_pixels=9000 is above"),
    ],
)
def test_limits_a_processor_has_not_are_errors(make: Any, limits: ImageLimits, says: str) -> None:
    with pytest.raises(ConfigError, match=says) as info:
        apply_image_limits(make(), limits, "org/model")
    assert "\n" not in str(info.value)


def test_no_limit_leaves_the_processor_alone() -> None:
    processor = _clip()
    assert apply_image_limits(processor, ImageLimits(), "m") == {}
