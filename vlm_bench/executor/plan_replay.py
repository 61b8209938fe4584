"""Replay a validated plan in the simulator, step by step, stopping at the first failure.

After the last step the scene settles (servo targets and UAV setpoint held), then the task's
goal predicates are checked, non-target objects' displacement is measured and the VLA metrics
are computed.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Literal

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.executor.goals import check_goals, describe_goal
from vlm_bench.executor.motion.arm_core import ArmCore
from vlm_bench.executor.motion.flight_clearance import FlightClearance
from vlm_bench.executor.motion.uav_moves import fly_to, move_target, stow_arm
from vlm_bench.executor.references import StepReferences
from vlm_bench.executor.sim_loop import ArmSkill, SimBudgetSpent, SimLoop, SimulatorUnstable
from vlm_bench.executor.skills.scripted_skills import default_skills
from vlm_bench.executor.vla_metrics import vla_scores
from vlm_bench.sim.constants import ARM_BASE_BODY
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.sim.scene import Scene, build_scene
from vlm_bench.sim.uav_control import GustConfig
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import (
    ArmTrace,
    ExecutionResult,
    ExecutorConfig,
    FailureCode,
    SkillFailure,
    StepOutcome,
)
from vlm_bench.types.plan import ArmStep, UavStep

PlanSteps = Sequence[UavStep | ArmStep]
SkillFactory = Callable[[SimLoop], dict[str, ArmSkill]]


def next_arm_step(plan: PlanSteps, index: int) -> ArmStep | None:
    """The first ARM step after ``plan[index]``, if any."""
    return next((s for s in plan[index + 1 :] if isinstance(s, ArmStep)), None)


def run_move(
    loop: SimLoop,
    refs: StepReferences,
    step: UavStep,
    arm: ArmStep | None,
    carrier: FlightClearance | None = None,
) -> None:
    """Fly ``step``, stopping for ``arm``, the next ARM step, if any. The arm is stowed first
    unless it holds something: folding a held object up against the arm knocks it out of the
    fingers, so it is carried where the pick lifted it, turned aside (by ``carrier``, the
    arm's flight clearance) where it would meet something on the way, and turned back after;
    where no turn clears the way, the UAV climbs first and flies that much higher, if that
    does."""
    ref = refs(loop.data, arm.object, arm.skill, loop.held) if arm else None
    flight = loop.config.flight
    if loop.held is None:
        stow_arm(loop, flight)
    start = loop.controller.setpoint.copy()
    target = move_target(start, refs.episode.uav_start.yaw_deg, step, ref)
    turn: float | None = 0.0
    if loop.held is not None and carrier is not None:
        turn = carrier.clear_for_flight(target - start)
        climb = carrier.flight_climb(target - start) if turn is None else np.zeros(3)
        if climb.any():  # climbed, it flies that much higher
            fly_to(loop, start + climb, flight)
            target = target + climb
    fly_to(loop, target, flight)
    if carrier is not None:
        carrier.turn_back(turn)


def episode_scene(episode: Episode, config: ExecutorConfig) -> Scene:
    """The episode's scene with the configured gusts on the UAV."""
    gust = (
        GustConfig(
            force_std=config.uav_noise, torque_std=0.05 * config.uav_noise, seed=config.noise_seed
        )
        if config.uav_noise > 0
        else None
    )
    return build_scene(episode, gust=gust)


def target_ids(episode: Episode) -> set[str]:
    """Objects the task is about (GT ARM objects and goal arguments); others are non-targets."""
    ids = {s.object for s in episode.gt_plan if isinstance(s, ArmStep)}
    ids |= {s.target for s in episode.gt_plan if isinstance(s, ArmStep) and s.target}
    for goal in episode.goals:
        ids.add(goal.object)
        if goal.target:
            ids.add(goal.target)
    return ids


def _agent(step: UavStep | ArmStep) -> Literal["UAV", "ARM"]:
    return "UAV" if isinstance(step, UavStep) else "ARM"


def _as_failure(result: SkillFailure | str | None) -> SkillFailure | None:
    """A skill's result as a typed failure (a bare string: :attr:`FailureCode.SKILL_FAILED`)."""
    if result is None or isinstance(result, SkillFailure):
        return result
    return SkillFailure(FailureCode.SKILL_FAILED, result)


class _Run:
    """One plan replay: the loop, references, skills and the outcomes so far."""

    def __init__(self, episode: Episode, loop: SimLoop, skills: dict[str, ArmSkill]) -> None:
        self.episode = episode
        self.loop = loop
        self.refs = StepReferences(episode, loop.model)
        self.skills = skills
        self._carrier: FlightClearance | None = None

    def carrier(self) -> FlightClearance:
        """The arm's planner for flights with an object in the hand (made when first needed)."""
        if self._carrier is None:
            self._carrier = FlightClearance(ArmCore(self.loop))
        return self._carrier

    def arm_step(self, step: ArmStep) -> tuple[SkillFailure | None, ArmTrace]:
        loop = self.loop
        ref = self.refs(loop.data, step.object, step.skill, loop.held)
        if ref is None:
            unknown = SkillFailure(FailureCode.UNKNOWN_OBJECT, f"unknown object {step.object!r}")
            return unknown, ArmTrace(object=step.object, known=False)
        point = np.array([ref.x, ref.y, ref.z])
        base = float(np.linalg.norm(loop.data.body(ARM_BASE_BODY).xpos - point))
        if step.skill == "place" and loop.held is not None:
            loop.watch(point, point)  # the held object's centre vs where it should rest
        else:
            loop.watch(*object_bounds(loop.model, loop.data, step.object, solid_only=True))
        try:
            skill = self.skills.get(step.skill)
            if skill is not None:
                failure = _as_failure(skill(loop, self.episode, step))
            else:
                failure = SkillFailure(
                    FailureCode.UNKNOWN_SKILL,
                    f"skill {step.skill!r} is not available in the executor",
                )
        finally:
            initial, best, tilt = loop.unwatch()
        attempted = initial is not None and best is not None and best < initial - 0.05
        trace = ArmTrace(
            object=step.object,
            known=True,
            base_distance=base,
            ee_distance=best,
            tilt_deg=tilt,
            attempted=attempted,
        )
        return failure, trace

    def step(self, index: int, step: UavStep | ArmStep, plan: PlanSteps) -> StepOutcome:
        loop = self.loop
        t0 = loop.time
        loop.take_collisions()
        arm: ArmTrace | None = None
        failure: SkillFailure | None = None
        try:
            if isinstance(step, UavStep):
                carrier = self.carrier() if loop.held is not None else None
                run_move(loop, self.refs, step, next_arm_step(plan, index), carrier)
            else:
                failure, arm = self.arm_step(step)
        except (SimulatorUnstable, SimBudgetSpent) as err:
            code = (
                FailureCode.SIM_BUDGET
                if isinstance(err, SimBudgetSpent)
                else FailureCode.SIMULATOR_UNSTABLE
            )
            failure = SkillFailure(code, str(err))
            if isinstance(step, ArmStep):
                arm = ArmTrace(object=step.object, known=True)
        return StepOutcome(
            index=index,
            agent=_agent(step),
            status="ok" if failure is None else "failed",
            reason=None if failure is None else failure.detail,
            failure_code=None if failure is None else failure.code,
            duration_s=loop.time - t0,
            collisions=loop.take_collisions(),
            arm=arm,
        )


def _replay_steps(run: _Run, plan: PlanSteps) -> tuple[list[StepOutcome], SkillFailure | None]:
    """Each step's outcome, stopping at the first failure (later steps are skipped), and
    that failure, its detail prefixed with the step's index."""
    outcomes: list[StepOutcome] = []
    failure: SkillFailure | None = None
    for index, step in enumerate(plan):
        if failure is not None:
            skipped = StepOutcome(
                index=index,
                agent=_agent(step),
                status="skipped",
                reason="earlier failure",
                failure_code=FailureCode.EARLIER_FAILURE,
            )
            outcomes.append(skipped)
            continue
        outcome = run.step(index, step, plan)
        outcomes.append(outcome)
        if outcome.reason is not None and outcome.failure_code is not None:
            failure = SkillFailure(outcome.failure_code, f"step {index}: {outcome.reason}")
    return outcomes, failure


def _goal_failure(episode: Episode, goals: tuple[bool, ...]) -> SkillFailure:
    """The failure naming the goals that do not hold."""
    missed = [describe_goal(g) for g, ok in zip(episode.goals, goals, strict=True) if not ok]
    return SkillFailure(FailureCode.GOAL_NOT_MET, "goal not met: " + ", ".join(missed))


def execute_plan(
    episode: Episode,
    plan: PlanSteps,
    config: ExecutorConfig | None = None,
    scene: Scene | None = None,
    arm_skills: SkillFactory = default_skills,
    observers: Sequence[Callable[[SimLoop], None]] = (),
) -> ExecutionResult:
    """Replay ``plan`` on ``episode``'s scene (built fresh unless ``scene`` is given).

    Args:
        episode: The episode (scene, goals, GT used for non-target objects).
        plan: Validated plan steps.
        config: Executor settings (default: the benchmark's).
        scene: A scene to run on instead of building one (it is modified).
        arm_skills: Makes the ARM skills for the loop (default: the scripted skills); a skill
            missing there fails its step with a reason. Hierarchical pipelines pass
            policy-driven skills here.
        observers: Called after every control step (e.g. a video recorder).

    Execution stops at the first failed step; later steps are skipped. The result is always
    returned (simulator blow-ups and a spent simulated-time budget,
    :meth:`~vlm_bench.types.execution.ExecutorConfig.sim_budget_s`, become failed steps).
    """
    wall0 = time.perf_counter()
    config = config or ExecutorConfig()
    loop = SimLoop(scene or episode_scene(episode, config), config)
    loop.observers.extend(observers)
    run = _Run(episode, loop, arm_skills(loop))
    movable = [o.id for o in episode.objects if object_kind(o.kind).movable]
    start = {i: np.array(loop.data.body(i).xpos) for i in movable}
    loop.deadline = loop.time + config.sim_budget_s(len(plan))
    outcomes, failure = _replay_steps(run, plan)
    loop.deadline = None  # settling is bounded by settle_s
    try:
        loop.hold(config.settle_s)
    except SimulatorUnstable as err:
        if failure is None:
            failure = SkillFailure(FailureCode.SIMULATOR_UNSTABLE, f"settling: {err}")
    goals = check_goals(episode, loop.model, loop.data)
    if failure is None and not all(goals):
        failure = _goal_failure(episode, goals)
    return _result(episode, loop, outcomes, goals, failure, start, time.perf_counter() - wall0)


def _result(
    episode: Episode,
    loop: SimLoop,
    outcomes: list[StepOutcome],
    goals: tuple[bool, ...],
    failure: SkillFailure | None,
    start: dict[str, FloatArray],
    wall_s: float,
) -> ExecutionResult:
    """The replay's result: outcomes, goals, non-targets' displacement from ``start``, the VLA
    metrics and the final state."""
    steps_ok = all(o.status == "ok" for o in outcomes)
    targets = target_ids(episode)
    displacement = {
        i: float(np.linalg.norm(loop.data.body(i).xpos - p))
        for i, p in start.items()
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
