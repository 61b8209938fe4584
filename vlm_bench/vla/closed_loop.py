"""A closed loop for hierarchical pipelines: a planner replans after a failed round and a user
policy drives the ARM steps, in one simulation (docs/hierarchical.md#closed-loop).

Each round executes the planner's plan from where the last one left the scene
(:class:`~vlm_bench.executor.live_episode.LiveEpisode`); a failed step (a policy timeout, a
skill's failure) or unmet goals end the round, and the planner is called again with the
episode as it stands now and the feedback a benchmark replan gets (the steps run so far, each
done or failed with its code and detail; what is held; whether only the task is incomplete)::

    result = run_closed_loop(episode, my_planner, arm_skills=policy_skills(my_policy))
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.executor.live_state import episode_now
from vlm_bench.executor.skills.scripted_skills import default_skills
from vlm_bench.executor.step_execution import SkillFactory
from vlm_bench.types.closed_loop import ExecutedStep, Feedback
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionResult, ExecutorConfig
from vlm_bench.types.plan import ArmStep, UavStep

Planner = Callable[[Episode, Feedback | None], Sequence[UavStep | ArmStep]]
"""Gets the episode as it stands and the feedback (None in round 0); returns the plan (the
rest of it, after round 0; no steps ends the loop)."""


@dataclass
class ClosedLoopResult:
    """Every round of one closed-loop episode."""

    plans: list[list[UavStep | ArmStep]] = field(default_factory=list)
    """Each round's plan."""
    results: list[ExecutionResult] = field(default_factory=list)
    """Each round's execution."""
    feedback: list[Feedback] = field(default_factory=list)
    """What each replan was told (one per round after the first)."""

    @property
    def success_round(self) -> int | None:
        """The round whose execution completed the task, if any."""
        return next((i for i, r in enumerate(self.results) if r.exec_success), None)


def executed_steps(
    plan: Sequence[UavStep | ArmStep], result: ExecutionResult
) -> list[ExecutedStep]:
    """The steps of ``plan`` that ran, done or failed with their code and detail."""
    out = []
    for step, outcome in zip(plan, result.steps, strict=True):
        if outcome.status == "skipped":
            break
        failed = outcome.status == "failed"
        out.append(
            ExecutedStep(
                step=step,
                status="failed" if failed else "done",
                code=str(outcome.failure_code) if failed and outcome.failure_code else None,
                detail=outcome.reason if failed else None,
            )
        )
    return out


def run_closed_loop(
    episode: Episode,
    planner: Planner,
    *,
    arm_skills: SkillFactory = default_skills,
    max_rounds: int = 3,
    config: ExecutorConfig | None = None,
) -> ClosedLoopResult:
    """Plan, execute and replan up to ``max_rounds`` times in one simulation (module doc);
    ``config`` holds the gusts and perturbations (default: the benchmark's, none)."""
    live = LiveEpisode(episode, config, arm_skills=arm_skills)
    out = ClosedLoopResult()
    ran: list[ExecutedStep] = []
    feedback: Feedback | None = None
    for round_index in range(max_rounds + 1):
        plan = list(planner(episode_now(live) if round_index else episode, feedback))
        if not plan:
            break
        result = live.execute(plan)
        out.plans.append(plan)
        out.results.append(result)
        ran.extend(executed_steps(plan, result))
        if result.exec_success:
            break
        feedback = Feedback(
            round=round_index + 1, executed=tuple(ran), held=live.held, incomplete=result.steps_ok
        )
        out.feedback.append(feedback)
    return out
