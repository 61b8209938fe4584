"""Properties: GT plans score 100 against themselves; scores stay in [0, 100]; subtask numbers
do not matter."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlm_bench.catalog.skills import arm_skill_names
from vlm_bench.parsing import parse_plan
from vlm_bench.scoring import direction_credit, loc_credits, score_plan
from vlm_bench.types.parse import ParsedStep
from vlm_bench.types.plan import ArmStep, Direction, UavStep, plan_to_json
from vlm_bench.types.scores import EmptyGtPolicy, PlanScores, ScoringConfig

IDS = ["rubiks_cube", "yellow_basket", "red_cup_1", "red_cup_2", "top_drawer"]

uav_steps = st.builds(
    UavStep,
    direction=st.sampled_from(list(Direction)),
    distance=st.none() | st.floats(min_value=0.05, max_value=20),
)


@st.composite
def arm_steps(draw: st.DrawFn) -> ArmStep:
    skill = draw(st.sampled_from(arm_skill_names()))
    target = draw(st.none() | st.sampled_from(IDS)) if skill == "push" else None
    return ArmStep(skill=skill, object=draw(st.sampled_from(IDS)), target=target)


plans = st.lists(uav_steps | arm_steps(), min_size=1, max_size=10)
configs = st.builds(
    ScoringConfig,
    alpha=st.floats(0, 1),
    neighbour_credit=st.floats(0, 100),
    empty_gt=st.sampled_from(list(EmptyGtPolicy)),
)


def _in_range(s: PlanScores) -> None:
    for value in (s.s_plan, s.s_loc, s.s_obj, s.s_skill, s.s_total):
        assert 0 <= value <= 100
    if s.succ:
        assert s.s_total == pytest.approx(100) and s.k == s.n == s.m


@settings(max_examples=200, deadline=None)
@given(plans)
def test_gt_against_itself_scores_100(gt: list[UavStep | ArmStep]) -> None:
    parsed = parse_plan(json.dumps(plan_to_json(gt)), IDS)
    assert parsed.tier == "valid"
    s = score_plan(parsed, gt)
    assert (s.s_plan, s.s_loc, s.s_obj, s.s_skill, s.s_total) == (100, 100, 100, 100, 100)
    assert s.succ and s.error_types == ()


_VALUES: list[Any] = [
    "UAV",
    "ARM",
    "front",
    "frontleft",
    "up",
    "down",
    "left",
    "pick",
    "place",
    "push",
    "grip",
    "rubiks_cube",
    "yellow_basket",
    "ghost",
    None,
    3,
]
pred_steps = st.fixed_dictionaries(
    {},
    optional={
        k: st.sampled_from(_VALUES)
        for k in ("tasktype", "direction", "skill", "object", "target", "distance")
    },
)
predictions = st.lists(pred_steps | st.integers(), max_size=12) | plans.map(plan_to_json)


@settings(max_examples=300, deadline=None)
@given(predictions, plans, configs)
def test_scores_stay_in_range(
    pred: list[Any], gt: list[UavStep | ArmStep], config: ScoringConfig
) -> None:
    s = score_plan(parse_plan(json.dumps(pred), IDS), gt, config)
    _in_range(s)
    assert s.k == len(pred) or s.k == 0
    assert s.m <= min(s.k, s.n) and s.m_obj <= s.n_obj and s.m_skill <= s.n_skill


@settings(max_examples=200, deadline=None)
@given(plans, plans, st.randoms(use_true_random=False))
def test_subtask_renumbering_does_not_change_scores(
    pred: list[UavStep | ArmStep], gt: list[UavStep | ArmStep], rnd: Any
) -> None:
    rows = plan_to_json(pred)
    renumbered = [row | {"subtask": rnd.randint(0, 50)} for row in rows]
    stripped = [{k: v for k, v in row.items() if k != "subtask"} for row in rows]
    base = score_plan(parse_plan(json.dumps(rows), IDS), gt)
    assert score_plan(parse_plan(json.dumps(renumbered), IDS), gt) == base
    assert score_plan(parse_plan(json.dumps(stripped), IDS), gt) == base


@settings(max_examples=200, deadline=None)
@given(plans, plans)
def test_succ_iff_same_plan(pred: list[UavStep | ArmStep], gt: list[UavStep | ArmStep]) -> None:
    s = score_plan(parse_plan(json.dumps(plan_to_json(pred)), IDS), gt)
    same = [
        p.model_copy(update={"distance": None}) if isinstance(p, UavStep) else p for p in pred
    ] == [g.model_copy(update={"distance": None}) if isinstance(g, UavStep) else g for g in gt]
    assert s.succ is same
    if same:
        assert s.s_total == 100 and s.error_types == ()
    else:
        assert s.error_types != ()


alignments = st.sampled_from(["content", "segment", "order"])


@settings(max_examples=200, deadline=None)
@given(plans, alignments)
def test_gt_against_itself_gets_full_s_loc_under_every_alignment(
    gt: list[UavStep | ArmStep], alignment: str
) -> None:
    parsed = parse_plan(json.dumps(plan_to_json(gt)), IDS)
    s = score_plan(parsed, gt, ScoringConfig(loc_alignment=alignment))  # type: ignore[arg-type]
    assert s.s_loc == 100 and all(c == 100 for c in s.loc_credit)


@settings(max_examples=300, deadline=None)
@given(predictions, plans, configs, alignments)
def test_s_loc_stays_in_range_under_every_alignment(
    pred: list[Any], gt: list[UavStep | ArmStep], config: ScoringConfig, alignment: str
) -> None:
    config = config.model_copy(update={"loc_alignment": alignment})
    s = score_plan(parse_plan(json.dumps(pred), IDS), gt, config)
    _in_range(s)
    assert len(s.loc_credit) == s.n_move
    assert all(0 <= c <= 100 for c in s.loc_credit)


def _loc_credits_before_segments(steps: Sequence[ParsedStep], gt: Sequence[Any]) -> list[float]:
    """``loc_credits`` as it was before the alignment option (the i-th with the i-th)."""
    predicted = [s for s in steps if s.tasktype == "UAV"]
    moves = [g for g in gt if isinstance(g, UavStep)]
    out: list[float] = []
    for i, g in enumerate(moves):
        p = predicted[i] if i < len(predicted) else None
        ok = p is not None and p.valid
        out.append(direction_credit(p.direction if ok and p else None, g.direction))
    return out


@settings(max_examples=300, deadline=None)
@given(predictions, plans)
def test_order_alignment_is_the_old_pairing(pred: list[Any], gt: list[UavStep | ArmStep]) -> None:
    parsed = parse_plan(json.dumps(pred), IDS)
    steps = parsed.steps if parsed.usable else ()
    expected = _loc_credits_before_segments(steps, gt)
    assert loc_credits(steps, gt, 40.0, "order") == expected
    s = score_plan(parsed, gt, ScoringConfig(loc_alignment="order"))
    assert s.loc_credit == tuple(expected)


@settings(max_examples=200, deadline=None)
@given(plans, st.lists(st.lists(st.sampled_from(list(Direction)), max_size=3), max_size=12))
def test_content_pairs_like_segment_when_the_arm_steps_are_the_gts(
    gt: list[UavStep | ArmStep], moves: list[list[Direction]]
) -> None:
    # The prediction keeps the GT's ARM steps and puts any moves around them.
    arms = [g for g in gt if isinstance(g, ArmStep)]
    pred: list[UavStep | ArmStep] = []
    for k in range(len(arms) + 1):
        pred += [UavStep(direction=d) for d in (moves[k] if k < len(moves) else [])]
        pred += arms[k : k + 1]
    steps = parse_plan(json.dumps(plan_to_json(pred)), IDS).steps
    assert loc_credits(steps, gt, 40.0, "content") == loc_credits(steps, gt, 40.0, "segment")


@settings(max_examples=200, deadline=None)
@given(plans, st.integers(0, 9), arm_steps())
def test_an_inserted_arm_step_keeps_content_s_loc_at_100(
    gt: list[UavStep | ArmStep], where: int, extra: ArmStep
) -> None:
    # The GT with one ARM step of other content inserted where no move precedes it (one there
    # would be cut off from its own ARM step): the GT's ARM steps are the only longest common
    # subsequence, every GT move keeps its segment, and S_loc stays 100.
    if any(
        isinstance(g, ArmStep) and (g.skill, g.object) == (extra.skill, extra.object) for g in gt
    ):
        return
    places = [i for i in range(len(gt) + 1) if i == 0 or isinstance(gt[i - 1], ArmStep)]
    at = places[where % len(places)]
    pred = [*gt[:at], extra, *gt[at:]]
    s = score_plan(parse_plan(json.dumps(plan_to_json(pred)), IDS), gt)
    assert s.s_loc == 100, (pred, s.loc_credit)
