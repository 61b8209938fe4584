"""The arm's IK iteration (``IkQp.velocity``) returns ``mink.solve_ik``'s velocity bit for bit,
so IK solutions, and every execution, are what they were with ``solve_ik``."""

from __future__ import annotations

import mink
import mujoco
import numpy as np

from vlm_bench.episodes import get_episode
from vlm_bench.executor.motion.ik import DAMPING, DT, TOP_DOWN_SEED, ArmIk, top_down_rotation
from vlm_bench.executor.step_execution import episode_scene
from vlm_bench.sim.constants import TCP_SITE
from vlm_bench.types.execution import ExecutorConfig


def test_each_iteration_equals_solve_ik_bit_for_bit() -> None:
    scene = episode_scene(get_episode("standard_pick_place", 0), ExecutorConfig())
    mujoco.mj_forward(scene.model, scene.data)
    ik = ArmIk(scene.model)
    rng = np.random.default_rng(0)
    compared = 0
    for trial in range(40):
        seed = np.array(TOP_DOWN_SEED) + rng.normal(0.0, 0.6, 7)
        ik._load(scene.data, np.clip(seed, ik.lo, ik.hi), None)
        tcp = ik.config.get_transform_frame_to_world(TCP_SITE, "site").translation()
        target = tcp + rng.normal(0.0, 0.2, 3)
        rotation = top_down_rotation(rng.uniform(-np.pi, np.pi))
        ik.frame.set_target(
            mink.SE3.from_rotation_and_translation(mink.SO3.from_matrix(rotation), target)
        )
        rest = ik.config.q.copy()
        if trial % 2:
            rest[ik._r_qadr] = np.clip(np.array(TOP_DOWN_SEED), ik.lo, ik.hi)
        ik.posture.set_target(rest)
        for _ in range(5):  # a few iterations along the solve's path
            err = ik.frame.compute_error(ik.config)
            fast = ik.qp.velocity(err, DT)
            reference = mink.solve_ik(
                ik.config, [ik.frame, ik.posture], DT, "daqp", damping=DAMPING, limits=ik.limits
            )
            assert fast.tobytes() == reference.tobytes()
            ik.config.integrate_inplace(reference, DT)
            compared += 1
    assert compared == 200


def test_a_solve_is_the_same_after_a_freeze_and_thaw_of_the_solver() -> None:
    import cloudpickle

    scene = episode_scene(get_episode("standard_pick_place", 0), ExecutorConfig())
    mujoco.mj_forward(scene.model, scene.data)
    ik = ArmIk(scene.model)
    tcp = ik.tcp_at(scene.data, np.array(TOP_DOWN_SEED))
    goal = tcp + np.array([0.05, -0.04, -0.03])
    copy = cloudpickle.loads(cloudpickle.dumps(ik))
    a = ik.solve(scene.data, goal, top_down_rotation(0.3), np.array(TOP_DOWN_SEED))
    b = copy.solve(scene.data, goal, top_down_rotation(0.3), np.array(TOP_DOWN_SEED))
    assert a[0].tobytes() == b[0].tobytes() and a[1] == b[1] and a[1] < 0.05
