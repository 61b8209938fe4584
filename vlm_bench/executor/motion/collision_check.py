"""What the robot would touch in a posture it is not in: collision queries on a scratch copy.

A query (:class:`CollisionQuery`) asks which geoms the robot, with given arm angles and the UAV
moved by a :class:`~vlm_bench.executor.motion.base_move.BaseMove`, would touch, other than
those it may (the object to grasp, a handle), with the fingers set to a width and the held
object (:class:`Carried`) moved with the hand; with a clearance, near misses count too.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from functools import cached_property

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.sim.constants import ARM_JOINTS, FINGER_JOINTS, TCP_SITE, UAV_FREEJOINT
from vlm_bench.sim.robot import robot_geom_ids
from vlm_bench.types.base import FloatArray


@dataclass(frozen=True, eq=False)
class Carried:
    """A held object, for collision checks: its free joint's qpos address, its geoms, and its
    pose in the TCP's frame (offset, m, and rotation)."""

    qadr: int
    geoms: set[int]
    offset: FloatArray
    rotation: FloatArray

    @cached_property
    def frozen_geoms(self) -> frozenset[int]:
        """:attr:`geoms` as a hashable set."""
        return frozenset(self.geoms)

    def key(self) -> tuple[int, frozenset[int], bytes, bytes]:
        """Hashable identity of the carried pose (for the collision cache)."""
        return (self.qadr, self.frozen_geoms, self.offset.tobytes(), self.rotation.tobytes())


@dataclass(frozen=True, eq=False)
class CollisionQuery:
    """What a collision check asks besides the arm's angles.

    Attributes:
        ignore: Geoms the robot may touch (the object to grasp or push, a handle).
        gripper: Finger opening to check with (``None``: as they are now).
        base: The UAV's move (``None``: where it is).
        carried: The held object, moved with the hand (``None``: nothing held).
        clearance: Near misses closer than this (m) count as touches.
    """

    ignore: frozenset[int] = field(default_factory=frozenset)
    gripper: float | None = None
    base: BaseMove | None = None
    carried: Carried | None = None
    clearance: float = 0.0

    @staticmethod
    def of(
        ignore: set[int] | frozenset[int],
        gripper: float | None = None,
        base: BaseMove | None = None,
        carried: Carried | None = None,
        clearance: float = 0.0,
    ) -> CollisionQuery:
        """A query ignoring ``ignore`` (any set)."""
        return CollisionQuery(frozenset(ignore), gripper, base, carried, clearance)

    def near(self, clearance: float) -> CollisionQuery:
        """The same query counting near misses closer than ``clearance`` (m)."""
        return CollisionQuery(self.ignore, self.gripper, self.base, self.carried, clearance)

    def key(self) -> tuple[object, ...]:
        """Hashable identity (for the collision cache)."""
        return (
            self.ignore,
            self.gripper,
            None if self.base is None else self.base.key(),
            None if self.carried is None else self.carried.key(),
            self.clearance,
        )


@dataclass(frozen=True)
class _Checker:
    """A model copy collision checks run on, its scratch data, and the per-geom flags of what
    moves with the robot there (its geoms and the held object's, as a list for fast lookup)."""

    model: mujoco.MjModel
    data: mujoco.MjData
    own: list[bool]


