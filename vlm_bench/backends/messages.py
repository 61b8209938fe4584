"""Chat messages in the OpenAI format (shared by the ``openai`` and ``vllm`` backends)."""

from __future__ import annotations

import base64
from collections.abc import Sequence
from typing import Any

from vlm_bench.types.generation import ContentPart, GenerationRequest, ImagePart


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
    """System, earlier turns and user messages with images as base64 PNG data URLs, in
    prompt order; an assistant turn is its text.

    Args:
        request: The request to send.
        system_role: Send the system text as a ``system`` message; when False (models whose
            chat template rejects a system role) it opens the first user turn instead.
        image_detail: Optional OpenAI ``detail`` hint (``low``/``high``/``auto``).
    """

    def convert(parts: Sequence[ContentPart]) -> list[dict[str, Any]]:
        return [
            _image_content(p, image_detail)
            if isinstance(p, ImagePart)
            else {"type": "text", "text": p.text}
            for p in parts
        ]

    turns = [(t.role, t.content) for t in request.history] + [("user", request.user)]
    messages: list[dict[str, Any]] = []
    if request.system and system_role:
        messages.append({"role": "system", "content": request.system})
    for i, (role, parts) in enumerate(turns):
        if role == "assistant":
            text = "".join(p.text for p in parts if not isinstance(p, ImagePart))
            messages.append({"role": "assistant", "content": text})
            continue
        content = convert(parts)
        if i == 0 and request.system and not system_role:
            content.insert(0, {"type": "text", "text": request.system})
        messages.append({"role": "user", "content": content})
    return messages
