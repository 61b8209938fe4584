"""Properties: the parser never raises; schema validity and the ``valid`` tier agree."""

from __future__ import annotations

import json
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

from vlm_bench.catalog.skills import skills
from vlm_bench.parsing import is_valid, parse_plan, plan_json_schema
from vlm_bench.types.parse import ParseResult

IDS = ["rubiks_cube", "yellow_basket", "red_cup_1"]

json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=20),
    lambda children: (
        st.lists(children, max_size=5) | st.dictionaries(st.text(max_size=10), children, max_size=5)
    ),
    max_leaves=30,
)

FRAGMENTS = [
    "[",
    "]",
    "{",
    "}",
    '"',
    "'",
    ",",
    ":",
    " ",
    "\n",
    "\\",
    "tasktype",
    "UAV",
    "arm",
    "direction",
    "front-left",
    "skill",
    "pick",
    "object",
    "rubiks_cube",
    "plan",
    "<think>",
    "</think>",
    "```",
    "```json",
    "True",
    "None",
    "NaN",
    "1e999",
    "-",
    "0",
    "subtask",
    "steps",
    "null",
]
fragment_text = st.lists(st.sampled_from(FRAGMENTS), max_size=40).map("".join)


def _check(result: ParseResult) -> None:
    assert result.tier in ("valid", "repaired", "invalid")
    assert result.usable == bool(result.steps)
    assert result.usable or result.errors
    ParseResult.model_validate_json(result.model_dump_json())


@settings(max_examples=300, deadline=None)
@given(st.text())
def test_never_raises_on_arbitrary_text(text: str) -> None:
    _check(parse_plan(text, IDS))


@settings(max_examples=300, deadline=None)
@given(fragment_text)
def test_never_raises_on_json_like_fragments(text: str) -> None:
    _check(parse_plan(text, IDS))


@settings(max_examples=200, deadline=None)
@given(json_values)
def test_never_raises_on_json_values(value: Any) -> None:
    _check(parse_plan(json.dumps(value), IDS))
    _check(parse_plan(repr(value), None))  # Python literal style
    _check(parse_plan(json.dumps(value)[:-1], IDS))  # truncated


def test_never_raises_on_deep_nesting() -> None:
    for text in ("[" * 5000, "[" * 3000 + "]" * 3000, '{"a":' * 2000, "[{" * 2000 + "}]" * 2000):
        _check(parse_plan(text, IDS))


_KEYS = ["subtask", "tasktype", "direction", "distance", "skill", "object", "target", "note"]
_VALUES: list[Any] = [
    "UAV",
    "ARM",
    "uav",
    "front",
    "Front",
    "up",
    "sideways",
    "pick",
    "grasp",
    "push",
    "move",
    "rubiks_cube",
    "yellow_basket",
    "Rubiks Cube",
    "ghost",
    0,
    1,
    2.5,
    -1,
    True,
    None,
]
steps = st.dictionaries(st.sampled_from(_KEYS), st.sampled_from(_VALUES), max_size=6)
step_like = st.fixed_dictionaries(
    {"tasktype": st.sampled_from(["UAV", "ARM"])},
    optional={k: st.sampled_from(_VALUES) for k in _KEYS if k != "tasktype"},
)


@settings(max_examples=400, deadline=None)
@given(st.lists(steps | step_like, min_size=1, max_size=4), st.sampled_from([IDS, None]))
def test_valid_tier_iff_schema_valid(plan: list[dict[str, Any]], ids: list[str] | None) -> None:
    """The schema and the step normaliser agree: schema-valid JSON parses cleanly as-is."""
    result = parse_plan(json.dumps(plan), ids)
    assert (result.tier == "valid") == is_valid(plan_json_schema(ids), plan)
    if result.tier == "valid":
        assert all(s.valid and not s.errors for s in result.steps)
        assert len(result.valid_steps()) == len(plan)


def test_skill_library_directions_match_the_plan_model() -> None:
    from vlm_bench.types.plan import Direction

    values = next(f.values for f in skills()["move"].fields if f.name == "direction")
    assert tuple(d.value for d in Direction) == values
