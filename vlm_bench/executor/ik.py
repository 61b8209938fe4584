"""Inverse kinematics of the arm's TCP with mink, on a robot-only model.

The solver works on a separate model holding only the aerial manipulator (15 dofs: the UAV's
free joint, 7 arm joints, 2 fingers): the UAV's dofs are frozen at the scene's current base pose
(``DofFreezingTask``), so only the arm moves. A top-down target fixes the TCP's z axis to world
−z and its x axis to a horizontal heading. The hanging arm reaches down "elbow-up"; a low-cost
posture task pulls solutions towards the seed (by default a known top-down posture).

Collision checks of candidate solutions run on a scratch copy of the full scene
(:meth:`ArmIk.collisions`).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import mink
import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.sim import constants as c
from vlm_bench.sim.robot import add_aerial_manipulator, robot_geom_ids
from vlm_bench.types.episode import UavPose

Vec = NDArray[np.float64]
TOP_DOWN_SEED = (-1.5, -1.76, 1.6, -2.54, -1.44, 1.71, 2.8)  # a known top-down grasp posture
SEED_POSTURES = (
    TOP_DOWN_SEED,
    (-1.01, -1.75, 1.32, -3.03, -1.8, 1.78, 1.68),  # top-down, 0.6 m below and 0.6 m out
    (2.14, -1.74, 1.32, -3.03, -1.8, 1.77, 0.11),  # the same, reaching to the other side
)
"""Postures IK restarts from when the given seed does not converge (from a reach scan)."""
POS_TOL = 0.004  # m
ROT_TOL = 0.03  # rad
DT = 0.1  # s, integration step of mink's velocity solution


def _robot_model() -> mujoco.MjModel:
    spec = mujoco.MjSpec()
    add_aerial_manipulator(spec, UavPose(pos=(0.0, 0.0, 1.0), yaw_deg=0.0))
    return spec.compile()


def top_down_rotation(heading_rad: float) -> Vec:
    """TCP orientation pointing down with its x axis along ``heading_rad``."""
    ch, sh = math.cos(heading_rad), math.sin(heading_rad)
    return np.array([[ch, sh, 0.0], [sh, -ch, 0.0], [0.0, 0.0, -1.0]])


def frontal_rotation(normal: Vec, fingers_up: bool = True) -> Vec:
    """TCP orientation approaching a vertical surface with outward ``normal`` (horizontal):
    the approach axis (z) points into the surface and the fingers close vertically (y axis
    along world ±z), to grasp a horizontal bar."""
    n = np.asarray(normal, dtype=np.float64)
    z = -n / np.linalg.norm(n)
    y = np.array([0.0, 0.0, 1.0 if fingers_up else -1.0])
    return np.column_stack([np.cross(y, z), y, z])


def _move_base(qpos: Vec, adr: int, base: Vec | None) -> None:
    """Move the UAV's free joint at ``qpos[adr:adr + 7]`` by ``base``: (x, y, z) m, world,
    and, where given, a turn about the vertical (rad, CCW) fourth."""
    if base is None:
        return
    qpos[adr : adr + 3] += base[:3]
    if len(base) > 3 and base[3]:
        half = 0.5 * float(base[3])
        turned = np.empty(4)
        mujoco.mju_mulQuat(
            turned, np.array([math.cos(half), 0.0, 0.0, math.sin(half)]), qpos[adr + 3 : adr + 7]
        )
        qpos[adr + 3 : adr + 7] = turned


@dataclass(frozen=True)
class Carried:
    """A held object, for collision checks: its free joint's qpos address, its geoms, and its
    pose in the TCP's frame (offset, m, and rotation)."""

    qadr: int
    geoms: set[int]
    offset: Vec
    rotation: Vec


