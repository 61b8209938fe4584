"""A live episode: one simulation that executes plan after plan from wherever the last left it.

Each :meth:`LiveEpisode.execute` runs a plan's steps from the current state, stopping at the
first failure, lets the scene settle, checks the task's goals and scores the round; the next
call continues the same simulation (the closed loop's replans, docs/design.md#closed-loop).
A single call on a fresh episode is :func:`execute_plan`.
Non-targets' displacement is measured from the episode's start, the simulated time is the
episode's clock, and the perturbations a round lists are those that fired in it.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.executor.goals import check_goals, describe_goal
from vlm_bench.executor.perturbations.perturber import Perturber
from vlm_bench.executor.sim_loop import SimLoop, SimulatorUnstable
from vlm_bench.executor.skills.scripted_skills import default_skills
from vlm_bench.executor.step_execution import (
    PlanExecution,
    SkillFactory,
    episode_scene,
    execute_steps,
    target_ids,
)
from vlm_bench.executor.vla_metrics import vla_scores
from vlm_bench.sim.scene import Scene
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import (
    ExecutionResult,
    ExecutorConfig,
    FailureCode,
    SkillFailure,
    StepOutcome,
)
from vlm_bench.types.plan import PlanSteps


def goal_failure(episode: Episode, goals: tuple[bool, ...]) -> SkillFailure:
    """The failure naming the goals that do not hold."""
    missed = [describe_goal(g) for g, ok in zip(episode.goals, goals, strict=True) if not ok]
    return SkillFailure(FailureCode.GOAL_NOT_MET, "goal not met: " + ", ".join(missed))


class LiveEpisode:
    """One episode's simulation, executing plans one after another (see module doc).

    Args:
        episode: The episode (scene, goals, GT used for non-target objects).
        config: Executor settings (default: the benchmark's).
        scene: A scene to run on instead of building one (it is modified).
        arm_skills: Makes the ARM skills for the loop (default: the scripted skills).
        observers: Called after every control step (e.g. a video recorder).

    The perturbations that fire are ``config.perturb`` (None: none, and results list none).
    """

    def __init__(
        self,
        episode: Episode,
        config: ExecutorConfig | None = None,
        scene: Scene | None = None,
        arm_skills: SkillFactory = default_skills,
        observers: Sequence[Callable[[SimLoop], None]] = (),
    ) -> None:
        self.episode = episode
        self.config = config or ExecutorConfig()
        self.loop = SimLoop(scene or episode_scene(episode, self.config), self.config)
        self.loop.observers.extend(observers)
        perturb = self.config.perturb
        self.perturber = Perturber(perturb, episode) if perturb is not None else None
        self.execution = PlanExecution(episode, self.loop, arm_skills(self.loop), self.perturber)
        movable = [o.id for o in episode.objects if object_kind(o.kind).movable]
        self.start: dict[str, FloatArray] = {
            i: np.array(self.loop.data.body(i).xpos) for i in movable
        }
        self.rounds = 0
        """Plans executed so far."""

    @property
    def held(self) -> str | None:
        """The object the gripper holds now, as the robot believes."""
        return self.loop.held

    def execute(self, plan: PlanSteps) -> ExecutionResult:
        """Run ``plan`` from the current state, settle, check the goals (see module doc).

        Execution stops at the first failed step; later steps are skipped. The result is
        always returned (simulator blow-ups and a spent simulated-time budget,
        :meth:`~vlm_bench.types.execution.ExecutorConfig.sim_budget_s`, become failed steps).
        """
        wall0 = time.perf_counter()
        fired = len(self.perturber.events) if self.perturber is not None else 0
        loop = self.loop
        if self.perturber is not None and self.rounds > 0:
            self.perturber.between_rounds(loop, self.rounds)
        loop.deadline = loop.time + self.config.sim_budget_s(len(plan))
        outcomes, failure = execute_steps(self.execution, plan)
        loop.deadline = None  # settling is bounded by settle_s
        try:
            loop.hold(self.config.settle_s)
        except SimulatorUnstable as err:
            if failure is None:
                failure = SkillFailure(FailureCode.SIMULATOR_UNSTABLE, f"settling: {err}")
        goals = check_goals(self.episode, loop.model, loop.data)
        if failure is None and not all(goals):
            failure = goal_failure(self.episode, goals)
        self.rounds += 1
        result = self._result(outcomes, goals, failure, time.perf_counter() - wall0)
        if self.perturber is None:
            return result
        events = tuple(self.perturber.events[fired:])
        return result.model_copy(update={"perturbations": events})

    def _result(
        self,
        outcomes: list[StepOutcome],
        goals: tuple[bool, ...],
        failure: SkillFailure | None,
        wall_s: float,
    ) -> ExecutionResult:
        """The round's result: outcomes, goals, non-targets' displacement from the start, the
        VLA metrics and the state now."""
        loop = self.loop
        steps_ok = all(o.status == "ok" for o in outcomes)
        targets = target_ids(self.episode)
        displacement = {
            i: float(np.linalg.norm(loop.data.body(i).xpos - p))
            for i, p in self.start.items()
            if i not in targets
        }
        collided = sorted({name for o in outcomes for name in o.collisions})
        return ExecutionResult(
            steps=tuple(outcomes),
            steps_ok=steps_ok,
            exec_success=steps_ok and all(goals) and failure is None,
            n_steps_done=sum(o.status == "ok" for o in outcomes),
            failure_reason=None if failure is None else failure.detail,
            failure_code=None if failure is None else failure.code,
            goals=goals,
            displacement=displacement,
            uav_collisions=tuple(collided),
            scores=vla_scores(outcomes, goals, displacement, loop.config.metrics),
            final_uav_pose=loop.uav_pose(),
            sim_time_s=loop.time,
            wall_time_s=wall_s,
        )


def execute_plan(
    episode: Episode,
    plan: PlanSteps,
    config: ExecutorConfig | None = None,
    scene: Scene | None = None,
    arm_skills: SkillFactory = default_skills,
    observers: Sequence[Callable[[SimLoop], None]] = (),
) -> ExecutionResult:
    """Execute ``plan`` on ``episode``'s scene (built fresh unless ``scene`` is given).

    Args:
        episode: The episode (scene, goals, GT used for non-target objects).
        plan: Validated plan steps.
        config: Executor settings (default: the benchmark's), gusts and perturbations included.
        scene: A scene to run on instead of building one (it is modified).
        arm_skills: Makes the ARM skills for the loop (default: the scripted skills); a skill
            missing there fails its step with a reason. Hierarchical pipelines pass
            policy-driven skills here.
        observers: Called after every control step (e.g. a video recorder).

    Execution stops at the first failed step; later steps are skipped. The result is always
    returned (simulator blow-ups and a spent simulated-time budget,
    :meth:`~vlm_bench.types.execution.ExecutorConfig.sim_budget_s`, become failed steps).
    """
    return LiveEpisode(episode, config, scene, arm_skills, observers).execute(plan)
