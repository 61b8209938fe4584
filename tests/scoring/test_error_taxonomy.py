"""Error taxonomy from the step alignment."""

from __future__ import annotations

import json
from typing import Any

from vlm_bench.parsing import parse_plan
from vlm_bench.scoring import align, classify_errors
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.types.scores import ErrorType as E

GT: list[UavStep | ArmStep] = [
    UavStep(direction=Direction.LEFT),
    ArmStep(object="cube", skill="pick"),
    UavStep(direction=Direction.FRONT),
    ArmStep(object="basket", skill="place"),
]


def classify(pred: list[Any]) -> tuple[E, ...]:
    return classify_errors(parse_plan(json.dumps(pred)), GT)


def u(d: str) -> dict[str, Any]:
    return {"tasktype": "UAV", "direction": d}


def a(skill: str, obj: str) -> dict[str, Any]:
    return {"tasktype": "ARM", "skill": skill, "object": obj}


def test_exact_plan_has_no_errors() -> None:
    assert classify([u("left"), a("pick", "cube"), u("front"), a("place", "basket")]) == ()


def test_wrong_type_in_place() -> None:
    assert classify([u("left"), a("pick", "cube"), a("pick", "cube"), a("place", "basket")]) == (
        E.WRONG_TYPE,
        E.MISSING_APPROACH,
    )


def test_wrong_skill_and_object() -> None:
    assert classify([u("left"), a("pull", "cube"), u("front"), a("place", "box")]) == (
        E.WRONG_OBJECT,
        E.WRONG_SKILL,
    )


def test_missing_approach_and_missing_step() -> None:
    # The second approach move is missing before "place basket".
    assert classify([u("left"), a("pick", "cube"), a("place", "basket")]) == (
        E.MISSING_STEP,
        E.MISSING_APPROACH,
    )


def test_missing_arm_step_only() -> None:
    assert classify([u("left"), a("pick", "cube"), u("front")]) == (E.MISSING_STEP,)


def test_extra_step() -> None:
    pred = [u("left"), u("up"), a("pick", "cube"), u("front"), a("place", "basket")]
    assert classify(pred) == (E.EXTRA_STEP,)


def test_wrong_order_replaces_the_alignment_noise() -> None:
    pred = [u("left"), a("place", "basket"), u("front"), a("pick", "cube")]
    assert classify(pred) == (E.WRONG_ORDER,)


def test_no_plan() -> None:
    assert classify_errors(parse_plan("sorry"), GT) == (E.NO_PLAN,)


def test_alignment_prefers_indels_for_a_shifted_plan() -> None:
    parsed = parse_plan(json.dumps([a("pick", "cube"), u("front"), a("place", "basket")]))
    ops = [(op.pred, op.gt) for op in align(parsed.steps, GT)]
    assert ops == [(None, 0), (0, 1), (1, 2), (2, 3)]
