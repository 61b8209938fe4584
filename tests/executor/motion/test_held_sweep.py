"""A UAV move a skill makes with an object in the hand counts what the arm, held out, sweeps
on the way (docs/decisions.md, "A skill's UAV move with an object in the hand")."""

from __future__ import annotations

from vlm_bench.episodes import get_episode
from vlm_bench.executor import execute_plan


def test_the_held_arm_does_not_drag_the_plate_out_from_under_the_release() -> None:
    # The banana lies 0.2 m beside the plate; the arm holding it low over the plate's rim
    # dragged the plate 0.14 m aside while the UAV moved for the release.
    episode = get_episode("irregular_on_plate", 5)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason
