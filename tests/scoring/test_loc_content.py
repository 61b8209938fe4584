"""S_loc with ARM steps matched by content (the default, docs/metrics.md#s_loc): a longest
common subsequence on (skill, object). Hand-computed; arithmetic in the comments."""

from __future__ import annotations

import json
from typing import Any

import pytest

from vlm_bench.parsing import parse_plan
from vlm_bench.scoring import common_subsequence, loc_credits, score_plan
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.types.scores import PlanScores, ScoringConfig

IDS = ["cube", "basket", "top_drawer"]
D = Direction
Gt = list[UavStep | ArmStep]


def uav(direction: str) -> dict[str, Any]:
    return {"tasktype": "UAV", "direction": direction}


def arm(skill: str, obj: str) -> dict[str, Any]:
    return {"tasktype": "ARM", "skill": skill, "object": obj}


def score(pred: list[Any], gt: Gt, **config: Any) -> PlanScores:
    return score_plan(parse_plan(json.dumps(pred), IDS), gt, ScoringConfig(**config))


def credits(pred: list[Any], gt: Gt, alignment: Any) -> list[float]:
    return loc_credits(parse_plan(json.dumps(pred), IDS).steps, gt, 40.0, alignment)


# GT: right, pick cube | front, place basket | left, pull top_drawer.
GT: Gt = [
    UavStep(direction=D.RIGHT),
    ArmStep(object="cube", skill="pick"),
    UavStep(direction=D.FRONT),
    ArmStep(object="basket", skill="place"),
    UavStep(direction=D.LEFT),
    ArmStep(object="top_drawer", skill="pull"),
]


def test_one_extra_arm_step_with_every_move_right_scores_100() -> None:
    pred = [
        uav("right"),
        arm("pick", "cube"),
        arm("pull", "top_drawer"),  # extra
        uav("front"),
        arm("place", "basket"),
        uav("left"),
        arm("pull", "top_drawer"),
    ]
    # Content: GT ARM keys (pick cube, place basket, pull drawer) vs predicted (pick cube,
    # pull drawer, place basket, pull drawer): LCS 3 = predicted 0, 2, 3. Segments: [right] vs
    # [right] 100; [front] vs [front] (before predicted ARM 2) 100; [left] vs [left] 100.
    s = score(pred, GT)
    assert s.loc_credit == (100, 100, 100) and s.s_loc == 100
    # Segment (k-th with k-th): [right]–[right] 100, [front]–[] 0, [left]–[front] 0 (90°)
    # → 100/3 = 33.3, the shift the content alignment removes.
    assert score(pred, GT, loc_alignment="segment").s_loc == pytest.approx(100 / 3)
    assert score(pred, GT, loc_alignment="order").s_loc == 100


def test_one_missing_arm_step_loses_only_its_segments_moves() -> None:
    pred = [uav("right"), arm("pick", "cube"), uav("left"), arm("pull", "top_drawer")]
    # Content: pick cube → predicted 0, place basket → none, pull drawer → predicted 1.
    # [right]–[right] 100; the place segment [front] scores 0; [left]–[left] 100 → 200/3.
    s = score(pred, GT)
    assert s.loc_credit == (100, 0, 100) and s.s_loc == pytest.approx(200 / 3)
    # Segment: [front]–[left] 0 and the 3rd GT ARM step has no 3rd predicted one: 0 → 100/3.
    assert credits(pred, GT, "segment") == [100, 0, 0]


def test_swapped_arm_steps_keep_only_the_earliest_gt_match() -> None:
    gt: Gt = GT[:4]  # right, pick cube | front, place basket
    pred = [uav("front"), arm("place", "basket"), uav("right"), arm("pick", "cube")]
    # LCS 1 either way; ties go to the earliest GT step: pick cube ↔ predicted 1, whose moves
    # are [right] → 100; place basket is unmatched → its [front] scores 0.
    assert credits(pred, gt, "content") == [100, 0]
    # Segment pairs by order, whatever the content: [right]–[front] 0, [front]–[right] 0.
    assert credits(pred, gt, "segment") == [0, 0]


def test_an_invalid_arm_step_matches_nothing_but_separates() -> None:
    gt: Gt = GT[:4]
    # "grip" is no skill: the step is invalid, matches no GT step, and ends a segment.
    pred = [uav("right"), arm("grip", "cube"), uav("front"), arm("place", "basket")]
    assert credits(pred, gt, "content") == [0, 100]
    assert credits(pred, gt, "segment") == [100, 100]


def test_the_trailing_segments_meet_whatever_the_arm_steps() -> None:
    gt: Gt = [*GT[:2], UavStep(direction=D.UP)]  # right, pick cube | trailing up
    pred = [uav("right"), arm("place", "basket"), uav("up")]
    # pick cube is unmatched: right → 0; trailing up–up 100.
    assert credits(pred, gt, "content") == [0, 100]


def test_content_equals_segment_when_the_arm_steps_are_the_gts() -> None:
    pred = [uav("front"), uav("up"), arm("pick", "cube"), uav("frontleft"), arm("place", "basket")]
    pred += [uav("left"), arm("pull", "top_drawer"), uav("down")]
    # [right]–[front] 0 (90°, the up has no GT partner); [front]–[frontleft] 40; [left]–[left].
    assert credits(pred, GT, "content") == credits(pred, GT, "segment") == [0, 40, 100]


def test_common_subsequence_ties_go_to_the_earliest_pairs() -> None:
    assert common_subsequence(["a", "b"], ["b", "a"]) == [1, -1]
    assert common_subsequence(["a"], ["a", "a"]) == [0]
    assert common_subsequence(["a", "a"], ["a"]) == [0, -1]
    assert common_subsequence(["a", "b", "c"], ["x", "a", "c", "b", "c"]) == [1, 3, 4]
    assert common_subsequence(["a"], [None]) == [-1]  # None matches nothing
    assert common_subsequence([], ["a"]) == [] and common_subsequence(["a"], []) == [-1]


def test_default_is_content() -> None:
    assert ScoringConfig().loc_alignment == "content"
    assert score([], GT).loc_credit == (0, 0, 0)


def test_a_repeated_arm_step_is_matched_at_its_first_occurrence() -> None:
    gt: Gt = [UavStep(direction=D.FRONT), ArmStep(object="cube", skill="pick")]
    pred = [arm("pick", "cube"), uav("front"), arm("pick", "cube")]
    # Ties go to the earliest: the GT pick meets the first predicted pick, whose segment is
    # empty → front 0 (docs/metrics.md states this price of the tie rule).
    assert credits(pred, gt, "content") == [0]
