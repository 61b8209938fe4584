"""PNG bytes of an image: the one encoder behind prompts, the snapshot cache and live views."""

from __future__ import annotations

import io

from vlm_bench.errors import ConfigError

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
# Level 1: several times faster than the default 6 at a slightly larger file; the pixels are
# the same, and a replan's hash (over the bytes) is stable because every view goes through here.
_COMPRESS_LEVEL = 1


def to_png(image: object) -> bytes:
    """PNG bytes from PNG bytes (passed through), a PIL image or an ``HxWx3`` uint8 array.

    Raises:
        ConfigError: Bytes that are not PNG, or an unsupported image type.
    """
    if isinstance(image, bytes | bytearray):
        if not bytes(image).startswith(PNG_MAGIC):
            raise ConfigError("image bytes are not PNG-encoded")
        return bytes(image)
    from PIL import Image

    if not isinstance(image, Image.Image):
        if not hasattr(image, "__array_interface__"):
            raise ConfigError(
                f"unsupported image type {type(image).__name__}; "
                "give PNG bytes, a PIL image or a uint8 array"
            )
        image = Image.fromarray(image)
    buf = io.BytesIO()
    image.save(buf, format="PNG", compress_level=_COMPRESS_LEVEL)
    return buf.getvalue()
