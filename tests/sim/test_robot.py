"""The aerial manipulator: names, Panda kinematics, hover, disturbance recovery, gusts, gripper."""

from __future__ import annotations

import math
from collections.abc import Callable

import mujoco
import numpy as np
import pytest
from numpy.typing import NDArray

from vlm_bench.sim import constants as c
from vlm_bench.sim.panda import flange_transform
from vlm_bench.sim.robot import (
    add_aerial_manipulator,
    arm_qpos,
    gripper_opening,
    robot_geom_ids,
    set_arm_qpos,
    set_arm_targets,
)
from vlm_bench.sim.uav_control import GustConfig, UavController
from vlm_bench.types.episode import UavPose

START = (0.0, 0.0, 1.5)
# Franka's published joint limits (rad).
PUBLISHED_LIMITS = [
    (-2.8973, 2.8973),
    (-1.7628, 1.7628),
    (-2.8973, 2.8973),
    (-3.0718, -0.0698),
    (-2.8973, 2.8973),
    (-0.0175, 3.7525),
    (-2.8973, 2.8973),
]
WORK_POSE = (0.0, 0.3, 0.0, -2.2, 0.0, 1.0, 0.785)
# Hand pointing straight down 0.62 m below and 0.42 m ahead of the UAV, elbow above the hand.
GRASP_POSE = (-1.5, -1.76, 1.6, -2.54, -1.44, 1.71, 2.8)


def build(
    yaw_deg: float = 0.0, extra: Callable[[mujoco.MjSpec], None] | None = None
) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    spec.option.timestep = c.PHYSICS_DT
    spec.worldbody.add_geom(name=c.FLOOR_GEOM, type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 5, 0.1])
    add_aerial_manipulator(spec, UavPose(pos=START, yaw_deg=yaw_deg))
    if extra is not None:
        extra(spec)
    model = spec.compile()
    data = mujoco.MjData(model)
    set_arm_qpos(model, data, c.ARM_STOW, c.GRIPPER_OPEN)
    set_arm_targets(model, data, c.ARM_STOW, c.GRIPPER_OPEN)
    return model, data


def simulate(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    controller: UavController,
    seconds: float,
    before_step: Callable[[float], None] | None = None,
) -> NDArray[np.float64]:
    """Step with the controller; returns the UAV position after every step."""
    steps = round(seconds / c.PHYSICS_DT)
    trace = np.empty((steps, 3))
    for k in range(steps):
        if before_step is not None:
            before_step(k * c.PHYSICS_DT)
        controller.apply(data)
        mujoco.mj_step(model, data)
        trace[k] = data.body(c.UAV_BODY).xpos
    return trace


def robot_self_contacts(model: mujoco.MjModel, data: mujoco.MjData) -> list[tuple[str, str]]:
    robot = set(robot_geom_ids(model))
    pairs = []
    for con in data.contact[: data.ncon]:
        if con.geom1 in robot and con.geom2 in robot:
            b1, b2 = model.geom_bodyid[con.geom1], model.geom_bodyid[con.geom2]
            pairs.append((model.body(b1).name, model.body(b2).name))
    return pairs


def dh_flange(q: list[float]) -> NDArray[np.float64]:
    """Reference Craig-DH forward kinematics of the Panda (flange in link 0's frame)."""
    a = [0, 0, 0, 0.0825, -0.0825, 0, 0.088, 0]
    d = [0.333, 0, 0.316, 0, 0.384, 0, 0, 0.107]
    alpha = [0, -math.pi / 2, math.pi / 2, math.pi / 2, -math.pi / 2, math.pi / 2, math.pi / 2, 0]
    pose = np.eye(4)
    for i, theta in enumerate([*q, 0.0]):
        rot_x = np.array(
            [
                [1, 0, 0, a[i]],
                [0, math.cos(alpha[i]), -math.sin(alpha[i]), 0],
                [0, math.sin(alpha[i]), math.cos(alpha[i]), 0],
                [0, 0, 0, 1],
            ]
        )
        rot_z = np.array(
            [
                [math.cos(theta), -math.sin(theta), 0, 0],
                [math.sin(theta), math.cos(theta), 0, 0],
                [0, 0, 1, d[i]],
                [0, 0, 0, 1],
            ]
        )
        pose = pose @ rot_x @ rot_z
    return pose


