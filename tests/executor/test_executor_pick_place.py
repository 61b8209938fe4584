"""End-to-end pick and place with real contacts (one known-good episode)."""

from __future__ import annotations

from vlm_bench.episodes.generate import make_episode
from vlm_bench.executor.executor import execute_plan
from vlm_bench.executor.goals import check_goals
from vlm_bench.executor.loop import SimLoop
from vlm_bench.sim.scene import build_scene


def test_gt_plan_container_geometry_bowl_seed0_reaches_goal() -> None:
    episode = make_episode("container_geometry_bowl", 0)
    scene = build_scene(episode)
    result = execute_plan(episode, episode.gt_plan, scene=scene)
    assert result.exec_success, result.failure_reason
    assert [s.status for s in result.steps] == ["ok", "ok", "ok"]
    loop = SimLoop(scene)
    for _ in range(20):  # settle 1 s
        loop.control_step()
    assert check_goals(episode, scene.model, scene.data) == (True,)


def test_place_without_pick_fails_with_reason() -> None:
    episode = make_episode("standard_pick_place", 0)
    plan = [episode.gt_plan[0], episode.gt_plan[2]]
    result = execute_plan(episode, plan)
    assert result.steps[1].status == "failed"
    assert result.failure_reason == "step 1: nothing held"