class ArmIk:
    """IK solver for one scene's arm.

    Args:
        model: The scene's compiled model (read for the arm's joint addresses and limits).
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.scratch = mujoco.MjData(model)
        self._wide: dict[float, tuple[mujoco.MjModel, mujoco.MjData]] = {}
        self.qadr = np.array([model.joint(j).qposadr[0] for j in c.ARM_JOINTS])
        self.lo = np.array([model.joint(j).range[0] for j in c.ARM_JOINTS]) + 0.01
        self.hi = np.array([model.joint(j).range[1] for j in c.ARM_JOINTS]) - 0.01
        self.site = int(model.site(c.TCP_SITE).id)
        self._robot_geoms = set(robot_geom_ids(model))
        self._uav_qadr = int(model.joint(c.UAV_FREEJOINT).qposadr[0])
        # The robot-only model mink solves on.
        self.robot = _robot_model()
        self._r_qadr = np.array([self.robot.joint(j).qposadr[0] for j in c.ARM_JOINTS])
        self._r_uav = int(self.robot.joint(c.UAV_FREEJOINT).qposadr[0])
        self.config = mink.Configuration(self.robot)
        uav_dofs = self.robot.joint(c.UAV_FREEJOINT).dofadr[0] + np.arange(6)
        finger_dofs = [
            self.robot.joint(j).dofadr[0]
            for j in range(self.robot.njnt)
            if self.robot.joint(j).name not in c.ARM_JOINTS
            and self.robot.joint(j).name != c.UAV_FREEJOINT
        ]
        self.frame = mink.FrameTask(
            c.TCP_SITE, "site", position_cost=1.0, orientation_cost=0.5, lm_damping=1e-3
        )
        self.posture = mink.PostureTask(self.robot, cost=1e-3)
        self.freeze = mink.DofFreezingTask(self.robot, [int(d) for d in [*uav_dofs, *finger_dofs]])
        self.limits = [mink.ConfigurationLimit(self.robot)]

    def _load(self, data: mujoco.MjData, q: Vec, base: Vec | None) -> None:
        """Robot-model configuration: the scene's UAV pose (moved by ``base``) with arm
        angles ``q``."""
        qpos = self.config.q.copy()
        qpos[self._r_uav : self._r_uav + 7] = data.qpos[self._uav_qadr : self._uav_qadr + 7]
        _move_base(qpos, self._r_uav, base)
        qpos[self._r_qadr] = q
        self.config.update(qpos)

    def solve(
        self,
        data: mujoco.MjData,
        pos: Vec,
        rotation: Vec,
        seed: Vec,
        iterations: int = 200,
        base: Vec | None = None,
        posture: Vec | None = None,
    ) -> tuple[Vec, float]:
        """Joint angles putting the TCP at ``pos`` with orientation ``rotation`` (3×3, world;
        see :func:`top_down_rotation`), with the UAV where it is (or moved by ``base``, m, to
        plan a base adjustment). A weak posture task pulls towards ``posture`` (default: the
        seed), which picks the branch among the arm's redundant solutions.

        Returns the solution and its residual (position error in m plus rotation error in
        rad); the caller decides whether it is good enough.
        """
        q0 = np.clip(np.asarray(seed, dtype=np.float64), self.lo, self.hi)
        self._load(data, q0, base)
        target = mink.SE3.from_rotation_and_translation(
            mink.SO3.from_matrix(np.asarray(rotation)), np.asarray(pos)
        )
        self.frame.set_target(target)
        rest = self.config.q.copy()
        if posture is not None:
            rest[self._r_qadr] = np.clip(posture, self.lo, self.hi)
        self.posture.set_target(rest)
        residual = math.inf
        for _ in range(iterations):
            err = self.frame.compute_error(self.config)
            e_pos, e_rot = float(np.linalg.norm(err[:3])), float(np.linalg.norm(err[3:]))
            residual = e_pos + e_rot
            if e_pos < POS_TOL and e_rot < ROT_TOL:
                break
            vel = mink.solve_ik(
                self.config,
                [self.frame, self.posture],
                DT,
                "daqp",
                damping=1e-3,
                limits=self.limits,
                constraints=[self.freeze],
            )
            self.config.integrate_inplace(vel, DT)
        q = np.clip(self.config.q[self._r_qadr], self.lo, self.hi)
        if not np.array_equal(q, self.config.q[self._r_qadr]):  # the residual of what is returned
            qpos = self.config.q.copy()
            qpos[self._r_qadr] = q
            self.config.update(qpos)
            err = self.frame.compute_error(self.config)
            residual = float(np.linalg.norm(err[:3])) + float(np.linalg.norm(err[3:]))
        return q, residual

    def _checker(self, clearance: float) -> tuple[mujoco.MjModel, mujoco.MjData]:
        """The model and scratch data collision checks run on: the scene's, or for a
        ``clearance`` a copy (made once) whose geoms all have it as collision margin."""
        if clearance <= 0.0:
            return self.model, self.scratch
        if clearance not in self._wide:
            wide = copy.copy(self.model)
            wide.geom_margin[:] = np.maximum(wide.geom_margin, clearance)
            self._wide[clearance] = (wide, mujoco.MjData(wide))
        return self._wide[clearance]

    def _pose(self, s: mujoco.MjData, data: mujoco.MjData, q: Vec, base: Vec | None) -> None:
        """Scratch ``s`` set to the scene's state with arm angles ``q`` (UAV moved by
        ``base``); kinematics not yet run."""
        s.qpos[:] = data.qpos
        _move_base(s.qpos, self._uav_qadr, base)
        s.qpos[self.qadr] = q

    def tcp_at(self, data: mujoco.MjData, q: Vec, base: Vec | None = None) -> Vec:
        """Where the TCP would be with arm angles ``q`` (UAV moved by ``base``), world."""
        self._pose(self.scratch, data, q, base)
        mujoco.mj_kinematics(self.model, self.scratch)
        return np.array(self.scratch.site_xpos[self.site])

    def room(self, q: Vec) -> Vec:
        """Each joint's distance in ``q`` from its nearer (inset) limit (rad)."""
        return np.minimum(q - self.lo, self.hi - q)

    def limit_margin(self, q: Vec) -> float:
        """Smallest distance of ``q`` from the (inset) joint limits (rad)."""
        return float(np.min(self.room(q)))

    def collisions(
        self,
        data: mujoco.MjData,
        q: Vec,
        ignore: set[int],
        gripper: float | None = None,
        base: Vec | None = None,
        carried: Carried | None = None,
        clearance: float = 0.0,
    ) -> list[int]:
        """Non-robot geoms the robot would touch with arm angles ``q`` (scene scratch copy, UAV
        moved by ``base``), other than the geoms in ``ignore``, and a robot geom for each
        contact of the arm with itself or the UAV (MuJoCo leaves out adjacent links); with
        ``carried``, the held object moves with the hand and what it would touch counts too.
        With ``clearance`` (m), non-robot geoms the robot (or the held object) would come
        closer to than that count as touched (checked on a copy of the model whose geoms have
        that collision margin)."""
        model, s = self._checker(clearance)
        self._pose(s, data, q, base)
        if gripper is not None:
            for name in c.FINGER_JOINTS:
                s.qpos[model.joint(name).qposadr[0]] = gripper
        mujoco.mj_kinematics(model, s)
        held: set[int] = set()
        if carried is not None:
            tcp, rot = s.site_xpos[self.site], s.site_xmat[self.site].reshape(3, 3)
            quat = np.empty(4)
            mujoco.mju_mat2Quat(quat, (rot @ carried.rotation).ravel())
            s.qpos[carried.qadr : carried.qadr + 3] = tcp + rot @ carried.offset
            s.qpos[carried.qadr + 3 : carried.qadr + 7] = quat
            mujoco.mj_kinematics(model, s)
            held = carried.geoms
        mujoco.mj_collision(model, s)
        hits = []
        for i in range(s.ncon):
            dist = float(s.contact.dist[i])
            if dist > clearance:
                continue
            g1, g2 = int(s.contact.geom[i][0]), int(s.contact.geom[i][1])
            r1, r2 = g1 in self._robot_geoms or g1 in held, g2 in self._robot_geoms or g2 in held
            if g1 in self._robot_geoms and g2 in self._robot_geoms:
                if dist <= 0.0:
                    hits.append(g1)  # the arm against itself or the UAV: it would jam there
            elif r1 != r2:
                other = g2 if r1 else g1
                if other not in ignore:
                    hits.append(other)
        return hits
