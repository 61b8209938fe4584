"""The planner's collision check (``CollisionChecker.collisions``) on its filtered model copy
reports exactly what a check on the full scene reports, and its cache never answers for a
changed scene."""

from __future__ import annotations

import pickle

import mujoco
import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import (
    Carried,
    CollisionChecker,
    CollisionQuery,
)
from vlm_bench.executor.motion.contact_filter import robot_only_collisions
from vlm_bench.executor.motion.ik import ArmIk
from vlm_bench.executor.step_execution import episode_scene
from vlm_bench.sim import constants as c
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.objects.builder_kit import free_joint_name
from vlm_bench.sim.robot import robot_geom_ids
from vlm_bench.types.execution import ExecutorConfig


def _reference(
    ik: ArmIk,
    data: mujoco.MjData,
    q: np.ndarray,
    ignore: set[int],
    gripper: float | None,
    base: BaseMove | None,
    carried: Carried | None,
    clearance: float,
) -> list[int]:
    """The check as it was written first: every contact of the full scene, one by one."""
    model = ik.model
    if clearance > 0:
        model = __import__("copy").copy(ik.model)
        model.geom_margin[:] = np.maximum(model.geom_margin, clearance)
    s = mujoco.MjData(model)
    s.qpos[:] = data.qpos
    if base is not None:
        base.apply(s.qpos, model.joint(c.UAV_FREEJOINT).qposadr[0])
    s.qpos[ik.qadr] = q
    if gripper is not None:
        for name in c.FINGER_JOINTS:
            s.qpos[model.joint(name).qposadr[0]] = gripper
    mujoco.mj_kinematics(model, s)
    held: set[int] = set()
    if carried is not None:
        tcp, rot = s.site_xpos[ik.site], s.site_xmat[ik.site].reshape(3, 3)
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, (rot @ carried.rotation).ravel())
        s.qpos[carried.qadr : carried.qadr + 3] = tcp + rot @ carried.offset
        s.qpos[carried.qadr + 3 : carried.qadr + 7] = quat
        mujoco.mj_kinematics(model, s)
        held = carried.geoms
    mujoco.mj_collision(model, s)
    robot = set(robot_geom_ids(model))
    hits = []
    for i in range(s.ncon):
        dist = float(s.contact.dist[i])
        if dist > clearance:
            continue
        g1, g2 = int(s.contact.geom[i][0]), int(s.contact.geom[i][1])
        r1, r2 = g1 in robot or g1 in held, g2 in robot or g2 in held
        if g1 in robot and g2 in robot:
            if dist <= 0.0:
                hits.append(g1)
        elif r1 != r2:
            other = g2 if r1 else g1
            if other not in ignore:
                hits.append(other)
    return hits


@pytest.mark.parametrize(
    ("task", "held"),
    [("standard_pick_place", None), ("drawer_interaction", None), ("variant_green_nut", "nut")],
)
def test_filtered_check_reports_what_the_full_scene_reports(task: str, held: str | None) -> None:
    episode = get_episode(task, 0)
    scene = episode_scene(episode, ExecutorConfig())
    model, data = scene.model, scene.data
    mujoco.mj_forward(model, data)
    ik, checker = ArmIk(model), CollisionChecker(model)
    rng = np.random.default_rng(0)
    joints = {model.joint(j).name for j in range(model.njnt)}
    movable = [o.id for o in episode.objects if free_joint_name(o.id) in joints]
    name = next((m for m in movable if held and held in m), movable[0])
    geoms = set(subtree_geoms(model, model.body(name).id))
    carried = Carried(
        qadr=int(model.joint(free_joint_name(name)).qposadr[0]),
        geoms=geoms,
        offset=np.array([0.0, 0.0, 0.08]),
        rotation=np.eye(3),
    )
    nonempty = 0
    for trial in range(150):
        q = rng.uniform(ik.lo, ik.hi)
        base = BaseMove(np.array([*rng.uniform(-0.3, 0.3, 2), rng.uniform(-0.6, 0.1)]))
        ignore = set(rng.choice(model.ngeom, 3).tolist()) if trial % 3 == 0 else set()
        args = (
            q,
            ignore,
            [None, c.GRIPPER_OPEN, c.GRIPPER_CLOSED][trial % 3],
            base,
            carried if trial % 2 else None,
            [0.0, 0.0, 0.03][trial % 3],
        )
        expected = _reference(ik, data, *args)
        query = CollisionQuery.of(*args[1:])
        assert checker.collisions(data, q, query) == expected
        assert checker.collisions(data, q, query) == expected  # from the cache
        nonempty += bool(expected)
    assert nonempty >= 5  # the postures do run into things (9 of 150 in version 3's GT)


