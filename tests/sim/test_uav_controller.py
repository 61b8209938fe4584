"""The UAV controller's per-step arithmetic (scalar, for speed) computes the control law as
written in vector form: cascaded P position loops with an integral, bounded; the lift through
the subtree's centre of mass; PD attitude scaled by the rotational inertia; the weight that
gravcomp hides from the base; and the gusts on top. At its rate (every few physics steps) it
updates the force at the first step of each period and holds it for the others."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor.step_execution import episode_scene
from vlm_bench.sim.uav_control import GustConfig, UavController
from vlm_bench.types.execution import ExecutorConfig


def _clip(v: np.ndarray, limit: float) -> np.ndarray:
    n = float(np.linalg.norm(v))
    return v * (limit / n) if n > limit else v


def _reference(ctl: UavController, data: mujoco.MjData, integral: np.ndarray) -> np.ndarray:
    """The control law in vector form: (force, torque) on the UAV body and the new integral."""
    g, b = ctl.gains, ctl.body
    pos = data.qpos[ctl._qpos : ctl._qpos + 3]
    vel = data.qvel[ctl._dof : ctl._dof + 3]
    error = ctl.setpoint - pos
    if np.linalg.norm(error) < g.i_zone and np.linalg.norm(vel) < g.i_speed:
        integral = _clip(integral + g.pos_i * ctl._dt * error, g.i_limit)
    accel = _clip(g.vel_p * (_clip(g.pos_p * error, g.max_speed) - vel) + integral, g.max_accel)
    grav = np.array(ctl.model.opt.gravity)
    force = ctl.mass * (accel - grav)
    torque = np.cross(data.subtree_com[b] - data.xipos[b], force)
    rot = data.xmat[b].reshape(3, 3)
    yaw = math.atan2(rot[1, 0], rot[0, 0])
    yaw_error = (ctl.yaw_setpoint - yaw + math.pi) % (2 * math.pi) - math.pi
    yaw_error = float(np.clip(yaw_error, -g.max_yaw_error, g.max_yaw_error))
    omega = rot @ data.qvel[ctl._dof + 3 : ctl._dof + 6]
    alpha = g.att_p * np.array([rot[1, 2], -rot[0, 2], yaw_error]) - g.att_d * omega
    inertia = data.M[ctl._rot_diag]
    torque += rot @ (inertia * (rot.T @ _clip(alpha, g.max_ang_accel)))
    comp = ctl._comp_bodies
    weights = ctl.model.body_mass[comp] * ctl.model.body_gravcomp[comp]
    moment = weights @ (data.xipos[comp] - data.xipos[b])
    force += weights.sum() * grav
    torque += np.cross(moment, grav)
    return np.concatenate([force, torque, integral])


@pytest.mark.parametrize("gust", [None, GustConfig(force_std=2.0, torque_std=0.3, seed=4)])
def test_scalar_controller_matches_the_vector_law(gust: GustConfig | None) -> None:
    episode = get_episode("standard_pick_place", 0)
    scene = episode_scene(episode, ExecutorConfig())
    model, data = scene.model, scene.data
    ctl = UavController(model, data, gust=gust, every=1)
    shadow = UavController(model, data, gust=gust, every=1)  # draws the same gusts
    rng = np.random.default_rng(1)
    integral = np.zeros(3)
    near = 0
    for step in range(300):
        # random states: near the setpoint (integral active) and far (bounds active)
        far = step % 2 == 0
        data.qvel[:] = rng.normal(0, 0.5 if far else 0.01, model.nv)
        ctl.set_setpoint(
            data.qpos[ctl._qpos : ctl._qpos + 3] + rng.normal(0, 1.0 if far else 0.01, 3), 40.0
        )
        shadow.set_setpoint(ctl.setpoint, 40.0)
        mujoco.mj_step(model, data)
        mujoco.mj_forward(model, data)
        expected = _reference(ctl, data, integral)
        ctl.apply(data)
        gust_now = shadow._next_gust(gust) if gust else np.zeros(6)
        np.testing.assert_allclose(data.xfrc_applied[ctl.body], expected[:6] + gust_now, atol=1e-9)
        np.testing.assert_allclose(ctl._integral, expected[6:], atol=1e-12)
        near += bool(np.any(expected[6:] != integral))
        integral = expected[6:]
    assert near > 10  # the integral branch ran


def test_force_updated_at_the_controller_rate_and_held_between() -> None:
    episode = get_episode("standard_pick_place", 0)
    scene = episode_scene(episode, ExecutorConfig())
    model, data = scene.model, scene.data
    ctl = UavController(model, data, every=5)
    ref = UavController(model, data, every=1)  # the same law, applied only at ctl's updates
    ref._dt = ctl._dt
    ref._set_gains()
    held = np.zeros(6)
    for step in range(20):
        mujoco.mj_step(model, data)
        ctl.set_setpoint(data.qpos[ctl._qpos : ctl._qpos + 3] + 0.05 * (step + 1), 10.0)
        ctl.apply(data)
        now = np.array(data.xfrc_applied[ctl.body])
        if step % 5 == 0:
            ref.set_setpoint(ctl.setpoint, 10.0)
            ref.apply(data)
            np.testing.assert_array_equal(data.xfrc_applied[ctl.body], now)
            assert not np.array_equal(now, held)  # a new force
            held = now
        else:
            np.testing.assert_array_equal(now, held)  # held, though the setpoint moved
