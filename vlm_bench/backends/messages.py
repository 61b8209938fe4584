"""Chat messages in the OpenAI format (shared by the ``openai`` and ``vllm`` backends)."""

from __future__ import annotations

import base64
from typing import Any

from vlm_bench.types.generation import GenerationRequest, ImagePart


def data_url(png: bytes) -> str:
    """A ``data:image/png;base64,...`` URL of PNG bytes."""
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _image_content(part: ImagePart, detail: str | None) -> dict[str, Any]:
    image_url: dict[str, Any] = {"url": data_url(part.png)}
    if detail is not None:
        image_url["detail"] = detail
    return {"type": "image_url", "image_url": image_url}


def openai_messages(
    request: GenerationRequest, *, system_role: bool = True, image_detail: str | None = None
) -> list[dict[str, Any]]:
    """System and user messages with images as base64 PNG data URLs, in prompt order.

    Args:
        request: The request to send.
        system_role: Send the system text as a ``system`` message; when False (models whose
            chat template rejects a system role) it opens the user turn instead.
        image_detail: Optional OpenAI ``detail`` hint (``low``/``high``/``auto``).
    """
    content: list[dict[str, Any]] = []
    if request.system and not system_role:
        content.append({"type": "text", "text": request.system})
    for part in request.user:
        if isinstance(part, ImagePart):
            content.append(_image_content(part, image_detail))
        else:
            content.append({"type": "text", "text": part.text})
    messages: list[dict[str, Any]] = []
    if request.system and system_role:
        messages.append({"role": "system", "content": request.system})
    messages.append({"role": "user", "content": content})
    return messages