def test_scene_compiles_with_named_parts() -> None:
    model, _ = build()
    for name in (*c.ARM_LINKS, c.HAND_BODY, c.LEFT_FINGER_BODY, c.RIGHT_FINGER_BODY, c.UAV_BODY):
        model.body(name)
    for name in (*c.ARM_ACTUATORS, c.GRIPPER_ACTUATOR):
        model.actuator(name)
    for name in (c.CAM_UAV, c.CAM_WRIST):
        model.camera(name)
    for name in (c.TCP_SITE, c.UAV_SITE):
        model.site(name)
    assert model.joint(c.UAV_FREEJOINT).type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert [model.geom(f"{c.ROTOR_GEOM_PREFIX}{k}").contype[0] for k in range(4)] == [1] * 4
    assert model.nu == 8


def test_arm_joints_have_published_limits() -> None:
    model, _ = build()
    for name, limits in zip(c.ARM_JOINTS, PUBLISHED_LIMITS, strict=True):
        joint = model.joint(name)
        assert joint.type[0] == mujoco.mjtJoint.mjJNT_HINGE
        np.testing.assert_allclose(joint.range, limits)
    for name in c.FINGER_JOINTS:
        np.testing.assert_allclose(model.joint(name).range, (0.0, c.GRIPPER_OPEN))


def test_arm_hangs_inverted_under_the_uav() -> None:
    _, data = build(yaw_deg=90.0)
    link0 = data.body(c.ARM_BASE_BODY)
    np.testing.assert_allclose(link0.xpos, np.add(START, (0, 0, -0.10)), atol=1e-9)
    rot = link0.xmat.reshape(3, 3)
    np.testing.assert_allclose(rot[:, 2], (0, 0, -1), atol=1e-9)  # z points down
    np.testing.assert_allclose(rot[:, 0], (0, 1, 0), atol=1e-9)  # x = UAV front (yaw 90°)


@pytest.mark.parametrize(
    "q",
    [
        [0.0] * 7,
        list(c.ARM_HOME),
        [0.5, -0.8, 1.2, -1.5, -0.7, 2.1, -1.0],
        [-2.0, 1.2, -0.4, -2.8, 2.5, 0.3, 2.0],
    ],
)
def test_forward_kinematics_match_dh(q: list[float]) -> None:
    model, data = build()
    set_arm_qpos(model, data, q, c.GRIPPER_OPEN)
    base = data.body(c.ARM_BASE_BODY)
    base_rot = base.xmat.reshape(3, 3)
    hand = data.body(c.HAND_BODY)
    flange_pos = base_rot.T @ (hand.xpos - base.xpos)
    # The hand is the flange turned -45° about its axis.
    hand_rot = base_rot.T @ hand.xmat.reshape(3, 3)
    turn = np.array([[1, -1, 0], [1, 1, 0], [0, 0, math.sqrt(2)]]) / math.sqrt(2)
    expected = dh_flange(q)
    np.testing.assert_allclose(flange_pos, expected[:3, 3], atol=1e-9)
    np.testing.assert_allclose(hand_rot @ turn, expected[:3, :3], atol=1e-9)
    np.testing.assert_allclose(flange_transform(q), expected, atol=1e-12)


