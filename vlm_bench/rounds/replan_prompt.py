"""A replan's generation request (docs/closed-loop.md): its prompt, the conversation of the
rounds before it, its request id and its cache key.

A :class:`Conversation` keeps each answered round of one episode: its request (images replaced
by a note unless the history shows them), the answer and the round's cache key. A replan's cache
key chains its prompt's hash with every earlier round's key and answer, so two episodes meet the
same cached answer only after the same conversation.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

from vlm_bench.parsing import plan_json_schema
from vlm_bench.prompting import build_replan_prompt
from vlm_bench.rounds.state import ReplanRequest
from vlm_bench.types.closed_loop import HistoryMode
from vlm_bench.types.episode import Episode
from vlm_bench.types.generation import (
    GenerationRequest,
    ImagePart,
    RequestMeta,
    TextPart,
    Turn,
)
from vlm_bench.types.prompt import PromptConfig
from vlm_bench.types.rounds import round_request_id


def kept_request(
    request: GenerationRequest | None, history: HistoryMode
) -> GenerationRequest | None:
    """What a later round's conversation needs of ``request``: its user turn, each image
    replaced by a note unless ``history`` is ``images`` (only the current views are shown)."""
    if request is None:
        return None
    user = tuple(
        TextPart(text=f"[{p.view} view of that moment, not shown again]")
        if isinstance(p, ImagePart) and history == "text"
        else p
        for p in request.user
    )
    return request.model_copy(update={"user": user, "history": ()})


@dataclass
class Conversation:
    """The answered rounds of one episode (see module doc)."""

    history: HistoryMode = "text"
    """How earlier rounds are shown: text only, or with their views."""
    turns: list[tuple[GenerationRequest | None, str, str]] = field(default_factory=list)
    """Each answered round: its request (None where not given), the answer, its cache key."""

    def add(self, request: GenerationRequest | None, answer: str, key: str) -> None:
        """Record an answered round."""
        self.turns.append((kept_request(request, self.history), answer, key))

    def history_turns(self) -> tuple[Turn, ...]:
        """The earlier rounds as turns: each request's user turn and the model's answer."""
        out: list[Turn] = []
        for request, answer, _ in self.turns:
            if request is not None:
                out.append(Turn(role="user", content=request.user))
            out.append(Turn(role="assistant", content=(TextPart(text=answer),)))
        return tuple(out)

    def chain_hash(self, prompt_hash: str) -> str:
        """A replan's cache key: its prompt, the conversation before it (every earlier round's
        key and answer) and how that conversation is shown."""
        digest = hashlib.sha256(f"{prompt_hash}|history={self.history}".encode())
        for _, answer, key in self.turns:
            digest.update(f"|{key}|".encode() + hashlib.sha256(answer.encode()).digest())
        return digest.hexdigest()


def replan_generation_request(
    key: str,
    episode: Episode,
    ask: ReplanRequest,
    config: PromptConfig,
    conversation: Conversation,
    constrained: bool = False,
    show_images: bool = True,
) -> tuple[GenerationRequest, str]:
    """The request of replan ``ask`` of episode ``key`` and its cache key.

    Args:
        key: The episode's key (the request id's stem).
        episode: The episode (instruction, few-shot selection, object order).
        ask: The replan's feedback and the state it plans from.
        config: The run's prompt options for the episode's instruction variant.
        conversation: The rounds answered before it.
        constrained: Attach the plan's JSON schema (constrained decoding).
        show_images: Attach the state's views (False: the planner reads none).
    """
    state, feedback = ask.state, ask.feedback
    images = state.images if show_images else None
    prompt = build_replan_prompt(episode, state.now, images, config, feedback, state.digest)
    object_ids = episode.object_ids()
    meta = RequestMeta(
        task_id=episode.task_id,
        seed=episode.seed,
        gt_plan=episode.gt_plan,
        arm_steps=tuple(episode.arm_steps()),
        object_ids=tuple(object_ids),
        round=feedback.round,
        done_steps=tuple(s.step for s in feedback.executed if s.status == "done"),
        held=state.held,
    )
    schema = plan_json_schema(object_ids) if constrained else None
    request = prompt.to_request(
        round_request_id(key, feedback.round), episode_id=key, meta=meta, json_schema=schema
    )
    request = request.model_copy(update={"history": conversation.history_turns()})
    return request, conversation.chain_hash(prompt.prompt_hash)
