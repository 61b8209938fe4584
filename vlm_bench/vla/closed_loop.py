"""A closed loop for hierarchical pipelines: a planner replans after a failed round and a user
policy drives the ARM steps, in one simulation (docs/hierarchical.md#closed-loop).

It drives the benchmark's round machine (:mod:`vlm_bench.rounds`): each round executes the
planner's plan from where the last one left the scene
(:class:`~vlm_bench.executor.live_episode.LiveEpisode`); a failed step (a policy timeout, a
skill's failure) or unmet goals end the round, and the planner is called again with the
episode as it stands now and the feedback a benchmark replan gets (the steps run so far, each
done or failed with its code and detail; what is held; whether only the task is incomplete),
within the same replans and step budget as a benchmark run::

    result = run_closed_loop(episode, my_planner, arm_skills=policy_skills(my_policy))
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.executor.skills.scripted_skills import default_skills
from vlm_bench.executor.step_execution import SkillFactory
from vlm_bench.rounds import ReplanRequest, RoundMachine, drive_episode
from vlm_bench.types.closed_loop import Feedback, LoopConfig
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionResult, ExecutorConfig
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.rounds import LoopOutcome

Planner = Callable[[Episode, Feedback | None], Sequence[UavStep | ArmStep]]
"""Gets the episode as it stands and the feedback (None in round 0); returns the plan (the
rest of it, after round 0; no steps ends the loop)."""


@dataclass
class ClosedLoopResult:
    """Every round of one closed-loop episode."""

    plans: list[list[UavStep | ArmStep]] = field(default_factory=list)
    """Each executed round's plan (a replan's cut to the step budget)."""
    results: list[ExecutionResult] = field(default_factory=list)
    """Each round's execution."""
    feedback: list[Feedback] = field(default_factory=list)
    """What each replan was told (one per round after the first)."""
    outcome: LoopOutcome | None = None
    """The episode summed up as a benchmark record's ``loop`` (why it ended, Succ@k)."""

    @property
    def success_round(self) -> int | None:
        """The round whose execution completed the task, if any."""
        return next((i for i, r in enumerate(self.results) if r.exec_success), None)


def run_closed_loop(
    episode: Episode,
    planner: Planner,
    *,
    arm_skills: SkillFactory = default_skills,
    max_rounds: int = 3,
    step_budget: int | None = None,
    config: ExecutorConfig | None = None,
) -> ClosedLoopResult:
    """Plan, execute and replan up to ``max_rounds`` times in one simulation (module doc);
    ``step_budget``: steps over all rounds (None: 3 x the GT plan's, as in a benchmark run);
    ``config`` holds the gusts and perturbations (default: the benchmark's, none)."""
    budget = LoopConfig(step_budget=step_budget).budget(len(episode.gt_plan))
    machine = RoundMachine(max_rounds, budget)  # max_rounds 0: the open loop
    live = LiveEpisode(episode, config, arm_skills=arm_skills)

    def ask(request: ReplanRequest) -> list[UavStep | ArmStep]:
        return list(planner(request.state.now, request.feedback))

    driven = drive_episode(machine, live, list(planner(episode, None)), ask)
    return ClosedLoopResult(
        plans=[list(p) for p in driven.plans],
        results=driven.results,
        feedback=[r.feedback for r in driven.requests],
        outcome=driven.outcome,
    )
