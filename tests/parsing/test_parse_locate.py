"""Locating the plan: stray brackets in the prose, and outputs of a megabyte (linear work)."""

from __future__ import annotations

import json
import random
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlm_bench.parsing import extract, parse_plan
from vlm_bench.parsing.locate import MAX_SEARCH_CHARS
from vlm_bench.parsing.wrappers import strip_think
from vlm_bench.scoring import score_plan
from vlm_bench.types.parse import ParseCode, ParseResult, Repair
from vlm_bench.types.plan import ArmStep, Direction, UavStep

IDS = ["red_cup", "yellow_basket"]
PLAN = (
    '[{"subtask":0,"tasktype":"UAV","direction":"front"},'
    '{"subtask":1,"tasktype":"ARM","object":"red_cup","skill":"pick"}]'
)
PY_PLAN = (
    "[{'subtask': 0, 'tasktype': 'UAV', 'direction': 'front'},"
    " {'subtask': 1, 'tasktype': 'ARM', 'object': 'red_cup', 'skill': 'pick'}]"
)
GT = [UavStep(direction=Direction.FRONT), ArmStep(object="red_cup", skill="pick")]
MB = 1_000_000


def assert_full_match(result: ParseResult, tier: str | None = "repaired") -> None:
    assert tier is None or result.tier == tier
    assert result.valid_steps() == GT and result.n_steps == 2
    scores = score_plan(result, GT)
    assert scores.s_total == 100.0 and scores.succ


# --- A stray "[" in the prose before the plan ------------------------------------------------

STRAY_PROSE = [
    "I will move [carefully] to the cup. ",
    "I will move [carefully to the cup. ",
    "Step [1: fly to the cup. ",
    "Here is a list [of things to do. ",
    "Step [1] then [2 and [3. ",
    "First [a, then [b, then [c, then [d. ",
    "Think [a [b [c [d [e: ok. ",
    "I [will [move [carefully [to [the [cup. ",
    "Step [1] Step [2] Step [3] Step [4] Step [5] Step [6]: ",
    "It's 6\" tall [see the note, so I'd fly low. ",
    "<think>The cup is [left.</think>\nPlan [final: ",
]


@pytest.mark.parametrize("prose", STRAY_PROSE)
@pytest.mark.parametrize("after", ["", " Done.", "\nLet me know."])
def test_stray_brackets_before_the_plan(prose: str, after: str) -> None:
    result = parse_plan(prose + PLAN + after, IDS)
    assert_full_match(result)
    assert ParseCode.TRUNCATED not in result.errors  # a bracket before the plan is not a cut
    assert Repair.EXTRACT in result.repairs and Repair.JSON_REPAIR not in result.repairs


@pytest.mark.parametrize("prose", STRAY_PROSE[:6])
def test_stray_bracket_before_a_plan_that_needs_repair(prose: str) -> None:
    result = parse_plan(prose + PY_PLAN, IDS)
    assert_full_match(result)
    assert Repair.JSON_REPAIR in result.repairs


def test_stray_bracket_then_draft_then_final_answer() -> None:
    draft = '[{"tasktype": "UAV", "direction": "back"}, {"tasktype": "UAV", "direction": "up"}]'
    result = parse_plan(f"I will [think first. Draft: {draft}\nFinal: {PLAN}", IDS)
    assert_full_match(result)  # the last plan, though the draft is as long


def test_truncation_after_the_plan_is_still_reported() -> None:
    result = parse_plan(PLAN + '\nNote: {"reason": "the cup is', IDS)
    assert result.valid_steps() == GT and ParseCode.TRUNCATED in result.errors
    wrapped = parse_plan('I [think. {"plan": ' + PLAN + ', "reason": "the cu', IDS)
    assert wrapped.valid_steps() == GT and ParseCode.TRUNCATED in wrapped.errors
    assert Repair.UNWRAP in wrapped.repairs


_PROSE_BITS = ["I", " ", "move", "to the cup", ".", ",", "\n", "[", "]", "(", ")", "Step", "1"]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from([*_PROSE_BITS, "{", "}", ":", "it's", "a list [of"]), max_size=30))
def test_any_prose_with_brackets_before_a_json_plan(bits: list[str]) -> None:
    assert_full_match(parse_plan("".join(bits) + " " + PLAN, IDS), tier=None)


# --- Reasoning blocks: the linear stripper does what the regex did ----------------------------

_OLD_THINK_BLOCK = re.compile(r"<(think|thinking|reasoning)\s*>.*?</\1\s*>", re.S | re.I)
_TAGS = ["<think>", "</think>", "<THINK >", "</Think>", "<thinking>", "</thinking>"]


