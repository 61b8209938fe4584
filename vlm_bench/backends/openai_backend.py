"""Any OpenAI-compatible chat server: vLLM, SGLang, LMDeploy, Ollama, ``transformers serve``, APIs.

Images go as base64 PNG data URLs. Requests run concurrently in a thread pool; connection
errors, timeouts, 408/409/429 and 5xx answers are retried with exponential backoff, then
recorded in the result. ``openai`` is imported only when the backend is built.

Constrained decoding sends ``response_format={"type": "json_schema", ...}`` with the request's
schema as is (non-strict). vLLM, SGLang and LMDeploy accept the plan schema's array root; hosted
APIs whose strict mode wants an object root answer 400, which is recorded per request.
"""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Literal

from pydantic import Field

from vlm_bench.backends.base import Backend, BackendArgs, require_schemas
from vlm_bench.backends.messages import openai_messages
from vlm_bench.errors import ConfigError, MissingExtraError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

BASE_URL_ENV = "VLM_BENCH_OPENAI_BASE_URL"
API_KEY_ENV = "OPENAI_API_KEY"
_RETRY_STATUS = frozenset({408, 409, 429})


class OpenAIArgs(BackendArgs):
    """``-M`` arguments of the openai backend."""

    base_url: str | None = Field(
        default=None, description=f"Server URL, e.g. http://127.0.0.1:8000/v1 (env {BASE_URL_ENV})."
    )
    api_key: str | None = Field(default=None, description=f"API key (env {API_KEY_ENV}).")
    concurrency: int = Field(default=8, ge=1, description="Requests in flight at once.")
    timeout_s: float = Field(default=120.0, gt=0, description="Per-request timeout (s).")
    retries: int = Field(default=4, ge=0, description="Retries of a transient failure.")
    backoff_s: float = Field(default=1.0, ge=0, description="First retry delay (s), doubling.")
    backoff_max_s: float = Field(default=30.0, ge=0, description="Longest retry delay (s).")
    system_role: bool = Field(default=True, description="Send a system message (else merge).")
    image_detail: Literal["low", "high", "auto"] | None = Field(
        default=None, description="OpenAI image detail hint."
    )
    max_tokens_param: Literal["max_tokens", "max_completion_tokens"] = Field(
        default="max_tokens", description="Name of the length limit parameter the server takes."
    )


def _describe(exc: BaseException) -> str:
    status = getattr(exc, "status_code", None)
    code = f" {status}" if status is not None else ""
    return f"{type(exc).__name__}{code}: {exc}"[:500]


class OpenAIBackend(Backend):
    """Chat completions against an OpenAI-compatible server."""

    name = "openai"
    Args = OpenAIArgs

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
            max_retries=0,  # retries are ours (tenacity), so they are counted and bounded
        )

    @property
    def max_concurrency(self) -> int:
        """The ``concurrency`` argument."""
        return self.args.concurrency

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
        if config.constrained and request.json_schema is not None:
            params["response_format"] = {
                "type": "json_schema",
                "json_schema": {"name": "plan", "schema": request.json_schema},
            }
        return params

    def _transient(self, exc: BaseException) -> bool:
        openai = self._openai
        if isinstance(exc, openai.APIConnectionError):  # includes timeouts
            return True
        if isinstance(exc, openai.APIStatusError):
            return exc.status_code >= 500 or exc.status_code in _RETRY_STATUS
        return False

    def _call(self, params: dict[str, Any]) -> Any:
        import tenacity

        retrying = tenacity.Retrying(
            stop=tenacity.stop_after_attempt(self.args.retries + 1),
            wait=tenacity.wait_exponential(
                multiplier=self.args.backoff_s, max=self.args.backoff_max_s
            ),
            retry=tenacity.retry_if_exception(self._transient),
            reraise=True,
        )
        return retrying(self._client.chat.completions.create, **params)

    def _one(self, request: GenerationRequest, config: GenerationConfig) -> GenerationResult:
        start = time.perf_counter()
        try:
            response = self._call(self.params(request, config))
        except self._openai.APIError as exc:
            return GenerationResult(
                id=request.id, error=_describe(exc), latency_s=time.perf_counter() - start
            )
        latency = time.perf_counter() - start
        if not response.choices:
            return GenerationResult(
                id=request.id, error="server returned no choices", latency_s=latency
            )
        choice = response.choices[0]
        usage = response.usage
        return GenerationResult(
            id=request.id,
            text=choice.message.content or "",
            latency_s=latency,
            prompt_tokens=usage.prompt_tokens if usage else None,
            completion_tokens=usage.completion_tokens if usage else None,
            finish_reason=choice.finish_reason,
        )

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """Send every request (``concurrency`` at a time); results in request order."""
        require_schemas(self.name, requests, config)
        if not requests:
            return []
        workers = min(self.args.concurrency, len(requests))
        with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="vlm-openai") as pool:
            return list(pool.map(lambda r: self._one(r, config), requests))

    def close(self) -> None:
        """Close the HTTP client."""
        self._client.close()
