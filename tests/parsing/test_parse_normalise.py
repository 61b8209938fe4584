"""Step normalisation: spellings, aliases, object ids, and invalid steps kept in place."""

from __future__ import annotations

import json
from typing import Any

import pytest

from vlm_bench.catalog.skills import skills
from vlm_bench.parsing import parse_plan
from vlm_bench.types.parse import ParseCode, ParsedStep
from vlm_bench.types.plan import Direction

IDS = ["rubiks_cube", "yellow_basket", "red_cup_1", "red_cup_2", "top_drawer"]


def one(step: dict[str, Any], ids: list[str] | None = IDS) -> ParsedStep:
    result = parse_plan(json.dumps([step]), ids)
    assert result.n_steps == 1
    return result.steps[0]


@pytest.mark.parametrize(
    "spelling",
    [
        "frontleft",
        "front-left",
        "Front Left",
        "front_left",
        "FRONTLEFT",
        "Front-Left",
        "left front",
        "forward left",
        "forward-left",
    ],
)
def test_direction_spellings(spelling: str) -> None:
    step = one({"tasktype": "UAV", "direction": spelling})
    assert step.valid and step.direction is Direction.FRONTLEFT and step.errors == ()


def test_every_direction_alias_of_the_skill_library_resolves() -> None:
    field = next(f for f in skills()["move"].fields if f.name == "direction")
    assert field.value_aliases, "the move skill declares direction aliases"
    for canonical, aliases in field.value_aliases.items():
        for alias in aliases:
            assert one({"tasktype": "UAV", "direction": alias}).direction == canonical, alias


@pytest.mark.parametrize(
    ("alias", "direction"),
    [("forward", "front"), ("Ascend", "up"), ("descend", "down"), ("backwards", "back")],
)
def test_direction_aliases(alias: str, direction: str) -> None:
    assert one({"tasktype": "UAV", "direction": alias}).direction == direction


@pytest.mark.parametrize("tasktype", ["uav", "Uav", " UAV ", "U.A.V."])
def test_tasktype_case_and_separators(tasktype: str) -> None:
    step = one({"tasktype": tasktype, "direction": "up"})
    assert step.valid and step.tasktype == "UAV"


def test_tasktype_arm_case_and_key_aliases() -> None:
    step = one({"Task_Type": "Arm", "Object": "rubiks_cube", "Action": "Grasp"})
    assert step.valid and (step.tasktype, step.skill, step.object) == ("ARM", "pick", "rubiks_cube")


def test_every_skill_alias_resolves() -> None:
    for spec in skills().values():
        for alias in (spec.name, *spec.aliases):
            if spec.agent == "ARM":
                step = one({"tasktype": "ARM", "skill": alias, "object": "rubiks_cube"})
            else:
                step = one({"tasktype": "UAV", "skill": alias, "direction": "up"})
            assert step.valid and step.skill == spec.name, alias


@pytest.mark.parametrize("skill", ["move", "fly", "Move", None])
def test_uav_step_with_or_without_move_skill(skill: str | None) -> None:
    step = one({"tasktype": "UAV", "skill": skill, "direction": "left"})
    assert step.valid and step.skill == "move"


@pytest.mark.parametrize(
    "reference",
    ["Rubiks Cube", "rubiks-cube", "RUBIKS_CUBE", "Rubik's cube", "RubiksCube", " rubiks cube "],
)
def test_object_ids_normalised_to_scene_ids(reference: str) -> None:
    step = one({"tasktype": "ARM", "skill": "pick", "object": reference})
    assert step.valid and step.object == "rubiks_cube" and step.errors == ()


def test_object_without_its_number_is_another_object() -> None:
    step = one({"tasktype": "ARM", "skill": "pick", "object": "red_cup"})
    assert step.valid and step.object == "red_cup"
    assert step.errors == (ParseCode.UNKNOWN_OBJECT,)
    assert one({"tasktype": "ARM", "skill": "pick", "object": "Red Cup 2"}).object == "red_cup_2"


def test_hallucinated_object_stays_valid() -> None:
    step = one({"tasktype": "ARM", "skill": "pick", "object": "golden_apple"})
    assert step.valid and step.errors == (ParseCode.UNKNOWN_OBJECT,)
    assert (
        parse_plan(
            json.dumps([{"tasktype": "ARM", "skill": "pick", "object": "golden_apple"}]), IDS
        ).tier
        == "repaired"
    )


