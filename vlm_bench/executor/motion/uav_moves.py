"""UAV ``move`` steps (docs/design.md#moves): where a move stops, and flying it with the arm stowed.

Stopping rule, shared with the ground truth through :func:`~vlm_bench.rules.move_stop`:

* ``distance`` given: fly exactly that far (at most ``max_move``);
* horizontal, an ARM step follows: stop where the path first comes to the stand-off of the next
  ARM step's object (or at its closest approach), at most ``max_move``;
* vertical, an ARM step follows: stop at the operating altitude of that object's reference point
  (no travel if it lies the other way), at most ``max_move``;
* no ARM step follows (or its object is unknown): ``default_move``.

The flight moves the controller's setpoint along the straight path with a trapezoidal speed
profile bounded by the configured speed, then holds the end point until the UAV has settled.
The UAV is never placed: it flies under the controller, and contacts are real.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.joint_moves import joint_move
from vlm_bench.executor.references import Reference
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.rules import move_stop
from vlm_bench.sim.constants import ARM_STOW, CONTROL_DT
from vlm_bench.sim.robot import arm_qpos, gripper_target, set_arm_targets
from vlm_bench.types.base import FloatArray
from vlm_bench.types.execution import FlightConfig
from vlm_bench.types.geometry import APPROACH, ApproachGeometry
from vlm_bench.types.plan import Direction, UavStep

STOWED_TOL = 0.02  # rad: the arm counts as stowed when every joint is this close
TURN_RATE = 0.8  # rad/s the heading setpoint turns at (a half turn in 4 s, an object in hand)
TURN_TOL = math.radians(1.0)  # heading error that ends a turn


def move_target(
    start: FloatArray,
    base_yaw_deg: float,
    step: UavStep,
    ref: Reference | None,
    geometry: ApproachGeometry = APPROACH,
) -> FloatArray:
    """End point (m, world) of ``step`` flown from ``start`` (see the module docstring).

    Args:
        start: UAV position at the start of the move.
        base_yaw_deg: UAV heading that defines the body frame (its yaw at episode start).
        step: The move.
        ref: Reference of the next ARM step's object, or ``None`` if there is none.
        geometry: Approach geometry (stand-offs, operating height, move lengths).
    """
    end = np.array(start, dtype=np.float64)
    if step.direction in (Direction.UP, Direction.DOWN):
        sign = 1.0 if step.direction is Direction.UP else -1.0
        if step.distance is not None:
            travel = step.distance
        elif ref is not None:
            travel = max(0.0, sign * (geometry.operating_altitude(ref.z) - start[2]))
        else:
            travel = geometry.default_move
        end[2] += sign * min(travel, geometry.max_move)
        return end
    heading = base_yaw_deg + step.direction.angle_deg
    ux, uy = math.cos(math.radians(heading)), math.sin(math.radians(heading))
    if step.distance is None and ref is not None:
        x, y = move_stop(
            (float(start[0]), float(start[1])),
            heading,
            (ref.x, ref.y),
            ref.standoff,
            geometry.max_move,
        )
        end[0], end[1] = x, y
        return end
    travel = min(
        step.distance if step.distance is not None else geometry.default_move, geometry.max_move
    )
    end[0] += ux * travel
    end[1] += uy * travel
    return end


def stow_arm(loop: SimLoop, flight: FlightConfig) -> None:
    """Move the arm to ``ARM_STOW`` along a smooth (minimum-jerk) joint trajectory."""
    goal = np.asarray(ARM_STOW, dtype=np.float64)
    if float(np.max(np.abs(arm_qpos(loop.model, loop.data) - goal))) < STOWED_TOL:
        set_arm_targets(loop.model, loop.data, goal, gripper_target(loop.model, loop.data))
        return
    joint_move(loop, goal, flight.stow_s)


def fly_to(loop: SimLoop, target: FloatArray, flight: FlightConfig) -> None:
    """Slide the setpoint from the current one to ``target`` and wait for the UAV to settle."""
    ctrl = loop.controller
    start = np.array(ctrl.setpoint, dtype=np.float64)
    yaw_deg = math.degrees(ctrl.yaw_setpoint)
    length = float(np.linalg.norm(target - start))
    if length > 1e-9:
        direction = (target - start) / length
        for s in _trapezoid(length, flight.speed, flight.accel):
            ctrl.set_setpoint(start + direction * s, yaw_deg)
            loop.control_step()
    ctrl.set_setpoint(target, yaw_deg)
    _settle(
        loop,
        flight,
        lambda: float(np.linalg.norm(loop.uav_position() - target)) < flight.settle_tol,
    )


def turn_to(loop: SimLoop, turn: float, flight: FlightConfig) -> None:
    """Turn the UAV's heading setpoint by ``turn`` (rad, CCW) at :data:`TURN_RATE`, holding
    its position, and wait for the heading to settle (as :func:`fly_to` waits for the
    position)."""
    ctrl = loop.controller
    start = ctrl.yaw_setpoint
    n = max(1, math.ceil(abs(turn) / (TURN_RATE * CONTROL_DT)))
    for i in range(1, n + 1):
        ctrl.set_setpoint(ctrl.setpoint, math.degrees(start + turn * i / n))
        loop.control_step()

    def on_heading() -> bool:
        yaw = math.radians(loop.uav_yaw_deg())
        return abs(math.remainder(ctrl.yaw_setpoint - yaw, 2 * math.pi)) < TURN_TOL

    _settle(loop, flight, on_heading)


def shift_base(loop: SimLoop, move: BaseMove) -> None:
    """Fly the UAV's setpoint by ``move`` and let it settle, turning its heading at the move's
    higher end (before a descent, after a climb or level move)."""
    flight = loop.config.flight
    if move.yaw and move.turns_first:
        turn_to(loop, move.yaw, flight)
    if np.any(move.xyz):
        fly_to(loop, np.array(loop.controller.setpoint) + move.xyz, flight)
    if move.yaw and not move.turns_first:
        turn_to(loop, move.yaw, flight)


def carry(loop: SimLoop, delta: FloatArray, speed: float) -> None:
    """Fly the UAV by ``delta`` (m, world) at ``speed`` with the arm's targets held, so the
    hand moves with the base (pushing, or pulling a drawer, farther than the arm reaches)."""
    flight = loop.config.flight
    slow = flight.model_copy(update={"speed": min(speed, flight.speed), "accel": 0.25})
    target = np.array(loop.controller.setpoint) + np.asarray(delta)
    fly_to(loop, target, slow)


def _settle(loop: SimLoop, flight: FlightConfig, there: Callable[[], bool]) -> None:
    """Hold the setpoint for at least ``flight.settle_min_s`` and at most
    ``flight.settle_max_s``, until the UAV is ``there`` and slower than ``flight.settle_speed``."""
    hold_min = round(flight.settle_min_s / CONTROL_DT)
    for i in range(round(flight.settle_max_s / CONTROL_DT)):
        loop.control_step()
        if i + 1 >= hold_min and there() and loop.uav_speed() < flight.settle_speed:
            return


def _trapezoid(length: float, speed: float, accel: float) -> list[float]:
    """Arc-length samples every control period of a trapezoidal speed profile."""
    t_acc = speed / accel
    if accel * t_acc * t_acc >= length:  # triangular: never reaches cruise speed
        t_acc = math.sqrt(length / accel)
        speed = accel * t_acc
    total = 2 * t_acc + (length - accel * t_acc * t_acc) / speed
    n = max(1, math.ceil(total / CONTROL_DT))
    out = []
    for i in range(1, n + 1):
        t = min(i * CONTROL_DT, total)
        if t < t_acc:
            s = 0.5 * accel * t * t
        elif t > total - t_acc:
            s = length - 0.5 * accel * (total - t) ** 2
        else:
            s = 0.5 * accel * t_acc * t_acc + speed * (t - t_acc)
        out.append(min(s, length))
    return out
