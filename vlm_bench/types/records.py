"""Episode records (one JSON line of ``records.jsonl``) and cached model responses.

Records are read back by every later release: loading is tolerant (unknown fields are ignored,
fields added later have defaults) and :func:`migrate_record` upgrades older layouts by
``schema_version`` before validation.
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any, Literal, Protocol

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    SerializerFunctionWrapHandler,
    model_serializer,
)

from vlm_bench.types.base import Utf8Str, omit_none
from vlm_bench.types.execution import ExecutionSummary
from vlm_bench.types.parse import ParseResult
from vlm_bench.types.rounds import LoopOutcome, RoundRecord
from vlm_bench.types.scores import PlanScores
from vlm_bench.types.task import InstructionVariant, Suite

RECORD_SCHEMA_VERSION = 2
"""Version of the record layout written by this release (see :func:`migrate_record`)."""

RecordStatus = Literal["ok", "error"]
"""``ok``: the model answered and the answer was scored (whatever its quality);
``error``: the episode has no result yet: the backend failed to answer (server error, timeout)
or the infrastructure lost its execution (a dead worker or node); a resume retries it."""

TIMING_FIELDS = frozenset({"latency_s", "batch_latency_s", "created"})
"""Fields that differ between two otherwise identical runs (and ``execution.wall_time_s``)."""


USAGE_FIELDS = (
    "latency_s",
    "batch_latency_s",
    "prompt_tokens",
    "completion_tokens",
    "finish_reason",
)
"""What a backend reports about one answer; carried from its result to the cached response and
on to the episode's record."""


class Usage(Protocol):
    """A generation result, cached response or record: anything that carries the usage fields."""

    @property
    def latency_s(self) -> float: ...
    @property
    def batch_latency_s(self) -> float | None: ...
    @property
    def prompt_tokens(self) -> int | None: ...
    @property
    def completion_tokens(self) -> int | None: ...
    @property
    def finish_reason(self) -> str | None: ...


def usage_of(source: Usage) -> dict[str, Any]:
    """The :data:`USAGE_FIELDS` of ``source``, as keyword arguments for the next holder."""
    return {name: getattr(source, name) for name in USAGE_FIELDS}


def episode_key(task_id: str, seed: int, variant: str) -> str:
    """The key of one episode in a run: ``task_id/seed/variant``."""
    return f"{task_id}/{seed}/{variant}"


def utc_now() -> datetime:
    """The current time in UTC (timestamps of records and manifests)."""
    return datetime.now(UTC)


class Tolerant(BaseModel):
    """Base of stored models: immutable, ignores fields it does not know (newer writers)."""

    model_config = ConfigDict(frozen=True, extra="ignore")


