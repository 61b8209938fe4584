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
STALL_AFTER = 60
"""Iterations a solve always gets before it may give up where it stalls."""
STALL_WINDOW = 30
STALL_GAIN = 0.05
"""A solve stalls when its lowest residual fell by less than this fraction in the last
:data:`STALL_WINDOW` iterations. Measured on 8,033 solves of four GT replays: 967 ran to the
200-iteration cap and 88 % of all iterations went to them; the rule saves 62 % of all
iterations, and of the 2,361 solves that reached an accepted residual it would have stopped 5
(0.2 %) before they did (the planner's other starts find those postures)."""


def stalled(best: list[float]) -> bool:
    """Whether a solve whose lowest residuals so far, per iteration, are ``best`` stalls
    (see :data:`STALL_GAIN`)."""
    n = len(best)
    return n > STALL_AFTER and best[-1] > (1.0 - STALL_GAIN) * best[n - 1 - STALL_WINDOW]


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

    def key(self) -> tuple[int, frozenset[int], bytes, bytes]:
        """Hashable identity of the carried pose (for the collision cache)."""
        return (self.qadr, frozenset(self.geoms), self.offset.tobytes(), self.rotation.tobytes())


class ArmIk:
    """IK solver for one scene's arm.

    Args:
        model: The scene's compiled model (read for the arm's joint addresses and limits).
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.scratch = mujoco.MjData(model)
        self._checkers: dict[float, tuple[mujoco.MjModel, mujoco.MjData, bool]] = {}
        self._robot_mask = np.zeros(model.ngeom, dtype=bool)
        self._robot_mask[robot_geom_ids(model)] = True
        self._finger_qadr = np.array([model.joint(j).qposadr[0] for j in c.FINGER_JOINTS])
        self._no_geoms = np.zeros(0, dtype=np.int64)
        self._state = b""
        self._hits: dict[tuple[object, ...], tuple[int, ...]] = {}
        self._ignore_masks: dict[frozenset[int], NDArray[np.bool_]] = {}
        self._ik_state = b""
        self._solves: dict[tuple[object, ...], tuple[Vec, float]] = {}
        """Solves for the UAV pose ``_ik_state`` (the planner repeats ~10 % exactly)."""
        """Collision checks of the scene state ``_state`` (the planner repeats ~20 % exactly)."""
        self.qadr = np.array([model.joint(j).qposadr[0] for j in c.ARM_JOINTS])
        self.lo = np.array([model.joint(j).range[0] for j in c.ARM_JOINTS]) + 0.01
        self.hi = np.array([model.joint(j).range[1] for j in c.ARM_JOINTS]) - 0.01
        self.site = int(model.site(c.TCP_SITE).id)
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
        rad); the caller decides whether it is good enough. A solve of more than
        :data:`STALL_AFTER` iterations gives up where it stalls (:func:`stalled`). The
        planner repeats ~10 % of its solves exactly: those are answered from a cache that
        holds while the UAV does not move.
        """
        uav = data.qpos[self._uav_qadr : self._uav_qadr + 7].tobytes()
        if uav != self._ik_state:
            self._ik_state = uav
            self._solves.clear()
        arrays = (pos, rotation, seed, base, posture)
        key = (
            iterations,
            *(None if a is None else np.asarray(a, np.float64).tobytes() for a in arrays),
        )
        hit = self._solves.get(key)
        if hit is None:
            hit = self._solve(data, pos, rotation, seed, iterations, base, posture)
            self._solves[key] = hit
        return hit[0].copy(), hit[1]

    def _solve(
        self,
        data: mujoco.MjData,
        pos: Vec,
        rotation: Vec,
        seed: Vec,
        iterations: int,
        base: Vec | None,
        posture: Vec | None,
    ) -> tuple[Vec, float]:
        """:meth:`solve` computed (no cache)."""
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
        best: list[float] = []  # the lowest residual so far, per iteration
        for _ in range(iterations):
            err = self.frame.compute_error(self.config)
            e_pos, e_rot = float(np.linalg.norm(err[:3])), float(np.linalg.norm(err[3:]))
            residual = e_pos + e_rot
            if e_pos < POS_TOL and e_rot < ROT_TOL:
                break
            best.append(min(residual, best[-1]) if best else residual)
            if iterations > STALL_AFTER and stalled(best):
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

    def _checker(self, clearance: float) -> tuple[mujoco.MjModel, mujoco.MjData, bool]:
        """The model and scratch data collision checks run on: a copy of the scene's model
        (made once per ``clearance``) that cannot report a pair of world geoms (see
        :func:`robot_only_collisions`), whose geoms all have ``clearance`` (m) as collision
        margin where it is positive; and whether its masks were set (else it reports all)."""
        if clearance not in self._checkers:
            check = copy.copy(self.model)
            filtered = robot_only_collisions(check, self._robot_mask)
            if clearance > 0.0:
                check.geom_margin[:] = np.maximum(check.geom_margin, clearance)
            self._checkers[clearance] = (check, mujoco.MjData(check), filtered)
        return self._checkers[clearance]

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
        state = _state_key(data)
        if state != self._state:
            self._state = state
            self._hits.clear()
        key = (
            np.asarray(q, dtype=np.float64).tobytes(),
            frozenset(ignore),
            gripper,
            None if base is None else np.asarray(base, dtype=np.float64).tobytes(),
            None if carried is None else carried.key(),
            clearance,
        )
        hits = self._hits.get(key)
        if hits is None:
            hits = self._collide(data, q, ignore, gripper, base, carried, clearance)
            self._hits[key] = hits
        return list(hits)

    def _collide(
        self,
        data: mujoco.MjData,
        q: Vec,
        ignore: set[int],
        gripper: float | None,
        base: Vec | None,
        carried: Carried | None,
        clearance: float,
    ) -> tuple[int, ...]:
        """:meth:`collisions` computed (no cache)."""
        model, s, filtered = self._checker(clearance)
        self._pose(s, data, q, base)
        if gripper is not None:
            s.qpos[self._finger_qadr] = gripper
        mujoco.mj_kinematics(model, s)
        held = self._no_geoms
        own = self._robot_mask
        if carried is not None:
            tcp, rot = s.site_xpos[self.site], s.site_xmat[self.site].reshape(3, 3)
            quat = np.empty(4)
            mujoco.mju_mat2Quat(quat, (rot @ carried.rotation).ravel())
            s.qpos[carried.qadr : carried.qadr + 3] = tcp + rot @ carried.offset
            s.qpos[carried.qadr + 3 : carried.qadr + 7] = quat
            mujoco.mj_kinematics(model, s)
            held = np.fromiter(carried.geoms, dtype=np.int64, count=len(carried.geoms))
            own = own.copy()
            own[held] = True
            if filtered:
                robot_side(model, held)  # the held object collides as the robot's geoms do
        try:
            mujoco.mj_collision(model, s)
        finally:
            if filtered and len(held):
                world_side(model, held, self._robot_mask)
        return contact_hits(s, clearance, own, self._robot_mask, self._ignore_mask(ignore))

    def _ignore_mask(self, ignore: set[int]) -> NDArray[np.bool_] | None:
        """Per-geom flags of ``ignore`` (None when empty), made once per set."""
        if not ignore:
            return None
        key = frozenset(ignore)
        mask = self._ignore_masks.get(key)
        if mask is None:
            mask = np.zeros(self.model.ngeom, dtype=bool)
            mask[list(key)] = True
            self._ignore_masks[key] = mask
        return mask


