"""The weight-free backends: oracle (GT), random (valid floor plans), mock (scripted)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from pydantic import TypeAdapter

from vlm_bench.backends import resolve_backend
from vlm_bench.catalog.skills import arm_skill_names
from vlm_bench.errors import ConfigError, DataFileError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, RequestMeta, TextPart
from vlm_bench.types.plan import ArmStep, Direction, PlanStep, UavStep, plan_to_json

CONFIG = GenerationConfig()
GT = (
    UavStep(direction=Direction.BACKRIGHT),
    ArmStep(object="red_mug", skill="pick"),
    ArmStep(object="blue_plate", skill="place"),
)
OBJECTS = ("red_mug", "blue_plate", "gray_basket", "top_drawer")
STEPS = TypeAdapter(list[PlanStep])


def _request(rid: str, meta: RequestMeta | None = None) -> GenerationRequest:
    return GenerationRequest(id=rid, system="s", user=(TextPart(text="u"),), meta=meta)


def _parse(text: str) -> list[UavStep | ArmStep]:
    rows = json.loads(text)
    assert [r.pop("subtask") for r in rows] == list(range(len(rows)))
    return STEPS.validate_python(rows)


def test_oracle_returns_the_gt_plan_in_paper_format() -> None:
    backend = resolve_backend("oracle", {})
    [ok, missing] = backend.generate(
        [_request("a", RequestMeta(gt_plan=GT)), _request("b")], CONFIG
    )
    assert json.loads(ok.text) == plan_to_json(GT) and ok.error is None
    assert json.loads(ok.text)[0] == {"subtask": 0, "tasktype": "UAV", "direction": "backright"}
    assert missing.text == "" and missing.error is not None and "gt_plan" in missing.error


def test_random_plans_are_valid_seeded_and_varied() -> None:
    backend = resolve_backend("random", {"seed": "3"})
    meta = RequestMeta(object_ids=OBJECTS)
    requests = [_request(f"ep-{i}", meta) for i in range(60)]
    results = backend.generate(requests, CONFIG)
    plans = [_parse(r.text) for r in results]
    assert all(1 <= len(p) <= 6 for p in plans)
    arm = [s for p in plans for s in p if isinstance(s, ArmStep)]
    assert {s.object for s in arm} <= set(OBJECTS) and {s.skill for s in arm} <= set(
        arm_skill_names()
    )
    assert all(s.target is None or s.skill == "push" for s in arm)
    assert len({len(p) for p in plans}) >= 4 and len({r.text for r in results}) > 50
    again = resolve_backend("random", {"seed": "3"}).generate(requests[:5], CONFIG)
    assert [r.text for r in again] == [r.text for r in results[:5]]
    other_seed = resolve_backend("random", {"seed": "4"}).generate(requests[:5], CONFIG)
    assert [r.text for r in other_seed] != [r.text for r in results[:5]]
    [no_objects] = backend.generate([_request("x", RequestMeta())], CONFIG)
    assert no_objects.error is not None and "object_ids" in no_objects.error


def test_random_length_bounds_are_arguments() -> None:
    backend = resolve_backend("random", {"min_steps": "2", "max_steps": "2"})
    meta = RequestMeta(object_ids=OBJECTS)
    results = backend.generate([_request(str(i), meta) for i in range(10)], CONFIG)
    assert {len(json.loads(r.text)) for r in results} == {2}
    with pytest.raises(ConfigError, match="min_steps"):
        resolve_backend("random", {"min_steps": "5", "max_steps": "2"})


def test_mock_scripted_file(tmp_path: Path) -> None:
    script = tmp_path / "outputs.jsonl"
    script.write_text(
        json.dumps({"id": "a", "text": "[]"})
        + "\n\n"
        + json.dumps({"id": "b", "error": "server exploded"})
        + "\n",
        encoding="utf-8",
    )
    backend = resolve_backend("mock", {"file": str(script)})
    a, b, c = backend.generate([_request("a"), _request("b"), _request("c")], CONFIG)
    assert (a.text, a.error) == ("[]", None)
    assert (b.text, b.error) == ("", "server exploded")
    assert c.error == "mock: no scripted output for id 'c'"


def test_mock_fixed_text_and_argument_errors(tmp_path: Path) -> None:
    backend = resolve_backend("mock", {"text": "hello"})
    assert [r.text for r in backend.generate([_request("x"), _request("y")], CONFIG)] == [
        "hello",
        "hello",
    ]
    with pytest.raises(ConfigError, match="exactly one of file"):
        resolve_backend("mock", {})
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"id": "a", "text": "x"}\nnot json\n', encoding="utf-8")
    with pytest.raises(DataFileError, match=r"bad.jsonl: line 2: invalid JSON"):
        resolve_backend("mock", {"file": str(bad)})
    with pytest.raises(DataFileError, match="cannot read"):
        resolve_backend("mock", {"file": str(tmp_path / "absent.jsonl")})
