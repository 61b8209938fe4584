"""What is left after a failed round, as the rules planner and the blind floor read it."""

from __future__ import annotations

from vlm_bench.rules import remaining_arm_steps
from vlm_bench.types.plan import ArmStep, Direction, UavStep

PICK_A = ArmStep(object="a", skill="pick")
PLACE_B = ArmStep(object="b", skill="place")
PICK_C = ArmStep(object="c", skill="pick")
PLACE_D = ArmStep(object="d", skill="place")
GT = [PICK_A, PLACE_B, PICK_C, PLACE_D]
MOVE = UavStep(direction=Direction.FRONT)


def test_nothing_done_leaves_everything() -> None:
    assert remaining_arm_steps(GT, [MOVE], None) == (0, GT)


def test_done_steps_are_matched_in_order() -> None:
    assert remaining_arm_steps(GT, [MOVE, PICK_A, MOVE, PLACE_B], None) == (2, GT[2:])
    assert remaining_arm_steps(GT, [PICK_A], "a") == (1, GT[1:])


def test_a_slipped_object_is_picked_again() -> None:
    assert remaining_arm_steps(GT, [PICK_A, PLACE_B, PICK_C, MOVE], None) == (2, GT[2:])


def test_all_done_but_incomplete_redoes_from_the_last_pick() -> None:
    assert remaining_arm_steps(GT, GT, None) == (2, GT[2:])
    push = [ArmStep(object="a", skill="push")]
    assert remaining_arm_steps(push, push, None) == (0, push)


def test_steps_not_in_the_gt_do_not_count() -> None:
    wrong = ArmStep(object="x", skill="pick")
    assert remaining_arm_steps(GT, [wrong, PLACE_B], None) == (0, GT)
