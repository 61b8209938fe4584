"""Records a scripted execution as (observation, action) pairs at the control rate (20 Hz).

The scripted skills drive the robot by moving the UAV controller's setpoint and heading and by
setting the arm's servo targets, then advancing one 50 ms control period. The
:class:`DemoRecorder`, a loop observer, reads those commands after every period and writes
them as the gym environment's 12-D action (:mod:`vlm_bench.vla.action`): the setpoint's move
in the body frame of the previous heading setpoint, the heading change, the joint targets and
the gripper command. Applying the recorded actions with :func:`~vlm_bench.vla.action.apply_action`
therefore issues the same commands, period by period: a replay reproduces the execution.
Each pair holds the observation *before* its action (rendered after the previous period).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import ARM_ACTUATORS, GRIPPER_ACTUATOR, GRIPPER_CLOSED, GRIPPER_OPEN
from vlm_bench.vla.action import ACTION_SIZE, MAX_UAV_STEP_M, MAX_YAW_STEP_RAD
from vlm_bench.vla.observation import ObservationRenderer, read_proprioception

BOUND_SLACK = 1e-6  # numerical slack on the action bounds (m, rad)


@dataclass(frozen=True)
class Command:
    """What the skills command during a control period."""

    setpoint: NDArray[np.float64]
    yaw: float
    joints: NDArray[np.float64]
    gripper: float

    @classmethod
    def read(cls, loop: SimLoop) -> Command:
        """The loop's current setpoint, heading setpoint, joint and gripper targets."""
        model, ctrl = loop.model, loop.data.ctrl
        joints = np.array([ctrl[model.actuator(n).id] for n in ARM_ACTUATORS], dtype=np.float64)
        return cls(
            setpoint=np.array(loop.controller.setpoint, dtype=np.float64),
            yaw=float(loop.controller.yaw_setpoint),
            joints=joints,
            gripper=float(ctrl[model.actuator(GRIPPER_ACTUATOR).id]),
        )


def action_between(before: Command, after: Command) -> NDArray[np.float64]:
    """The 12-D action that turns command ``before`` into ``after`` (ACTION_FIELDS order)."""
    move = after.setpoint - before.setpoint
    cos, sin = math.cos(before.yaw), math.sin(before.yaw)
    dx = cos * move[0] + sin * move[1]  # world move in the body frame of the heading setpoint
    dy = -sin * move[0] + cos * move[1]
    dyaw = math.remainder(after.yaw - before.yaw, 2 * math.pi)
    grip = (after.gripper - GRIPPER_CLOSED) / (GRIPPER_OPEN - GRIPPER_CLOSED)
    values = [dx, dy, float(move[2]), dyaw, *after.joints.tolist(), min(1.0, max(0.0, grip))]
    return np.array(values, dtype=np.float64).reshape(ACTION_SIZE)


def within_bounds(action: NDArray[np.float64]) -> bool:
    """Whether the UAV deltas of ``action`` fit the action space (a replay would clip them)."""
    uav = np.abs(action[:3]).max() <= MAX_UAV_STEP_M + BOUND_SLACK
    return bool(uav and abs(action[3]) <= MAX_YAW_STEP_RAD + BOUND_SLACK)


@dataclass
class DemoFrames:
    """The recorded frames of one execution, in time order."""

    views: tuple[str, ...]
    states: list[NDArray[np.float32]] = field(default_factory=list)
    actions: list[NDArray[np.float32]] = field(default_factory=list)
    images: dict[str, list[NDArray[np.uint8]]] = field(default_factory=dict)
    arm_steps: list[int] = field(default_factory=list)
    """Per frame: the index (in the plan) of the ARM step it belongs to, -1 in a UAV move."""
    out_of_bounds: int = 0
    """Frames whose UAV deltas exceed the action space's bounds."""

    def __len__(self) -> int:
        return len(self.actions)


class DemoRecorder:
    """A loop observer recording every control period (module doc).

    Args:
        loop: The loop to record, before its first control step.
        observer: Renders the images of each observation.
    """

    def __init__(self, loop: SimLoop, observer: ObservationRenderer) -> None:
        self.observer = observer
        self.frames = DemoFrames(views=observer.config.views)
        self.frames.images = {v: [] for v in self.frames.views}
        self.arm_step = -1
        """The plan index of the ARM step running now (-1: none); set by the skills' wrapper."""
        self._command = Command.read(loop)
        self._pending = self._observe(loop)

    def _observe(self, loop: SimLoop) -> tuple[NDArray[np.float32], dict[str, NDArray[np.uint8]]]:
        state = read_proprioception(loop).to_array()
        return state, self.observer.images(loop)

    def __call__(self, loop: SimLoop) -> None:
        command = Command.read(loop)
        action = action_between(self._command, command)
        frames = self.frames
        frames.out_of_bounds += not within_bounds(action)
        state, images = self._pending
        frames.states.append(state)
        frames.actions.append(action.astype(np.float32))
        for view in frames.views:
            frames.images[view].append(images[view])
        frames.arm_steps.append(self.arm_step)
        self._command = command
        self._pending = self._observe(loop)