WORLD = (2, 1)
"""(contype, conaffinity) of a world geom in a collision-check model: no world pair collides."""
ROBOT = (1, 3)
"""(contype, conaffinity) of a robot geom there: it collides with the world and itself."""


def robot_only_collisions(model: mujoco.MjModel, robot: NDArray[np.bool_]) -> bool:
    """Give ``model``'s colliding geoms the masks :data:`WORLD` and :data:`ROBOT` (``robot``:
    per-geom flags), so ``mj_collision`` reports only pairs with a robot geom in them: objects
    resting on tables (~35 contacts per check) are never reported. Exact where every geom
    either collides with all others or with none (contype = conaffinity ∈ {0, 1}, as in all
    the benchmark's scenes); other masks are left as they are. Whether it set them."""
    types, affinities = model.geom_contype, model.geom_conaffinity
    if not np.all((types == affinities) & (types <= 1)):
        return False
    world_side(model, np.flatnonzero(~robot), robot)
    robot_side(model, np.flatnonzero(robot))
    return True


def robot_side(model: mujoco.MjModel, geoms: NDArray[np.int64]) -> None:
    """Make ``geoms`` (colliding ones) collide as the robot's (a held object)."""
    solid = geoms[(model.geom_contype[geoms] | model.geom_conaffinity[geoms]) != 0]
    model.geom_contype[solid], model.geom_conaffinity[solid] = ROBOT


def world_side(model: mujoco.MjModel, geoms: NDArray[np.int64], robot: NDArray[np.bool_]) -> None:
    """Make ``geoms`` (colliding, non-robot ones) collide as the world's again."""
    colliding = (model.geom_contype[geoms] | model.geom_conaffinity[geoms]) != 0
    solid = geoms[colliding & ~robot[geoms]]
    model.geom_contype[solid], model.geom_conaffinity[solid] = WORLD


def contact_hits(
    s: mujoco.MjData,
    clearance: float,
    own: NDArray[np.bool_],
    robot: NDArray[np.bool_],
    ignore: NDArray[np.bool_] | None,
) -> tuple[int, ...]:
    """The hits of :meth:`ArmIk.collisions` in ``s``'s contacts, in contact order: for each
    contact within ``clearance`` of an ``own`` geom (the robot's or the held object's) with a
    geom that is neither that nor in ``ignore``, that geom; for each penetrating contact of
    two ``robot`` geoms, the first (per-geom flags)."""
    n = s.ncon
    if n == 0:
        return ()
    geom = s.contact.geom[:n]
    dist = s.contact.dist[:n]
    near = dist <= clearance
    if not near.all():
        geom, dist = geom[near], dist[near]
    mine = own[geom]
    jam = robot[geom[:, 0]] & robot[geom[:, 1]] & (dist <= 0.0)
    other = np.where(mine[:, 0], geom[:, 1], geom[:, 0])
    touch = mine[:, 0] != mine[:, 1]
    if ignore is not None:
        touch &= ~ignore[other]
    return tuple(np.where(jam, geom[:, 0], other)[jam | touch].tolist())


def _state_key(data: mujoco.MjData) -> bytes:
    """The scene state a collision check depends on (joint positions and mocap poses)."""
    key: bytes = data.qpos.tobytes() + data.mocap_pos.tobytes() + data.mocap_quat.tobytes()
    return key