def test_hover_holds_setpoint_within_1cm() -> None:
    model, data = build()
    controller = UavController(model, data)
    setpoint = np.array([0.05, -0.03, 1.52])  # start 6 cm off, so the loop has work to do
    controller.set_setpoint(setpoint, 10.0)
    simulate(model, data, controller, 1.5)
    trace = simulate(model, data, controller, 2.0)
    max_error = float(np.linalg.norm(trace - setpoint, axis=1).max())
    print(f"hover: max position error over 2 s after settling = {max_error * 1000:.3f} mm")
    assert max_error < 0.01
    rot = data.body(c.UAV_BODY).xmat.reshape(3, 3)
    assert math.degrees(math.atan2(rot[1, 0], rot[0, 0])) == pytest.approx(10.0, abs=0.2)
    assert rot[2, 2] > math.cos(math.radians(0.5))  # level
    np.testing.assert_allclose(arm_qpos(model, data), c.ARM_STOW, atol=1e-3)


def test_arm_swing_disturbs_base_and_controller_recovers() -> None:
    model, data = build()
    controller = UavController(model, data)
    setpoint = np.array(START)
    stow, work = np.array(c.ARM_STOW), np.array(WORK_POSE)

    def unfold(t: float) -> None:
        s = min(1.0, t / 1.5)
        set_arm_targets(model, data, list((1 - s) * stow + s * work), c.GRIPPER_OPEN)

    def swing(t: float) -> None:  # joint speeds up to ~2 rad/s, the Panda's rated speed
        q = work.copy()
        q[0] += 0.8 * math.sin(2 * math.pi * 0.4 * t)
        q[1] += 0.5 * math.sin(2 * math.pi * 0.6 * t)
        set_arm_targets(model, data, list(q), c.GRIPPER_OPEN)

    simulate(model, data, controller, 2.0, unfold)
    during = simulate(model, data, controller, 2.5, swing)
    after = simulate(model, data, controller, 4.0)
    displacement = float(np.linalg.norm(during - setpoint, axis=1).max())
    errors = np.linalg.norm(after - setpoint, axis=1)
    outside = np.flatnonzero(errors >= 0.01)
    recovery = (outside[-1] + 1) * c.PHYSICS_DT if outside.size else 0.0
    print(
        f"swing: max base displacement {displacement * 1000:.1f} mm; "
        f"back within 1 cm {recovery:.2f} s after the swing; final error {errors[-1] * 1000:.3f} mm"
    )
    assert displacement > 0.02  # measured 33 mm
    assert recovery < 3.0
    assert errors[-1] < 0.002
    # The arm's weight, held off-centre, is carried level: lift goes through the subtree's COM.
    assert data.body(c.UAV_BODY).xmat[8] > math.cos(math.radians(0.5))


def test_gusts_are_reproducible_by_seed() -> None:
    def trajectory(gust: GustConfig | None) -> NDArray[np.float64]:
        model, data = build()
        controller = UavController(model, data, gust=gust)
        return simulate(model, data, controller, 1.0)

    calm = trajectory(None)
    first = trajectory(GustConfig(force_std=20.0, torque_std=2.0, seed=3))
    again = trajectory(GustConfig(force_std=20.0, torque_std=2.0, seed=3))
    other = trajectory(GustConfig(force_std=20.0, torque_std=2.0, seed=4))
    np.testing.assert_array_equal(first, again)
    assert np.abs(first - calm).max() > 0.005
    assert np.abs(first - other).max() > 0.005


def test_stow_pose_is_compact_and_contact_free() -> None:
    model, data = build()
    controller = UavController(model, data)
    assert robot_self_contacts(model, data) == []
    simulate(model, data, controller, 0.5)
    assert robot_self_contacts(model, data) == []
    depth, radius = arm_extent(model, data)
    print(f"stow: arm reaches {depth:.3f} m below the UAV origin, {radius:.3f} m out from its axis")
    assert depth < 0.52  # the shoulder housing, 0.43 m down plus its radius, is the lowest part
    assert radius < 0.41