def test_without_scene_ids_objects_are_only_normalised() -> None:
    step = one({"tasktype": "ARM", "skill": "pick", "object": "Golden Apple"}, ids=None)
    assert step.valid and step.object == "golden_apple" and step.errors == ()


def test_push_target_and_null_like_values() -> None:
    step = one(
        {"tasktype": "ARM", "skill": "push", "object": "red_cup_1", "target": "Yellow Basket"}
    )
    assert (step.object, step.target) == ("red_cup_1", "yellow_basket")
    step = one({"tasktype": "ARM", "skill": "pick", "object": "red_cup_1", "target": "none"})
    assert step.target is None and step.errors == ()


def test_distance_is_parsed_or_dropped() -> None:
    assert one({"tasktype": "UAV", "direction": "up", "distance": "1.5 m"}).distance == 1.5
    bad = one({"tasktype": "UAV", "direction": "up", "distance": -2})
    assert bad.valid and bad.distance is None and bad.errors == (ParseCode.BAD_VALUE,)


@pytest.mark.parametrize(
    ("step", "code"),
    [
        ({"tasktype": "BOAT", "direction": "up"}, ParseCode.UNKNOWN_TASKTYPE),
        ({"tasktype": 3, "direction": "up"}, ParseCode.UNKNOWN_TASKTYPE),
        # tasktype is required and never inferred, even when a direction says "UAV".
        ({"direction": "up"}, ParseCode.MISSING_FIELD),
        ({"tasktype": "UAV"}, ParseCode.MISSING_FIELD),
        ({"tasktype": "UAV", "direction": "towards the cube"}, ParseCode.UNKNOWN_DIRECTION),
        ({"tasktype": "UAV", "direction": 90}, ParseCode.UNKNOWN_DIRECTION),
        ({"tasktype": "UAV", "direction": "up", "skill": "pick"}, ParseCode.UNKNOWN_SKILL),
        ({"tasktype": "ARM", "object": "rubiks_cube"}, ParseCode.MISSING_FIELD),
        ({"tasktype": "ARM", "object": "rubiks_cube", "skill": "grip"}, ParseCode.UNKNOWN_SKILL),
        ({"tasktype": "ARM", "object": "rubiks_cube", "skill": "move"}, ParseCode.UNKNOWN_SKILL),
        ({"tasktype": "ARM", "skill": "pick"}, ParseCode.MISSING_FIELD),
        ({"tasktype": "ARM", "skill": "pick", "object": None}, ParseCode.MISSING_FIELD),
        ({"tasktype": "ARM", "skill": "pick", "object": ["rubiks_cube"]}, ParseCode.BAD_VALUE),
    ],
)
def test_invalid_steps(step: dict[str, Any], code: ParseCode) -> None:
    parsed = one(step)
    assert not parsed.valid and code in parsed.errors
    assert parsed.to_step() is None


def test_invalid_steps_stay_in_place() -> None:
    plan = [
        {"tasktype": "UAV", "direction": "left"},
        {"tasktype": "ARM", "skill": "grip", "object": "Rubiks Cube"},
        "then place it",
        {"tasktype": "ARM", "skill": "place", "object": "yellow_basket"},
    ]
    result = parse_plan(json.dumps(plan), IDS)
    assert result.tier == "repaired" and ParseCode.SCHEMA in result.errors
    assert [s.valid for s in result.steps] == [True, False, False, True]
    assert [s.index for s in result.steps] == [0, 1, 2, 3]
    # The invalid ARM step keeps its (normalised) object: it counts against S_obj.
    assert result.steps[1].object == "rubiks_cube" and result.steps[1].skill is None
    assert [type(s).__name__ for s in result.valid_steps()] == ["UavStep", "ArmStep"]


def test_subtask_numbers_are_ignored() -> None:
    plan = [
        {"subtask": 7, "tasktype": "ARM", "skill": "pick", "object": "rubiks_cube"},
        {"subtask": 0, "tasktype": "UAV", "direction": "up"},
    ]
    result = parse_plan(json.dumps(plan), IDS)
    assert result.tier == "valid"
    assert [s.tasktype for s in result.steps] == ["ARM", "UAV"]


def test_valid_uav_step_drops_object_references() -> None:
    step = one({"tasktype": "UAV", "direction": "left", "object": "rubiks_cube"})
    assert step.valid and step.object is None
    bad = one({"tasktype": "UAV", "direction": "nowhere", "object": "rubiks_cube"})
    assert not bad.valid and bad.object == "rubiks_cube"
