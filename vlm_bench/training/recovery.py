"""Recoveries for replanning data: the GT plan executed under perturbations, and each replan the
``rules`` planner makes from the state a failed round left, until the task is done or the loop
ends (docs/training.md#replanning-rows).

This is a closed-loop run with the GT as round 0's answer and ``rules`` as the planner of every
replan, in one simulation per episode. It follows :mod:`vlm_bench.runner.loop_jobs` (the round
executes on one live episode; where it fails, the episode is frozen, then the state is described
and rendered, and the next round continues from the frozen episode) and
:class:`~vlm_bench.runner.loop_executions.LoopExecutions` (the feedback, the step budget, the end
rules), so that a replan request built from a :class:`FailedRound` is the one a run sends:
``tests/training/test_sft_rows.py`` checks it against a real run's requests.
"""

from __future__ import annotations

from dataclasses import dataclass

from vlm_bench.backends.rules_planner import RulesBackend
from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.prompting import build_replan_prompt
from vlm_bench.runner.loop_rounds import ran_steps
from vlm_bench.types.closed_loop import ExecutedStep, Feedback
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionSummary
from vlm_bench.types.generation import RequestMeta
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.prompt import PromptConfig
from vlm_bench.types.run import RunConfig

Steps = tuple[UavStep | ArmStep, ...]


@dataclass(frozen=True)
class FailedRound:
    """The state a failed round left: what a replan is told and shown."""

    feedback: Feedback
    """The steps run so far, what is held, whether only goals are unmet."""
    now: Episode
    """The episode as it stands (its scene text is the state now)."""
    images: dict[str, bytes]
    """PNG views of the state now, by view name (the run's views, resolution and labels)."""
    digest: str
    """The simulator state's digest."""
    answer: Steps
    """The rules planner's replan, whole (a run executes it cut to the step budget left)."""


@dataclass(frozen=True)
class Recovery:
    """Every round of one perturbed episode: round 0 executed the GT plan."""

    episode: Episode
    failed: tuple[FailedRound, ...]
    """Each failed round's state and the replan that followed it, in order."""
    executions: tuple[ExecutionSummary, ...]
    """Each round's execution (round 0 first)."""
    end: str
    """success, max_rounds, budget, no_plan (rules found none) or executor_crash."""

    @property
    def recovered(self) -> bool:
        """Some replan completed the task."""
        return self.end == "success" and len(self.executions) > 1


def replan_meta(episode: Episode, feedback: Feedback) -> RequestMeta:
    """A replan request's episode facts, as a closed-loop run fills them."""
    return RequestMeta(
        task_id=episode.task_id,
        seed=episode.seed,
        gt_plan=episode.gt_plan,
        arm_steps=tuple(episode.arm_steps()),
        object_ids=tuple(episode.object_ids()),
        round=feedback.round,
        done_steps=tuple(s.step for s in feedback.executed if s.status == "done"),
        held=feedback.held,
    )


def rules_replan(episode: Episode, now: Episode, feedback: Feedback, digest: str) -> Steps | None:
    """The ``rules`` planner's answer to a replan whose prompt gives the scene as text (what it
    reads), or None where it has no plan."""
    config = PromptConfig(k_shot=0, views=(), scene_as_text=True)
    prompt = build_replan_prompt(episode, now, None, config, feedback, digest)
    request = prompt.to_request("rules", meta=replan_meta(episode, feedback))
    plan = RulesBackend().plan(request)
    return None if isinstance(plan, str) or not plan else tuple(plan)


def recover(episode: Episode, config: RunConfig) -> Recovery:
    """Execute the GT plan under ``config``'s perturbations and gusts, and let ``rules`` replan
    after each failed round, up to ``config.max_rounds`` replans within the step budget.

    The views of each failed state are ``config``'s (none with ``images`` off)."""
    from vlm_bench.executor.live_snapshot import freeze, thaw
    from vlm_bench.executor.live_state import episode_now, render_now, state_digest
    from vlm_bench.runner.plan_executor import crash_summary
    from vlm_bench.sim.mujoco_log import route_mujoco_log
    from vlm_bench.sim.scene import build_spec

    route_mujoco_log()
    views = config.views if config.images else ()
    budget = config.loop_config().budget(len(episode.gt_plan))
    live = LiveEpisode(episode, config.executor_config())
    plan: Steps = tuple(episode.gt_plan)
    executed: list[ExecutedStep] = []
    failed: list[FailedRound] = []
    executions: list[ExecutionSummary] = []
    while True:
        try:
            summary = ExecutionSummary.of(live.execute(list(plan)))
        except Exception as exc:  # noqa: BLE001  (an executor bug ends this episode, not the export)
            executions.append(crash_summary(exc, 0.0))
            return Recovery(episode, tuple(failed), tuple(executions), "executor_crash")
        executions.append(summary)
        executed.extend(ran_steps(plan, summary))
        end = _end(summary, len(executions), config.max_rounds, len(executed), budget)
        if end is not None:
            return Recovery(episode, tuple(failed), tuple(executions), end)
        frozen = freeze(live)  # before rendering, as a run's worker does
        digest = state_digest(live)
        now = episode_now(live)
        images = render_now(live, now, views, config.resolution, config.labels)
        feedback = Feedback(
            round=len(executions),
            executed=tuple(executed),
            held=live.held,
            incomplete=summary.steps_ok,
        )
        answer = rules_replan(episode, now, feedback, digest)
        if answer is None:
            return Recovery(episode, tuple(failed), tuple(executions), "no_plan")
        failed.append(FailedRound(feedback, now, images, digest, answer))
        plan = answer[: budget - len(executed)]
        live = thaw(frozen, build_spec(episode))


def _end(
    summary: ExecutionSummary, rounds: int, max_rounds: int, used: int, budget: int
) -> str | None:
    """Why the loop ends after a round, as a run decides it, or None to replan."""
    if summary.exec_success:
        return "success"
    if rounds > max_rounds:
        return "max_rounds"
    if used >= budget:
        return "budget"
    return None
