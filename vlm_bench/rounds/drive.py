"""Drive one episode's round machine synchronously in this process (the ``vla`` closed loop, a
harness's solver): execute each round on one live simulation, ask the planner for each replan.

::

    machine = RoundMachine.closed(LoopConfig(), len(episode.gt_plan))
    driven = drive_episode(machine, LiveEpisode(episode), first_plan, ask_model)
    driven.outcome.succ_at
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from vlm_bench.parsing import parse_plan
from vlm_bench.rounds.machine import Action, Done, Execute, RoundMachine, Step
from vlm_bench.rounds.state import ReplanRequest, StateView, describe_state, round_outcome
from vlm_bench.types.execution import ExecutionResult
from vlm_bench.types.rounds import LoopOutcome

if TYPE_CHECKING:
    from vlm_bench.executor.live_episode import LiveEpisode

Answer = str | Sequence[Step] | None
"""A planner's answer: its text in the paper's JSON format (parsed; its valid steps run), the
steps themselves, or None (no plan: the episode ends)."""


@dataclass
class DrivenEpisode:
    """Every round of one driven episode."""

    plans: list[tuple[Step, ...]] = field(default_factory=list)
    """Each executed round's steps (after the step budget)."""
    results: list[ExecutionResult] = field(default_factory=list)
    """Each executed round's execution."""
    requests: list[ReplanRequest] = field(default_factory=list)
    """Each replan asked for (one per round after the first)."""
    outcome: LoopOutcome | None = None
    """How the episode ended."""


def answer_steps(answer: Answer, object_ids: Sequence[str]) -> list[Step] | None:
    """The steps to execute of ``answer`` (text: its parse's valid steps, if usable)."""
    if answer is None or not isinstance(answer, str):
        return None if answer is None else list(answer)
    parse = parse_plan(answer, list(object_ids))
    return parse.valid_steps() if parse.usable else None


def drive_episode(
    machine: RoundMachine,
    live: LiveEpisode,
    first: Answer,
    ask_model: Callable[[ReplanRequest], Answer],
    view: StateView | None = None,
) -> DrivenEpisode:
    """Run the episode's rounds until the machine says done (module doc).

    Args:
        machine: A fresh round machine (its budget and replans).
        live: The episode's simulation (each round continues where the last left it).
        first: Round 0's plan.
        ask_model: Answers a replan from its feedback and the state now.
        view: What views of the state a replan shows (default: none rendered).
    """
    out = DrivenEpisode()
    object_ids = live.episode.object_ids()
    action: Action = machine.start(answer_steps(first, object_ids))
    while not isinstance(action, Done):
        if isinstance(action, Execute):
            result = live.execute(list(action.steps))
            out.plans.append(action.steps)
            out.results.append(result)
            action = machine.executed_round(round_outcome(result, live.held))
        else:
            state = describe_state(live, view or StateView())
            request = ReplanRequest(action.feedback, state)
            out.requests.append(request)
            action = machine.answered(answer_steps(ask_model(request), object_ids))
    out.outcome = action.outcome
    return out
