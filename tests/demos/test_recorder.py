"""The recorder's action is the one that re-issues the executor's command: applied by the gym
environment's ``command_action`` from the previous command, it gives the same setpoint,
heading, joint targets and gripper (a replay issues what the execution issued)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlm_bench.episodes import get_episode
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.executor.step_execution import episode_scene
from vlm_bench.sim.constants import GRIPPER_OPEN
from vlm_bench.sim.robot import set_arm_targets
from vlm_bench.types.execution import ExecutorConfig
from vlm_bench.vla.action import VlaAction, command_action, joint_limits
from vlm_bench.vla.demos.recorder import Command, action_between, within_bounds


@pytest.fixture(scope="module")
def loop() -> SimLoop:
    episode = get_episode("standard_pick_place", 0)
    return SimLoop(episode_scene(episode, ExecutorConfig()))


step = st.floats(-0.035, 0.035)


@settings(max_examples=40, deadline=None)
@given(
    yaw0=st.floats(-math.pi, math.pi),
    move=st.tuples(step, step, step),
    turn=st.floats(-0.09, 0.09),
    grip=st.floats(0.0, 1.0),
    fraction=st.floats(0.0, 1.0),
)
def test_the_recorded_action_reissues_the_command(
    loop: SimLoop,
    yaw0: float,
    move: tuple[float, float, float],
    turn: float,
    grip: float,
    fraction: float,
) -> None:
    ctrl = loop.controller
    ctrl.set_setpoint([0.3, -0.2, 1.4], math.degrees(yaw0))
    low, high = joint_limits(loop.model)
    q0, q1 = low + 0.3 * (high - low), low + fraction * (high - low)
    set_arm_targets(loop.model, loop.data, q0, 0.0)
    before = Command.read(loop)
    # the executor's next command, written as the skills write it
    ctrl.set_setpoint(before.setpoint + np.array(move) / math.sqrt(3), math.degrees(yaw0 + turn))
    set_arm_targets(loop.model, loop.data, q1, grip * GRIPPER_OPEN)
    after = Command.read(loop)
    action = action_between(before, after)
    assert within_bounds(action)
    # back to the previous command, then re-issue it from the recorded action
    ctrl.set_setpoint(before.setpoint, math.degrees(before.yaw))
    set_arm_targets(loop.model, loop.data, before.joints, before.gripper)
    command_action(loop, VlaAction.from_array(action))
    again = Command.read(loop)
    assert np.allclose(again.setpoint, after.setpoint, atol=1e-12)
    assert abs(math.remainder(again.yaw - after.yaw, 2 * math.pi)) < 1e-12
    assert np.allclose(again.joints, after.joints, atol=1e-12)
    assert again.gripper == pytest.approx(after.gripper, abs=1e-12)


def test_a_setpoint_jump_is_out_of_the_action_space() -> None:
    before = Command(np.zeros(3), 0.0, np.zeros(7), 0.0)
    far = Command(np.array([0.2, 0.0, 0.0]), 0.0, np.zeros(7), 0.0)
    spin = Command(np.zeros(3), 0.5, np.zeros(7), 0.0)
    assert not within_bounds(action_between(before, far))
    assert not within_bounds(action_between(before, spin))
    assert within_bounds(action_between(before, before))
