"""Recoveries for replanning data: the GT plan executed under perturbations, and each replan the
``rules`` planner makes from the state a failed round left, until the task is done or the loop
ends (docs/training.md#replanning-rows).

This is a closed-loop episode with the GT as round 0's answer and ``rules`` as the planner of
every replan, driven by the same round machine as a run (:mod:`vlm_bench.rounds`: the feedback,
the step budget, the end rules), so that a replan request built from a :class:`FailedRound` is
the one a run sends: ``tests/training/test_sft_rows.py`` checks it against a real run's requests.
"""

from __future__ import annotations

from dataclasses import dataclass

from vlm_bench.backends.rules_planner import RulesBackend
from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.prompting import build_replan_prompt
from vlm_bench.rounds import ReplanRequest, RoundMachine, StateView, drive_episode
from vlm_bench.types.closed_loop import Feedback
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionSummary, FailureCode
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
    from vlm_bench.sim.mujoco_log import route_mujoco_log

    route_mujoco_log()
    machine = RoundMachine.closed(config.loop_config(), len(episode.gt_plan))
    live = LiveEpisode(episode, config.executor_config())
    view = StateView(
        views=config.views if config.images else (), size=config.resolution, labels=config.labels
    )
    failed: list[FailedRound] = []

    def ask(request: ReplanRequest) -> Steps | None:
        state = request.state
        answer = rules_replan(episode, state.now, request.feedback, state.digest)
        if answer is not None:
            failed.append(
                FailedRound(request.feedback, state.now, state.images, state.digest, answer)
            )
        return answer

    try:
        driven = drive_episode(machine, live, tuple(episode.gt_plan), ask, view)
    except Exception as exc:  # noqa: BLE001  (an executor bug ends this episode, not the export)
        done = tuple(e for e in machine.executions if e is not None)
        crash = ExecutionSummary(
            exec_success=False,
            steps_ok=False,
            n_steps_done=0,
            s_task=0.0,
            sim_time_s=0.0,
            failure_reason=f"executor raised {type(exc).__name__}: {exc}",
            failure_code=FailureCode.EXECUTOR_CRASH,
            wall_time_s=0.0,
        )
        return Recovery(episode, tuple(failed), (*done, crash), "executor_crash")
    executions = tuple(ExecutionSummary.of(r) for r in driven.results)
    end = driven.outcome.end if driven.outcome is not None else "no_plan"
    return Recovery(episode, tuple(failed), executions, end)
