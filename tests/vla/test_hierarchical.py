"""Hierarchical API: a user policy drives ARM steps with the 12-D action at 20 Hz."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from vlm_bench.episodes import get_episode
from vlm_bench.errors import ConfigError
from vlm_bench.executor import SimLoop, default_skills, execute_plan
from vlm_bench.executor.references import StepReferences
from vlm_bench.executor.step_execution import execute_move, next_arm_step
from vlm_bench.sim import constants as c
from vlm_bench.sim.robot import arm_qpos, gripper_opening
from vlm_bench.sim.scene import build_scene
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import FailureCode, SkillFailure
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.vla import (
    PolicyOutput,
    Proprioception,
    VlaAction,
    VlaObservation,
    apply_action,
    grasped_object,
    policy_skills,
)
from vlm_bench.vla.action import (
    MAX_UAV_STEP_M,
    MAX_YAW_STEP_RAD,
    gripper_command_to_opening,
    joint_limits,
)
from vlm_bench.vla.observation import PROPRIO_SIZE

PICK = ArmStep(object="gray_cube", skill="pick")
DOCS = Path(__file__).resolve().parents[2] / "docs" / "hierarchical.md"
Script = Callable[[VlaObservation], PolicyOutput]


class Recorder:
    """A policy that follows ``script`` and records every call."""

    def __init__(self, script: Script) -> None:
        self.script = script
        self.calls: list[tuple[ArmStep, VlaObservation]] = []

    def __call__(self, observation: VlaObservation, step: ArmStep) -> PolicyOutput:
        self.calls.append((step, observation))
        return self.script(observation)


def _loop(seed: int = 0) -> tuple[Episode, SimLoop]:
    episode = get_episode("standard_pick_place", seed)
    return episode, SimLoop(build_scene(episode))


def _run_step(
    policy: Recorder, seed: int = 0, max_steps: int = 200
) -> tuple[SimLoop, SkillFailure | None]:
    """Run one policy-driven ARM step without images; returns the loop and the skill's result."""
    episode, loop = _loop(seed)
    skill = policy_skills(policy, max_steps=max_steps, views=())(loop)["pick"]
    return loop, skill(episode, PICK)


def test_action_array_round_trip_and_clipping() -> None:
    values = [0.01, -0.02, 0.03, 0.05, 0.1, 0.2, 0.3, -1.0, 0.5, 1.0, 0.7, 0.25]
    action = VlaAction.from_array(values)
    assert np.allclose(action.to_array(), values)
    again = VlaAction.from_array(action.to_array())  # float32 array form: equal up to rounding
    assert np.array_equal(again.to_array(), action.to_array())
    big = VlaAction.from_array([1.0, -1.0, 2.0, -3.0, *[0.0] * 7, 4.0])
    assert (big.dx, big.dy, big.dz) == (MAX_UAV_STEP_M, -MAX_UAV_STEP_M, MAX_UAV_STEP_M)
    assert big.dyaw == -MAX_YAW_STEP_RAD
    assert big.gripper == 1.0
    with pytest.raises(ConfigError, match="12 values"):
        VlaAction.from_array([0.0] * 11)
    with pytest.raises(ConfigError, match="finite"):
        VlaAction.from_array([math.nan] + [0.0] * 11)
    with pytest.raises(ValidationError):
        VlaAction(dx=0.2, joints=(0.0,) * 7, gripper=1.0)


def test_gripper_command_maps_linearly_to_the_opening() -> None:
    assert gripper_command_to_opening(1.0) == c.GRIPPER_OPEN
    assert gripper_command_to_opening(0.0) == c.GRIPPER_CLOSED
    assert gripper_command_to_opening(0.5) == pytest.approx(0.02)
    _, loop = _loop()
    for _ in range(10):
        apply_action(loop, VlaAction(joints=c.ARM_OBSERVE, gripper=0.5))
    assert loop.data.ctrl[loop.model.actuator(c.GRIPPER_ACTUATOR).id] == pytest.approx(0.02)
    assert gripper_opening(loop.model, loop.data) == pytest.approx(0.02, abs=0.003)


def test_joint_targets_are_reached_and_clipped_to_the_limits() -> None:
    _, loop = _loop()
    goal = np.array(c.ARM_OBSERVE) + np.array([0.2, -0.2, -0.2, 0.2, 0.2, -0.2, 0.2])
    for _ in range(10):  # 0.5 s
        apply_action(loop, VlaAction(joints=tuple(goal), gripper=1.0))
    assert np.max(np.abs(arm_qpos(loop.model, loop.data) - goal)) < 0.01
    low, high = joint_limits(loop.model)
    apply_action(loop, VlaAction(joints=(9.0, -9.0, 9.0, 9.0, 0.0, 9.0, 0.0), gripper=1.0))
    ctrl = [loop.data.ctrl[loop.model.actuator(a).id] for a in c.ARM_ACTUATORS]
    assert ctrl[:4] == pytest.approx([high[0], low[1], high[2], high[3]])
    assert ctrl[5] == pytest.approx(high[5])


@pytest.mark.parametrize("seed", [0, 1])
def test_uav_delta_moves_the_uav_in_the_body_frame(seed: int) -> None:
    def script(obs: VlaObservation) -> VlaAction | None:
        if obs.step_index >= 50:
            return None
        move = obs.step_index < 10  # 10 × (3 cm forward, 2 cm left), then hover
        return VlaAction(
            dx=0.03 if move else 0.0,
            dy=0.02 if move else 0.0,
            joints=c.ARM_OBSERVE,
            gripper=1.0,
        )

    episode = get_episode("standard_pick_place", seed)
    start = np.array(episode.uav_start.pos)
    loop, reason = _run_step(Recorder(script), seed)
    assert reason is None
    yaw = math.radians(episode.uav_start.yaw_deg)
    expected = start + np.array(
        [0.3 * math.cos(yaw) - 0.2 * math.sin(yaw), 0.3 * math.sin(yaw) + 0.2 * math.cos(yaw), 0.0]
    )
    assert np.linalg.norm(loop.uav_position() - expected) < 0.02
    assert abs(loop.uav_yaw_deg() - episode.uav_start.yaw_deg) < 1.0


def test_yaw_delta_turns_the_uav() -> None:
    def script(obs: VlaObservation) -> VlaAction | None:
        if obs.step_index >= 40:
            return None
        return VlaAction(dyaw=0.1 if obs.step_index < 5 else 0.0, joints=c.ARM_OBSERVE, gripper=1)

    episode = get_episode("standard_pick_place", 0)
    loop, _ = _run_step(Recorder(script))
    turned = (loop.uav_yaw_deg() - episode.uav_start.yaw_deg + 180) % 360 - 180
    assert turned == pytest.approx(math.degrees(0.5), abs=1.5)
    assert np.linalg.norm(loop.uav_position() - np.array(episode.uav_start.pos)) < 0.02


def test_a_policy_that_never_finishes_fails_the_step() -> None:
    policy = Recorder(lambda obs: VlaAction.holding(obs.proprio).to_array())  # array form
    loop, reason = _run_step(policy, max_steps=5)
    assert isinstance(reason, SkillFailure)
    assert reason.code is FailureCode.POLICY_TIMEOUT
    assert "within 5 control steps" in reason.detail
    assert len(policy.calls) == 5
    assert loop.time == pytest.approx(5 * c.CONTROL_DT)


def test_done_flag_ends_the_step_after_applying_the_action() -> None:
    policy = Recorder(lambda obs: VlaAction.holding(obs.proprio, done=obs.step_index == 2))
    loop, reason = _run_step(policy)
    assert reason is None
    assert len(policy.calls) == 3
    assert loop.time == pytest.approx(3 * c.CONTROL_DT)


def test_observation_carries_images_proprioception_and_the_step() -> None:
    episode, loop = _loop()
    policy = Recorder(lambda obs: None)
    skill = policy_skills(policy, views=("wrist", "uav"), render_size=16)(loop)["place"]
    step = ArmStep(object="yellow_basket", skill="place")
    assert skill(episode, step) is None
    ((seen, obs),) = policy.calls
    assert seen == step and obs.step == step and obs.step_index == 0
    assert obs.step_text == "place yellow_basket"
    assert obs.instruction == episode.instruction("explicit")
    assert list(obs.images) == ["wrist", "uav"]
    assert all(i.shape == (16, 16, 3) and i.dtype == np.uint8 for i in obs.images.values())
    assert np.allclose(obs.proprio.uav_pos, loop.uav_position())
    assert np.allclose(obs.proprio.joints, c.ARM_OBSERVE, atol=1e-6)
    assert obs.proprio.gripper == pytest.approx(c.GRIPPER_OPEN)
    proprio = obs.proprio.to_array()
    assert proprio.shape == (PROPRIO_SIZE,)
    assert Proprioception.from_array(proprio).joints == pytest.approx(obs.proprio.joints)
    assert set(obs.arrays()) == {"wrist", "uav", "proprio"}


def test_execute_plan_flies_uav_moves_and_hands_arm_steps_to_the_policy() -> None:
    episode = get_episode("standard_pick_place", 0)
    policy = Recorder(lambda obs: None if obs.step_index >= 3 else VlaAction.holding(obs.proprio))
    result = execute_plan(
        episode, episode.gt_plan, arm_skills=policy_skills(policy, views=("wrist",), render_size=8)
    )
    arm_steps = [s for s in episode.gt_plan if isinstance(s, ArmStep)]
    called = [step for step, _ in policy.calls]
    assert called == [s for s in arm_steps for _ in range(4)]  # 3 actions, then None
    assert [o.status for o in result.steps] == ["ok"] * len(episode.gt_plan)
    assert isinstance(episode.gt_plan[0], UavStep)
    first_arm = policy.calls[0][1]
    gt_pose = np.array(episode.gt_uav_poses[0].pos)
    assert np.linalg.norm(np.array(first_arm.proprio.uav_pos) - gt_pose) < 0.05
    assert result.goals == (False,)  # the policy only hovered: the goals judge the outcome
    assert not result.exec_success
    assert result.failure_reason is not None and "goal not met" in result.failure_reason
    assert result.failure_code is FailureCode.GOAL_NOT_MET


def test_an_unhandled_skill_fails_as_unavailable() -> None:
    episode = get_episode("standard_pick_place", 0)
    plan = [ArmStep(object="gray_cube", skill="pick")]
    result = execute_plan(
        episode, plan, arm_skills=policy_skills(lambda o, s: None, skills=("place",), views=())
    )
    assert result.steps[0].status == "failed"
    assert result.steps[0].reason is not None and "not available" in result.steps[0].reason
    assert result.steps[0].failure_code is FailureCode.UNKNOWN_SKILL


def test_held_object_follows_the_grasp() -> None:
    episode, loop = _loop()
    assert grasped_object(loop, episode) is None
    refs = StepReferences(episode, loop.model)
    execute_move(loop, refs, episode.uav_steps()[0], next_arm_step(episode.gt_plan, 0))
    assert default_skills(loop)["pick"](episode, PICK) is None
    assert grasped_object(loop, episode) == "gray_cube"
    loop.held = None
    keep_closed = Recorder(
        lambda obs: VlaAction(joints=obs.proprio.joints, gripper=0.0, done=obs.step_index == 1)
    )
    skill = policy_skills(keep_closed, views=())(loop)["pick"]
    assert skill(episode, PICK) is None
    assert loop.held == "gray_cube"


def test_the_documented_policy_example_runs(capsys: pytest.CaptureFixture[str]) -> None:
    (example, _) = re.findall(r"```python\n(.*?)```", DOCS.read_text(), re.S)
    exec(compile(example, str(DOCS), "exec"), {"__name__": "docs_example"})
    assert "[('UAV', 'ok'), ('ARM', 'ok'), ('ARM', 'ok')]" in capsys.readouterr().out
