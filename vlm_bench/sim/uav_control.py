"""Position and attitude controller that holds the floating UAV base at a setpoint.

The UAV is abstracted as a fully actuated rigid body: every ``UAV_CONTROL_EVERY`` physics steps
the controller writes one world-frame force and torque on the UAV body (``data.xfrc_applied``),
held in between; the base is never teleported, so arm motion and contacts disturb it. The
loops:

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
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from vlm_bench.sim import constants as c
from vlm_bench.sim.robot import robot_body_ids
from vlm_bench.types.base import Frozen

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
    """Holds the UAV at a position and heading by writing ``xfrc_applied`` (module doc).

    Args:
        model: Compiled model containing the aerial manipulator.
        data: Its data (only read here; :meth:`apply` takes the data to write).
        gains: Gains and limits.
        gust: Optional random wind.
        every: Physics steps per update (:data:`~vlm_bench.sim.constants.UAV_CONTROL_EVERY`):
            :meth:`apply`, called every step, computes the force at the first of each
            ``every`` calls and leaves it in ``data`` for the others.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        gains: UavGains | None = None,
        gust: GustConfig | None = None,
        every: int = c.UAV_CONTROL_EVERY,
    ) -> None:
        self.model = model
        self.every = every
        self._tick = 0
        self.gains = gains or UavGains()
        self.gust = gust
        self.body = int(model.body(c.UAV_BODY).id)
        joint = model.joint(c.UAV_FREEJOINT)
        self._qpos = int(joint.qposadr[0])
        self._dof = int(joint.dofadr[0])
        self._rot_diag = np.array([_diag_index(model, self._dof + 3 + k) for k in range(3)])
        self.mass = float(model.body_subtreemass[self.body])
        self._grav = tuple(float(x) for x in model.opt.gravity)
        self._dt = float(model.opt.timestep) * every  # the controller's period
        # Bodies under the base whose weight gravcomp hides from it.
        subtree = robot_body_ids(model)
        self._comp_bodies = np.array([b for b in subtree if model.body_gravcomp[b] > 0], dtype=int)
        self._comp_weights = (model.body_mass * model.body_gravcomp)[self._comp_bodies]
        self._comp_weight = float(self._comp_weights.sum())
        self._integral: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self._set_gains()
        self._gust_rng = np.random.default_rng(gust.seed if gust else 0)
        self._gust_state = np.zeros(6)
        self.setpoint = np.array(data.qpos[self._qpos : self._qpos + 3], dtype=np.float64)
        w, z = data.qpos[self._qpos + 3], data.qpos[self._qpos + 6]
        self.yaw_setpoint = 2.0 * math.atan2(float(z), float(w))
        self._data_views: _Views | None = None

    def __getstate__(self) -> dict[str, object]:
        """Pickled without the views into MjData: a pickle copies a view, which then no longer
        follows the data (they are made again on first use, executor/frozen_episode.py)."""
        return {**self.__dict__, "_data_views": None}

    def set_setpoint(self, pos: Sequence[float] | Array, yaw_deg: float) -> None:
        """Hold position ``pos`` (m, world) and heading ``yaw_deg`` (deg, CCW from world +x)."""
        self.setpoint = np.array(pos, dtype=np.float64)
        self.yaw_setpoint = math.radians(yaw_deg)

    def reset(self) -> None:
        """Clear the integral term and the gust state (restart the gust sequence)."""
        self._integral = (0.0, 0.0, 0.0)
        self._tick = 0
        self._gust_state[:] = 0.0
        self._gust_rng = np.random.default_rng(self.gust.seed if self.gust else 0)

    def apply(self, data: mujoco.MjData) -> None:
        """Write this step's force and torque on the UAV body; call before every ``mj_step``.

        Runs at every physics step, so it works on Python floats over views of ``data``
        made once per data (numpy calls on 3-vectors cost ~1 µs each: 5× slower), with the
        gains read once into a tuple. Between updates (``every``) the force stays as written."""
        tick = self._tick
        self._tick = tick + 1 if tick + 1 < self.every else 0
        if tick:
            return
        v = self._data_views
        if v is None or v.data is not data:
            v = self._views(data)
        if self._gains_of is not self.gains:
            self._set_gains()
        pos_p, vel_p, k_i, i_zone, i_speed, i_limit, max_speed, max_accel = self._pos_gains
        att_p, att_d, max_yaw_error, max_ang_accel = self._att_gains
        # Position: cascaded P loops with an integral near the setpoint, bounded.
        px, py, pz = v.qpos.tolist()
        vx, vy, vz, w0, w1, w2 = v.qvel.tolist()
        sx, sy, sz = self.setpoint.tolist()
        ex, ey, ez = sx - px, sy - py, sz - pz
        cx, cy, cz = _clip3(pos_p * ex, pos_p * ey, pos_p * ez, max_speed)
        i = self._integral
        if (
            math.sqrt(ex * ex + ey * ey + ez * ez) < i_zone
            and math.sqrt(vx * vx + vy * vy + vz * vz) < i_speed
        ):  # no wind-up in transients
            i = self._integral = _clip3(i[0] + k_i * ex, i[1] + k_i * ey, i[2] + k_i * ez, i_limit)
        ax, ay, az = _clip3(
            vel_p * (cx - vx) + i[0],
            vel_p * (cy - vy) + i[1],
            vel_p * (cz - vz) + i[2],
            max_accel,
        )
        gx, gy, gz = self._grav
        m = self.mass
        fx, fy, fz = m * (ax - gx), m * (ay - gy), m * (az - gz)
        # ...applied through the subtree's centre of mass: the torque of the lever to it.
        com, cog = v.subtree_com.tolist(), v.xipos.tolist()
        lx, ly, lz = com[0] - cog[0], com[1] - cog[1], com[2] - cog[2]
        tx, ty, tz = ly * fz - lz * fy, lz * fx - lx * fz, lx * fy - ly * fx
        # Attitude: PD levelling and bounded yaw tracking, scaled by the rotational inertia.
        r = v.xmat.tolist()
        yaw = math.atan2(r[3], r[0])
        yaw_error = (self.yaw_setpoint - yaw + math.pi) % (2 * math.pi) - math.pi
        yaw_error = max(-max_yaw_error, min(max_yaw_error, yaw_error))
        ox = r[0] * w0 + r[1] * w1 + r[2] * w2
        oy = r[3] * w0 + r[4] * w1 + r[5] * w2
        oz = r[6] * w0 + r[7] * w1 + r[8] * w2
        # tilt error: z_body × z_world, the axis (and sine) of the rotation that levels it
        bx, by, bz = _clip3(
            att_p * r[5] - att_d * ox,
            -att_p * r[2] - att_d * oy,
            att_p * yaw_error - att_d * oz,
            max_ang_accel,
        )
        inertia, (d0, d1, d2) = v.M.item, v.rot_diag
        # body-frame angular acceleration times inertia, back to the world frame
        kx = inertia(d0) * (r[0] * bx + r[3] * by + r[6] * bz)
        ky = inertia(d1) * (r[1] * bx + r[4] * by + r[7] * bz)
        kz = inertia(d2) * (r[2] * bx + r[5] * by + r[8] * bz)
        tx += r[0] * kx + r[1] * ky + r[2] * kz
        ty += r[3] * kx + r[4] * ky + r[5] * kz
        tz += r[6] * kx + r[7] * ky + r[8] * kz
        # The weight gravcomp hides from the base, as force and torque at its COM (the
        # weighted sum stays numpy's, whose summation order a Python loop would not keep).
        w = self._comp_weight
        np.matmul(self._comp_weights, v.comp_xipos, out=v.comp_sum)
        mx, my, mz = v.comp_sum.tolist()
        mx, my, mz = mx - w * cog[0], my - w * cog[1], mz - w * cog[2]
        fx, fy, fz = fx + w * gx, fy + w * gy, fz + w * gz
        tx += my * gz - mz * gy
        ty += mz * gx - mx * gz
        tz += mx * gy - my * gx
        out = v.xfrc
        if self.gust is not None:
            gust = self._next_gust(self.gust)
            out[:] = (fx, fy, fz, tx, ty, tz)
            out += gust
        else:
            out[:] = (fx, fy, fz, tx, ty, tz)

    def _set_gains(self) -> None:
        """:attr:`gains` as the tuples :meth:`apply` unpacks (the integral gain times the
        physics step, as it is used)."""
        g = self.gains
        self._pos_gains = (
            g.pos_p,
            g.vel_p,
            g.pos_i * self._dt,
            g.i_zone,
            g.i_speed,
            g.i_limit,
            g.max_speed,
            g.max_accel,
        )
        self._att_gains = (g.att_p, g.att_d, g.max_yaw_error, g.max_ang_accel)
        self._gains_of: UavGains | None = g

    def _views(self, data: mujoco.MjData) -> _Views:
        """The views of ``data`` :meth:`apply` reads and writes (made once per data)."""
        views = self._data_views
        if views is None or views.data is not data:
            b, q, d = self.body, self._qpos, self._dof
            comp = self._comp_bodies
            views = self._data_views = _Views(
                data=data,
                qpos=data.qpos[q : q + 3],
                qvel=data.qvel[d : d + 6],
                subtree_com=data.subtree_com[b],
                xipos=data.xipos[b],
                xmat=data.xmat[b],
                M=data.M,
                rot_diag=tuple(self._rot_diag.tolist()),
                comp_xipos=data.xipos[comp[0] : comp[-1] + 1]
                if len(comp) and np.array_equal(comp, np.arange(comp[0], comp[-1] + 1))
                else data.xipos[comp],
                xfrc=data.xfrc_applied[b],
                comp_sum=np.zeros(3),
            )
        return views

    def _next_gust(self, gust: GustConfig) -> Array:
        decay = math.exp(-self._dt / gust.correlation_time)
        std = np.array([gust.force_std] * 3 + [gust.torque_std] * 3)
        noise = self._gust_rng.standard_normal(6) * std * math.sqrt(1.0 - decay**2)
        self._gust_state = decay * self._gust_state + noise
        return self._gust_state.copy()


@dataclass
class _Views:
    """Views into one MjData (they follow it as it steps; a gathered copy does not)."""

    data: mujoco.MjData
    qpos: Array
    qvel: Array
    subtree_com: Array
    xipos: Array
    xmat: Array
    M: Array
    rot_diag: tuple[int, ...]
    comp_xipos: Array
    xfrc: Array
    comp_sum: Array
    """Where :meth:`UavController.apply` writes the gravcomp bodies' weighted positions."""


def _clip3(x: float, y: float, z: float, limit: float) -> tuple[float, float, float]:
    """(x, y, z) scaled down to norm ``limit`` where it is longer."""
    norm = math.sqrt(x * x + y * y + z * z)
    if norm > limit:
        k = limit / norm
        return x * k, y * k, z * k
    return x, y, z


def _diag_index(model: mujoco.MjModel, dof: int) -> int:
    """Index of the diagonal entry of ``dof`` in the sparse (CSR) inertia ``data.M``."""
    start = int(model.M_rowadr[dof])
    cols = model.M_colind[start : start + int(model.M_rownnz[dof])]
    return start + int(np.flatnonzero(cols == dof)[0])