def _regex_strip_think(text: str) -> str:
    """The former implementation (quadratic on unclosed tags), as the reference."""
    text = _OLD_THINK_BLOCK.sub("", text)
    closes = list(re.finditer(r"</(?:think|thinking|reasoning)\s*>", text, re.I))
    if closes:
        text = text[closes[-1].end() :]
    opened = re.search(r"<(?:think|thinking|reasoning)\s*>", text, re.I)
    return text[: opened.start()] if opened else text


@settings(max_examples=300, deadline=None)
@given(st.lists(st.sampled_from([*_TAGS, "<reasoning>", "</reasoning>", "a", "[1]", "\n"])))
def test_strip_think_matches_the_regex(parts: list[str]) -> None:
    text = "".join(parts)
    assert strip_think(text) == _regex_strip_think(text)


# --- Outputs of a megabyte parse to the right result (no timing asserts) ---------------------


def test_a_megabyte_plan_is_too_long_and_searched_in_windows() -> None:
    step = "{'subtask': 0, 'tasktype': 'UAV', 'direction': 'front'}, "
    result = parse_plan("[" + step * (MB // len(step)) + "]", IDS)
    assert result.tier == "invalid" and ParseCode.TOO_LONG in result.errors
    assert Repair.WINDOW in result.repairs and not result.steps


def test_megabyte_of_unclosed_think_tags() -> None:
    tags = "<think>" * (MB // 7)
    unclosed = parse_plan(tags + PLAN, IDS)  # an unclosed block runs to the end, as when small
    assert unclosed.tier == "invalid" and unclosed.errors == (ParseCode.NO_JSON,)
    assert_full_match(parse_plan(tags + "</think>" + PLAN, IDS))


def test_megabyte_of_prose_with_brackets_then_the_plan() -> None:
    rng = random.Random(0)
    words = ["the", "cup", "[", "{", "]", "}", "[1]", "{x}", "a", "list", ":", ",", "'", '"']
    prose = " ".join(rng.choice(words) for _ in range(MB // 2))
    assert len(prose) > MB
    result = parse_plan(prose + "\n" + PLAN, IDS)
    assert_full_match(result)
    assert Repair.WINDOW in result.repairs


def test_a_plan_before_a_megabyte_of_looping_prose_is_found() -> None:
    loop = "and then I fly up again. " * (MB // 25)
    result = parse_plan("Plan: " + PLAN + "\n" + loop, IDS)
    assert_full_match(result)
    assert Repair.WINDOW in result.repairs and ParseCode.TRUNCATED not in result.errors


def test_output_up_to_the_bound_is_searched_whole() -> None:
    text = PLAN + " " + "x" * (MAX_SEARCH_CHARS - len(PLAN) - 1)
    assert len(text) == MAX_SEARCH_CHARS
    whole = parse_plan(text, IDS)
    assert_full_match(whole)
    assert Repair.WINDOW not in whole.repairs
    assert Repair.WINDOW in parse_plan(text + "x", IDS).repairs


def test_json_repair_work_is_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    handed: list[int] = []
    repair = extract.json_repair.loads

    def counting(text: str, *args: object, **kwargs: object) -> object:
        handed.append(len(text))
        return repair(text, *args, **kwargs)

    monkeypatch.setattr(extract.json_repair, "loads", counting)
    step = "{'subtask': 0, 'tasktype': 'UAV', 'direction': 'front'}, "
    for text in ("[" + step * (MB // len(step)) + "]", "a [b: {c: d} " * (MB // 13)):
        handed.clear()
        parse_plan(text, IDS)
        # each of the two windows searched has its own budget
        assert len(handed) <= 2 * extract.MAX_REPAIRS
        assert sum(handed) <= len(text) // 10, sum(handed)  # a bounded amount, not the text
        assert sum(handed) <= 2 * extract.MAX_REPAIR_CHARS


def test_extraction_of_a_megabyte_json_array_is_linear() -> None:
    steps = [{"subtask": i, "tasktype": "UAV", "direction": "front"} for i in range(14_000)]
    text = "I will fly [slowly: " + json.dumps(steps) + " Done."
    cands, _ = extract.candidates(text)
    assert max(len(c.value) for c in cands if isinstance(c.value, list)) == 14_000


def test_long_whitespace_in_a_number_field() -> None:
    text = '[{"tasktype": "UAV", "direction": "up", "distance": "1' + " " * 200_000 + 'x"}]'
    step = parse_plan(text, IDS).steps[0]
    assert step.valid and step.distance is None and ParseCode.BAD_VALUE in step.errors
