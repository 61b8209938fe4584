"""A knob the GT's stand-off leaves close under the arm base, behind the UAV's heading, is
turned (docs/decisions.md, "A knob is turned from the reach planner's UAV assists")."""

from __future__ import annotations

from vlm_bench.episodes import get_episode
from vlm_bench.executor import execute_plan


def test_a_knob_close_under_the_arm_base_is_turned() -> None:
    episode = get_episode("hybrid_interaction_stove", 8)
    knob_step = next(
        i for i, s in enumerate(episode.gt_plan) if getattr(s, "skill", "") == "rotate"
    )
    result = execute_plan(episode, episode.gt_plan[: knob_step + 1])
    assert result.steps_ok, result.failure_reason
