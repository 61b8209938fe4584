"""Prompts: Jinja2 templates over the skill library, few-shot examples, and the user turn."""

from vlm_bench.prompting.builder import build_prompt, prompt_config_hash, render_system, render_text
from vlm_bench.prompting.examples import (
    check_no_leakage,
    few_shot_examples,
    find_leakage,
    select_examples,
)
from vlm_bench.prompting.replan import build_replan_prompt

__all__ = [
    "build_prompt",
    "build_replan_prompt",
    "check_no_leakage",
    "few_shot_examples",
    "find_leakage",
    "prompt_config_hash",
    "render_system",
    "render_text",
    "select_examples",
]
