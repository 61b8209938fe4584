"""The parser on realistic VLM outputs: tiers, repairs and plan-level codes."""

from __future__ import annotations

import json

import pytest

from vlm_bench.parsing import parse_plan
from vlm_bench.types.parse import ParseCode, ParseResult, Repair
from vlm_bench.types.plan import ArmStep, Direction, UavStep

IDS = ["rubiks_cube", "yellow_basket", "red_cup_1", "red_cup_2", "top_drawer"]
PAPER = (
    '[{"subtask": 0, "tasktype": "UAV", "direction": "frontleft"}, '
    '{"subtask": 1, "tasktype": "ARM", "object": "rubiks_cube", "skill": "pick"}]'
)
PAPER_STEPS = [UavStep(direction=Direction.FRONTLEFT), ArmStep(object="rubiks_cube", skill="pick")]


def test_paper_example_is_valid_tier() -> None:
    result = parse_plan(PAPER, IDS)
    assert result.tier == "valid"
    assert result.errors == () and result.repairs == ()
    assert result.valid_steps() == PAPER_STEPS
    assert result.n_steps == 2 and result.usable
    assert [s.index for s in result.steps] == [0, 1]
    assert result.steps[1].raw == json.loads(PAPER)[1]


@pytest.mark.parametrize(
    ("text", "repairs"),
    [
        (f"```json\n{PAPER}\n```", (Repair.STRIP_FENCE,)),
        (f"```\n{PAPER}\n```", (Repair.STRIP_FENCE,)),
        (f"Here is the plan:\n{PAPER}\nLet me know!", (Repair.EXTRACT,)),
        (f"Plan:\n```json\n{PAPER}\n```\nThe UAV first flies [closer].", (Repair.STRIP_FENCE,)),
        (f"<think>The cube is [left]. {{maybe}}</think>\n{PAPER}", (Repair.STRIP_THINK,)),
        (f"reasoning without an opening tag</think>{PAPER}", (Repair.STRIP_THINK,)),
        (f'{{"plan": {PAPER}}}', (Repair.UNWRAP,)),
        (f'{{"steps": {PAPER}, "reason": "cube is left"}}', (Repair.UNWRAP,)),
        (f"[{PAPER}]", (Repair.UNWRAP,)),
        (json.dumps(PAPER), (Repair.DECODE_STRING,)),
        (
            "[{'subtask': 0, 'tasktype': 'UAV', 'direction': 'frontleft'},"
            " {'subtask': 1, 'tasktype': 'ARM', 'object': 'rubiks_cube', 'skill': 'pick'}]",
            (Repair.JSON_REPAIR,),
        ),
        (
            PAPER.replace("}]", "},]").replace('"frontleft"}', '"frontleft",}'),
            (Repair.JSON_REPAIR,),
        ),
        (
            '{"tasktype": "UAV", "direction": "frontleft"}\n'
            '{"tasktype": "ARM", "object": "rubiks_cube", "skill": "pick"}',
            (Repair.EXTRACT, Repair.JOIN_OBJECTS),
        ),
        ("I'll go [don't worry] now: " + PAPER, (Repair.EXTRACT,)),
        (
            'Draft: [{"tasktype": "UAV", "direction": "back"}]\nFinal answer: ' + PAPER,
            (Repair.EXTRACT,),
        ),
    ],
)
def test_repaired_outputs_recover_the_plan(text: str, repairs: tuple[Repair, ...]) -> None:
    result = parse_plan(text, IDS)
    assert result.tier == "repaired"
    assert result.repairs == repairs
    assert result.valid_steps() == PAPER_STEPS
    assert ParseCode.TRUNCATED not in result.errors


def test_python_literals_are_repaired() -> None:
    text = (
        "[{'tasktype': 'UAV', 'direction': 'front', 'distance': None, 'final': False},"
        " {'tasktype': 'ARM', 'object': 'red_cup_1', 'skill': 'pick', 'target': None}]"
    )
    result = parse_plan(text, IDS)
    assert result.tier == "repaired"
    assert result.valid_steps() == [
        UavStep(direction=Direction.FRONT),
        ArmStep(object="red_cup_1", skill="pick"),
    ]


def test_truncated_output_keeps_complete_steps() -> None:
    text = PAPER[: PAPER.index('"skill"') - 2]  # cut inside the ARM step
    result = parse_plan(text, IDS)
    assert result.tier == "repaired"
    assert ParseCode.TRUNCATED in result.errors and ParseCode.SCHEMA in result.errors
    assert result.steps[0].valid and result.steps[0].direction is Direction.FRONTLEFT
    # The cut step lacks its skill: it stays in place, invalid.
    assert result.n_steps == 2 and not result.steps[1].valid
    assert ParseCode.MISSING_FIELD in result.steps[1].errors


def test_truncated_before_any_step_is_invalid() -> None:
    result = parse_plan('```json\n[{"subta', IDS)
    assert result.tier == "invalid"
    assert ParseCode.TRUNCATED in result.errors


def test_unclosed_think_block_is_dropped() -> None:
    result = parse_plan('<think>maybe [{"tasktype": "UAV", "direction": "up"}] then', IDS)
    assert result.tier == "invalid" and result.errors == (ParseCode.NO_JSON,)


@pytest.mark.parametrize(
    ("text", "code"),
    [
        ("", ParseCode.EMPTY),
        ("   \n\t", ParseCode.EMPTY),
        ("I cannot help with that.", ParseCode.NO_JSON),
        ("[]", ParseCode.EMPTY_PLAN),
        ('{"plan": []}', ParseCode.EMPTY_PLAN),
        ('["fly left", "pick the cube"]', ParseCode.NOT_A_PLAN),
        ('{"answer": "the cube", "confidence": 0.9}', ParseCode.NOT_A_PLAN),
        ('[{"name": "cube", "color": "red"}, {"name": "basket"}]', ParseCode.NOT_A_PLAN),
        ("42", ParseCode.NOT_A_PLAN),
        ("The objects are [cube, basket].", ParseCode.NO_JSON),  # not JSON, not repaired
        ('The objects are ["cube", "basket"].', ParseCode.NOT_A_PLAN),
    ],
)
def test_no_usable_plan(text: str, code: ParseCode) -> None:
    result = parse_plan(text, IDS)
    assert result.tier == "invalid" and not result.usable
    assert code in result.errors
    assert result.steps == () and result.valid_steps() == []


def test_result_round_trips_through_json() -> None:
    text = '[{"tasktype": "UAV", "direction": "up", "distance": NaN}, 7]'
    result = parse_plan(text, IDS)
    again = ParseResult.model_validate_json(result.model_dump_json())
    assert again == result
    assert result.steps[0].errors == (ParseCode.BAD_VALUE,) and result.steps[0].valid
    assert result.steps[1].errors == (ParseCode.NOT_AN_OBJECT,)
    assert result.all_errors() == (ParseCode.SCHEMA, ParseCode.BAD_VALUE, ParseCode.NOT_AN_OBJECT)


def test_lone_surrogate_escapes_still_serialise() -> None:
    result = parse_plan('[{"tasktype": "UAV", "direction": "up", "note": "\\ud800"}]', IDS)
    assert result.steps[0].valid
    assert ParseResult.model_validate_json(result.model_dump_json()).steps[0].valid
