"""Arm motions shared by the skills: minimum-jerk joint moves and holds at 20 Hz."""

from __future__ import annotations

import numpy as np

from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import ARM_ACTUATORS, CONTROL_DT
from vlm_bench.sim.robot import arm_qpos, gripper_target, set_arm_targets
from vlm_bench.types.base import FloatArray

JOINT_SPEED = 0.8  # rad/s, mean over a joint move: faster swings of the 18 kg arm shove the UAV
HELD_JOINT_SPEED = 0.4  # rad/s, holding an object: slow enough that one held off its centre of
# mass does not swing loose


def min_jerk(s: float) -> float:
    """Minimum-jerk progress (0 → 1) at normalised time ``s`` in [0, 1]."""
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


def joint_move(
    loop: SimLoop,
    goal: FloatArray,
    seconds: float,
    gripper: float | None = None,
    speed: float = JOINT_SPEED,
) -> None:
    """Servo the arm from where it is to ``goal`` along a minimum-jerk joint trajectory taking
    ``seconds``, or longer for a wide swing (mean ``speed``, rad/s); the gripper keeps its
    current command unless ``gripper`` is given."""
    q0 = arm_qpos(loop.model, loop.data)
    grip = gripper_target(loop.model, loop.data) if gripper is None else gripper
    seconds = max(seconds, float(np.max(np.abs(goal - q0))) / speed)
    n = max(1, round(seconds / CONTROL_DT))
    for i in range(1, n + 1):
        set_arm_targets(loop.model, loop.data, q0 + (goal - q0) * min_jerk(i / n), grip)
        loop.control_step()


def hold_with_gripper(loop: SimLoop, seconds: float, gripper: float) -> None:
    """Keep the arm's targets, command the gripper to ``gripper`` and wait ``seconds``."""
    targets = np.array([loop.data.ctrl[loop.model.actuator(a).id] for a in ARM_ACTUATORS])
    set_arm_targets(loop.model, loop.data, targets, gripper)
    loop.hold(seconds)
