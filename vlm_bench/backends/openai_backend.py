"""Any OpenAI-compatible chat server: vLLM, SGLang, LMDeploy, Ollama, ``transformers serve``, APIs.

This module maps a request to a chat-completions call and its answer to a result; concurrency,
retries with backoff (connection errors, timeouts, 408, 429 and 5xx answers; never another 4xx)
and per-request timing are :class:`~.request_backend.RequestBackend`'s. Images go as base64 PNG
data URLs. A failed request's error keeps the server's own reason. ``openai`` is imported only
when the backend is built.

The server is checked when the backend is built (:func:`~.openai_checks.preflight`): a server
that is down stops the run at once with the cause. A batch whose every request found no server
(after its retries) stops the run too: finished episodes are kept, and re-running resumes.

Constrained decoding first checks that the server enforces ``response_format``
(:func:`~.openai_checks.check_structured_outputs`), then sends each request's schema as is
(non-strict). vLLM, SGLang and LMDeploy accept the plan schema's array root; hosted APIs whose
strict mode wants an object root answer 400, which is recorded per request. Settings the OpenAI
API lacks (``top_k``, ``repetition_penalty``) go in the request body only when they differ from
their neutral values, which servers such as vLLM read.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from typing import Any, Literal

from pydantic import Field

from vlm_bench.backends.backend import OPERATIONAL
from vlm_bench.backends.messages import openai_messages
from vlm_bench.backends.openai_checks import check_structured_outputs, preflight, server_url
from vlm_bench.backends.request_backend import (
    RequestArgs,
    RequestBackend,
    RequestFailed,
    transient_status,
)
from vlm_bench.errors import ConfigError, MissingExtraError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

BASE_URL_ENV = "VLM_BENCH_OPENAI_BASE_URL"
API_KEY_ENV = "OPENAI_API_KEY"


class OpenAIArgs(RequestArgs):
    """``-M`` arguments of the openai backend."""

    # Not operational: the URL names the server that answers, and a server elsewhere may serve
    # other weights under the same name (a resume against it is refused).
    base_url: str | None = Field(
        default=None, description=f"Server URL, e.g. http://127.0.0.1:8000/v1 (env {BASE_URL_ENV})."
    )
    api_key: str | None = Field(default=None, description=f"API key (env {API_KEY_ENV}).")
    system_role: bool = Field(default=True, description="Send a system message (else merge).")
    image_detail: Literal["low", "high", "auto"] | None = Field(
        default=None, description="OpenAI image detail hint."
    )
    max_tokens_param: Literal["max_tokens", "max_completion_tokens"] = Field(
        default="max_tokens", description="Name of the length limit parameter the server takes."
    )
    check_server: bool = Field(
        default=True,
        description="Check at load that the server answers (GET /models).",
        json_schema_extra=OPERATIONAL,
    )
    check_timeout_s: float = Field(
        default=5.0,
        gt=0,
        description="How long the load-time check waits for an answer (s).",
        json_schema_extra=OPERATIONAL,
    )


def not_json(body: str) -> str:
    """The error of a 200 answer whose body is not a JSON completion."""
    return f"the server sent a body that is not JSON (first 80 bytes: {body[:80]!r})"


def server_reason(body: object, fallback: str) -> str:
    """The server's own words in an error body: ``{"error": {"message": ...}}`` (OpenAI,
    vLLM), ``{"detail": ...}`` (FastAPI servers), ``{"message": ...}``, or the text itself."""
    if isinstance(body, dict):
        for key in ("message", "detail", "error"):
            value = body.get(key)
            if isinstance(value, dict):
                return server_reason(value, fallback)
            if isinstance(value, str) and value.strip():
                return value.strip()
    if isinstance(body, str) and body.strip():
        return body.strip()
    return fallback


class OpenAIBackend(RequestBackend):
    """Chat completions against an OpenAI-compatible server."""

    name = "openai"
    Args = OpenAIArgs
    args: OpenAIArgs

    def __init__(self, model: str, args: OpenAIArgs | None = None) -> None:
        if not model:
            raise ConfigError("backend 'openai' needs a model name: --model openai/<name>")
        try:
            import openai
        except ImportError:
            raise MissingExtraError("openai", "openai") from None
        self.model = model
        self.args = args or OpenAIArgs()
        self._openai = openai
        self._client = openai.OpenAI(
            base_url=self.args.base_url or os.environ.get(BASE_URL_ENV) or None,
            api_key=self.args.api_key or os.environ.get(API_KEY_ENV) or "EMPTY",
            timeout=self.args.timeout_s,
            max_retries=0,  # retries are RequestBackend's, so they are counted and bounded
        )
        self._structured_ok = False
        if self.args.check_server:
            preflight(self._client, openai, self.args.check_timeout_s)

    def params(self, request: GenerationRequest, config: GenerationConfig) -> dict[str, Any]:
        """Keyword arguments of ``chat.completions.create`` for one request."""
        params: dict[str, Any] = {
            "model": self.model,
            "messages": openai_messages(
                request, system_role=self.args.system_role, image_detail=self.args.image_detail
            ),
            self.args.max_tokens_param: config.max_new_tokens,
            "temperature": config.temperature,
            "top_p": config.top_p,
        }
        if not config.greedy:
            params["seed"] = config.seed
        extra: dict[str, Any] = {}  # beyond the OpenAI API: sent only when not neutral
        if config.repetition_penalty != 1.0:
            extra["repetition_penalty"] = config.repetition_penalty
        if not config.greedy and config.top_k > 0:
            extra["top_k"] = config.top_k
        if extra:
            params["extra_body"] = extra
        if config.constrained and request.json_schema is not None:
            params["response_format"] = {
                "type": "json_schema",
                "json_schema": {"name": "plan", "schema": request.json_schema},
            }
        return params

    def where(self) -> str:
        """The server's URL."""
        return f"the server at {server_url(self._client)}"

    def before_batch(self, requests: Sequence[GenerationRequest], config: GenerationConfig) -> None:
        """Under constrained decoding, check once that the server enforces json_schema.

        Raises:
            ConfigError: The server rejects or ignores ``response_format`` json_schema.
        """
        if config.constrained and not self._structured_ok:
            check_structured_outputs(
                self._client, self._openai, self.model, self.args.max_tokens_param
            )
            self._structured_ok = True

    def _failure(self, exc: BaseException) -> RequestFailed:
        openai = self._openai
        if isinstance(exc, openai.APIStatusError):
            status = exc.status_code
            reason = server_reason(exc.body, exc.message)
            return RequestFailed(
                f"{type(exc).__name__} {status}: {reason}", transient=transient_status(status)
            )
        if isinstance(exc, openai.APIConnectionError):  # includes timeouts
            timeout = isinstance(exc, openai.APITimeoutError)
            return RequestFailed(
                f"{type(exc).__name__}: {exc}", transient=True, unreachable=not timeout
            )
        return RequestFailed(f"{type(exc).__name__}: {exc}")

    def complete(self, request: GenerationRequest, config: GenerationConfig) -> GenerationResult:
        """One chat completion.

        Raises:
            RequestFailed: The server answered with an error, or not at all, or not JSON.
        """
        try:
            response = self._client.chat.completions.create(**self.params(request, config))
        except self._openai.APIError as exc:
            raise self._failure(exc) from None
        except json.JSONDecodeError as exc:  # a JSON content type over a body that is not
            raise RequestFailed(not_json(exc.doc)) from None
        if isinstance(response, str):  # the client hands back a body it could not decode
            raise RequestFailed(not_json(response))
        if not response.choices or response.choices[0].message is None:
            raise RequestFailed("server returned no choices")
        choice = response.choices[0]
        usage = response.usage
        return GenerationResult(
            id=request.id,
            text=choice.message.content or "",
            prompt_tokens=usage.prompt_tokens if usage else None,
            completion_tokens=usage.completion_tokens if usage else None,
            finish_reason=choice.finish_reason,
        )

    def close(self) -> None:
        """Close the HTTP client."""
        self._client.close()
