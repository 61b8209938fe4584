"""The plan schema handed to constrained decoders bounds the number of steps (so a grammar can
close the array); the parser applies the same bound (``too_long``)."""

from __future__ import annotations

import json

from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.parsing import is_valid, parse_plan, plan_json_schema
from vlm_bench.parsing.schema import MAX_PLAN_STEPS
from vlm_bench.types.parse import ParseCode

STEP = {"tasktype": "UAV", "direction": "front"}


def test_the_bound_leaves_room_for_every_gt_plan() -> None:
    tasks = all_tasks()
    specs = tasks.values() if isinstance(tasks, dict) else tasks
    longest = max(len(plan) for task in specs for plan in load_materialised(task).gt_plans.values())
    assert plan_json_schema()["maxItems"] == MAX_PLAN_STEPS >= 2 * longest


def test_the_decoding_schema_and_the_parser_bound_steps_alike() -> None:
    long_plan = [STEP] * (MAX_PLAN_STEPS + 1)
    assert is_valid(plan_json_schema(), [STEP] * MAX_PLAN_STEPS)
    assert not is_valid(plan_json_schema(), long_plan)
    assert "maxItems" not in plan_json_schema(max_steps=None)
    assert parse_plan(json.dumps([STEP] * MAX_PLAN_STEPS)).tier == "valid"
    too_long = parse_plan(json.dumps(long_plan))
    assert too_long.tier == "invalid" and too_long.errors == (ParseCode.TOO_LONG,)
    assert not too_long.steps  # nothing to execute
