"""Any OpenAI-compatible chat server: vLLM, SGLang, LMDeploy, Ollama, ``transformers serve``, APIs.

Images go as base64 PNG data URLs. Requests run concurrently in a thread pool; connection
errors, timeouts, 408/409/429 and 5xx answers are retried with exponential backoff, then
recorded in the result. ``openai`` is imported only when the backend is built.

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
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Literal

from pydantic import Field

from vlm_bench.backends.backend import (
    OPERATIONAL,
    Backend,
    BackendArgs,
    require_schemas,
)
from vlm_bench.backends.messages import openai_messages
from vlm_bench.backends.openai_checks import (
    ServerUnreachableError,
    check_structured_outputs,
    preflight,
    server_url,
)
from vlm_bench.errors import ConfigError, MissingExtraError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

BASE_URL_ENV = "VLM_BENCH_OPENAI_BASE_URL"
API_KEY_ENV = "OPENAI_API_KEY"
_RETRY_STATUS = frozenset({408, 409, 429})


class OpenAIArgs(BackendArgs):
    """``-M`` arguments of the openai backend."""

    # Not operational: the URL names the server that answers, and a server elsewhere may serve
    # other weights under the same name (a resume against it is refused).
    base_url: str | None = Field(
        default=None, description=f"Server URL, e.g. http://127.0.0.1:8000/v1 (env {BASE_URL_ENV})."
    )
    api_key: str | None = Field(default=None, description=f"API key (env {API_KEY_ENV}).")
    concurrency: int = Field(
        default=8, ge=1, description="Requests in flight at once.", json_schema_extra=OPERATIONAL
    )
    timeout_s: float = Field(
        default=120.0, gt=0, description="Per-request timeout (s).", json_schema_extra=OPERATIONAL
    )
    retries: int = Field(
        default=4,
        ge=0,
        description="Retries of a transient failure.",
        json_schema_extra=OPERATIONAL,
    )
    backoff_s: float = Field(
        default=1.0,
        ge=0,
        description="First retry delay (s), doubling.",
        json_schema_extra=OPERATIONAL,
    )
    backoff_max_s: float = Field(
        default=30.0, ge=0, description="Longest retry delay (s).", json_schema_extra=OPERATIONAL
    )
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
        self._structured_ok = False
        if self.args.check_server:
            preflight(self._client, openai, self.args.check_timeout_s)

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

    def _one(
        self, request: GenerationRequest, config: GenerationConfig
    ) -> tuple[GenerationResult, bool]:
        """The request's result (``latency_s``: its own time, retries included), and whether it
        failed for want of a server."""
        start = time.perf_counter()
        try:
            response = self._call(self.params(request, config))
        except self._openai.APIError as exc:
            unreachable = isinstance(exc, self._openai.APIConnectionError) and not isinstance(
                exc, self._openai.APITimeoutError
            )
            own = time.perf_counter() - start
            return GenerationResult(id=request.id, error=_describe(exc), latency_s=own), unreachable
        except json.JSONDecodeError as exc:  # a JSON content type over a body that is not
            own = time.perf_counter() - start
            return GenerationResult(id=request.id, error=not_json(exc.doc), latency_s=own), False
        own = time.perf_counter() - start
        if isinstance(response, str):  # the client hands back a body it could not decode
            return GenerationResult(id=request.id, error=not_json(response), latency_s=own), False
        if not response.choices or response.choices[0].message is None:
            result = GenerationResult(id=request.id, error="server returned no choices")
            return result.model_copy(update={"latency_s": own}), False
        choice = response.choices[0]
        usage = response.usage
        result = GenerationResult(
            id=request.id,
            latency_s=own,
            text=choice.message.content or "",
            prompt_tokens=usage.prompt_tokens if usage else None,
            completion_tokens=usage.completion_tokens if usage else None,
            finish_reason=choice.finish_reason,
        )
        return result, False

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """Send every request (``concurrency`` at a time); results in request order.

        Raises:
            ConfigError: ``config.constrained`` and the server does not enforce json_schema.
            ServerUnreachableError: Every request found no server, even after its retries.
        """
        require_schemas(self.name, requests, config)
        if not requests:
            return []
        if config.constrained and not self._structured_ok:
            check_structured_outputs(
                self._client, self._openai, self.model, self.args.max_tokens_param
            )
            self._structured_ok = True
        start = time.perf_counter()
        workers = min(self.args.concurrency, len(requests))
        with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="vlm-openai") as pool:
            answers = list(pool.map(lambda r: self._one(r, config), requests))
        if all(unreachable for _, unreachable in answers):
            raise ServerUnreachableError(
                f"the server at {server_url(self._client)} stopped answering "
                f"({answers[0][0].error}); finished episodes are saved, re-run to resume"
            )
        # Concurrent requests each have their own time; the call's is the batch's.
        wall_s = time.perf_counter() - start
        return [r.model_copy(update={"batch_latency_s": wall_s}) for r, _ in answers]

    def close(self) -> None:
        """Close the HTTP client."""
        self._client.close()
