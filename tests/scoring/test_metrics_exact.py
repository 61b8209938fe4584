"""Hand-computed metric values (docs/design.md#metrics); the arithmetic is in the comments."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

import pytest
from pydantic import ValidationError

from vlm_bench.errors import ConfigError
from vlm_bench.parsing import parse_plan
from vlm_bench.scoring import direction_credit, plan_score, score_plan
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.types.scores import EmptyGtPolicy, ErrorType, PlanScores, ScoreWeights, ScoringConfig

IDS = ["rubiks_cube", "cube", "basket", "yellow_basket"]
D = Direction


def uav(direction: str) -> dict[str, Any]:
    return {"tasktype": "UAV", "direction": direction}


def arm(skill: str, obj: str, target: str | None = None) -> dict[str, Any]:
    step = {"tasktype": "ARM", "skill": skill, "object": obj}
    return step | ({"target": target} if target else {})


def score(pred: list[Any], gt: Sequence[UavStep | ArmStep], **config: Any) -> PlanScores:
    return score_plan(parse_plan(json.dumps(pred), IDS), gt, ScoringConfig(**config))


PAPER_GT: list[UavStep | ArmStep] = [
    UavStep(direction=D.FRONTLEFT),
    ArmStep(object="rubiks_cube", skill="pick"),
]
# N = 3: front, pick cube, place basket.
GT3: list[UavStep | ArmStep] = [
    UavStep(direction=D.FRONT),
    ArmStep(object="cube", skill="pick"),
    ArmStep(object="basket", skill="place"),
]


def test_paper_example_against_itself() -> None:
    s = score([uav("frontleft"), arm("pick", "rubiks_cube")], PAPER_GT)
    assert (s.s_plan, s.s_loc, s.s_obj, s.s_skill, s.s_total) == (100, 100, 100, 100, 100)
    assert s.succ and s.error_types == ()
    assert (s.m, s.k, s.n, s.n_move, s.m_obj, s.k_obj, s.n_obj, s.m_skill, s.n_skill) == (
        2,
        2,
        2,
        1,
        1,
        0,
        1,
        1,
        1,
    )


def test_missing_uav_step() -> None:
    s = score([arm("pick", "rubiks_cube")], PAPER_GT)
    # K=1, N=2; position 0: ARM vs UAV → M=0.
    # S_plan = 100·[0.5·0/2 + 0.5·max(0, 1 − |1−2|/2)] = 100·0.25 = 25
    assert (s.m, s.k, s.n) == (0, 1, 2)
    assert s.s_plan == 25
    assert s.s_loc == 0  # the only GT move has no predicted UAV step
    assert s.s_obj == 100 and s.s_skill == 100  # {rubiks_cube}, {pick} fully covered
    assert s.s_total == pytest.approx(0.25 * (25 + 0 + 100 + 100))  # 56.25
    assert not s.succ
    assert s.error_types == (ErrorType.MISSING_STEP, ErrorType.MISSING_APPROACH)


@pytest.mark.parametrize(
    ("gt", "pred", "credit"),
    [
        (D.FRONTLEFT, "front", 40),  # 45° apart
        (D.FRONTLEFT, "left", 40),
        (D.FRONTRIGHT, "front", 40),  # wraps around 0°/315°
        (D.FRONT, "frontright", 40),
        (D.BACK, "backright", 40),
        (D.FRONTLEFT, "backleft", 0),  # 90°
        (D.FRONT, "left", 0),
        (D.FRONT, "back", 0),  # 180°
        (D.UP, "down", 0),
        (D.UP, "up", 100),
        (D.UP, "front", 0),  # up/down only match themselves
        (D.FRONT, "up", 0),
    ],
)
def test_direction_credit(gt: Direction, pred: str, credit: float) -> None:
    s = score([uav(pred), arm("pick", "rubiks_cube")], [UavStep(direction=gt), PAPER_GT[1]])
    assert s.s_loc == credit and s.loc_credit == (credit,)
    # S_plan, S_obj, S_skill are 100: S_total = 0.25·(300 + credit)
    assert s.s_total == pytest.approx(0.25 * (300 + credit))
    assert s.succ is (credit == 100)
    assert (ErrorType.WRONG_DIRECTION in s.error_types) is (credit < 100)


def test_neighbour_credit_is_configurable() -> None:
    assert direction_credit(D.FRONT, D.FRONTRIGHT, neighbour=50) == 50
    s = score([uav("front"), arm("pick", "rubiks_cube")], PAPER_GT, neighbour_credit=25)
    assert s.s_loc == 25


def test_hallucinated_object() -> None:
    gt: list[UavStep | ArmStep] = [
        UavStep(direction=D.LEFT),
        ArmStep(object="cube", skill="pick"),
        UavStep(direction=D.FRONT),
        ArmStep(object="basket", skill="place"),
    ]
    parsed = parse_plan(
        json.dumps([uav("left"), arm("pick", "cube"), uav("front"), arm("place", "ghost")]), IDS
    )
    assert parsed.steps[3].valid  # a hallucination keeps the step valid
    s = score_plan(parsed, gt)
    # R = {cube, basket}, Q = {cube, ghost}: M_obj = 1, K_obj = 2 − 1 = 1, N_obj = 2
    # S_obj = 100·max(0, (1 − 1)/2) = 0
    assert (s.m_obj, s.k_obj, s.n_obj) == (1, 1, 2)
    assert s.s_obj == 0
    assert s.s_plan == 100 and s.s_skill == 100
    # S_loc (content): "place ghost" matches no GT ARM step, so the GT move before "place
    # basket" has no partner segment: credits (100, 0) → 50. By segment (order of ARM steps): 100.
    assert s.loc_credit == (100, 0) and s.s_loc == 50
    assert s.s_total == 0.25 * (100 + 50 + 0 + 100)  # 62.5
    assert score_plan(parsed, gt, ScoringConfig(loc_alignment="segment")).s_loc == 100
    assert s.error_types == (ErrorType.WRONG_OBJECT,)


def test_extra_steps_k5_n3() -> None:
    pred = [
        uav("front"),
        arm("pick", "cube"),
        arm("place", "basket"),
        uav("up"),
        arm("push", "cube"),
    ]
    s = score(pred, GT3)
    # K=5, N=3, M=3 (the first three positions match).
    # S_plan = 100·[0.5·3/3 + 0.5·max(0, 1 − 2/3)] = 100·(0.5 + 1/6) = 66.67
    assert (s.m, s.k, s.n) == (3, 5, 3)
    assert s.s_plan == pytest.approx(100 * (0.5 + 0.5 / 3))
    # Q = {cube, basket, cube}, R = {cube, basket}: M_obj = 2, K_obj = 1 → 100·(2−1)/2 = 50
    assert (s.m_obj, s.k_obj, s.n_obj) == (2, 1, 2) and s.s_obj == 50
    assert s.s_skill == 100 and s.s_loc == 100  # {pick, place} covered; first move is front
    assert s.s_total == pytest.approx(0.25 * (100 * (0.5 + 0.5 / 3) + 100 + 50 + 100))
    assert not s.succ and s.error_types == (ErrorType.EXTRA_STEP,)


def test_length_term_floors_at_zero() -> None:
    # K=7, N=3: max(0, 1 − 4/3) = 0; M=3 → S_plan = 100·0.5·3/3 = 50
    pred = [uav("front"), arm("pick", "cube"), arm("place", "basket")] + [uav("up")] * 4
    assert score(pred, GT3).s_plan == 50
    assert plan_score(m=3, k=7, n=3) == 50


def test_alpha_is_configurable() -> None:
    # α = 1: S_plan = 100·M/N = 100·0/2 (missing UAV step shifts the types)
    assert score([arm("pick", "rubiks_cube")], PAPER_GT, alpha=1.0).s_plan == 0
    # α = 0: only length: 100·(1 − 1/2) = 50
    assert score([arm("pick", "rubiks_cube")], PAPER_GT, alpha=0.0).s_plan == 50


def test_invalid_step_counts_toward_k_and_matches_nothing() -> None:
    pred = [uav("front"), arm("grip", "cube"), arm("place", "basket")]  # "grip" is no skill
    s = score(pred, GT3)
    # K=3, N=3; position 1 is invalid → M = 2.
    # S_plan = 100·[0.5·2/3 + 0.5·1] = 83.33
    assert (s.m, s.k) == (2, 3)
    assert s.s_plan == pytest.approx(100 * (1 / 3 + 0.5))
    # The invalid step's "cube" counts against: Q = {basket (valid), cube (invalid)}
    # M_obj = |{basket} ∩ {cube, basket}| = 1, K_obj = 2 − 1 = 1 → S_obj = 100·0/2 = 0
    assert (s.m_obj, s.k_obj) == (1, 1) and s.s_obj == 0
    # Valid ARM skills {place} cover 1 of {pick, place} → 50
    assert (s.m_skill, s.n_skill) == (1, 2) and s.s_skill == 50
    # S_loc (content): the invalid step matches no GT ARM step, so "front" (before the GT
    # pick) has no partner → 0. By segment the invalid step is the 1st ARM step → 100.
    assert s.s_loc == 0 and score(pred, GT3, loc_alignment="segment").s_loc == 100
    assert s.s_total == pytest.approx(0.25 * (100 * (1 / 3 + 0.5) + 0 + 0 + 50))
    assert s.error_types == (ErrorType.WRONG_SKILL,)


def test_unknown_tasktype_step_in_place() -> None:
    pred = [
        uav("front"),
        {"tasktype": "boat", "direction": "up"},
        arm("pick", "cube"),
        arm("place", "basket"),
    ]
    s = score(pred, GT3)
    # K=4, N=3; positions: 0 UAV=UAV ✓, 1 invalid ✗, 2 ARM=ARM ✓ → M = 2
    # S_plan = 100·[0.5·2/3 + 0.5·(1 − 1/3)] = 66.67
    assert (s.m, s.k) == (2, 4)
    assert s.s_plan == pytest.approx(100 * (1 / 3 + 1 / 3))
    assert s.s_obj == 100 and s.s_skill == 100 and s.s_loc == 100
    assert s.error_types == (ErrorType.EXTRA_STEP,)


def test_invalid_uav_step_occupies_its_index() -> None:
    gt: list[UavStep | ArmStep] = [
        UavStep(direction=D.LEFT),
        ArmStep(object="cube", skill="pick"),
        UavStep(direction=D.FRONT),
        ArmStep(object="basket", skill="place"),
    ]
    pred = [uav("towards the cube"), arm("pick", "cube"), uav("front"), arm("place", "basket")]
    s = score(pred, gt)
    # ω = (0 for the invalid 1st move, 100 for front = front) → S_loc = 50
    assert s.loc_credit == (0, 100) and s.s_loc == 50
    assert s.m == 3  # the invalid step matches no type
    assert ErrorType.WRONG_DIRECTION in s.error_types


def test_wrong_order() -> None:
    pred = [uav("front"), arm("place", "basket"), arm("pick", "cube")]
    s = score(pred, GT3)
    # Types match position by position, same multisets: S_plan, S_obj, S_skill are 100.
    # S_loc (content): one ARM step matches (ties to the earliest GT step: pick cube, the 2nd
    # predicted ARM step, with no move before it), so "front" scores 0 → S_total 75.
    assert (s.s_plan, s.s_loc, s.s_obj, s.s_skill, s.s_total) == (100, 0, 100, 100, 75)
    # By segment (ARM steps by order) front meets front: every score is 100, yet no Succ.
    s = score(pred, GT3, loc_alignment="segment")
    assert (s.s_plan, s.s_loc, s.s_obj, s.s_skill, s.s_total) == (100, 100, 100, 100, 100)
    assert not s.succ
    assert s.error_types == (ErrorType.WRONG_ORDER,)


@pytest.mark.parametrize("text", ["[]", "", "no plan", '{"plan": []}', "[1, 2]"])
def test_no_usable_plan_scores_zero(text: str) -> None:
    s = score_plan(parse_plan(text, IDS), GT3, ScoringConfig(empty_gt=EmptyGtPolicy.FULL))
    assert (s.s_plan, s.s_loc, s.s_obj, s.s_skill, s.s_total) == (0, 0, 0, 0, 0)
    assert not s.succ and s.k == 0 and s.n == 3
    assert s.error_types == (ErrorType.NO_PLAN,)


def test_all_invalid_steps_still_get_the_length_term() -> None:
    s = score([{"tasktype": "boat"}, {"skill": "dance"}, {"direction": "inside"}], GT3)
    # M=0, K=N=3 → S_plan = 100·[0 + 0.5·1] = 50; nothing else matches
    assert s.s_plan == 50 and s.s_loc == 0 and s.s_obj == 0 and s.s_skill == 0
    assert s.s_total == 12.5


def test_distance_is_ignored_by_succ() -> None:
    pred = [
        {"tasktype": "UAV", "direction": "frontleft", "distance": 3.0},
        arm("pick", "rubiks_cube"),
    ]
    assert score(pred, PAPER_GT).succ


def test_push_target_counts_as_an_object_reference() -> None:
    gt: list[UavStep | ArmStep] = [
        UavStep(direction=D.UP),
        ArmStep(object="cube", skill="push", target="basket"),
    ]
    s = score([uav("up"), arm("push", "cube", "yellow_basket")], gt)
    # R = {cube, basket}, Q = {cube, yellow_basket}: M_obj = 1, K_obj = 1 → 0
    assert (s.m_obj, s.k_obj, s.n_obj) == (1, 1, 2) and s.s_obj == 0
    assert s.error_types == (ErrorType.WRONG_OBJECT,)


def test_empty_gt_policy_for_a_plan_without_moves() -> None:
    gt: list[UavStep | ArmStep] = [ArmStep(object="cube", skill="pick")]
    assert score([arm("pick", "cube")], gt).s_loc == 100  # none expected, none given
    assert score([uav("left"), arm("pick", "cube")], gt).s_loc == 0  # strict: extra move
    relaxed = score([uav("left"), arm("pick", "cube")], gt, empty_gt=EmptyGtPolicy.FULL)
    assert relaxed.s_loc == 100 and relaxed.n_move == 0


def test_empty_gt_policy_for_a_plan_without_arm_steps() -> None:
    gt: list[UavStep | ArmStep] = [UavStep(direction=D.UP)]
    exact = score([uav("up")], gt)
    assert (exact.s_obj, exact.s_skill, exact.s_total) == (100, 100, 100) and exact.succ
    extra = score([uav("up"), arm("pick", "cube")], gt)
    assert (extra.s_obj, extra.s_skill) == (0, 0)  # strict: K_obj = 1, an ARM step not asked for


def test_weights() -> None:
    s = score(
        [arm("pick", "rubiks_cube")],
        PAPER_GT,
        weights=ScoreWeights(plan=0.5, loc=0.5, obj=0.0, skill=0.0),
    )
    assert s.s_total == pytest.approx(0.5 * 25 + 0.5 * 0)
    with pytest.raises(ValidationError, match="sum to 1"):
        ScoreWeights(plan=0.5, loc=0.5, obj=0.5, skill=0.5)
    with pytest.raises(ValidationError):
        ScoringConfig(alpha=1.5)


def test_empty_gt_is_a_config_error() -> None:
    with pytest.raises(ConfigError, match="empty"):
        score_plan(parse_plan("[]"), [])