def test_cache_follows_the_scene() -> None:
    episode = get_episode("standard_pick_place", 0)
    scene = episode_scene(episode, ExecutorConfig())
    model, data = scene.model, scene.data
    mujoco.mj_forward(model, data)
    ik, checker = ArmIk(model), CollisionChecker(model)
    q = np.asarray(ik.lo + ik.hi) / 2
    low = BaseMove.vertical(-5.0)  # the UAV moved into the floor: the robot hits it
    query = CollisionQuery.of(set(), None, low)
    assert checker.collisions(data, q, query)
    uav = model.joint(c.UAV_FREEJOINT).qposadr[0]
    data.qpos[uav + 2] += 10.0  # the scene changed: the same call must not answer from cache
    assert checker.collisions(data, q, query) == _reference(
        ik, data, q, set(), None, low, None, 0.0
    )


def test_world_pairs_are_never_reported() -> None:
    episode = get_episode("standard_pick_place", 0)
    scene = episode_scene(episode, ExecutorConfig())
    model = __import__("copy").copy(scene.model)
    model.opt.enableflags &= ~int(mujoco.mjtEnableBit.mjENBL_SLEEP)  # resting objects report
    data = mujoco.MjData(model)
    data.qpos[:] = scene.data.qpos
    for _ in range(250):  # the objects settle onto their tables
        mujoco.mj_step(model, data)
    robot = np.zeros(model.ngeom, dtype=bool)
    robot[robot_geom_ids(model)] = True
    mujoco.mj_collision(model, data)
    full = data.ncon
    world_pairs = int(np.sum(~robot[data.contact.geom[:full]].any(axis=1)))
    assert world_pairs > 5  # objects rest on tables
    assert robot_only_collisions(model, robot)
    mujoco.mj_collision(model, data)
    assert not np.any(~robot[data.contact.geom[: data.ncon]].any(axis=1))


def test_a_pickled_checker_writes_its_own_scratch_data() -> None:
    """A live episode's snapshot pickles the checker: the views it caches into its scratch data
    must follow the unpickled data, not stay copies of the old one."""
    episode = get_episode("variant_green_nut", 0)
    scene = episode_scene(episode, ExecutorConfig())
    model, data = scene.model, scene.data
    mujoco.mj_forward(model, data)
    ik, checker = ArmIk(model), CollisionChecker(model)
    name = next(o.id for o in episode.objects if "nut" in o.id)
    carried = Carried(
        qadr=int(model.joint(free_joint_name(name)).qposadr[0]),
        geoms=set(subtree_geoms(model, model.body(name).id)),
        offset=np.array([0.0, 0.0, 0.08]),
        rotation=np.eye(3),
    )
    rng = np.random.default_rng(3)
    postures = [rng.uniform(ik.lo, ik.hi) for _ in range(40)]
    low = BaseMove(np.array([0.0, 0.0, -0.4]))
    for q in postures[:5]:  # the views are made and used before the pickle
        checker.collisions(data, q, CollisionQuery.of(set(), None, low, carried))
    thawed = pickle.loads(pickle.dumps(checker))
    nonempty = 0
    for q in postures[5:]:
        expected = _reference(ik, data, q, set(), None, low, carried, 0.0)
        assert thawed.collisions(data, q, CollisionQuery.of(set(), None, low, carried)) == expected
        nonempty += bool(expected)
    assert nonempty > 3
