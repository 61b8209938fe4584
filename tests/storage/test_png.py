"""The one PNG encoder: pixels round-trip, PNG bytes pass through, other input is a ConfigError."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

from vlm_bench.errors import ConfigError
from vlm_bench.storage.png import to_png


def test_array_and_pil_image_encode_the_same_pixels() -> None:
    pixels = np.random.default_rng(0).integers(0, 256, (8, 6, 3), dtype=np.uint8)
    png = to_png(pixels)
    assert to_png(png) == png  # PNG bytes pass through unchanged
    assert to_png(Image.fromarray(pixels)) == png
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(png))), pixels)


@pytest.mark.parametrize("image", [b"GIF89a", "picture.png", 3])
def test_not_an_image_is_a_config_error(image: object) -> None:
    with pytest.raises(ConfigError, match=r"PNG|unsupported image type"):
        to_png(image)
