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
from vlm_bench.executor.motion.contact_filter import (
    HELD,
    contact_hits,
    robot_only_collisions,
    robot_side,
)
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


@dataclass(frozen=True)
class _Views:
    """Views into a checker's scratch data: its qpos and the TCP's position and rotation."""

    data: mujoco.MjData
    qpos: FloatArray
    tcp_pos: FloatArray
    tcp_mat: FloatArray


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
        self._arm = _index(self._arm_qadr)
        self._fingers = _index(self._finger_qadr)
        self._views: dict[int, _Views] = {}

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
        v = self._scratch_views(check)
        qpos = v.qpos
        qpos[:] = data.qpos
        if query.base is not None:
            query.base.apply(qpos, self._uav_qadr)
        qpos[self._arm] = q
        if query.gripper is not None:
            qpos[self._fingers] = query.gripper
        mujoco.mj_kinematics(model, s)
        if carried is not None:
            tcp, rot, a = v.tcp_pos, v.tcp_mat, carried.qadr
            mujoco.mju_mat2Quat(qpos[a + 3 : a + 7], (rot @ carried.rotation).ravel())
            np.add(tcp, rot @ carried.offset, out=qpos[a : a + 3])
            mujoco.mj_kinematics(model, s)
        mujoco.mj_collision(model, s)
        ignore = self._ignore(query.ignore)
        return contact_hits(s, query.clearance, check.own, self._robot, ignore)

    def _scratch_views(self, check: _Checker) -> _Views:
        """The views of ``check.data`` :meth:`_collide` writes and reads (made once per
        checker; a pickle copies a view, so they are not pickled)."""
        views = self._views.get(id(check))
        if views is None or views.data is not check.data:
            s = check.data
            views = self._views[id(check)] = _Views(
                s, s.qpos, s.site_xpos[self._site], s.site_xmat[self._site].reshape(3, 3)
            )
        return views

    def __getstate__(self) -> dict[str, object]:
        """Pickled without the scratch views (made again on first use)."""
        return {**self.__dict__, "_views": {}}

    def _checker(self, clearance: float, carried: Carried | None) -> _Checker:
        """The model collision checks with ``clearance`` and ``carried`` in the hand run on: a
        copy of the scene's model (made once per clearance and held object) that cannot report
        a pair of world geoms (see :func:`robot_only_collisions`), where the held object's
        geoms collide with the world's (not with the hand holding it: :data:`HELD`), and whose
        geoms all have ``clearance`` (m) as collision margin where it is positive."""
        held = frozenset() if carried is None else carried.frozen_geoms
        key = (clearance, held)
        check = self._checkers.get(key)
        if check is None:
            model = copy.copy(self.model)
            own = self._robot_mask.copy()
            ids = np.fromiter(held, dtype=np.int64, count=len(held))
            own[ids] = True
            if robot_only_collisions(model, self._robot_mask):
                robot_side(model, ids, HELD)
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


def _index(adr: NDArray[np.int64]) -> slice | NDArray[np.int64]:
    """``adr`` as a slice where it is a run of consecutive addresses (a view, no gather)."""
    if len(adr) and np.array_equal(adr, np.arange(adr[0], adr[0] + len(adr))):
        return slice(int(adr[0]), int(adr[0]) + len(adr))
    return adr


def _state_key(data: mujoco.MjData) -> bytes:
    """The scene state a collision check depends on (joint positions and mocap poses)."""
    key: bytes = data.qpos.tobytes() + data.mocap_pos.tobytes() + data.mocap_quat.tobytes()
    return key
