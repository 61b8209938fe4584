"""Model text → parse → plan → scores → episode record, and the records an episode ends with
when its answer or its execution fails. Never raises on model output."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from vlm_bench.catalog.model_cards import answer_format_of
from vlm_bench.runner.answers import Answer
from vlm_bench.scoring.answer import Evaluation, evaluate_answer
from vlm_bench.types.episode import Episode
from vlm_bench.types.parse import AnswerFormat
from vlm_bench.types.plan import plan_to_json
from vlm_bench.types.records import CachedResponse, EpisodeRecord, usage_of
from vlm_bench.types.scores import ScoringConfig
from vlm_bench.types.task import InstructionVariant

EXECUTION_LOST = "execution lost to the infrastructure"
"""Start of the message of a record whose execution the infrastructure lost (retried on resume)."""


def evaluate_output(
    text: str, episode: Episode, scoring: ScoringConfig, answer_format: AnswerFormat | None = None
) -> Evaluation:
    """Parse ``text`` against the episode's object ids (and the model's documented answer
    format, if any) and score it against its GT plan (see
    :func:`~vlm_bench.scoring.answer.evaluate_answer`)."""
    return evaluate_answer(text, episode.object_ids(), episode.gt_plan, scoring, answer_format)


@dataclass(frozen=True)
class EpisodeInfo:
    """Identity of an episode within a run (what every record of it repeats)."""

    run_id: str
    key: str
    variant: InstructionVariant
    model: str
    prompt_hash: str
    object_order: tuple[str, ...] = ()
    first_target_visible: bool | None = None

    def record_fields(self, episode: Episode) -> dict[str, Any]:
        """The fields every record of this episode carries, answered or not."""
        return {
            "run_id": self.run_id,
            "key": self.key,
            "task_id": episode.task_id,
            "suite": episode.suite,
            "seed": episode.seed,
            "variant": self.variant,
            "model": self.model,
            "prompt_hash": self.prompt_hash,
            "object_order": self.object_order,
            "first_target_visible": self.first_target_visible,
            "gt_plan": plan_to_json(episode.gt_plan),
        }


def scored_record(
    info: EpisodeInfo,
    episode: Episode,
    response: CachedResponse,
    scoring: ScoringConfig,
    *,
    cached: bool = False,
) -> EpisodeRecord:
    """The ``ok`` record of an episode the model answered."""
    ev = evaluate_output(response.text, episode, scoring, answer_format_of(info.model))
    return EpisodeRecord(
        **info.record_fields(episode),
        raw_output=response.text,
        parse=ev.parse,
        plan=ev.plan,
        scores=ev.scores,
        error_tags=ev.error_tags,
        **usage_of(response),
        cached=cached,
        status="ok",
    )


def error_record(
    info: EpisodeInfo, episode: Episode, error: str, latency_s: float = 0.0
) -> EpisodeRecord:
    """The ``error`` record of an episode the backend failed to answer (retried on resume)."""
    return EpisodeRecord(
        **info.record_fields(episode),
        latency_s=latency_s,
        backend_error=error,
        error_tags=("backend_error",),
        status="error",
    )


def lost_record(record: EpisodeRecord, reason: str) -> EpisodeRecord:
    """``record`` as an ``error`` record whose execution the infrastructure lost: a resume scores
    its cached answer again and executes it."""
    return record.model_copy(
        update={
            "status": "error",
            "execution": None,
            "backend_error": f"{EXECUTION_LOST} ({reason}); a resume runs it again",
            "error_tags": ("execution_lost",),
        }
    )


def answered_record(
    info: EpisodeInfo, episode: Episode, answer: Answer, scoring: ScoringConfig
) -> EpisodeRecord:
    """Round 0's record: scored where the model answered, else the backend's error."""
    if answer.response is None:
        return error_record(info, episode, answer.error or "", answer.latency_s)
    return scored_record(info, episode, answer.response, scoring, cached=answer.cached)
