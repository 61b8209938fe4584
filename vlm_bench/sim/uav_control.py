"""Position and attitude controller that holds the floating UAV base at a setpoint.

The UAV is abstracted as a fully actuated rigid body: every physics step the controller writes
one world-frame force and torque on the UAV body (``data.xfrc_applied``); the base is never
teleported, so arm motion and contacts disturb it. The loops:

* position: a cascaded P (position → bounded velocity) and P (velocity → acceleration) loop,
  plus an integral on the position error near the setpoint (absorbs held payloads), with a
  bounded acceleration;
* feed-forward lift of the whole subtree mass (UAV + arm), applied through the subtree's centre
  of mass so that the arm's weight does not tip the airframe;
* attitude: PD levelling of roll/pitch and yaw tracking with a bounded yaw error, scaled by the
  current rotational inertia of the subtree about the base.

The arm's gravity compensation (``gravcomp``) is meant to act inside the arm's joints, but MuJoCo
also applies it to the free joint of the base, which would make the arm weightless for the UAV.
The controller adds that weight back as a force and torque on the base, so the UAV carries it.

Optional gusts (:class:`GustConfig`): an Ornstein–Uhlenbeck force/torque with the given
stationary standard deviation, reproducible by seed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from vlm_bench.sim import constants as c
from vlm_bench.sim.robot import robot_body_ids
from vlm_bench.types.world import Frozen

Array = NDArray[np.float64]


class UavGains(Frozen):
    """Controller gains and limits (mass-normalised, so they hold for any payload)."""

    pos_p: float = Field(default=3.3, gt=0, description="Position error → velocity (1/s).")
    vel_p: float = Field(default=10.0, gt=0, description="Velocity error → acceleration (1/s).")
    pos_i: float = Field(default=36.0, ge=0, description="Integral gain on position (1/s³).")
    i_zone: float = Field(default=0.05, gt=0, description="Integrate only within this error (m).")
    i_speed: float = Field(default=0.05, gt=0, description="...and below this speed (m/s).")
    i_limit: float = Field(default=4.0, ge=0, description="Integral term bound (m/s²).")
    max_speed: float = Field(default=1.0, gt=0, description="Speed bound (m/s).")
    max_accel: float = Field(default=6.0, gt=0, description="Commanded acceleration bound (m/s²).")
    att_p: float = Field(default=64.0, gt=0, description="Attitude error → angular acc. (1/s²).")
    att_d: float = Field(default=16.0, gt=0, description="Angular rate → angular acc. (1/s).")
    max_yaw_error: float = Field(default=0.5, gt=0, description="Yaw error bound (rad).")
    max_ang_accel: float = Field(default=30.0, gt=0, description="Angular acc. bound (rad/s²).")


class GustConfig(Frozen):
    """Random wind on the UAV: Gaussian force/torque noise (the paper's UAV disturbance)."""

    force_std: float = Field(ge=0, description="Stationary std of each force component (N).")
    torque_std: float = Field(default=0.0, ge=0, description="Std of each torque component (N·m).")
    seed: int = Field(default=0, description="Random seed; equal seeds give equal gusts.")
    correlation_time: float = Field(
        default=0.5, gt=0, description="Time constant of the gust process (s)."
    )


class UavController:
    """Holds the UAV at a position and heading by writing ``xfrc_applied`` every physics step.

    Args:
        model: Compiled model containing the aerial manipulator.
        data: Its data (only read here; :meth:`apply` takes the data to write).
        gains: Gains and limits.
        gust: Optional random wind.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        gains: UavGains | None = None,
        gust: GustConfig | None = None,
    ) -> None:
        self.model = model
        self.gains = gains or UavGains()
        self.gust = gust
        self.body = int(model.body(c.UAV_BODY).id)
        joint = model.joint(c.UAV_FREEJOINT)
        self._qpos = int(joint.qposadr[0])
        self._dof = int(joint.dofadr[0])
        self._rot_diag = np.array([_diag_index(model, self._dof + 3 + k) for k in range(3)])
        self.mass = float(model.body_subtreemass[self.body])
        self._gravity = np.array(model.opt.gravity, dtype=np.float64)
        self._dt = float(model.opt.timestep)
        # Bodies under the base whose weight gravcomp hides from it.
        subtree = robot_body_ids(model)
        self._comp_bodies = np.array([b for b in subtree if model.body_gravcomp[b] > 0], dtype=int)
        self._comp_weights = (model.body_mass * model.body_gravcomp)[self._comp_bodies]
        self._comp_weight = float(self._comp_weights.sum())
        self._integral = np.zeros(3)
        self._gust_rng = np.random.default_rng(gust.seed if gust else 0)
        self._gust_state = np.zeros(6)
        self.setpoint = np.array(data.qpos[self._qpos : self._qpos + 3], dtype=np.float64)
        w, z = data.qpos[self._qpos + 3], data.qpos[self._qpos + 6]
        self.yaw_setpoint = 2.0 * math.atan2(float(z), float(w))

    def set_setpoint(self, pos: Sequence[float] | Array, yaw_deg: float) -> None:
        """Hold position ``pos`` (m, world) and heading ``yaw_deg`` (deg, CCW from world +x)."""
        self.setpoint = np.array(pos, dtype=np.float64)
        self.yaw_setpoint = math.radians(yaw_deg)

    def reset(self) -> None:
        """Clear the integral term and the gust state (restart the gust sequence)."""
        self._integral[:] = 0.0
        self._gust_state[:] = 0.0
        self._gust_rng = np.random.default_rng(self.gust.seed if self.gust else 0)

    def apply(self, data: mujoco.MjData) -> None:
        """Write this step's force and torque on the UAV body; call before every ``mj_step``."""
        force, torque = self._position_force(data)
        rot = data.xmat[self.body].reshape(3, 3)
        torque += self._attitude_torque(data, rot)
        weight, weight_torque = self._hidden_weight(data)
        force += weight
        torque += weight_torque
        if self.gust is not None:
            gust = self._next_gust(self.gust)
            force += gust[:3]
            torque += gust[3:]
        data.xfrc_applied[self.body, :3] = force
        data.xfrc_applied[self.body, 3:] = torque

    def _position_force(self, data: mujoco.MjData) -> tuple[Array, Array]:
        """Force at the body's COM and the torque that moves it to the subtree COM."""
        g = self.gains
        pos = data.qpos[self._qpos : self._qpos + 3]
        vel = data.qvel[self._dof : self._dof + 3]
        error = self.setpoint - pos
        vel_cmd = _clip_norm(g.pos_p * error, g.max_speed)
        if _norm(error) < g.i_zone and _norm(vel) < g.i_speed:  # no wind-up in transients
            self._integral = _clip_norm(self._integral + g.pos_i * self._dt * error, g.i_limit)
        accel = _clip_norm(g.vel_p * (vel_cmd - vel) + self._integral, g.max_accel)
        force = self.mass * (accel - self._gravity)
        lever = data.subtree_com[self.body] - data.xipos[self.body]
        return force, _cross(lever, force)

    def _attitude_torque(self, data: mujoco.MjData, rot: Array) -> Array:
        g = self.gains
        # Tilt error: z_body × z_world, the axis (and sine) of the rotation that levels the body.
        tilt_x, tilt_y = rot[1, 2], -rot[0, 2]
        yaw = math.atan2(rot[1, 0], rot[0, 0])
        yaw_error = (self.yaw_setpoint - yaw + math.pi) % (2 * math.pi) - math.pi
        yaw_error = max(-g.max_yaw_error, min(g.max_yaw_error, yaw_error))
        omega = rot @ data.qvel[self._dof + 3 : self._dof + 6]
        alpha = g.att_p * np.array([tilt_x, tilt_y, yaw_error]) - g.att_d * omega
        alpha_body = rot.T @ _clip_norm(alpha, g.max_ang_accel)
        inertia = data.M[self._rot_diag]
        return np.asarray(rot @ (inertia * alpha_body), dtype=np.float64)

    def _hidden_weight(self, data: mujoco.MjData) -> tuple[Array, Array]:
        """Weight of the gravity-compensated bodies, as force and torque at the base's COM."""
        levers = data.xipos[self._comp_bodies] - data.xipos[self.body]
        moment = self._comp_weights @ levers  # Σ m_i r_i; gravity is common to all bodies
        return self._comp_weight * self._gravity, _cross(moment, self._gravity)

    def _next_gust(self, gust: GustConfig) -> Array:
        decay = math.exp(-self._dt / gust.correlation_time)
        std = np.array([gust.force_std] * 3 + [gust.torque_std] * 3)
        noise = self._gust_rng.standard_normal(6) * std * math.sqrt(1.0 - decay**2)
        self._gust_state = decay * self._gust_state + noise
        return self._gust_state.copy()


def _diag_index(model: mujoco.MjModel, dof: int) -> int:
    """Index of the diagonal entry of ``dof`` in the sparse (CSR) inertia ``data.M``."""
    start = int(model.M_rowadr[dof])
    cols = model.M_colind[start : start + int(model.M_rownnz[dof])]
    return start + int(np.flatnonzero(cols == dof)[0])


def _norm(vec: Array) -> float:
    return math.sqrt(float(vec[0]) ** 2 + float(vec[1]) ** 2 + float(vec[2]) ** 2)


def _clip_norm(vec: Array, limit: float) -> Array:
    norm = _norm(vec)
    return vec * (limit / norm) if norm > limit else vec


def _cross(a: Array, b: Array) -> Array:
    """Cross product of two 3-vectors (``np.cross`` costs ~20 µs per call)."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )
