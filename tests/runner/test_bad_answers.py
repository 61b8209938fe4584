"""One bad answer is one recorded result: whatever a model writes, scoring returns, a run over
such answers completes, and its resume does not trip on the cached answers again."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import vlm_bench.api as api
from vlm_bench.runner.rescore import score_output
from vlm_bench.scoring import answer as scoring_answer
from vlm_bench.storage import latest_records
from vlm_bench.types.parse import ParseCode, Repair
from vlm_bench.types.records import OutputScore
from vlm_bench.types.run import RunConfig

TASK, SEED = "standard_pick_place", 0
MB = 1_000_000
STEP = '{"tasktype": "UAV", "direction": "up", "distance": %s}'
ARM = '{"tasktype": "ARM", "skill": "pick", "object": "%s"}'
FRAGMENTS = [
    *("[", "]", "{", "}", '"', "'", ",", ":", " ", "\\", "-", "9", "NaN", "1e999", "null"),
    *("tasktype", "UAV", "ARM", "direction", "up", "skill", "pick", "object", "plan"),
    *("<think>", "</think>", "```json\n", "```", "\\ud800", "\ud800", "\udfff"),
]


def _huge_int(digits: int) -> str:
    return "[" + STEP % ("9" * digits) + "]"


def _deep(depth: int, opener: str) -> str:
    closer = {"[": "]", '{"a": ': "}"}[opener]
    return opener * depth + "1" + closer * depth


def _repeat(piece: str, size: int) -> str:
    return (piece * (size // max(1, len(piece)) + 1))[:size]


def _long_plan(steps: int) -> str:
    return "[" + ",".join([STEP % 1] * steps) + "]"


fragments = st.lists(st.sampled_from(FRAGMENTS), min_size=1, max_size=12).map("".join)
surrogates = st.text(st.characters(min_codepoint=0xD800, max_codepoint=0xDFFF), min_size=1)
shapes = st.one_of(
    st.integers(4_301, 30_000).map(_huge_int),
    st.integers(4_301, 30_000).map(lambda n: "Plan: [1, -" + "7" * n + "] done"),
    st.builds(_deep, st.integers(30, 100_000), st.sampled_from(["[", '{"a": '])),
    surrogates.map(lambda s: "[" + ARM % s + "]"),
    surrogates,
    st.builds(_repeat, fragments, st.integers(200_000, MB)),
    st.integers(21, 3_000).map(_long_plan),
    fragments,
    st.text(),
)
# Shapes inside prose, code fences or reasoning blocks, as models write them.
outputs = st.builds(
    lambda before, shape, after: before + shape + after,
    st.sampled_from(["", "Here is the plan: ", "```json\n", "<think>", "</think>\n"]),
    shapes,
    st.sampled_from(["", "\n```", " That is all.", "<think>"]),
)


def _check(score: OutputScore) -> None:
    assert score.parse.tier in ("valid", "repaired", "invalid")
    OutputScore.model_validate_json(score.model_dump_json())
    assert 0 <= score.scores.s_total <= 100


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(outputs)
def test_score_output_returns_for_every_output(text: str) -> None:
    _check(score_output(TASK, SEED, text))


@pytest.mark.slow
@settings(max_examples=20_000, deadline=None, suppress_health_check=list(HealthCheck))
@given(outputs)
def test_fuzz_20000_outputs(text: str) -> None:
    _check(score_output(TASK, SEED, text))


def test_an_integer_too_long_for_python_is_a_bad_value() -> None:
    score = score_output(TASK, SEED, _huge_int(5_000))
    step = score.parse.steps[0]
    assert step.valid and step.distance is None and ParseCode.BAD_VALUE in step.errors


def test_a_plan_longer_than_the_schema_allows_is_too_long() -> None:
    score = score_output(TASK, SEED, _long_plan(150))
    assert score.parse.tier == "invalid" and score.parse.errors == (ParseCode.TOO_LONG,)
    assert score.plan == []


def test_what_scoring_raises_is_the_outputs_recorded_error(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    real = scoring_answer.score_plan

    def fragile(parsed, gt, config):  # type: ignore[no-untyped-def]
        if parsed.steps:
            raise ArithmeticError("scoring bug")
        return real(parsed, gt, config)

    monkeypatch.setattr(scoring_answer, "score_plan", fragile)
    score = score_output(TASK, SEED, '[{"tasktype": "UAV", "direction": "up"}]')
    assert score.parse.errors == (ParseCode.ERROR,) and score.error_tags[0] == "error"
    assert score.parse.detail == "ArithmeticError: scoring bug"


BAD = {
    "huge_int": _huge_int(5_000),
    "huge_int_in_prose": "Plan: [1, " + "9" * 6_000 + "]",
    "deep": _deep(50_000, "["),
    "surrogates": "[" + ARM % "\ud800cup\udfff" + "] \ud83d",
    "escaped_surrogate": '[{"tasktype": "ARM", "skill": "pick", "object": "\\ud800"}]',
    "megabyte": _repeat('[{"tasktype": "UAV", "direction": ', MB),
    "too_long": _long_plan(500),
}


def test_a_run_over_bad_answers_completes_and_its_resume_does_not_redo_them(
    tmp_path: Path,
) -> None:
    script = tmp_path / "answers.jsonl"
    keys = [f"{TASK}/{seed}/{v}" for seed in (0, 1, 2, 3) for v in ("explicit", "implicit")]
    texts = [*BAD.values(), "[" + ARM % "red_cup" + "]"]
    with script.open("w", encoding="utf-8") as fh:
        for key, text in zip(keys, texts, strict=False):
            # json.dumps writes lone surrogates as \\ud800 escapes: the mock reads them back.
            fh.write(json.dumps({"id": key, "text": text}) + "\n")
    config = RunConfig(
        model="mock",
        backend_args={"file": str(script)},
        tasks=(TASK,),
        seeds=(0, 1, 2, 3),
        resolution=32,
        execute=False,
    )
    out = tmp_path / "run"
    first = api.run(config, out=out)
    assert first.stats.scored == len(keys) and first.stats.errors == 0
    records = {r.key: r for r in latest_records(out / "records.jsonl")}
    codes = {name: records[key].parse.errors for name, key in zip(BAD, keys, strict=False)}
    assert ParseCode.TOO_LONG in codes["too_long"]
    assert records[keys[0]].parse.steps[0].errors == (ParseCode.BAD_VALUE,)
    assert "\ufffd" in records[keys[3]].raw_output  # stored as UTF-8 can hold it
    assert Repair.WINDOW in records[keys[5]].parse.repairs
    again = api.run(config, out=out)  # every episode is done: nothing is parsed again
    assert again.stats.skipped == len(keys) and again.stats.scored == 0
    rescored = api.rescore(out)
    assert rescored.stats.changed == 0
