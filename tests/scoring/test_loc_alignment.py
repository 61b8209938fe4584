"""S_loc pairing by segment and by order (docs/metrics.md#s_loc); hand-computed, arithmetic in
the comments. Segment k = the UAV moves before the k-th ARM step; the trailing segment = the
moves after the last one. The default, content, matches ARM steps on (skill, object): where
the predicted ARM steps are the GT's, as here unless a test names an alignment, it pairs the
segments as ``segment`` does (tests/scoring/test_loc_content.py has the cases that differ)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

import pytest
from pydantic import ValidationError

from vlm_bench.parsing import parse_plan
from vlm_bench.scoring import loc_credits, score_plan
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.types.scores import PlanScores, ScoringConfig

IDS = ["cube", "basket", "top_drawer", "rubiks_cube"]
D = Direction
Gt = list[UavStep | ArmStep]


def uav(direction: str) -> dict[str, Any]:
    return {"tasktype": "UAV", "direction": direction}


def arm(skill: str, obj: str, target: str | None = None) -> dict[str, Any]:
    step = {"tasktype": "ARM", "skill": skill, "object": obj}
    return step | ({"target": target} if target else {})


def score(pred: list[Any], gt: Sequence[UavStep | ArmStep], **config: Any) -> PlanScores:
    return score_plan(parse_plan(json.dumps(pred), IDS), gt, ScoringConfig(**config))


def credits(pred: list[Any], gt: Sequence[UavStep | ArmStep], alignment: Any) -> list[float]:
    return loc_credits(parse_plan(json.dumps(pred), IDS).steps, gt, 40.0, alignment)


# GT: up, frontleft, pull top_drawer. The prediction forgets the `up`.
DRAWER_GT: Gt = [
    UavStep(direction=D.UP),
    UavStep(direction=D.FRONTLEFT),
    ArmStep(object="top_drawer", skill="pull"),
]
DRAWER_PRED = [uav("frontleft"), arm("pull", "top_drawer")]

# GT: right, pick cube | front, place basket | up, left, pull top_drawer.
THREE_GT: Gt = [
    UavStep(direction=D.RIGHT),
    ArmStep(object="cube", skill="pick"),
    UavStep(direction=D.FRONT),
    ArmStep(object="basket", skill="place"),
    UavStep(direction=D.UP),
    UavStep(direction=D.LEFT),
    ArmStep(object="top_drawer", skill="pull"),
]
THREE_PRED = [
    uav("right"),
    arm("pick", "cube"),
    arm("place", "basket"),
    uav("left"),
    arm("pull", "top_drawer"),
]

PICK_PLACE_GT: Gt = [
    UavStep(direction=D.FRONT),
    ArmStep(object="cube", skill="pick"),
    UavStep(direction=D.LEFT),
    ArmStep(object="basket", skill="place"),
]


def test_drawer_missing_up_by_segment() -> None:
    s = score(DRAWER_PRED, DRAWER_GT, loc_alignment="segment")
    assert s == score(DRAWER_PRED, DRAWER_GT)  # content: the same ARM step
    # Segment 0: GT horizontal [frontleft] vs predicted [frontleft] → 100;
    # GT vertical [up] vs predicted [] → 0. Credits in GT order (up, frontleft) = (0, 100).
    assert s.loc_credit == (0, 100) and s.n_move == 2
    assert s.s_loc == 50  # (0 + 100) / 2
    # K=2, N=3; positions 0 UAV=UAV ✓, 1 ARM≠UAV → M=1.
    # S_plan = 100·[0.5·1/3 + 0.5·(1 − 1/3)] = 50; S_obj = S_skill = 100
    assert s.s_plan == pytest.approx(50)
    assert s.s_total == pytest.approx(0.25 * (50 + 50 + 100 + 100))  # 75


def test_drawer_missing_up_by_order() -> None:
    s = score(DRAWER_PRED, DRAWER_GT, loc_alignment="order")
    # Predicted UAV steps [frontleft]: GT up vs frontleft → 0, GT frontleft vs none → 0.
    assert s.loc_credit == (0, 0) and s.s_loc == 0
    assert s.s_total == pytest.approx(0.25 * (50 + 0 + 100 + 100))  # 62.5


def test_three_segments() -> None:
    # Segments: GT [right] | [front] | [up, left] | [] ; predicted [right] | [] | [left] | [].
    # right–right 100; front–nothing 0; left–left 100 and up–nothing 0 (vertical apart).
    # Credits in GT order (right, front, up, left) = (100, 0, 0, 100) → S_loc = 200/4 = 50
    s = score(THREE_PRED, THREE_GT, loc_alignment="segment")
    assert s.loc_credit == (100, 0, 0, 100) and s.s_loc == 50
    # By order, predicted moves [right, left]: right–right 100, front–left 0 (90°),
    # up–none 0, left–none 0 → 100/4 = 25
    o = score(THREE_PRED, THREE_GT, loc_alignment="order")
    assert o.loc_credit == (100, 0, 0, 0) and o.s_loc == 25
    # Only S_loc depends on the alignment.
    assert (s.s_plan, s.s_obj, s.s_skill) == (o.s_plan, o.s_obj, o.s_skill)


def test_neighbour_credit_within_a_segment() -> None:
    gt: Gt = [UavStep(direction=D.FRONTLEFT), ArmStep(object="cube", skill="pick")]
    pred = [uav("up"), uav("front"), arm("pick", "cube")]
    # Segment: horizontal frontleft vs front (45°) → 40; the predicted up has no GT partner.
    assert score(pred, gt).loc_credit == (40,) and score(pred, gt).s_loc == 40
    assert score(pred, gt, neighbour_credit=25).s_loc == 25
    # Order: frontleft vs the first predicted move, up → 0.
    assert score(pred, gt, loc_alignment="order").s_loc == 0


def test_extra_moves_in_a_segment_cost_nothing_in_s_loc() -> None:
    gt: Gt = [UavStep(direction=D.FRONT), ArmStep(object="cube", skill="pick")]
    s = score([uav("front"), uav("left"), uav("up"), arm("pick", "cube")], gt)
    # front–front 100; left and up have no GT partner: S_loc = 100.
    assert s.loc_credit == (100,) and s.s_loc == 100
    # S_plan pays: K=4, N=2, M=1 (pos 0) → 100·[0.5·1/2 + 0.5·max(0, 1 − 2/2)] = 25
    assert s.s_plan == 25


def test_a_move_in_the_wrong_segment_gets_no_credit() -> None:
    # Both moves before the pick: GT [front] | [left] vs predicted [front, left] | [].
    pred = [uav("front"), uav("left"), arm("pick", "cube"), arm("place", "basket")]
    assert credits(pred, PICK_PLACE_GT, "segment") == [100, 0]  # S_loc 50
    assert credits(pred, PICK_PLACE_GT, "order") == [100, 100]  # S_loc 100
    # The approach move after the ARM step: GT [front] | [] vs predicted [] | [front].
    gt: Gt = [UavStep(direction=D.FRONT), ArmStep(object="cube", skill="pick")]
    late = [arm("pick", "cube"), uav("front")]
    assert score(late, gt).s_loc == 0
    assert score(late, gt, loc_alignment="order").s_loc == 100


def test_gt_segment_without_a_predicted_arm_step_scores_zero() -> None:
    gt: Gt = [*PICK_PLACE_GT, UavStep(direction=D.UP)]
    pred = [uav("front"), arm("pick", "cube"), uav("left"), uav("up")]
    # GT [front] | [left] | trailing [up]; predicted [front] | trailing [left, up].
    # front–front 100; the 2nd GT ARM step has no predicted partner: left → 0;
    # trailing: vertical up–up 100 (the predicted left has no horizontal GT partner).
    assert credits(pred, gt, "segment") == [100, 0, 100]
    # Order: front–front, left–left, up–up.
    assert credits(pred, gt, "order") == [100, 100, 100]


def test_segments_are_matched_by_arm_order_not_content() -> None:
    # The ARM steps are swapped: segment k still pairs with predicted segment k.
    pred = [uav("front"), arm("place", "basket"), uav("left"), arm("pick", "cube")]
    assert credits(pred, PICK_PLACE_GT, "segment") == [100, 100]


def test_invalid_arm_step_separates_and_unknown_tasktype_does_not() -> None:
    # "grip" is no skill: the step is invalid but still ends segment 0.
    pred = [uav("front"), arm("grip", "cube"), uav("left"), arm("place", "basket")]
    assert credits(pred, PICK_PLACE_GT, "segment") == [100, 100]
    # A step of unknown tasktype is neither a move nor a separator.
    boat = {"tasktype": "boat", "skill": "pick", "object": "cube"}
    pred = [uav("front"), boat, arm("pick", "cube"), uav("left"), arm("place", "basket")]
    assert credits(pred, PICK_PLACE_GT, "segment") == [100, 100]


def test_invalid_uav_step_occupies_a_horizontal_slot() -> None:
    gt: Gt = [
        UavStep(direction=D.LEFT),
        UavStep(direction=D.UP),
        UavStep(direction=D.FRONT),
        ArmStep(object="cube", skill="pick"),
    ]
    pred = [uav("towards the cube"), uav("up"), uav("front"), arm("pick", "cube")]
    # Horizontal: GT [left, front] vs predicted [invalid, front] → 0, 100; vertical up–up 100.
    # Credits in GT order (left, up, front) = (0, 100, 100).
    s = score(pred, gt)
    assert s.loc_credit == (0, 100, 100)
    assert s.s_loc == pytest.approx(200 / 3)


def test_invalid_vertical_uav_step_occupies_a_vertical_slot() -> None:
    gt: Gt = [
        UavStep(direction=D.UP),
        UavStep(direction=D.FRONT),
        ArmStep(object="cube", skill="pick"),
    ]
    bad_up = {"tasktype": "UAV", "direction": "up", "skill": "dance"}  # invalid, resolved to up
    pred = [bad_up, uav("front"), arm("pick", "cube")]
    assert not parse_plan(json.dumps(pred), IDS).steps[0].valid
    # Vertical: up vs the invalid up → 0; horizontal: front–front 100.
    assert credits(pred, gt, "segment") == [0, 100]
    # Order: up vs the invalid step → 0, front–front 100.
    assert credits(pred, gt, "order") == [0, 100]


def test_one_credit_per_gt_move_in_gt_order() -> None:
    pred = [uav("down"), arm("pull", "top_drawer")]
    for alignment in ("segment", "order"):
        assert len(credits(pred, THREE_GT, alignment)) == 4
    assert credits([], THREE_GT, "segment") == [0, 0, 0, 0]
    assert credits([], THREE_GT, "order") == [0, 0, 0, 0]


def test_config_default_and_old_configs() -> None:
    assert ScoringConfig().loc_alignment == "content"
    assert ScoringConfig(loc_alignment="order").loc_alignment == "order"
    assert ScoringConfig(loc_alignment="segment").loc_alignment == "segment"
    # A ScoringConfig saved before the field existed loads with the default.
    weights = {"plan": 0.25, "loc": 0.25, "obj": 0.25, "skill": 0.25}
    old = {"alpha": 0.5, "weights": weights, "neighbour_credit": 40.0, "empty_gt": "strict"}
    assert ScoringConfig.model_validate(old).loc_alignment == "content"
    config = ScoringConfig(loc_alignment="order")
    assert ScoringConfig.model_validate_json(config.model_dump_json()) == config
    with pytest.raises(ValidationError):
        ScoringConfig(loc_alignment="hungarian")  # type: ignore[arg-type]


def test_order_reproduces_the_old_credits() -> None:
    # The credits the order pairing gave before the alignment option existed.
    assert score(THREE_PRED, THREE_GT, loc_alignment="order").loc_credit == (100, 0, 0, 0)
    assert score(DRAWER_PRED, DRAWER_GT, loc_alignment="order").loc_credit == (0, 0)
    assert score(DRAWER_PRED, DRAWER_GT).loc_credit == (0, 100)  # the default differs
