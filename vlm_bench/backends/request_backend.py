"""Backends that answer one request per call (an HTTP API): concurrency, retries and backoff.

A subclass maps a request to one call and the call's answer to a result
(:meth:`RequestBackend.complete`), raising :class:`RequestFailed` for a failed call. This class
runs a batch ``concurrency`` requests at a time, retries a transient failure with exponential
backoff (tenacity: ``backoff_s``, doubling, at most ``backoff_max_s``), records a final failure
in the request's result (never raised), times each request, and stops the run when every
request of a batch found no server. A client error (HTTP 4xx other than 408 and 429) is final
at once: asking again gets the same answer.
"""

from __future__ import annotations

import time
from abc import abstractmethod
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import ClassVar

from pydantic import Field
from tenacity import Retrying, retry_if_exception, stop_after_attempt, wait_exponential

from vlm_bench.backends.backend import OPERATIONAL, Backend, BackendArgs, require_schemas
from vlm_bench.errors import VlmBenchError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

RETRY_STATUS = frozenset({408, 429})
"""HTTP client errors worth retrying (request timeout, too many requests); every 5xx is too."""


def transient_status(status: int) -> bool:
    """Whether an HTTP answer with ``status`` may succeed when asked again."""
    return status >= 500 or status in RETRY_STATUS


class ServerUnreachableError(VlmBenchError):
    """The server does not answer (down, wrong URL, refused connection)."""


class RequestFailed(Exception):
    """One call failed: ``detail`` is recorded as the request's error (with the server's own
    reason, where it gave one)."""

    def __init__(self, detail: str, *, transient: bool = False, unreachable: bool = False) -> None:
        super().__init__(detail)
        self.detail = detail[:500]
        self.transient = transient
        """Asking again may succeed (a connection error, a timeout, HTTP 408/429/5xx)."""
        self.unreachable = unreachable
        """No server answered at all."""


class RequestArgs(BackendArgs):
    """``-M`` arguments every request backend takes (all operational)."""

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


class RequestBackend(Backend):
    """A backend whose one call answers one request (module doc)."""

    Args: ClassVar[type[BackendArgs]] = RequestArgs
    args: RequestArgs

    @abstractmethod
    def complete(self, request: GenerationRequest, config: GenerationConfig) -> GenerationResult:
        """Answer one request with one call.

        Raises:
            RequestFailed: The call failed (transient or not, server reachable or not).
        """

    def before_batch(self, requests: Sequence[GenerationRequest], config: GenerationConfig) -> None:
        """Hook run once before a batch's calls (e.g. a server check); nothing by default."""

    def where(self) -> str:
        """Who answers, for messages (the server's URL)."""
        return f"the {self.name} server"

    @property
    def max_concurrency(self) -> int:
        """The ``concurrency`` argument."""
        return self.args.concurrency

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """Answer every request (``concurrency`` at a time); results in request order.

        Raises:
            ServerUnreachableError: Every request found no server, even after its retries.
        """
        require_schemas(self.name, requests, config)
        if not requests:
            return []
        self.before_batch(requests, config)
        start = time.perf_counter()
        workers = min(self.args.concurrency, len(requests))
        with ThreadPoolExecutor(max_workers=workers, thread_name_prefix=f"vlm-{self.name}") as pool:
            answers = list(pool.map(lambda r: self._attempts(r, config), requests))
        if all(unreachable for _, unreachable in answers):
            raise ServerUnreachableError(
                f"{self.where()} stopped answering ({answers[0][0].error}); finished episodes "
                "are saved, re-run to resume"
            )
        # Concurrent requests each have their own time; the call's is the batch's.
        wall_s = time.perf_counter() - start
        return [r.model_copy(update={"batch_latency_s": wall_s}) for r, _ in answers]

    def _attempts(
        self, request: GenerationRequest, config: GenerationConfig
    ) -> tuple[GenerationResult, bool]:
        """The request's result (``latency_s``: its own time, retries included), and whether it
        failed for want of a server."""
        retrying = Retrying(
            retry=retry_if_exception(lambda e: isinstance(e, RequestFailed) and e.transient),
            stop=stop_after_attempt(self.args.retries + 1),
            wait=wait_exponential(multiplier=self.args.backoff_s, max=self.args.backoff_max_s),
            reraise=True,
        )
        start = time.perf_counter()
        try:
            result = retrying(self.complete, request, config)
        except RequestFailed as failure:
            own = time.perf_counter() - start
            failed = GenerationResult(id=request.id, error=failure.detail, latency_s=own)
            return failed, failure.unreachable
        return result.model_copy(update={"latency_s": time.perf_counter() - start}), False
