"""UAV moves: the executor's stopping rule lands GT plans where the GT expects them."""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.episodes.gt_builder import DRAWER_PULL
from vlm_bench.executor.live_episode import execute_plan
from vlm_bench.executor.motion.uav_moves import move_target
from vlm_bench.executor.references import Reference, StepReferences
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.executor.skills.grasping import grasp_skills
from vlm_bench.executor.step_execution import execute_move, next_arm_step
from vlm_bench.sim.constants import part_joint
from vlm_bench.sim.scene import build_scene
from vlm_bench.types.geometry import APPROACH
from vlm_bench.types.plan import ArmStep, Direction, UavStep

GT_TOL = 0.05  # m

# Episodes whose GT flights are collision-free (some others clip baskets/boxes on tables with
# the stowed arm, which hangs 0.49 m below the UAV; see the executor report).
CASES = [
    ("standard_pick_place", 0),
    ("standard_pick_place", 1),
    ("standard_pick_place", 2),
    ("drawer_interaction", 0),
    ("drawer_interaction", 2),
    ("spatial_ref_top_drawer", 1),
    ("hybrid_interaction_stove", 1),
]


@pytest.mark.parametrize(("task", "seed"), CASES)
def test_gt_moves_end_at_gt_poses(task: str, seed: int) -> None:
    episode = get_episode(task, seed)
    scene = build_scene(episode)
    loop = SimLoop(scene)
    refs = StepReferences(episode, scene.model)
    plan = episode.gt_plan
    checked = 0
    for index, step in enumerate(plan):
        if isinstance(step, UavStep):
            execute_move(loop, refs, step, next_arm_step(plan, index))
            expected = np.array(episode.gt_uav_poses[index].pos)
            error = float(np.linalg.norm(loop.uav_position() - expected))
            assert error < GT_TOL, f"step {index} {step.direction}: {error:.3f} m from GT"
            assert loop.take_collisions() == ()
            checked += 1
        elif step.skill in ("pull", "close"):
            # ARM skills are not executed here; only the drawer state that later moves depend on.
            adr = scene.model.joint(part_joint(step.object)).qposadr[0]
            scene.data.qpos[adr] = DRAWER_PULL if step.skill == "pull" else 0.0
            mujoco.mj_forward(scene.model, scene.data)
            loop.take_collisions()
        elif step.skill == "pick":
            loop.held = step.object  # the place that follows approaches the held object's rest
    assert checked >= 1
    assert abs(loop.uav_yaw_deg() - episode.uav_start.yaw_deg) < 1.0


REF = Reference(x=2.0, y=0.5, z=0.8, standoff=0.4)


def test_move_target_distance_default_and_max() -> None:
    start = np.array([0.0, 0.0, 1.4])
    end = move_target(start, 90.0, UavStep(direction=Direction.FRONT, distance=0.7), REF)
    assert np.allclose(end, [0.0, 0.7, 1.4])
    end = move_target(start, 0.0, UavStep(direction=Direction.LEFT), None)
    assert np.allclose(end, [0.0, APPROACH.default_move, 1.4])
    end = move_target(start, 0.0, UavStep(direction=Direction.BACK, distance=9.0), None)
    assert np.allclose(end, [-APPROACH.max_move, 0.0, 1.4])


def test_move_target_stops_at_standoff_and_altitude() -> None:
    start = np.array([0.0, 0.5, APPROACH.operating_altitude(REF.z) + 0.3])
    end = move_target(start, 0.0, UavStep(direction=Direction.FRONT), REF)
    assert math.isclose(end[0], 2.0 - REF.standoff) and math.isclose(end[1], 0.5)
    down = move_target(start, 0.0, UavStep(direction=Direction.DOWN), REF)
    assert math.isclose(down[2], APPROACH.operating_altitude(REF.z))
    up = move_target(start, 0.0, UavStep(direction=Direction.UP), REF)  # wrong way: no travel
    assert math.isclose(up[2], start[2])
    away = move_target(start, 0.0, UavStep(direction=Direction.BACK), REF)  # never closer
    assert np.allclose(away, start)


def test_execute_plan_fails_unavailable_skill_and_skips_rest() -> None:
    """A skill set without ``push`` (e.g. a user's policy skills) fails that step."""
    episode = get_episode("standard_pick_place", 0)
    plan = [
        UavStep(direction=Direction.UP, distance=0.1),
        ArmStep(object="gray_cube", skill="push"),
        UavStep(direction=Direction.DOWN, distance=0.1),
    ]
    result = execute_plan(episode, plan, arm_skills=grasp_skills)
    assert [s.status for s in result.steps] == ["ok", "failed", "skipped"]
    assert result.n_steps_done == 1 and not result.exec_success
    assert result.failure_reason is not None and "push" in result.failure_reason
    assert abs(result.final_uav_pose.pos[2] - (episode.uav_start.pos[2] + 0.1)) < 0.02
    assert result.sim_time_s > 0.5


def test_instability_is_a_failed_result(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """...and MuJoCo's warning about it goes to the log, not to MUJOCO_LOG.TXT in the working
    folder of a user who called the executor from Python (MuJoCo's defaults restored first)."""
    monkeypatch.chdir(tmp_path)
    mujoco.set_mju_user_warning(None)
    defaults = mujoco.MjLogConfig.get()
    defaults.logto_file = True
    defaults.set()
    episode = get_episode("standard_pick_place", 0)
    scene = build_scene(episode)
    scene.data.qvel[:] = np.nan
    result = execute_plan(episode, [UavStep(direction=Direction.UP)], scene=scene)
    assert result.steps[0].status == "failed"
    assert result.failure_reason == "step 0: simulator unstable"
    assert list(tmp_path.iterdir()) == []
