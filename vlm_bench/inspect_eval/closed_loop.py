"""The closed-loop solver of ``vlm_bench/aerial -T loop=closed``: it drives the episode's round
machine (:mod:`vlm_bench.rounds`, the one the runner's pool drives) on a live simulation.

Round 0 is the sample's own generate. Each later round executes in the simulator (in a worker
thread: MuJoCo is synchronous); after a failed round the machine asks for a replan, whose
request is built by the runner's own code (:func:`vlm_bench.rounds.replan_generation_request`:
``prompts/replan.j2`` with the new views and the typed feedback, the earlier rounds as history)
and becomes the conversation inspect sends next. The machine's outcome (Succ@0..K, rounds, the
failure of each round) and each replan's cache key (its prompt and the conversation before it,
as a run's record stores it) go to the sample's metadata for the scorer.
"""

from __future__ import annotations

import base64
import os
from pathlib import Path
from typing import Any

import anyio
from inspect_ai.model import (
    ChatMessage,
    ChatMessageAssistant,
    ChatMessageSystem,
    ChatMessageUser,
    Content,
    ContentImage,
    ContentText,
)
from inspect_ai.solver import Generate, Solver, TaskState, solver

from vlm_bench.episodes import get_episode
from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.inspect_eval.options import TaskOptions, loop_run_config
from vlm_bench.inspect_eval.scoring import LOOP_OUTCOME, ROUND_ZERO
from vlm_bench.rounds import ReplanRequest, RoundMachine, StateView, drive_episode
from vlm_bench.rounds.replan_prompt import Conversation, replan_generation_request
from vlm_bench.runner.episode_request import episode_request, run_snapshots
from vlm_bench.runner.selection import EpisodeRef
from vlm_bench.storage import SnapshotCache
from vlm_bench.types.generation import ContentPart, GenerationRequest, ImagePart
from vlm_bench.types.run import RunConfig

SIMULATIONS = anyio.CapacityLimiter(max(1, os.cpu_count() or 1))
"""Episodes simulated at once (each drive holds a worker thread and a MuJoCo scene)."""


def _content(parts: tuple[ContentPart, ...]) -> list[Content]:
    # A solver's messages carry their images inline (inspect materialises file references
    # in sample inputs only).
    return [
        ContentImage(image="data:image/png;base64," + base64.b64encode(p.png).decode())
        if isinstance(p, ImagePart)
        else ContentText(text=p.text)
        for p in parts
    ]


def request_messages(request: GenerationRequest) -> list[ChatMessage]:
    """A backend request as inspect messages: system, the earlier rounds, the new user turn."""
    messages: list[ChatMessage] = [ChatMessageSystem(content=request.system)]
    for turn in request.history:
        content = _content(turn.content)
        if turn.role == "assistant":
            text = "".join(c.text for c in content if isinstance(c, ContentText))
            messages.append(ChatMessageAssistant(content=text))
        else:
            messages.append(ChatMessageUser(content=content))
    messages.append(ChatMessageUser(content=_content(request.user)))
    return messages


class EpisodeLoop:
    """One sample's closed loop: its episode, machine, simulation and conversation."""

    def __init__(self, config: RunConfig, metadata: dict[str, Any], cache: Path) -> None:
        self.config = config
        self.key = str(metadata["key"])
        self.ref = EpisodeRef(
            str(metadata["task_id"]), int(metadata["seed"]), metadata["instruction"]
        )
        self.episode = get_episode(self.ref.task_id, self.ref.seed)
        self.cache = cache
        self.conversation = Conversation(config.history)

    def first_request(self) -> GenerationRequest:
        """Round 0's request as the run builds it (the start of every replan's history)."""
        source = run_snapshots(self.config, SnapshotCache(self.cache))
        try:
            images = source.images(self.episode) if self.config.images else None
            prompt, request = episode_request(self.config, self.ref, self.episode, images)
        finally:
            source.close()
        self.prompt_hash = prompt.prompt_hash
        return request

    def replan_request(self, ask: ReplanRequest) -> tuple[GenerationRequest, str]:
        """A replan's request (and cache key), built as the runner builds it."""
        return replan_generation_request(
            self.key,
            self.episode,
            ask,
            self.config.prompt_config(self.ref.variant),
            self.conversation,
            constrained=self.config.generation.constrained,
            show_images=self.config.images,
        )

    def drive(self, first: str, ask: Any) -> Any:
        """Run every round (in a worker thread); ``ask`` answers a replan."""
        machine = RoundMachine.closed(self.config.loop_config(), len(self.episode.gt_plan))
        live = LiveEpisode(self.episode, self.config.executor_config())
        view = StateView(
            views=self.config.views if self.config.images else (),
            size=self.config.resolution,
            labels=self.config.labels,
        )
        return drive_episode(machine, live, first, ask, view)


def closed_loop_solver(options: TaskOptions) -> Solver:
    """The solver of ``-T loop=closed`` (see the module doc)."""
    from vlm_bench.resources import results_dir
    from vlm_bench.storage import default_snapshot_cache

    config = loop_run_config(options)
    cache = default_snapshot_cache(results_dir() / "inspect")

    @solver
    def vlm_bench_closed_loop() -> Solver:
        async def solve(state: TaskState, generate: Generate) -> TaskState:
            state = await generate(state)
            first = state.output.completion
            state.metadata[ROUND_ZERO] = first
            loop = EpisodeLoop(config, state.metadata, cache)
            first_request = await anyio.to_thread.run_sync(loop.first_request)
            loop.conversation.add(first_request, first, loop.prompt_hash)
            keys: list[str] = []

            async def replan(ask: ReplanRequest) -> str:
                nonlocal state
                request, key = loop.replan_request(ask)
                state.messages = request_messages(request)
                state = await generate(state)
                answer = state.output.completion
                loop.conversation.add(request, answer, key)
                keys.append(key)
                return answer

            def ask_model(ask: ReplanRequest) -> str:
                return anyio.from_thread.run(replan, ask)

            async with SIMULATIONS:
                driven = await anyio.to_thread.run_sync(loop.drive, first, ask_model)
            outcome = driven.outcome.model_dump(mode="json")
            state.metadata[LOOP_OUTCOME] = {**outcome, "replan_keys": keys}
            return state

        return solve

    return vlm_bench_closed_loop()
