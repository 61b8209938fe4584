"""The backend interface: one required method, optional hooks, typed ``-M key=value`` args."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from typing import ClassVar, Self, TypeVar

from pydantic import BaseModel, ConfigDict, JsonValue, ValidationError

from vlm_bench.closing import ClosesOnExit
from vlm_bench.errors import ConfigError, first_problem
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

OPERATIONAL: dict[str, JsonValue] = {"operational": True}
"""``json_schema_extra`` of a backend argument that cannot change an answer, only how fast or
where answers come (timeouts, retries and their backoff, concurrency, device placement): a
run's config hash leaves it out, so a resume may change it. Anything that can change the
text generated (weights, dtype, attention kernel, image limits, sharding) is not operational."""


class BackendArgs(BaseModel):
    """Base of every backend's ``-M key=value`` arguments (strings coerced to field types).

    Mark operational fields with ``Field(..., json_schema_extra=OPERATIONAL)``.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    @classmethod
    def operational_fields(cls) -> frozenset[str]:
        """Names of the fields marked :data:`OPERATIONAL`."""
        return frozenset(
            name
            for name, field in cls.model_fields.items()
            if isinstance(field.json_schema_extra, dict)
            and field.json_schema_extra.get("operational") is True
        )


A = TypeVar("A", bound=BackendArgs)


def parse_args(backend: str, model: type[A], raw: Mapping[str, str]) -> A:
    """Validate ``-M`` arguments against a backend's args model.

    Raises:
        ConfigError: One line naming the bad key or value and listing the valid keys.
    """
    valid = ", ".join(sorted(model.model_fields)) or "(none)"
    unknown = sorted(set(raw) - set(model.model_fields))
    if unknown:
        raise ConfigError(
            f"unknown -M argument {unknown[0]!r} for backend {backend!r}; valid: {valid}"
        )
    try:
        return model.model_validate(dict(raw))
    except ValidationError as exc:
        where, why, _ = first_problem(exc)
        key = where or "(args)"
        got = raw.get(key)
        value = f"={got!r}" if got is not None else ""
        raise ConfigError(
            f"invalid -M argument {key}{value} for backend {backend!r}: {why}; valid keys: {valid}"
        ) from None


class Backend(ClosesOnExit, ABC):
    """Generates completions for batches of requests.

    Subclasses implement :meth:`generate`. A backend never raises for a failed generation:
    server errors, timeouts and out-of-memory batches become ``GenerationResult.error``.
    Exceptions are for configuration errors (bad args, missing extras, missing schema). A
    backend whose one call answers one request (an HTTP API) subclasses
    :class:`~vlm_bench.backends.request_backend.RequestBackend` instead and implements only
    that call: retries, backoff and concurrency are its hooks, written once.
    """

    name: ClassVar[str] = "backend"
    """Registry name (used in messages)."""
    Args: ClassVar[type[BackendArgs]] = BackendArgs
    """The ``-M key=value`` arguments it accepts; the constructor takes ``(model, args)``."""
    sees_images: ClassVar[bool] = True
    """Its answers may depend on the requests' images. False (a planner that reads only the
    text): the run renders no views for it and its requests carry none."""

    @classmethod
    def from_args(cls, model: str, raw: Mapping[str, str]) -> Self:
        """Build from a model name and raw ``-M`` strings (validated against :attr:`Args`)."""
        return cls(model, parse_args(cls.name, cls.Args, raw))  # type: ignore[call-arg]

    @abstractmethod
    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """Complete every request; results come back in request order, one per request."""

    @property
    def max_concurrency(self) -> int:
        """How many requests the caller may usefully hand over at once (1 = sequential)."""
        return 1

    def close(self) -> None:
        """Release models, clients or servers. Idempotent."""


def require_schemas(
    backend: str, requests: Sequence[GenerationRequest], config: GenerationConfig
) -> None:
    """Constrained decoding needs a schema on every request.

    Raises:
        ConfigError: Names the first request without ``json_schema``.
    """
    if not config.constrained:
        return
    for req in requests:
        if req.json_schema is None:
            raise ConfigError(
                f"backend {backend!r}: constrained decoding needs GenerationRequest.json_schema "
                f"(request {req.id!r} has none)"
            )


def share_wall_time(results: Sequence[GenerationResult], wall_s: float) -> list[GenerationResult]:
    """Give each result of one call its share of the call's wall time (``latency_s``) and the
    call's whole wall time (``batch_latency_s``), so per-episode times sum to the time spent."""
    if not results:
        return []
    share = wall_s / len(results)
    return [r.model_copy(update={"latency_s": share, "batch_latency_s": wall_s}) for r in results]
