"""push slides objects by finger contact: next to a target, or off their support."""

from __future__ import annotations

import pytest
from incidents import incident_episode

from vlm_bench.episodes import get_episode
from vlm_bench.executor import execute_plan
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep


@pytest.fixture(scope="module")
def push_cube() -> Episode:
    return get_episode("non_prehensile_push_cube", 0)


def test_push_next_to_target_moves_the_cube_without_lifting_it(push_cube: Episode) -> None:
    heights: list[float] = []
    result = execute_plan(
        push_cube,
        push_cube.gt_plan,
        observers=[lambda loop: heights.append(float(loop.data.body("blue_cube").xpos[2]))],
    )
    assert result.exec_success, result.failure_reason
    assert max(heights) - min(heights) < 0.01  # slid, never lifted
    assert result.displacement.get("yellow_basket", 0.0) < 0.01  # the distractor stays


def test_pushing_towards_the_distractor_misses_the_goal(push_cube: Episode) -> None:
    move, _ = push_cube.gt_plan
    plan = [move, ArmStep(object="blue_cube", skill="push", target="yellow_basket")]
    result = execute_plan(push_cube, plan)
    assert result.goals == (False,) and not result.exec_success


@pytest.mark.parametrize(
    ("step", "reason"),
    [
        (ArmStep(object="table", skill="push"), "table cannot be pushed"),
        (ArmStep(object="ghost", skill="push"), "unknown object 'ghost'"),
    ],
)
def test_push_of_what_cannot_move_fails_with_a_reason(
    push_cube: Episode, step: ArmStep, reason: str
) -> None:
    result = execute_plan(push_cube, [push_cube.gt_plan[0], step])
    assert result.failure_reason == f"step 1: {reason}"


def test_push_without_target_takes_the_box_off_the_table() -> None:
    episode = get_episode("clear_desk_push_box", 0)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason
    assert result.displacement["white_box"] < 0.01  # the look-alike stays


def test_the_way_down_to_a_push_keeps_off_the_cube() -> None:
    """preposition_by_dont seed 3: the only plan tried from the UAV's pose swept the arm
    across the table and knocked the cube 0.16 m aside before the push began (it then moved
    0.06 m the wrong way). Clear plans from other UAV poses now come first."""
    episode = incident_episode("preposition_by_dont", 3)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason
    assert result.goals == (True,)


def test_a_push_stroke_is_planned_along_the_line_the_hand_takes() -> None:
    """abstract_intent_clear seed 7: the stroke was planned from its end posture alone; IK
    lost the line halfway, the UAV carried the hand the rest of the way, drifted 3 cm sideways
    and slid it past the box, which stayed on the table. The stroke's line is now previewed,
    and where IK cannot follow it the UAV carries the hand from the start."""
    episode = incident_episode("abstract_intent_clear", 7)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason
    assert result.goals == (True,)


def test_a_push_from_a_low_uav_behind_the_object_is_planned_from_higher() -> None:
    """Version 3's non_prehensile_push_cube seed 0: the UAV flies back to the cube and waits
    6 cm below version 2's altitude; no stroke is reachable from there or lower, one from 6 cm
    higher is (``Pusher._assists`` tries higher last)."""
    episode = get_episode("non_prehensile_push_cube", 0)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason
