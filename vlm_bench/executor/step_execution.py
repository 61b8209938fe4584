"""One plan step at a time on a live simulation loop: UAV moves, ARM skills, their outcomes.

:class:`PlanExecution` executes steps on a loop that may already have executed earlier steps (a
closed loop's later rounds continue the same simulation); :func:`execute_steps` executes a plan's
steps in order and stops at the first failure.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal

import numpy as np

from vlm_bench.executor.motion.arm_core import ArmCore
from vlm_bench.executor.motion.flight_clearance import FlightClearance
from vlm_bench.executor.motion.uav_moves import fly_to, move_target, stow_arm
from vlm_bench.executor.perturbations.gust import gust_config
from vlm_bench.executor.perturbations.perturber import Perturber
from vlm_bench.executor.references import StepReferences
from vlm_bench.executor.sim_loop import SimBudgetSpent, SimLoop, SimulatorUnstable, Skill
from vlm_bench.rules.effects import effect_of
from vlm_bench.sim.constants import ARM_BASE_BODY
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.sim.scene import Scene, build_scene
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import (
    ArmTrace,
    ExecutorConfig,
    FailureCode,
    SkillFailure,
    StepOutcome,
)
from vlm_bench.types.plan import ArmStep, PlanSteps, UavStep

SkillFactory = Callable[[SimLoop], dict[str, Skill]]


def next_arm_step(plan: PlanSteps, index: int) -> ArmStep | None:
    """The first ARM step after ``plan[index]``, if any."""
    return next((s for s in plan[index + 1 :] if isinstance(s, ArmStep)), None)


def execute_move(
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
    return build_scene(episode, gust=gust_config(episode, config))


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


class PlanExecution:
    """Executes plan steps on one loop: references, skills, and the perturbations (if any) that
    fire before ARM steps and during flights."""

    def __init__(
        self,
        episode: Episode,
        loop: SimLoop,
        skills: dict[str, Skill],
        perturber: Perturber | None = None,
    ) -> None:
        self.episode = episode
        self.loop = loop
        self.refs = StepReferences(episode, loop.model)
        self.skills = skills
        self.perturber = perturber
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
        if effect_of(step.skill).needs_held and loop.held is not None:
            loop.watch(point, point)  # the held object's centre vs where it should rest
        else:
            loop.watch(*object_bounds(loop.model, loop.data, step.object, solid_only=True))
        try:
            skill = self.skills.get(step.skill)
            if skill is not None:
                failure = skill(self.episode, step)
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

    def _move(self, index: int, step: UavStep, plan: PlanSteps) -> None:
        loop = self.loop
        carrier = self.carrier() if loop.held is not None else None
        if self.perturber is None:
            execute_move(loop, self.refs, step, next_arm_step(plan, index), carrier)
            return
        self.perturber.flight_started(loop, index, plan)
        try:
            execute_move(loop, self.refs, step, next_arm_step(plan, index), carrier)
        finally:
            self.perturber.flight_ended(loop)

    def step(self, index: int, step: UavStep | ArmStep, plan: PlanSteps) -> StepOutcome:
        loop = self.loop
        t0 = loop.time
        loop.take_collisions()
        arm: ArmTrace | None = None
        failure: SkillFailure | None = None
        try:
            if isinstance(step, UavStep):
                self._move(index, step, plan)
            else:
                if self.perturber is not None:
                    self.perturber.before_arm_step(loop, index, step)
                failure, arm = self.arm_step(step)
                if self.perturber is not None:
                    self.perturber.after_arm_step(loop, index, step, failure is None)
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


def execute_steps(
    execution: PlanExecution, plan: PlanSteps
) -> tuple[list[StepOutcome], SkillFailure | None]:
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
        outcome = execution.step(index, step, plan)
        outcomes.append(outcome)
        if outcome.reason is not None and outcome.failure_code is not None:
            failure = SkillFailure(outcome.failure_code, f"step {index}: {outcome.reason}")
    return outcomes, failure
