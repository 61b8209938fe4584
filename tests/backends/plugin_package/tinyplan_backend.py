"""A whole HTTP backend of another package: a message mapper and a call (the test's plug-in).

Installed for the test by its dist-info's entry point (``vlm_bench.backends``: ``tinyplan``);
concurrency, retries and backoff are :class:`RequestBackend`'s.
"""

from __future__ import annotations

import json
import urllib.error
import urllib.request

from vlm_bench.backends.request_backend import (
    RequestArgs,
    RequestBackend,
    RequestFailed,
    transient_status,
)
from vlm_bench.types.generation import (
    GenerationConfig,
    GenerationRequest,
    GenerationResult,
    TextPart,
)


class TinyArgs(RequestArgs):
    """``-M`` arguments: the server's URL besides the request backend's own."""

    base_url: str = "http://127.0.0.1:1"


class TinyPlanBackend(RequestBackend):
    """POSTs the prompt's text to ``<base_url>/plan`` and returns the body's ``plan``."""

    name = "tinyplan"
    Args = TinyArgs
    args: TinyArgs
    sees_images = False

    def __init__(self, model: str, args: TinyArgs | None = None) -> None:
        self.model = model
        self.args = args or TinyArgs()

    def complete(self, request: GenerationRequest, config: GenerationConfig) -> GenerationResult:
        text = "\n".join(part.text for part in request.user if isinstance(part, TextPart))
        body = json.dumps({"model": self.model, "prompt": text}).encode()
        try:
            with urllib.request.urlopen(
                urllib.request.Request(f"{self.args.base_url}/plan", data=body, method="POST"),
                timeout=self.args.timeout_s,
            ) as answer:
                plan = json.loads(answer.read())["plan"]
        except urllib.error.HTTPError as exc:
            reason = exc.read().decode(errors="replace")
            raise RequestFailed(
                f"HTTP {exc.code}: {reason}", transient=transient_status(exc.code)
            ) from None
        except urllib.error.URLError as exc:
            raise RequestFailed(str(exc.reason), transient=True, unreachable=True) from None
        return GenerationResult(id=request.id, text=json.dumps(plan), finish_reason="stop")