def arm_extent(model: mujoco.MjModel, data: mujoco.MjData) -> tuple[float, float]:
    """Depth below the UAV origin and distance from its vertical axis of the arm's geom boxes."""
    uav_id = model.body(c.UAV_BODY).id
    uav = data.xpos[uav_id]
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    depth = radius = 0.0
    for g in robot_geom_ids(model):
        if model.geom_bodyid[g] == uav_id:
            continue
        centre, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
        corners = (centre + signs * half) @ data.geom_xmat[g].reshape(3, 3).T + data.geom_xpos[g]
        depth = max(depth, float((uav[2] - corners[:, 2]).max()))
        radius = max(radius, float(np.hypot(*(corners[:, :2] - uav[:2]).T).max()))
    return depth, radius


def test_yaw_tracking_and_speed_bound() -> None:
    model, data = build()
    controller = UavController(model, data)
    controller.set_setpoint((1.5, -1.0, 1.8), 120.0)
    speeds = []
    simulate(model, data, controller, 4.0, lambda t: speeds.append(np.linalg.norm(data.qvel[:3])))
    rot = data.body(c.UAV_BODY).xmat.reshape(3, 3)
    assert math.degrees(math.atan2(rot[1, 0], rot[0, 0])) == pytest.approx(120.0, abs=0.5)
    np.testing.assert_allclose(data.body(c.UAV_BODY).xpos, (1.5, -1.0, 1.8), atol=0.01)
    assert max(speeds) < 1.1 * controller.gains.max_speed


def test_gripper_opens_and_closes() -> None:
    model, data = build()
    controller = UavController(model, data)
    set_arm_targets(model, data, c.ARM_STOW, c.GRIPPER_CLOSED)
    simulate(model, data, controller, 0.5)
    assert gripper_opening(model, data) < 0.001
    set_arm_targets(model, data, c.ARM_STOW, c.GRIPPER_OPEN)
    simulate(model, data, controller, 0.5)
    assert gripper_opening(model, data) > c.GRIPPER_OPEN - 0.001
    left, right = (data.body(n).xpos for n in (c.LEFT_FINGER_BODY, c.RIGHT_FINGER_BODY))
    assert float(np.linalg.norm(left - right)) == pytest.approx(2 * c.GRIPPER_OPEN, abs=0.002)


def test_fingers_hold_a_cube_while_the_uav_climbs() -> None:
    model, data = build()
    set_arm_qpos(model, data, GRASP_POSE, c.GRIPPER_OPEN)
    tcp = data.site(c.TCP_SITE).xpos.copy()
    hand_x = data.body(c.HAND_BODY).xmat.reshape(3, 3)[:, 0]
    half_yaw = math.atan2(hand_x[1], hand_x[0]) / 2
    half = 0.025  # 5 cm, 0.3 kg cube, faces square to the fingers, on a pedestal

    def add_cube(spec: mujoco.MjSpec) -> None:
        top = tcp[2] - half
        spec.worldbody.add_geom(
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=[tcp[0], tcp[1], top / 2],
            size=[0.03, 0.03, top / 2],
        )
        cube = spec.worldbody.add_body(
            name="cube", pos=list(tcp), quat=[math.cos(half_yaw), 0, 0, math.sin(half_yaw)]
        )
        cube.add_freejoint()
        cube.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[half] * 3, mass=0.3)

    model, data = build(extra=add_cube)
    set_arm_qpos(model, data, GRASP_POSE, c.GRIPPER_OPEN)
    set_arm_targets(model, data, GRASP_POSE, c.GRIPPER_CLOSED)
    controller = UavController(model, data)
    simulate(model, data, controller, 0.6)
    assert gripper_opening(model, data) == pytest.approx(half, abs=0.004)
    controller.set_setpoint(np.add(START, (0, 0, 0.3)), 0.0)
    simulate(model, data, controller, 3.0)
    rise = data.body("cube").xpos[2] - tcp[2]
    slip = float(np.linalg.norm(data.site(c.TCP_SITE).xpos - data.body("cube").xpos))
    print(f"grasp: cube lifted {rise * 1000:.0f} mm, {slip * 1000:.1f} mm off the TCP")
    assert rise > 0.28
    assert slip < 0.005