class EpisodeRecord(Tolerant):
    """The outcome of one episode of a run: what was asked, what came back, how it scored."""

    schema_version: int = Field(default=RECORD_SCHEMA_VERSION, description="Record layout.")
    run_id: str = Field(description="Run id (the run folder's name).")
    key: str = Field(description="Episode key task_id/seed/variant, unique within a run.")
    task_id: str = Field(description="Task id.")
    suite: Suite = Field(description="Task suite.")
    seed: int = Field(ge=0, description="Episode seed.")
    variant: InstructionVariant = Field(description="Instruction variant (explicit/implicit).")
    model: str = Field(description="Model string of the run.")
    prompt_hash: str = Field(default="", description="Prompt.prompt_hash of the request.")
    object_order: tuple[str, ...] = Field(
        default=(), description="Object ids in the order the prompt listed them (shuffled)."
    )
    first_target_visible: bool | None = Field(
        default=None, description="The first ARM step's object is in the uav view at the start."
    )
    raw_output: Utf8Str = Field(
        default="", description="The model's text, verbatim (lone surrogates: U+FFFD)."
    )
    parse: ParseResult | None = Field(default=None, description="Parser result (None on error).")
    plan: list[dict[str, Any]] | None = Field(
        default=None, description="Valid predicted steps in the paper's JSON format."
    )
    gt_plan: list[dict[str, Any]] = Field(
        default_factory=list, description="The episode's GT plan in the paper's JSON format."
    )
    scores: PlanScores | None = Field(default=None, description="Metrics (None on error).")
    error_tags: tuple[str, ...] = Field(
        default=(), description="Parse codes then planning error types, duplicates removed."
    )
    latency_s: float = Field(
        default=0.0, ge=0, description="This episode's share of its batch's backend time (s)."
    )
    batch_latency_s: float | None = Field(
        default=None, ge=0, description="Backend wall time of the whole batch it was in (s)."
    )
    prompt_tokens: int | None = Field(default=None, description="Prompt tokens, if known.")
    completion_tokens: int | None = Field(default=None, description="Generated tokens.")
    finish_reason: str | None = Field(default=None, description="Why generation stopped.")
    cached: bool = Field(default=False, description="The answer came from the response cache.")
    execution: ExecutionSummary | None = Field(
        default=None, description="Outcome of executing the plan (None: not executed)."
    )
    backend_error: Utf8Str | None = Field(
        default=None, description="Why an error record has no result (backend, lost execution)."
    )
    status: RecordStatus = Field(description="ok or error (see RecordStatus).")
    created: datetime = Field(default_factory=utc_now, description="When it was written (UTC).")
    rounds: tuple[RoundRecord, ...] | None = Field(
        default=None, description="Closed loop: the replans after round 0 (None: open loop)."
    )
    loop: LoopOutcome | None = Field(
        default=None, description="Closed loop: the episode summed up (None: open loop)."
    )

    @model_serializer(mode="wrap")
    def _omit_open_loop(self, handler: SerializerFunctionWrapHandler) -> Any:
        return omit_none(handler(self), ("rounds", "loop"))

    @property
    def ok(self) -> bool:
        """True when the model answered (the record counts in the metrics)."""
        return self.status == "ok"

    def without_timing(self) -> dict[str, Any]:
        """The record as JSON data minus :data:`TIMING_FIELDS`, ``cached`` and the execution's
        wall time (comparisons)."""
        data = self.model_dump(mode="json", exclude=set(TIMING_FIELDS) | {"cached"})
        executions = [data.get("execution")]
        for row in data.get("rounds") or ():
            for name in ("latency_s", "cached"):
                row.pop(name, None)
            executions.append(row.get("execution"))
        for execution in executions:
            if execution is not None:
                execution.pop("wall_time_s", None)
        return data


class OutputScore(BaseModel):
    """One raw model output scored against an episode's GT plan (:func:`vlm_bench.score_output`)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    task_id: str = Field(description="Task id.")
    seed: int = Field(ge=0, description="Episode seed.")
    instruction: InstructionVariant = Field(description="Instruction variant the output answers.")
    parse: ParseResult = Field(description="What the parser made of the output.")
    plan: list[dict[str, Any]] = Field(description="The valid predicted steps, paper format.")
    gt_plan: list[dict[str, Any]] = Field(description="The episode's GT plan, paper format.")
    scores: PlanScores = Field(description="Planning scores against the GT plan.")
    error_tags: tuple[str, ...] = Field(
        description="Parser codes, then planning error types (duplicates removed)."
    )


class CachedResponse(Tolerant):
    """One line of ``responses.jsonl``: a model answer keyed by episode key and prompt hash."""

    key: str = Field(description="Episode key task_id/seed/variant.")
    prompt_hash: str = Field(description="Hash of the prompt that produced the answer.")
    text: Utf8Str = Field(description="The model's text, verbatim (lone surrogates: U+FFFD).")
    latency_s: float = Field(
        default=0.0, ge=0, description="This answer's share of its batch's backend time (s)."
    )
    batch_latency_s: float | None = Field(
        default=None, ge=0, description="Backend wall time of the whole batch it was in (s)."
    )
    prompt_tokens: int | None = Field(default=None, description="Prompt tokens, if known.")
    completion_tokens: int | None = Field(default=None, description="Generated tokens.")
    finish_reason: str | None = Field(default=None, description="Why generation stopped.")
    created: datetime = Field(default_factory=utc_now, description="When it was cached (UTC).")


def migrate_record(data: dict[str, Any]) -> dict[str, Any]:
    """Upgrade a stored record's JSON to the current layout (before validation).

    A record without ``schema_version`` is read as version 1. Version 2 adds ``execution``
    (absent in version 1 records, read as None: not executed), so no upgrade step is needed yet;
    the stored version is kept, telling which release wrote the record. A layout change that
    renames or reshapes fields bumps :data:`RECORD_SCHEMA_VERSION` and adds its upgrade step
    here, keyed by the stored version.
    """
    version = data.get("schema_version", 1)
    if not isinstance(version, int) or version < 1:
        raise ValueError(f"schema_version must be a positive integer, got {version!r}")
    return {**data, "schema_version": version}
