"""The paper's 12-D low-level action (20 Hz) and how it drives the robot for one control period.

Order of the array form: ``dx, dy, dz, dyaw`` (the UAV deltas), ``q1..q7`` (absolute arm joint
targets, rad), ``gripper``. The UAV deltas move the position controller's setpoint, not the
body: ``dx`` forward, ``dy`` left, ``dz`` up in the UAV body frame (rotated by the current yaw
setpoint), ``dyaw`` counter-clockwise. Each is bounded per step, ±:data:`MAX_UAV_STEP_M` (0.05 m,
i.e. 1 m/s, the controller's speed limit) and ±:data:`MAX_YAW_STEP_RAD` (0.1 rad, 2 rad/s).
Joint targets are clipped to the model's joint limits when applied. The gripper command is in
[0, 1]: 1 fully open (:data:`~vlm_bench.sim.constants.GRIPPER_OPEN`, 0.04 m per finger), 0 closed,
linear in between.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray
from pydantic import ConfigDict, Field

from vlm_bench.errors import ConfigError
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import ARM_JOINTS, GRIPPER_CLOSED, GRIPPER_OPEN
from vlm_bench.sim.robot import set_arm_targets
from vlm_bench.types.base import FloatArray, Frozen
from vlm_bench.vla.observation import JointAngles, Proprioception

MAX_UAV_STEP_M = 0.05  # m per control step along each body axis
MAX_YAW_STEP_RAD = 0.1  # rad per control step
ACTION_SIZE = 12
ACTION_FIELDS = ("dx", "dy", "dz", "dyaw", *(f"q{i}" for i in range(1, 8)), "gripper")
"""Names of the entries of :meth:`VlaAction.to_array`, in order."""

_M = MAX_UAV_STEP_M
_YAW = MAX_YAW_STEP_RAD


class VlaAction(Frozen):
    """One 50 ms command: UAV setpoint deltas, arm joint targets and the gripper.

    Constructing one validates the bounds; :meth:`from_array` clips to them instead (for raw
    network outputs).
    """

    dx: float = Field(default=0.0, ge=-_M, le=_M, description="Setpoint move forward (m).")
    dy: float = Field(default=0.0, ge=-_M, le=_M, description="Setpoint move left (m).")
    dz: float = Field(default=0.0, ge=-_M, le=_M, description="Setpoint move up (m).")
    dyaw: float = Field(default=0.0, ge=-_YAW, le=_YAW, description="Heading change, CCW (rad).")
    joints: JointAngles = Field(description="Absolute targets of the 7 arm joints (rad).")
    gripper: float = Field(ge=0.0, le=1.0, description="1 = open, 0 = closed.")
    done: bool = Field(
        default=False, description="Apply this action, then end the ARM step (hierarchical API)."
    )

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    def to_array(self) -> NDArray[np.float32]:
        """The 12 values in :data:`ACTION_FIELDS` order (``done`` is not part of it)."""
        values = [self.dx, self.dy, self.dz, self.dyaw, *self.joints, self.gripper]
        return np.array(values, dtype=np.float32)

    @classmethod
    def from_array(
        cls, values: Sequence[float] | NDArray[np.floating], done: bool = False
    ) -> VlaAction:
        """An action from 12 values in :data:`ACTION_FIELDS` order, clipped to the bounds.

        Raises:
            ConfigError: Not 12 values, or a value is NaN or infinite.
        """
        v = np.asarray(values, dtype=np.float64).reshape(-1)
        if v.shape != (ACTION_SIZE,):
            raise ConfigError(f"an action has {ACTION_SIZE} values, got {v.size}")
        if not np.all(np.isfinite(v)):
            raise ConfigError(f"action values must be finite, got {v.tolist()}")
        low, high = action_bounds()
        v = np.clip(v, low, high)
        q = [float(x) for x in v[4:11]]
        return cls(
            dx=float(v[0]),
            dy=float(v[1]),
            dz=float(v[2]),
            dyaw=float(v[3]),
            joints=(q[0], q[1], q[2], q[3], q[4], q[5], q[6]),
            gripper=float(v[11]),
            done=done,
        )

    @classmethod
    def holding(cls, proprio: Proprioception, done: bool = False) -> VlaAction:
        """Hold still: no UAV deltas, the current joint angles and gripper opening as targets."""
        grip = (proprio.gripper - GRIPPER_CLOSED) / (GRIPPER_OPEN - GRIPPER_CLOSED)
        return cls(joints=proprio.joints, gripper=min(1.0, max(0.0, grip)), done=done)


def action_bounds(
    joint_low: Sequence[float] | FloatArray | None = None,
    joint_high: Sequence[float] | FloatArray | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Lower and upper bounds of the array form (joints unbounded unless limits are given)."""
    n = len(ARM_JOINTS)
    q_lo = [-math.inf] * n if joint_low is None else [float(x) for x in joint_low]
    q_hi = [math.inf] * n if joint_high is None else [float(x) for x in joint_high]
    lo = [-_M, -_M, -_M, -_YAW, *q_lo, 0.0]
    hi = [_M, _M, _M, _YAW, *q_hi, 1.0]
    return np.array(lo, dtype=np.float64), np.array(hi, dtype=np.float64)


def joint_limits(model: mujoco.MjModel) -> tuple[FloatArray, FloatArray]:
    """Lower and upper limits of the 7 arm joints (rad), read from the model."""
    ranges = np.array([model.joint(name).range for name in ARM_JOINTS], dtype=np.float64)
    return ranges[:, 0].copy(), ranges[:, 1].copy()


def gripper_command_to_opening(command: float) -> float:
    """Finger opening (m) of a gripper command in [0, 1] (clipped): 1 open, 0 closed."""
    command = min(1.0, max(0.0, float(command)))
    return GRIPPER_CLOSED + command * (GRIPPER_OPEN - GRIPPER_CLOSED)


def command_action(loop: SimLoop, action: VlaAction) -> None:
    """Write ``action`` to the UAV setpoint and the arm servos, without stepping."""
    ctrl = loop.controller
    yaw = ctrl.yaw_setpoint
    cos, sin = math.cos(yaw), math.sin(yaw)
    delta = np.array([cos * action.dx - sin * action.dy, sin * action.dx + cos * action.dy])
    ctrl.setpoint = ctrl.setpoint + np.array([delta[0], delta[1], action.dz])
    ctrl.yaw_setpoint = math.remainder(yaw + action.dyaw, 2 * math.pi)
    low, high = joint_limits(loop.model)
    q = np.clip(np.array(action.joints, dtype=np.float64), low, high)
    set_arm_targets(loop.model, loop.data, q, gripper_command_to_opening(action.gripper))


def apply_action(loop: SimLoop, action: VlaAction) -> None:
    """Command ``action`` and advance one 50 ms control period.

    Raises:
        SimulatorUnstable: The simulation blew up during the period.
    """
    command_action(loop, action)
    loop.control_step()
