"""SFT examples (docs/training.md#sft-export-schema): a run's request for an episode, in the
conversational form trl's ``SFTTrainer`` takes for vision-language models, with the plan the
model should answer as the last assistant turn.

A plan example is round 0's request (what ``vlm-bench prompt`` shows) answered with the GT
plan. A replan example is the request a closed-loop run sends after a failed round (system,
the earlier rounds as turns, the replan's user turn from ``prompts/replan.j2`` with the views
of the state now) answered with the ``rules`` planner's recovery
(:mod:`~vlm_bench.training.recovery`). Messages follow the hf backend's own layout
(:func:`~vlm_bench.backends.hf.hf_messages`): a system message, then the turns, each image a
``{"type": "image"}`` part in prompt order whose picture is the same-index entry of ``images``.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any, Literal

from pydantic import Field

from vlm_bench.backends.hf import hf_messages
from vlm_bench.prompting.templates import plan_json
from vlm_bench.rounds import ReplanRequest
from vlm_bench.rounds.replan_prompt import Conversation, replan_generation_request
from vlm_bench.rounds.state import RoundState
from vlm_bench.runner.episode_request import episode_request
from vlm_bench.runner.selection import EpisodeRef
from vlm_bench.training.recovery import FailedRound, Recovery
from vlm_bench.types.base import Frozen
from vlm_bench.types.episode import Episode
from vlm_bench.types.generation import GenerationRequest
from vlm_bench.types.plan import ArmStep, UavStep, plan_to_json
from vlm_bench.types.run import RunConfig
from vlm_bench.types.task import InstructionVariant

RowKind = Literal["plan", "replan"]


class SftExample(Frozen):
    """One SFT row (the dataset's columns, docs/training.md#sft-export-schema)."""

    key: str = Field(description="task_id/seed/instruction/round: unique in an export.")
    task_id: str = Field(description="Task id.")
    suite: str = Field(description="Suite of the task.")
    seed: int = Field(ge=0, description="Episode seed.")
    instruction: InstructionVariant = Field(description="Instruction variant (explicit/implicit).")
    round: int = Field(ge=0, description="0: the first plan; k: the k-th replan.")
    kind: RowKind = Field(description="plan (GT plan) or replan (the rules planner's recovery).")
    messages: tuple[dict[str, Any], ...] = Field(
        description="system, user (and earlier assistant/user) turns, the target as the last "
        "assistant turn; content parts {type: text|image, text}."
    )
    images: tuple[bytes, ...] = Field(
        repr=False, description="PNG of each image part, in the order the parts appear."
    )
    target: str = Field(description="The last assistant turn's text: the plan to answer.")
    prompt_hash: str = Field(description="The request's cache key in a run (its prompt hash).")


def target_text(steps: list[UavStep | ArmStep] | tuple[UavStep | ArmStep, ...]) -> str:
    """A plan as the prompt's own examples show one: the paper's JSON, one step per line."""
    return plan_json(plan_to_json(list(steps)))


def sft_messages(request: GenerationRequest, target: str) -> list[dict[str, Any]]:
    """The request's conversation as the hf backend lays it out, image parts as placeholders
    (``{"type": "image", "text": None}``), and ``target`` as the assistant's answer."""
    laid_out = hf_messages(request, [None] * len(request.images()))
    messages = [
        {
            "role": m["role"],
            "content": [{"type": p["type"], "text": p.get("text")} for p in m["content"]],
        }
        for m in laid_out
    ]
    messages.append({"role": "assistant", "content": [{"type": "text", "text": target}]})
    return messages


def _example(
    ref: EpisodeRef,
    episode: Episode,
    round_index: int,
    request: GenerationRequest,
    target: str,
    prompt_hash: str,
) -> SftExample:
    return SftExample(
        key=f"{ref.key}/{round_index}",
        task_id=ref.task_id,
        suite=episode.suite.value,
        seed=ref.seed,
        instruction=ref.variant,
        round=round_index,
        kind="plan" if round_index == 0 else "replan",
        messages=tuple(sft_messages(request, target)),
        images=tuple(p.png for p in request.images()),
        target=target,
        prompt_hash=prompt_hash,
    )


def replan_request(
    config: RunConfig,
    ref: EpisodeRef,
    episode: Episode,
    failed: FailedRound,
    conversation: Conversation,
) -> tuple[str, GenerationRequest]:
    """The cache key and request of a replan, as a closed-loop run builds them after
    ``failed`` with ``conversation`` before it."""
    state = RoundState(failed.now, failed.feedback.held, failed.images, failed.digest)
    request, key = replan_generation_request(
        ref.key,
        episode,
        ReplanRequest(failed.feedback, state),
        config.prompt_config(ref.variant),
        conversation,
        constrained=config.generation.constrained,
        show_images=config.images and bool(failed.images),
    )
    return key, request


def episode_examples(
    config: RunConfig,
    ref: EpisodeRef,
    episode: Episode,
    images: dict[str, bytes] | None,
    recovery: Recovery | None = None,
    *,
    unrecovered: bool = False,
) -> Iterator[SftExample]:
    """The plan example of one episode and instruction variant, then (given the ``recovery``
    of its perturbed execution, where it recovered, or always with ``unrecovered``) one replan
    example per failed round.

    Args:
        config: The export's prompt options (a run's).
        ref: Task, seed and instruction variant.
        episode: The episode ``ref`` names.
        images: The views of the first frame, by name (None with ``images`` off).
        recovery: The episode's perturbed rounds (:func:`~vlm_bench.training.recovery.recover`).
    """
    prompt, request = episode_request(config, ref, episode, images)
    answer = target_text(episode.gt_plan)
    yield _example(ref, episode, 0, request, answer, prompt.prompt_hash)
    if recovery is None or not (recovery.recovered or unrecovered):
        return
    conversation = Conversation(history=config.history)
    conversation.add(request, answer, prompt.prompt_hash)
    for failed in recovery.failed:
        key, replan = replan_request(config, ref, episode, failed, conversation)
        answer = target_text(failed.answer)
        yield _example(ref, episode, failed.feedback.round, replan, answer, key)
        conversation.add(replan, answer, key)
