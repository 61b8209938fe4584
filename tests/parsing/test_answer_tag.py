"""A model's documented answer format (GLM-4.1V-Thinking's ``<think>…</think><answer>…</answer>``)
is clean output: parse tier ``valid``, the reasoning kept, nothing counted as repaired."""

from __future__ import annotations

import pytest

from vlm_bench.catalog.model_cards import answer_format_of, model_card
from vlm_bench.parsing import parse_plan
from vlm_bench.report import parse_tier_rates, records_frame
from vlm_bench.types.parse import AnswerFormat, Repair

IDS = ["rubiks_cube", "yellow_basket"]
PLAN = (
    '[{"subtask": 0, "tasktype": "UAV", "direction": "front"}, '
    '{"subtask": 1, "tasktype": "ARM", "object": "rubiks_cube", "skill": "pick"}]'
)
REASONING = "The cube is ahead of the UAV [front], so fly front, then pick it."
GLM = f"<think>{REASONING}</think>\n<answer>{PLAN}</answer>"
TAGS = AnswerFormat(reasoning="think", answer="answer")


def test_the_documented_format_is_valid_and_keeps_the_reasoning() -> None:
    result = parse_plan(GLM, IDS, TAGS)
    assert result.tier == "valid" and result.repairs == () and result.errors == ()
    assert result.reasoning == REASONING
    assert result.n_steps == 2


def test_without_the_cards_format_it_stays_repaired() -> None:
    result = parse_plan(GLM, IDS)
    assert result.tier == "repaired" and Repair.STRIP_THINK in result.repairs


@pytest.mark.parametrize(
    "text",
    [
        f"Sure!\n{GLM}",  # prose outside the blocks
        f"<think>{REASONING}</think>\n{PLAN}",  # no answer tag
        f"{GLM}\n<answer>[]</answer>",  # a second answer
        f"<think>{REASONING}</think><answer>```json\n{PLAN}\n```</answer>",  # a fence inside
    ],
)
def test_other_forms_are_repaired(text: str) -> None:
    result = parse_plan(text, IDS, TAGS)
    assert result.tier == "repaired"


def test_the_opening_tag_may_be_in_the_prompt() -> None:
    result = parse_plan(f"{REASONING}</think><answer>{PLAN}</answer>", IDS, TAGS)
    assert result.tier == "valid" and result.reasoning == REASONING


def test_the_glm_thinking_card_documents_its_format() -> None:
    card = model_card("glm-4.1v-9b-thinking")
    assert card.answer_format == TAGS
    assert answer_format_of("glm-4.1v-9b-thinking") == TAGS
    assert answer_format_of("vllm/zai-org/GLM-4.1V-9B-Thinking") == TAGS
    assert answer_format_of("qwen3-vl-8b") is None and answer_format_of("mock") is None


def test_a_thinking_runs_repaired_share_does_not_count_clean_answers() -> None:
    import json

    from vlm_bench.episodes import get_episode
    from vlm_bench.runner.evaluate import EpisodeInfo, scored_record
    from vlm_bench.types.plan import plan_to_json
    from vlm_bench.types.records import CachedResponse
    from vlm_bench.types.scores import ScoringConfig

    episode = get_episode("standard_pick_place", 0)
    gt = json.dumps(plan_to_json(episode.gt_plan))
    text = f"<think>{REASONING}</think><answer>{gt}</answer>"
    info = EpisodeInfo("r", "k", "explicit", "glm-4.1v-9b-thinking", "h")
    record = scored_record(
        info, episode, CachedResponse(key="k", prompt_hash="h", text=text), ScoringConfig()
    )
    assert record.parse is not None and record.parse.tier == "valid"
    assert record.parse.reasoning == REASONING  # kept in the record
    assert record.scores is not None and record.scores.s_total == 100.0
    tiers = parse_tier_rates(records_frame([record])).iloc[0]
    assert (tiers.valid, tiers.repaired) == (100.0, 0.0)