class CollisionChecker:
    """Collision queries on one scene, answered on scratch copies of its model.

    Args:
        model: The scene's compiled model.
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self._checkers: dict[tuple[float, frozenset[int]], _Checker] = {}
        self._robot_mask = np.zeros(model.ngeom, dtype=bool)
        self._robot_mask[robot_geom_ids(model)] = True
        self._robot = self._robot_mask.tolist()
        self._finger_qadr = np.array([model.joint(j).qposadr[0] for j in FINGER_JOINTS])
        self._arm_qadr = np.array([model.joint(j).qposadr[0] for j in ARM_JOINTS])
        self._uav_qadr = int(model.joint(UAV_FREEJOINT).qposadr[0])
        self._site = int(model.site(TCP_SITE).id)
        self._state = b""
        self._hits: dict[tuple[object, ...], tuple[int, ...]] = {}
        """Collision checks of the scene state ``_state`` (the planner repeats ~20 % exactly)."""
        self._ignore_flags: dict[frozenset[int], list[bool]] = {}

    def collisions(self, data: mujoco.MjData, q: FloatArray, query: CollisionQuery) -> list[int]:
        """Non-robot geoms the robot would touch with arm angles ``q`` (scene scratch copy, UAV
        moved by ``query.base``), other than those in ``query.ignore``, and a robot geom for
        each contact of the arm with itself or the UAV (MuJoCo leaves out adjacent links);
        with ``query.carried``, the held object moves with the hand and what it would touch
        counts too. With ``query.clearance`` (m), non-robot geoms the robot (or the held
        object) would come closer to than that count as touched (checked on a copy of the
        model whose geoms have that collision margin)."""
        state = _state_key(data)
        if state != self._state:
            self._state = state
            self._hits.clear()
        key = (np.asarray(q, dtype=np.float64).tobytes(), *query.key())
        hits = self._hits.get(key)
        if hits is None:
            hits = self._collide(data, q, query)
            self._hits[key] = hits
        return list(hits)

    def _collide(
        self, data: mujoco.MjData, q: FloatArray, query: CollisionQuery
    ) -> tuple[int, ...]:
        """:meth:`collisions` computed (no cache)."""
        carried = query.carried
        check = self._checker(query.clearance, carried)
        model, s = check.model, check.data
        s.qpos[:] = data.qpos
        if query.base is not None:
            query.base.apply(s.qpos, self._uav_qadr)
        s.qpos[self._arm_qadr] = q
        if query.gripper is not None:
            s.qpos[self._finger_qadr] = query.gripper
        mujoco.mj_kinematics(model, s)
        if carried is not None:
            tcp, rot = s.site_xpos[self._site], s.site_xmat[self._site].reshape(3, 3)
            quat = np.empty(4)
            mujoco.mju_mat2Quat(quat, (rot @ carried.rotation).ravel())
            s.qpos[carried.qadr : carried.qadr + 3] = tcp + rot @ carried.offset
            s.qpos[carried.qadr + 3 : carried.qadr + 7] = quat
            mujoco.mj_kinematics(model, s)
        mujoco.mj_collision(model, s)
        ignore = self._ignore(query.ignore)
        return contact_hits(s, query.clearance, check.own, self._robot, ignore)

    def _checker(self, clearance: float, carried: Carried | None) -> _Checker:
        """The model collision checks with ``clearance`` and ``carried`` in the hand run on: a
        copy of the scene's model (made once per clearance and held object) that cannot report
        a pair of world geoms (see :func:`robot_only_collisions`), where the held object's
        geoms collide as the robot's do, and whose geoms all have ``clearance`` (m) as collision
        margin where it is positive."""
        held = frozenset() if carried is None else carried.frozen_geoms
        key = (clearance, held)
        check = self._checkers.get(key)
        if check is None:
            model = copy.copy(self.model)
            own = self._robot_mask.copy()
            ids = np.fromiter(held, dtype=np.int64, count=len(held))
            own[ids] = True
            if robot_only_collisions(model, self._robot_mask):
                robot_side(model, ids)
            if clearance > 0.0:
                model.geom_margin[:] = np.maximum(model.geom_margin, clearance)
            check = self._checkers[key] = _Checker(model, mujoco.MjData(model), own.tolist())
        return check

    def _ignore(self, ignore: frozenset[int]) -> list[bool] | None:
        """Per-geom flags of ``ignore`` (None when empty), made once per set."""
        if not ignore:
            return None
        flags = self._ignore_flags.get(ignore)
        if flags is None:
            flags = [False] * self.model.ngeom
            for g in ignore:
                flags[g] = True
            self._ignore_flags[ignore] = flags
        return flags


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
    robot_side(model, np.flatnonzero(robot))
    world = np.flatnonzero(~robot & ((types | affinities) != 0))
    model.geom_contype[world], model.geom_conaffinity[world] = WORLD
    return True


def robot_side(model: mujoco.MjModel, geoms: NDArray[np.int64]) -> None:
    """Make ``geoms`` (colliding ones) collide as the robot's (its own, a held object's)."""
    solid = geoms[(model.geom_contype[geoms] | model.geom_conaffinity[geoms]) != 0]
    model.geom_contype[solid], model.geom_conaffinity[solid] = ROBOT


def contact_hits(
    s: mujoco.MjData,
    clearance: float,
    own: list[bool],
    robot: list[bool],
    ignore: list[bool] | None,
) -> tuple[int, ...]:
    """The hits of :meth:`CollisionChecker.collisions` in ``s``'s contacts, in contact order:
    for each contact within ``clearance`` of an ``own`` geom (the robot's or the held object's)
    with a geom that is neither that nor in ``ignore``, that geom; for each penetrating contact
    of two ``robot`` geoms, the first (per-geom flags). A plain loop: a check has a handful of
    contacts, where numpy's per-call cost is most of the time."""
    if s.ncon == 0:
        return ()
    contact = s.contact
    hits = []
    for (g0, g1), dist in zip(contact.geom.tolist(), contact.dist.tolist(), strict=True):
        if not dist <= clearance:
            continue
        if robot[g0] and robot[g1] and dist <= 0.0:
            hits.append(g0)
        elif own[g0] != own[g1]:
            other = g1 if own[g0] else g0
            if ignore is None or not ignore[other]:
                hits.append(other)
    return tuple(hits)


def _state_key(data: mujoco.MjData) -> bytes:
    """The scene state a collision check depends on (joint positions and mocap poses)."""
    key: bytes = data.qpos.tobytes() + data.mocap_pos.tobytes() + data.mocap_quat.tobytes()
    return key
