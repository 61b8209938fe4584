"""The aerial manipulator: the quad-X UAV with the Panda hanging under it, and arm helpers.

Link 0 of the arm sits :attr:`~vlm_bench.types.geometry.ApproachGeometry.arm_base_below_uav`
below the UAV origin with its z axis pointing down (the arm hangs inverted); link 0's +x is the
UAV's front. Joints and actuators are always addressed by name: actuators of attached specs are
ordered first, so indices are not stable across scenes.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.errors import ConfigError
from vlm_bench.sim import constants as c
from vlm_bench.sim.panda import add_panda
from vlm_bench.sim.uav import add_uav
from vlm_bench.types.episode import UavPose
from vlm_bench.types.geometry import APPROACH

JointVector = Sequence[float] | NDArray[np.float64]
IMPRATIO = 10.0  # frictional-to-normal constraint impedance ratio: firm, non-creeping grasps
ARM_MOUNT_QUAT = (0.0, 1.0, 0.0, 0.0)  # 180° about x: link 0's z points down, x stays forward


def add_aerial_manipulator(spec: mujoco.MjSpec, start: UavPose) -> None:
    """Add the UAV with the Panda mounted under it to ``spec.worldbody`` at ``start``.

    Also sets two scene-wide solver options the robot needs: the ``implicitfast`` integrator (the
    arm's stiff servos, kv up to 450 N·m·s/rad on 0.1 kg·m² armature, are unstable with explicit
    Euler at the physics step) and elliptic friction cones with ``impratio`` 10 (with the default
    pyramidal cones a held 0.3 kg cube creeps out of the fingers at ~2 mm/s; with these,
    ~0.1 mm/s).

    Args:
        spec: Scene spec to add the robot to.
        start: UAV body position (m) and heading (deg, CCW from world +x; UAV +x is its front).
    """
    uav = add_uav(spec, start)
    add_panda(spec, uav, (0.0, 0.0, -APPROACH.arm_base_below_uav), ARM_MOUNT_QUAT)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = IMPRATIO


def _check_pose(q: JointVector, gripper: float) -> tuple[NDArray[np.float64], float]:
    if len(q) != len(c.ARM_JOINTS):
        raise ConfigError(f"arm pose needs {len(c.ARM_JOINTS)} joint angles, got {len(q)}")
    return np.asarray(q, dtype=np.float64), min(max(float(gripper), 0.0), c.GRIPPER_OPEN)


def set_arm_qpos(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    q: JointVector,
    gripper: float,
) -> None:
    """Put the arm at joint angles ``q`` (rad) and each finger at ``gripper`` (m), at rest.

    Sets positions and zeroes the velocities of the 7 arm joints and 2 finger joints (``gripper``
    clipped to ``[0, GRIPPER_OPEN]``), then runs ``mj_forward`` so derived quantities (site
    poses, contacts) match. Servo targets are left alone: call :func:`set_arm_targets` too so the
    servos hold the pose.

    Raises:
        ConfigError: ``q`` does not have 7 entries.
    """
    angles, gripper = _check_pose(q, gripper)
    for name, value in zip(c.ARM_JOINTS, angles, strict=True):
        _set_joint(model, data, name, float(value))
    for name in c.FINGER_JOINTS:
        _set_joint(model, data, name, gripper)
    mujoco.mj_forward(model, data)


def _set_joint(model: mujoco.MjModel, data: mujoco.MjData, name: str, value: float) -> None:
    joint = model.joint(name)
    data.qpos[joint.qposadr[0]] = value
    data.qvel[joint.dofadr[0]] = 0.0


def set_arm_targets(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    q: JointVector,
    gripper: float,
) -> None:
    """Set the servo targets: joint angles ``q`` (rad) and finger opening ``gripper`` (m each).

    ``gripper`` is the gripper actuator's control: the opening of each finger, from ``0``
    (closed) to :data:`~vlm_bench.sim.constants.GRIPPER_OPEN` (0.04 m, 8 cm between pads);
    values outside are clipped. Joint targets outside the joint limits are clipped by the
    actuators' control ranges.

    Raises:
        ConfigError: ``q`` does not have 7 entries.
    """
    angles, gripper = _check_pose(q, gripper)
    for name, value in zip(c.ARM_ACTUATORS, angles, strict=True):
        data.ctrl[model.actuator(name).id] = float(value)
    data.ctrl[model.actuator(c.GRIPPER_ACTUATOR).id] = gripper


def arm_qpos(model: mujoco.MjModel, data: mujoco.MjData) -> NDArray[np.float64]:
    """Current angles (rad) of the 7 arm joints, in joint order."""
    return np.array([data.qpos[model.joint(name).qposadr[0]] for name in c.ARM_JOINTS])


def gripper_opening(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """Current mean finger opening (m per finger)."""
    return float(np.mean([data.qpos[model.joint(n).qposadr[0]] for n in c.FINGER_JOINTS]))


def gripper_target(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """The gripper actuator's current command (m per finger; 0 = squeeze closed)."""
    return float(data.ctrl[model.actuator(c.GRIPPER_ACTUATOR).id])


def robot_body_ids(model: mujoco.MjModel) -> list[int]:
    """Ids of the UAV body and every body under it (arm, hand, fingers)."""
    root = model.body(c.UAV_BODY).id
    ids: list[int] = []
    for body in range(model.nbody):
        walk = body
        while walk > 0 and walk != root:
            walk = int(model.body_parentid[walk])
        if walk == root:
            ids.append(body)
    return ids


def robot_geom_ids(model: mujoco.MjModel) -> list[int]:
    """Ids of all geoms on the robot (for telling robot contacts from the world's)."""
    bodies = set(robot_body_ids(model))
    return [g for g in range(model.ngeom) if int(model.geom_bodyid[g]) in bodies]
