"""Replay a validated plan in the simulator, step by step, stopping at the first failure."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from vlm_bench.executor.grasping import grasp_skills
from vlm_bench.executor.loop import ArmSkill, SimLoop, SimulatorUnstable
from vlm_bench.executor.references import object_reference
from vlm_bench.executor.types import ExecutionResult, ExecutorConfig, StepOutcome
from vlm_bench.executor.uav_move import fly_to, move_target, stow_arm
from vlm_bench.sim.scene import Scene, build_scene
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep, UavStep

PlanSteps = Sequence[UavStep | ArmStep]


def next_arm_step(plan: PlanSteps, index: int) -> ArmStep | None:
    """The first ARM step after ``plan[index]``, if any."""
    return next((s for s in plan[index + 1 :] if isinstance(s, ArmStep)), None)


def run_move(loop: SimLoop, episode: Episode, step: UavStep, arm: ArmStep | None) -> None:
    """Fly ``step`` (arm stowed first), stopping for ``arm``, the next ARM step, if any."""
    ref = object_reference(episode, loop.model, loop.data, arm.object) if arm else None
    flight = loop.config.flight
    stow_arm(loop, flight)
    start = loop.controller.setpoint.copy()
    target = move_target(start, episode.uav_start.yaw_deg, step, ref)
    fly_to(loop, target, flight)


def execute_plan(
    episode: Episode,
    plan: PlanSteps,
    config: ExecutorConfig | None = None,
    scene: Scene | None = None,
    arm_skills: Callable[[SimLoop], dict[str, ArmSkill]] = grasp_skills,
) -> ExecutionResult:
    """Replay ``plan`` on ``episode``'s scene (built fresh unless ``scene`` is given).

    ARM steps run through the skills ``arm_skills`` makes for the loop (default: scripted
    ``pick`` and ``place``); a skill missing there fails the step with a reason.
    Execution stops at the first failed step; later steps are skipped.
    """
    wall0 = time.perf_counter()
    loop = SimLoop(scene or build_scene(episode), config)
    skills = arm_skills(loop)
    outcomes: list[StepOutcome] = []
    failure: str | None = None
    for index, step in enumerate(plan):
        if failure is not None:
            outcomes.append(StepOutcome(index=index, status="skipped", reason="earlier failure"))
            continue
        t0 = loop.time
        loop.take_collisions()
        reason: str | None
        try:
            if isinstance(step, UavStep):
                run_move(loop, episode, step, next_arm_step(plan, index))
                reason = None
            elif step.skill in skills:
                reason = skills[step.skill](loop, episode, step)
            else:
                reason = f"skill {step.skill!r} is not available in the executor"
        except SimulatorUnstable as err:
            reason = str(err)
        outcomes.append(
            StepOutcome(
                index=index,
                status="ok" if reason is None else "failed",
                reason=reason,
                duration_s=loop.time - t0,
                collisions=loop.take_collisions(),
            )
        )
        if reason is not None:
            failure = f"step {index}: {reason}"
    done = sum(o.status == "ok" for o in outcomes)
    return ExecutionResult(
        steps=tuple(outcomes),
        exec_success=failure is None,
        n_steps_done=done,
        failure_reason=failure,
        final_uav_pose=loop.uav_pose(),
        sim_time_s=loop.time,
        wall_time_s=time.perf_counter() - wall0,
    )
