"""The plan JSON Schema is generated from the skill library, and the validator is exact."""

from __future__ import annotations

import json

import pytest

from vlm_bench.catalog.skills import arm_skill_names, skills
from vlm_bench.errors import DataFileError
from vlm_bench.parsing import is_valid, plan_json_schema, schema_violations, step_json_schema
from vlm_bench.parsing.vocab import build_vocabulary, vocabulary
from vlm_bench.types.plan import Direction
from vlm_bench.types.skill import SkillField, SkillSpec

PAPER_EXAMPLE = [
    {"subtask": 0, "tasktype": "UAV", "direction": "frontleft"},
    {"subtask": 1, "tasktype": "ARM", "object": "rubiks_cube", "skill": "pick"},
]


def test_schema_enums_come_from_the_skill_library() -> None:
    variants = {
        v["properties"]["tasktype"]["const"]: v for v in plan_json_schema()["items"]["anyOf"]
    }
    assert set(variants) == {"UAV", "ARM"}
    uav, arm = variants["UAV"], variants["ARM"]
    move = skills()["move"]
    direction_values = next(f.values for f in move.fields if f.name == "direction")
    assert uav["properties"]["direction"]["enum"] == list(direction_values or ())
    assert set(uav["properties"]["direction"]["enum"]) == {d.value for d in Direction}
    assert arm["properties"]["skill"]["enum"] == arm_skill_names()
    assert uav["properties"]["skill"]["enum"] == ["move"]
    # UAV has one skill, so the paper's UAV steps need no "skill"; ARM steps do.
    assert uav["required"] == ["tasktype", "direction"]
    assert arm["required"] == ["tasktype", "skill", "object"]
    assert set(arm["properties"]) == {"subtask", "tasktype", "skill", "object", "target"}
    assert set(uav["properties"]) == {"subtask", "tasktype", "skill", "direction", "distance"}
    json.dumps(plan_json_schema(["a"]))  # serialisable as is


def test_object_enum_only_when_ids_are_given() -> None:
    arm = step_json_schema("ARM", ["rubiks_cube", "yellow_basket", "rubiks_cube"])
    assert arm["properties"]["object"]["enum"] == ["rubiks_cube", "yellow_basket"]
    assert arm["properties"]["target"]["enum"] == ["rubiks_cube", "yellow_basket"]
    assert "enum" not in step_json_schema("ARM")["properties"]["object"]


def test_paper_example_validates() -> None:
    assert is_valid(plan_json_schema(), PAPER_EXAMPLE)
    assert is_valid(plan_json_schema(["rubiks_cube"]), PAPER_EXAMPLE)
    assert not is_valid(plan_json_schema(["yellow_basket"]), PAPER_EXAMPLE)


@pytest.mark.parametrize(
    ("plan", "keyword"),
    [
        ([], "minItems"),
        ({"plan": PAPER_EXAMPLE}, "type"),
        ([{"tasktype": "UAV", "direction": "front-left"}], "anyOf"),
        ([{"tasktype": "UAV"}], "anyOf"),
        ([{"tasktype": "ARM", "object": "x", "skill": "grasp"}], "anyOf"),
        ([{"tasktype": "ARM", "object": "x", "skill": "pick", "note": 1}], "anyOf"),
        ([{"tasktype": "UAV", "direction": "up", "distance": 0}], "anyOf"),
        ([{"tasktype": "UAV", "direction": "up", "subtask": True}], "anyOf"),
        ([{"tasktype": "UAV", "direction": "up", "subtask": 1.5}], "anyOf"),
    ],
)
def test_schema_rejects(plan: object, keyword: str) -> None:
    violations = schema_violations(plan_json_schema(), plan)
    assert any(v.split(": ")[1] == keyword for v in violations), violations


def test_validator_uses_json_semantics() -> None:
    assert is_valid({"type": "integer"}, 1.0)
    assert not is_valid({"type": "integer"}, True)
    assert not is_valid({"type": "number"}, False)
    assert not is_valid({"enum": [1]}, True)
    assert not is_valid({"const": False}, 0)
    assert is_valid({"type": "integer", "minimum": 0}, 10**400)
    assert not is_valid({"type": "number"}, float("nan"))
    assert not is_valid({"type": "number"}, float("inf"))


def test_uav_step_with_move_skill_is_schema_valid() -> None:
    plan = [{"tasktype": "UAV", "skill": "move", "direction": "up", "distance": 1.5}]
    assert is_valid(plan_json_schema(), plan)


def _spec(name: str, aliases: tuple[str, ...]) -> SkillSpec:
    obj = SkillField(name="object", type="object", required=True, description="d")
    return SkillSpec(name=name, agent="ARM", description="d", aliases=aliases, fields=(obj,))


def test_ambiguous_aliases_are_a_data_error() -> None:
    library = {"pick": _spec("pick", ("grab",)), "pull": _spec("pull", ("Grab",))}
    with pytest.raises(DataFileError, match="grab"):
        build_vocabulary(library)


def test_shipped_vocabulary_builds() -> None:
    vocab = vocabulary()
    assert vocab.agents == {"uav": "UAV", "arm": "ARM"}
    assert vocab.object_fields == ("object", "target")
